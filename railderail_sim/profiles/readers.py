"""Profile file readers: plain two-column text and SIMPACK ``.prw`` / ``.prr``.

See :func:`load_profile`. Errors are :class:`ProfileError` (a ``ValueError``) with one message naming the
file, the line and the offending value.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._shapes import SplineShape
from .profile import Profile, ProfileError

__all__ = ["load_profile", "estimate_noise", "MIN_SMOOTHING", "GAUGE_DEPTH"]

#: Smallest smoothing used by the automatic choice (m): 0.01 um, above the rounding noise of files
#: written with 8 significant digits, far below any measurement noise.
MIN_SMOOTHING = 1.0e-8
#: Depth below the crown top (m) at which rails are re-centred (gauge measuring depth).
GAUGE_DEPTH = 0.014

_MIN_POINTS = 10
_MIN_SPACING = 1.0e-5      # m: points closer than 0.01 mm to the previous kept point are merged
_VERTICAL_SLOPE = math.tan(math.radians(89.0))  # steeper than 89 deg counts as "truly vertical"
_MIN_SPAN, _MAX_SPAN = 0.005, 1.0  # m: plausible lateral extent of a wheel or rail profile
_MAX_HEIGHT = 0.5          # m: plausible vertical extent

_UNITS = {"mm": 1e-3, "m": 1.0}

# SIMPACK keys: name -> value type ("int", "real", "str")
_SIMPACK_HEADER_KEYS = {"version": "int", "type": "int"}
_SIMPACK_SPLINE_KEYS = {
    "approx.smooth": "real", "file": "str", "file.mtime": "int", "comment": "str", "type": "int",
    "point.dist.min": "real", "shift.y": "real", "shift.z": "real", "rotate": "real",
    "bound.y.min": "real", "bound.y.max": "real", "bound.z.min": "real", "bound.z.max": "real",
    "mirror.y": "int", "mirror.z": "int", "inversion": "int", "units.len": "str", "units.ang": "str",
    "units.len.f": "real", "units.ang.f": "real",
}


@dataclass
class _Points:
    """Points as read (file units), with the line number and the raw text of each value."""

    path: str
    y: np.ndarray
    z: np.ndarray
    line: np.ndarray
    ytok: list
    ztok: list
    notes: list = field(default_factory=list)

    def take(self, idx) -> None:
        idx = np.asarray(idx)
        self.y, self.z, self.line = self.y[idx], self.z[idx], self.line[idx]
        self.ytok = [self.ytok[i] for i in idx]
        self.ztok = [self.ztok[i] for i in idx]

    def err(self, i: int, what: str, tok) -> ProfileError:
        ln = int(self.line[i])
        return ProfileError(f"{self.path}, line {ln}: {what} {tok!r}", path=self.path, line=ln, value=tok)


# ============================================================================ parsing
def _number(path, ln, tok, what="value"):
    try:
        v = float(tok)
    except ValueError:
        raise ProfileError(f"{path}, line {ln}: {what} {tok!r} is not a number", path=path, line=ln,
                           value=tok) from None
    if not math.isfinite(v):
        raise ProfileError(f"{path}, line {ln}: {what} {tok!r} is not a finite number", path=path,
                           line=ln, value=tok)
    return v


def _data_line(path, ln, s, ncols_ok):
    toks = [t for t in re.split(r"[,\s;]+", s.strip()) if t]
    if len(toks) not in ncols_ok:
        want = " or ".join(str(n) for n in ncols_ok)
        raise ProfileError(f"{path}, line {ln}: expected {want} numbers (y z), found {len(toks)} in "
                           f"{s.strip()!r}", path=path, line=ln, value=s.strip())
    y = _number(path, ln, toks[0], "y value")
    z = _number(path, ln, toks[1], "z value")
    for t in toks[2:]:
        _number(path, ln, t, "weight")
    return y, z, toks[0], toks[1]


def _parse_text(path: str, text: str):
    units, kind, rows = None, None, []
    for ln, raw in enumerate(text.splitlines(), start=1):
        s = raw.strip()
        if not s:
            continue
        if s.startswith("#"):
            m = re.match(r"#\s*(units|kind)\s*[:=]\s*(\S+)", s, re.IGNORECASE)
            if m:
                key, val = m.group(1).lower(), m.group(2).strip().lower()
                if key == "units":
                    if val not in _UNITS:
                        raise ProfileError(f"{path}, line {ln}: units {m.group(2)!r} are not accepted; "
                                           "use 'mm' or 'm'", path=path, line=ln, value=m.group(2))
                    units = val
                else:
                    if val not in ("wheel", "rail"):
                        raise ProfileError(f"{path}, line {ln}: kind {m.group(2)!r} is not accepted; "
                                           "use 'wheel' or 'rail'", path=path, line=ln, value=m.group(2))
                    kind = val
            continue
        s = s.split("#", 1)[0]
        rows.append((ln,) + _data_line(path, ln, s, (2,)))
    last = len(text.splitlines())
    return rows, (units or "mm"), kind, last


def _strip_bang(s: str) -> str:
    """Remove a '!' comment that is not inside a quoted string."""
    q = None
    for i, c in enumerate(s):
        if q:
            if c == q:
                q = None
        elif c in "'\"":
            q = c
        elif c == "!":
            return s[:i]
    return s


def _parse_simpack(path: str, text: str):
    header, spline, rows = {}, {}, []
    stack = []
    point_begin_line = None
    point_end_seen = False
    last = 0
    for ln, raw in enumerate(text.splitlines(), start=1):
        last = ln
        s = _strip_bang(raw).strip()
        if not s:
            continue
        m = re.fullmatch(r"([A-Za-z_]+)\.(begin|end)", s)
        if m:
            sec, what = m.group(1).lower(), m.group(2)
            if sec not in ("header", "spline", "point"):
                raise ProfileError(f"{path}, line {ln}: unknown section {m.group(0)!r}; SIMPACK profile "
                                   "files have header, spline and point sections", path=path, line=ln,
                                   value=m.group(0))
            if what == "begin":
                if sec == "point" and stack != ["spline"]:
                    raise ProfileError(f"{path}, line {ln}: 'point.begin' must be inside the spline "
                                       "section", path=path, line=ln, value=s)
                if sec != "point" and stack:
                    raise ProfileError(f"{path}, line {ln}: {s!r} inside section {stack[-1]!r}",
                                       path=path, line=ln, value=s)
                if sec == "point":
                    if point_begin_line is not None:
                        raise ProfileError(f"{path}, line {ln}: second 'point.begin' (the first is on "
                                           f"line {point_begin_line})", path=path, line=ln, value=s)
                    point_begin_line = ln
                stack.append(sec)
            else:
                if stack and stack[-1] == "point" and sec != "point":
                    raise ProfileError(f"{path}, line {ln}: 'point.begin' on line {point_begin_line} is "
                                       f"never closed by 'point.end' (found {s!r})", path=path, line=ln,
                                       value="point.end")
                if not stack or stack[-1] != sec:
                    if sec == "point":
                        raise ProfileError(f"{path}, line {ln}: 'point.end' without 'point.begin'",
                                           path=path, line=ln, value=s)
                    raise ProfileError(f"{path}, line {ln}: {s!r} does not close the open section "
                                       f"{(stack[-1] + '.begin') if stack else '(none)'}", path=path,
                                       line=ln, value=s)
                stack.pop()
                if sec == "point":
                    point_end_seen = True
            continue
        if stack and stack[-1] == "point":
            rows.append((ln,) + _data_line(path, ln, s, (2, 3)))
            continue
        if "=" in s:
            key, val = (t.strip() for t in s.split("=", 1))
            key_l = key.lower()
            if not stack:
                raise ProfileError(f"{path}, line {ln}: key {key!r} outside the header and spline "
                                   "sections", path=path, line=ln, value=key)
            table, store = ((_SIMPACK_HEADER_KEYS, header) if stack[-1] == "header"
                            else (_SIMPACK_SPLINE_KEYS, spline))
            if key_l not in table:
                raise ProfileError(f"{path}, line {ln}: unknown {stack[-1]} key {key!r}; known keys are "
                                   f"{', '.join(sorted(table))}", path=path, line=ln, value=key)
            typ = table[key_l]
            if typ == "str":
                store[key_l] = val.strip().strip("'\"")
            else:
                v = _number(path, ln, val, f"{key} value")
                store[key_l] = int(round(v)) if typ == "int" else v
            continue
        if re.fullmatch(r"[-+0-9.eEdD]+([,\s;]+[-+0-9.eEdD]+){1,2}", s):
            raise ProfileError(f"{path}, line {ln}: point data {s!r} outside point.begin/point.end (is "
                               "'point.begin' missing?)", path=path, line=ln, value=s)
        raise ProfileError(f"{path}, line {ln}: cannot read {s!r} (expected 'key = value', a section "
                           "marker or, inside point.begin/point.end, numbers)", path=path, line=ln,
                           value=s)
    if point_begin_line is None:
        raise ProfileError(f"{path}, line {last}: no 'point.begin' found; a SIMPACK profile needs its "
                           "points between point.begin and point.end", path=path, line=last,
                           value="point.begin")
    if not point_end_seen:
        raise ProfileError(f"{path}, line {last}: 'point.begin' on line {point_begin_line} is never "
                           "closed by 'point.end'", path=path, line=last, value="point.end")
    if stack:
        raise ProfileError(f"{path}, line {last}: section {stack[-1]!r} is never closed",
                           path=path, line=last, value=stack[-1] + ".end")
    return rows, header, spline, last


def _simpack_transform(pts: _Points, sp: dict) -> float:
    """Apply the spline-section processing in the order CONTACT reads it; return metres per file unit.

    Order: point.dist.min, shift.y/z, rotate (about the file origin, rad = value / units.ang.f;
    y' = y cos a - z sin a, z' = y sin a + z cos a), bound.y (drop points outside when min < max),
    bound.z (clip when min < max), mirror.y, mirror.z, inversion (reverse the order), units.len.f
    (file value / units.len.f = metres; 1 if absent).
    """
    applied = []
    d = sp.get("point.dist.min", 0.0)
    if d >= 1e-12:
        keep = [0]
        for i in range(1, len(pts.y)):
            if abs(pts.y[i] - pts.y[keep[-1]]) > d:
                keep.append(i)
        pts.take(keep)
        applied.append(f"point.dist.min={d:g}")
    sy, sz = sp.get("shift.y", 0.0), sp.get("shift.z", 0.0)
    if sy or sz:
        pts.y, pts.z = pts.y + sy, pts.z + sz
        applied.append(f"shift=({sy:g}, {sz:g})")
    rot = sp.get("rotate", 0.0)
    if rot:
        af = sp.get("units.ang.f", 1.0)
        if af == 0:
            raise ProfileError(f"{pts.path}: units.ang.f = 0 is not accepted (it must be the number of "
                               "angle units per radian)", path=pts.path, value=af)
        a = rot / af
        c, s = math.cos(a), math.sin(a)
        pts.y, pts.z = c * pts.y - s * pts.z, s * pts.y + c * pts.z
        applied.append(f"rotate={a:g} rad")
    ymin, ymax = sp.get("bound.y.min", 1.0), sp.get("bound.y.max", 0.0)
    if ymin < ymax:
        pts.take(np.nonzero((pts.y >= ymin) & (pts.y <= ymax))[0])
        applied.append(f"bound.y=[{ymin:g}, {ymax:g}]")
    zmin, zmax = sp.get("bound.z.min", 1.0), sp.get("bound.z.max", 0.0)
    if zmin < zmax:
        pts.z = np.clip(pts.z, zmin, zmax)
        applied.append(f"bound.z=[{zmin:g}, {zmax:g}]")
    if sp.get("mirror.y", 0) == 1:
        pts.y = -pts.y
        applied.append("mirror.y")
    if sp.get("mirror.z", 0) == 1:
        pts.z = -pts.z
        applied.append("mirror.z")
    if sp.get("inversion", 0) == 1:
        pts.take(np.arange(len(pts.y))[::-1])
        applied.append("inversion")
    f = sp.get("units.len.f", 1.0)
    if f <= 0:
        raise ProfileError(f"{pts.path}: units.len.f = {f!r} is not accepted; it must be the number of "
                           "length units per metre (1000 for mm)", path=pts.path, value=f)
    applied.append(f"units.len.f={f:g}")
    pts.notes.append("SIMPACK processing: " + ", ".join(applied))
    return 1.0 / f


# ============================================================================ reduction
def _reduce_single_valued(pts: _Points, kind: str) -> None:
    """Reduce the ordered points (metres, our frame) to a single-valued z(y) over the useful range.

    1. Points closer than 0.01 mm (chord) to the previous kept point are dropped (duplicates and the
       very dense runs some files put on steep faces).
    2. The sequence is oriented so that y mostly increases.
    3. Starting at the highest point (wheel: flange tip; rail: crown top), the profile is followed in
       both directions while y strictly increases away from it and the piece is not steeper than 89 deg.
       It stops where the profile becomes truly vertical (steeper than 89 deg: wheel back face, rim face,
       bottom of a rail side face) or turns back under itself after a steep part (underside of a rail
       head). Everything beyond is dropped. A reversal of y on a part that is not steep (both
       neighbouring pieces flatter than 45 deg) cannot be reduced and raises ProfileError.
    """
    keep = [0]
    for i in range(1, len(pts.y)):
        j = keep[-1]
        if math.hypot(pts.y[i] - pts.y[j], pts.z[i] - pts.z[j]) > _MIN_SPACING:
            keep.append(i)
    n_dup = len(pts.y) - len(keep)
    pts.take(keep)
    if pts.y[-1] < pts.y[0]:
        pts.take(np.arange(len(pts.y))[::-1])
    y, z = pts.y, pts.z
    n = len(y)
    i0 = int(np.argmax(z))

    def steep(a, b):
        if min(a, b) < 0 or max(a, b) >= n:
            return False
        return abs(z[b] - z[a]) >= abs(y[b] - y[a])

    def walk(step):
        j = i0
        while 0 <= j + step < n:
            k = j + step
            dy = (y[k] - y[j]) * step
            if dy > 0.0 and abs(z[k] - z[j]) <= _VERTICAL_SLOPE * dy:
                j = k
                continue
            if dy <= 0.0 and not (steep(j - step, j) or steep(j, k) or steep(k, k + step)):
                raise pts.err(k, f"y value does not increase (after {pts.ytok[j]!r} on line "
                              f"{int(pts.line[j])}) on a part of the profile that is not vertical, so "
                              "it cannot be reduced to a single-valued z(y):", pts.ytok[k])
            break
        return j

    lo, hi = walk(-1), walk(+1)
    dropped = (lo, n - 1 - hi)
    pts.take(np.arange(lo, hi + 1))
    pts.notes.append(f"reduced to single-valued z(y): {n_dup} near-duplicate points merged, {dropped[0]} "
                     f"points dropped at the low-y end and {dropped[1]} at the high-y end "
                     "(vertical or overhanging parts)")


# ============================================================================ smoothing
def estimate_noise(y: np.ndarray, z: np.ndarray, half: int = 3) -> float:
    """Robust estimate (m) of the RMS noise of profile points, measured normal to the profile.

    For every point with ``half`` neighbours on each side, a cubic is least-squares fitted to the
    ``2*half+1`` points around it; the residual at the centre, divided by sqrt(1 - h) (h: its hat-matrix
    diagonal, so that it has the noise variance) and by sqrt(1 + z'^2) (vertical -> normal), is
    collected. The estimate is 1.4826 x the median absolute residual (a MAD: arc joints and other
    isolated model errors do not inflate it).
    """
    n = len(y)
    if n < 2 * half + 1:
        return 0.0
    win = np.arange(-half, half + 1)[None, :] + np.arange(half, n - half)[:, None]
    yy = y[win] - y[half:n - half, None]
    sc = np.max(np.abs(yy), axis=1, keepdims=True)
    a = (yy / sc)[:, :, None] ** np.arange(3, -1, -1)       # (m, 2h+1, 4) cubic design matrices
    pinv = np.linalg.pinv(a)                                 # (m, 4, 2h+1)
    coef = np.einsum("mkj,mj->mk", pinv, z[win])
    hii = np.einsum("mk,mk->m", a[:, half, :], pinv[:, :, half])
    r = (z[half:n - half] - np.einsum("mk,mk->m", a[:, half, :], coef)) / np.sqrt(
        np.maximum(1.0 - hii, 1e-12))
    slope = coef[:, 2] / sc[:, 0]
    res = r / np.sqrt(1.0 + slope * slope)
    return float(1.4826 * np.median(np.abs(res)))


# ============================================================================ public reader
def load_profile(path, kind: str | None = None, *, inclination: float | None = None,
                 recentre: bool | None = None, smoothing: float | None = None,
                 name: str | None = None) -> Profile:
    """Read a wheel or rail profile file into a :class:`Profile` in our frames.

    Formats (chosen by content: a file with ``header.begin``/``spline.begin``/``point.begin`` lines is
    SIMPACK, anything else plain text):

    * **Plain text**: two numbers per line, ``y z`` (whitespace or comma separated), already in our
      frame (wheel: y from the rolling circle, flange at negative y, z = radius increase; rail: y to
      the field side, z up). ``#`` starts a comment. Optional header comments ``# units: mm`` or
      ``# units: m`` (default mm) and ``# kind: wheel`` / ``# kind: rail``.
    * **SIMPACK** ``.prw`` (wheel) / ``.prr`` (rail): keys between ``header.begin/end`` and
      ``spline.begin/end``, points between ``point.begin/end`` (y z [weight]); ``!`` comments. The
      processing keys are applied in this order: point.dist.min, shift.y/z, rotate (about x, in
      units.ang.f per rad), bound.y/z, mirror.y, mirror.z, inversion, units.len.f (file units per
      metre). ``type`` (0 rail, 1 wheel) gives the kind. SIMPACK's z points down: for a wheel that is
      already our "radius increase" (flange tip positive), for a rail z is negated. After the
      processing, the flange (wheel) and gauge side (rail) are at negative y, as in our frames.
      ``approx.smooth`` and point weights are read but not used (our smoothing is ``smoothing``).

    Then the points are reduced to a single-valued z(y) over the useful range: from the highest point
    (flange tip / crown top) outward until the profile turns truly vertical (> 89 deg) or back under
    itself -- for a wheel from just inside the flange back to the rim, for a rail the head between the
    lowest points of its two side faces (details in ``_reduce_single_valued``). The result is fitted
    with a cubic smoothing spline (:class:`SplineShape`) so that slope and curvature are not noisy.

    Parameters
    ----------
    kind: 'wheel' or 'rail'; required for text files without ``# kind:``; for SIMPACK files it must
        agree with the header type if given.
    inclination: rails only. Tangent of the inclination the data carry (e.g. ``1/40`` for a rail
        already canted 1:40 toward the gauge side, like the Manchester benchmark UIC60); the data are
        rotated back by ``atan(inclination)`` about the file origin. Default: none.
    recentre: rails only. Shift the profile so that z = 0 at the crown top and y = 0 midway between
        the two side faces 14 mm below the top (the head axis of a symmetric head). Default: True for
        SIMPACK rails (their reference point is file specific), False for text rails.
    smoothing: allowed RMS deviation (m) of the points normal to the profile. Default (None):
        automatic, ``max(estimate_noise(points), MIN_SMOOTHING)`` -- the noise of the data estimated
        from local cubic fits, at least 0.01 um (files of computed points, such as the shipped ones,
        get 0.01 um, i.e. practically interpolation without rounding ripple; measured profiles get
        their own noise level). 0 interpolates the points exactly (knots at every point).
    name: profile name (default: the file name).

    Raises ProfileError (a ValueError) naming the file, line and value for: non-numeric or non-finite
    values, fewer than 10 points, y that cannot be reduced to single-valued, extents implausible for
    the length unit (narrower than 5 mm or wider than 1 m), unknown SIMPACK keys or sections, missing
    point.begin/point.end, and a wheel whose flange is at positive y.
    """
    p = Path(path)
    spath = str(path)
    if kind is not None and kind not in ("wheel", "rail"):
        raise ValueError(f"kind {kind!r} is not accepted; use 'wheel', 'rail' or None")
    if smoothing is not None and not (smoothing >= 0.0 and math.isfinite(smoothing)):
        raise ValueError(f"smoothing={smoothing!r} m is not accepted; use a value >= 0 (e.g. 5e-7)")
    try:
        text = p.read_text(encoding="utf-8", errors="replace")
    except OSError as e:
        raise ProfileError(f"{spath}: cannot read the file ({e.strerror or e})", path=spath) from None

    simpack = bool(re.search(r"^\s*(header|spline|point)\.begin\b", text, re.MULTILINE))
    if simpack:
        rows, header, spline, last = _parse_simpack(spath, text)
        ftype = header.get("type")
        fkind = {0: "rail", 1: "wheel"}.get(ftype) if ftype is not None else None
        if ftype is not None and fkind is None:
            raise ProfileError(f"{spath}: header type {ftype!r} is not accepted (0 = rail, 1 = wheel)",
                               path=spath, value=ftype)
        if fkind is None:
            fkind = {".prw": "wheel", ".prr": "rail"}.get(p.suffix.lower())
    else:
        rows, units, fkind, last = _parse_text(spath, text)
    if kind is not None and fkind is not None and kind != fkind:
        raise ProfileError(f"{spath}: the file declares a {fkind} profile but kind={kind!r} was asked for",
                           path=spath, value=fkind)
    kind = kind or fkind
    if kind is None:
        raise ProfileError(f"{spath}: the profile kind is unknown; pass kind='wheel' or 'rail' or add a "
                           "'# kind: wheel' line", path=spath)
    if len(rows) < _MIN_POINTS:
        raise ProfileError(f"{spath}, line {last}: only {len(rows)} profile points; at least "
                           f"{_MIN_POINTS} are needed", path=spath, line=last, value=len(rows))

    pts = _Points(spath, np.array([r[1] for r in rows]), np.array([r[2] for r in rows]),
                  np.array([r[0] for r in rows]), [r[3] for r in rows], [r[4] for r in rows])
    if simpack:
        scale = _simpack_transform(pts, spline)
        if len(pts.y) < _MIN_POINTS:
            raise ProfileError(f"{spath}, line {last}: only {len(pts.y)} profile points left after the "
                               f"SIMPACK processing; at least {_MIN_POINTS} are needed", path=spath,
                               line=last, value=len(pts.y))
        unit_desc = f"units.len.f = {spline.get('units.len.f', 1.0):g} length units per metre"
        pts.y, pts.z = pts.y * scale, pts.z * scale
        if kind == "rail":
            pts.z = -pts.z
        fmt = "SIMPACK"
    else:
        pts.y, pts.z = pts.y * _UNITS[units], pts.z * _UNITS[units]
        unit_desc = f"unit '{units}'"
        fmt = f"text ({units})"

    # plausibility of the extent for the declared unit
    span = float(pts.y.max() - pts.y.min())
    if not (_MIN_SPAN <= span <= _MAX_SPAN):
        i = int(np.argmax(np.abs(pts.y)))
        raise pts.err(i, f"the profile is {span * 1e3:.4g} mm wide, implausible for a wheel or rail "
                      f"(accepted {_MIN_SPAN * 1e3:g} mm to {_MAX_SPAN * 1e3:g} mm); check the length "
                      f"unit ({unit_desc}); extreme y value", pts.ytok[i])
    height = float(pts.z.max() - pts.z.min())
    if height > _MAX_HEIGHT:
        i = int(np.argmax(np.abs(pts.z)))
        raise pts.err(i, f"the profile is {height * 1e3:.4g} mm high, implausible for a wheel or rail "
                      f"(at most {_MAX_HEIGHT * 1e3:g} mm); check the length unit ({unit_desc}); "
                      "extreme z value", pts.ztok[i])

    if kind == "wheel" and (inclination or recentre):
        raise ValueError("inclination and recentre apply to rail profiles only; pass them as None for "
                         "a wheel")
    if kind == "rail" and inclination:
        a = math.atan(float(inclination))
        c, s = math.cos(a), math.sin(a)
        pts.y, pts.z = c * pts.y + s * pts.z, -s * pts.y + c * pts.z
        pts.notes.append(f"un-inclined: rotated by -atan({float(inclination):.6g}) = {-a:.6g} rad about "
                         "the file origin (data canted toward the gauge side, y < 0)")

    _reduce_single_valued(pts, kind)
    if len(pts.y) < _MIN_POINTS:
        raise ProfileError(f"{spath}, line {int(pts.line[0])}: only {len(pts.y)} points are left after "
                           f"reducing to a single-valued z(y); at least {_MIN_POINTS} are needed",
                           path=spath, line=int(pts.line[0]), value=len(pts.y))

    if kind == "wheel":
        itip = int(np.argmax(pts.z))
        if pts.y[itip] > 0.0:
            raise pts.err(itip, "the flange tip is at positive y; the flange must be at negative y "
                          "(toward the back face): flip the sign of y (SIMPACK: mirror.y = 1). Tip y",
                          pts.ytok[itip])
        if not (pts.y[0] < 0.0 < pts.y[-1]):
            raise pts.err(len(pts.y) - 1, "the wheel profile does not cover y = 0 (the nominal rolling "
                          "circle) after reduction; last y", pts.ytok[-1])
    else:
        if pts.y[-1] - pts.y[0] < 0.020:
            raise pts.err(len(pts.y) - 1, f"the rail head covers only {(pts.y[-1] - pts.y[0]) * 1e3:.3g} "
                          "mm after reduction (at least 20 mm needed); last y", pts.ytok[-1])

    if smoothing is None:
        noise = estimate_noise(pts.y, pts.z)
        smoothing = max(noise, MIN_SMOOTHING)
        how_smooth = f"automatic (estimated noise {noise * 1e6:.3g} um, floor {MIN_SMOOTHING * 1e6:g} um)"
    else:
        how_smooth = "as given"
    shape = SplineShape(pts.y, pts.z, smoothing)
    if recentre is None:
        recentre = simpack and kind == "rail"
    if recentre:
        if kind != "rail":
            raise ValueError("recentre applies to rail profiles only")
        tmp = Profile(name="tmp", kind="rail", y=pts.y, z=pts.z, shape=shape)
        ztop = float(tmp.eval(tmp.top_y()))
        try:
            a, b = tmp.head_sides_y(GAUGE_DEPTH)
            yc = 0.5 * (a + b)
            how = f"y = 0 midway between the side faces {GAUGE_DEPTH * 1e3:g} mm below the top"
        except ValueError:
            yc = tmp.top_y()
            how = f"y = 0 at the crown top (the head is less than {GAUGE_DEPTH * 1e3:g} mm deep)"
        pts.y, pts.z = pts.y - yc, pts.z - ztop
        shape = SplineShape(pts.y, pts.z, smoothing)
        pts.notes.append(f"re-centred: {how}, z = 0 at the crown top (shift y by {-yc * 1e3:+.4f} mm, "
                         f"z by {-ztop * 1e3:+.4f} mm)")
    pts.notes.append(f"cubic smoothing spline: RMS normal deviation allowed {smoothing * 1e6:.3g} um "
                     f"({how_smooth}), {shape.n_knots} knots for {len(pts.y)} points")
    notes = (f"read from {p.name} ({fmt}, lines {int(pts.line.min())}-{int(pts.line.max())} kept).\n"
             + "\n".join("- " + s for s in pts.notes))
    return Profile(name=name or p.name, kind=kind, y=pts.y, z=pts.z, source=f"file {spath}",
                   notes=notes, shape=shape)
