"""Arc-built profiles: UIC60 (EN 13674-1 60E1) rail head and the reconstructed LM wheel.

Both are exact tangent-continuous chains of arcs and lines (:class:`ArcChain`). Geometry is computed
in millimetres from the defining radii/centres and converted to metres at the end.
"""
from __future__ import annotations

from functools import lru_cache
import math

import numpy as np

from ._shapes import Arc, ArcChain, Line
from .profile import Profile

__all__ = ["uic60", "lm", "LM_PRW_EXTRACT_MM", "LM_PARAMS_MM", "LM_DATUM_SHIFT_MM",
           "UIC60_PARAMS_MM", "lm_chain_mm", "uic60_chain_mm"]

_MM = 1e-3
_POINT_STEP = 1e-4  # 0.1 mm spacing of the Profile point arrays (the shape itself is exact)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.hypot(v[0], v[1])


def _scaled(pieces, s: float):
    out = []
    for p in pieces:
        if isinstance(p, Arc):
            out.append(Arc(p.yc * s, p.zc * s, p.r * s, p.branch, p.ya * s, p.yb * s))
        else:
            out.append(Line(p.y0 * s, p.z0 * s, p.m, p.ya * s, p.yb * s))
    return out


def _shifted(pieces, dz: float):
    out = []
    for p in pieces:
        if isinstance(p, Arc):
            out.append(Arc(p.yc, p.zc + dz, p.r, p.branch, p.ya, p.yb))
        else:
            out.append(Line(p.y0, p.z0 + dz, p.m, p.ya, p.yb))
    return out


def _mirror(pieces):
    """Mirror y -> -y (pieces returned in increasing y)."""
    out = []
    for p in reversed(pieces):
        if isinstance(p, Arc):
            out.append(Arc(0.0 - p.yc, p.zc, p.r, p.branch, 0.0 - p.yb, 0.0 - p.ya))
        else:
            out.append(Line(0.0 - p.y0, p.z0, -p.m, 0.0 - p.yb, 0.0 - p.ya))
    return out


def _from_chain(name, kind, chain_mm: ArcChain, source, notes) -> Profile:
    chain = ArcChain(_scaled(chain_mm.pieces, _MM))
    y = chain.sample_points(_POINT_STEP)
    notes = notes + "\nPieces as built (mm, this profile's frame):\n" + chain.describe(1e3)
    return Profile(name=name, kind=kind, y=y, z=chain(y), source=source, notes=notes, shape=chain)


# =====================================================================================  UIC60 / 60E1
#: Defining dimensions of the 60E1 head (mm), EN 13674-1 as encoded in rohrbecka/EN13674 P60E1.swift.
UIC60_PARAMS_MM = {
    "r_crown": 300.0,          # crown arc, centre (0, -300)
    "y_crown_end": 20.456 / 2,  # R300/R80 tangent point (half of 20.456)
    "r_shoulder": 80.0,
    "y_shoulder_end": 52.053 / 2,  # R80/R13 tangent point (half of 52.053)
    "r_corner": 13.0,
    "side_face_slope": 20.0,   # side face 1:20 (flares outward going down)
    "underside_slope": 1 / 2.75,  # underside of head 1:2.75 ...
    "underside_z_axis": -51.0,     # ... through (0, -51) on the axis (head-web junction)
}


def uic60_chain_mm() -> ArcChain:
    """The 60E1 head as an ArcChain in mm (un-inclined rail frame, z = 0 at the crown top).

    Field side: R300 -> R80 -> R13 -> 1:20 side face, cut at its theoretical intersection with the
    1:2.75 underside of the head (y = 37.159, z = -37.487 mm); the gauge side is the mirror image.
    """
    p = UIC60_PARAMS_MM
    c300 = np.array([0.0, -p["r_crown"]])
    y1 = p["y_crown_end"]
    p1 = np.array([y1, c300[1] + np.sqrt(p["r_crown"] ** 2 - y1 ** 2)])
    c80 = p1 + p["r_shoulder"] * _unit(c300 - p1)
    y2 = p["y_shoulder_end"]
    p2 = np.array([y2, c80[1] + np.sqrt(p["r_shoulder"] ** 2 - (y2 - c80[0]) ** 2)])
    c13 = p2 + p["r_corner"] * _unit(c80 - p2)
    k = p["side_face_slope"]
    p3 = c13 + p["r_corner"] * np.array([k, 1.0]) / np.hypot(k, 1.0)  # where the R13 tangent is 1:20
    # side face z = p3z - k (y - p3y) meets underside z = z_ax + y * m at the corner
    m, z_ax = p["underside_slope"], p["underside_z_axis"]
    y_corner = (p3[1] + k * p3[0] - z_ax) / (k + m)
    right = [
        Arc(0.0, c300[1], p["r_crown"], +1, 0.0, y1),
        Arc(c80[0], c80[1], p["r_shoulder"], +1, y1, y2),
        Arc(c13[0], c13[1], p["r_corner"], +1, y2, p3[0]),
        Line(p3[0], p3[1], -k, p3[0], y_corner),
    ]
    return ArcChain(_mirror(right) + right)


_UIC60_NOTES = """\
UIC60 = EN 13674-1 60E1 rail head, built exactly from its arcs; un-inclined rail frame (y to the field
side, 0 on the axis of symmetry; z up, 0 at the crown top). Inclination (1:40) is applied by the contact
geometry, not here.
Dimensions, source, confidence:
- crown R300, centre (0, -300 mm), to |y| = 10.228 mm (20.456/2): EN 13674-1 via rohrbecka/EN13674
  P60E1.swift [verified]; re-computed tangent point z = -0.1744 mm.
- shoulder R80 to |y| = 26.0265 mm (52.053/2), centre (+-7.5005, -80.1279): same source [verified].
- gauge corner R13 until its tangent is 1:20, at (+-36.000, -14.300 mm), centre (+-23.0160, -14.9491):
  same source [verified]; head width 72.00 mm at 14.3 mm, 71.96 mm at 14 mm.
- side face 1:20, cut at its theoretical intersection with the 1:2.75 underside of the head through
  (0, -51 mm): y = +-37.159 mm, z = -37.487 mm (depth 37.49 mm below the crown). The R3 fillet between
  face and underside (it starts ~2.2 mm above that corner) is omitted: it curls back under the head
  (not single-valued) and is never touched by a wheel. Same cut as the Manchester-benchmark data.
- cross-check against the Manchester-benchmark UIC60 v3 file (un-inclined 1:40, re-centred;
  uic60_mbench()): crown (|y| <= 10 mm) identical to 0.01 um; beyond it the file's R80 starts at
  |y| = 10.50 mm (centre +-7.700, -80.135) instead of 10.228 mm, which lifts the file's shoulder and
  gauge corner by up to 0.040 mm: max normal deviation 0.039 mm (at |y| = 26 mm). Head width at 14 mm:
  71.963 mm here, 71.968 mm in the file. Which tangent point EN 13674-1 really prints (20.456 or 21.0
  mm chord) was not checked in the standard itself; the difference is far below wear and tolerances."""


@lru_cache(maxsize=None)
def uic60() -> Profile:
    """UIC60 (60E1) rail head from its EN 13674-1 arcs, un-inclined rail frame, cut at 37.49 mm depth."""
    return _from_chain("UIC60 (60E1)", "rail", uic60_chain_mm(),
                       "EN 13674-1 60E1 head arcs (via rohrbecka/EN13674 P60E1.swift); exact arcs",
                       _UIC60_NOTES)


# =====================================================================================  LM wheel
#: Coordinate extract (y, z in mm) of SIMPACK's example wheel profile LM.prw, as republished in
#: wenquantongxin/OpenRailVehicleDynamics (gz18_reference_wheel_profile.json), read off that table at these
#: y. z is in the LM.prw datum (z(0) = -0.093 mm).
LM_PRW_EXTRACT_MM = np.array([
    (-64.5, 21.964), (-62.0, 24.642), (-60.0, 26.092), (-58.0, 27.014), (-56.0, 27.532),
    (-54.0, 27.700), (-52.0, 27.532), (-50.0, 27.015), (-48.0, 26.094), (-46.0, 24.805),
    (-44.0, 23.130), (-42.0, 20.910), (-40.0, 17.728), (-39.0, 15.447), (-38.0, 12.802),
    (-37.0, 10.658), (-36.0, 9.256), (-34.0, 7.189), (-32.0, 5.793), (-30.0, 4.839),
    (-28.0, 4.202), (-25.0, 3.378), (-20.0, 2.223), (-15.0, 1.334), (-10.0, 0.704),
    (-5.0, 0.270), (0.0, -0.093), (5.0, -0.389), (10.0, -0.620), (15.0, -0.785),
    (20.0, -0.883), (25.0, -0.916), (30.0, -1.000), (34.5, -1.217),
])

#: Parameters of the LM reconstruction (mm; LM.prw datum before the z shift). "fit" = least-squares fit
#: to LM_PRW_EXTRACT_MM with every tangency built in; "data" = circle fits to that table (kept at
#: their clean values); "assumed" = not in any data.
LM_PARAMS_MM = {
    "tip_r": 12.0,            # data: flange tip R12
    "tip_cy": -54.00,         # data: tip 16.0 mm from the back face
    "tip_cz": 15.70,          # data/fit: tip at z = 27.70 (flange height 27.70 over z = 0 of LM.prw)
    "face_r": 20.04,          # fit (data: ~20.1); internally tangent to the tip arc
    "face_cy": -57.86,        # data (face centre y); face centre z follows from the tangency
    "flank_deg": 69.36,       # fit: short straight flank = max flange angle (data: ~69.6 deg)
    "root_r": 13.73,          # fit (data: ~14, "not a clean arc"); tangent to flank and R100
    "r100": 100.0,            # data; centre y = 0, internally tangent to R380
    "r380": 380.0,            # data; centre y = +25
    "r380_cz": 379.084,       # fit (data: 379.09); gives z(0) = -0.093 as in LM.prw
    "r150": 150.0,            # data; convex, centre y = +25 (inflection with R380 at y = +25)
    "back_face_y": -70.0,     # assumed: rolling circle 70 mm from the back face (1493 - 1353)/2
    "back_r": 25.0,           # fit to the two points at y = -64.5, -62 (data: "~20-35, not one arc");
                              # tangent to the tip arc and to the vertical back face
    "y_start": -69.5,         # assumed: profile starts 0.5 mm inside the back face (slope ~77 deg)
    "outer_slope": 1.0 / 8.0, # assumed: 1:8 outer tread (recollection "1:8 chamfer", unverified)
    "rim_face_y": 65.0,       # assumed: rim width 135 mm from the back face (recollection)
}


def _lm_pieces_mm(par: dict) -> list:
    c12 = np.array([par["tip_cy"], par["tip_cz"]])
    r12, rf, rr = par["tip_r"], par["face_r"], par["root_r"]
    # flange face: internally tangent to the tip arc, centre at the given y
    dyf = par["face_cy"] - c12[0]
    cf = np.array([par["face_cy"], c12[1] - np.sqrt((rf - r12) ** 2 - dyf ** 2)])
    p12f = cf + rf * _unit(c12 - cf)
    # straight flank at the flange angle theta, tangent to the face arc
    th = np.radians(par["flank_deg"])
    nrm = np.array([math.sin(th), math.cos(th)])
    dirn = np.array([math.cos(th), -math.sin(th)])
    pf = cf + rf * nrm
    # tread arcs: R380 centre (25, cz); R100 centre (0, .) internally tangent to R380
    r100, r380, r150 = par["r100"], par["r380"], par["r150"]
    c380 = np.array([25.0, par["r380_cz"]])
    c100 = np.array([0.0, c380[1] - np.sqrt((r380 - r100) ** 2 - 25.0 ** 2)])
    # root: tangent to the flank line (centre at rr along nrm from it) and internally to R100
    a0 = pf + rr * nrm - c100
    b = 2.0 * (a0 @ dirn)
    c = a0 @ a0 - (r100 - rr) ** 2
    disc = b * b - 4.0 * c
    if disc < 0.0:
        raise ValueError("LM parameters admit no flange root arc tangent to both flank and R100")
    roots = [t for t in ((-b - np.sqrt(disc)) / 2.0, (-b + np.sqrt(disc)) / 2.0) if t >= 0.0]
    if not roots:
        raise ValueError("LM parameters give a negative flank length")
    t = min(roots)
    q = pf + t * dirn
    cr = q + rr * nrm
    pr100 = c100 + r100 * _unit(cr - c100)
    p100_380 = c380 + r380 * _unit(c100 - c380)
    c150 = np.array([25.0, c380[1] - r380 - r150])
    # outer tread: R150 until its slope is -outer_slope, then the straight slope to the rim face
    phi = math.atan(par["outer_slope"])
    pt = c150 + r150 * np.array([math.sin(phi), math.cos(phi)])
    # flange back: arc tangent to the vertical back face and internally to the tip arc
    rb = par["back_r"]
    cb_y = par["back_face_y"] + rb
    cb = np.array([cb_y, c12[1] - np.sqrt((rb - r12) ** 2 - (cb_y - c12[0]) ** 2)])
    pb12 = cb + rb * _unit(c12 - cb)
    return [
        Arc(cb[0], cb[1], rb, +1, par["y_start"], pb12[0]),
        Arc(c12[0], c12[1], r12, +1, pb12[0], p12f[0]),
        Arc(cf[0], cf[1], rf, +1, p12f[0], pf[0]),
        Line(pf[0], pf[1], -math.tan(th), pf[0], q[0]),
        Arc(cr[0], cr[1], rr, -1, q[0], pr100[0]),
        Arc(c100[0], c100[1], r100, -1, pr100[0], p100_380[0]),
        Arc(c380[0], c380[1], r380, -1, p100_380[0], 25.0),
        Arc(c150[0], c150[1], r150, +1, 25.0, pt[0]),
        Line(pt[0], pt[1], -par["outer_slope"], pt[0], par["rim_face_y"]),
    ]


def lm_chain_mm(params: dict | None = None, *, prw_datum: bool = False) -> ArcChain:
    """The LM reconstruction as an ArcChain in mm.

    ``prw_datum=False`` (default, as used by :func:`lm`): z shifted so that z(0) = 0 (our wheel frame);
    ``True``: in the datum of SIMPACK's LM.prw (z(0) = -0.093 mm), for comparison with the extract.
    """
    par = dict(LM_PARAMS_MM)
    if params:
        par.update(params)
    pieces = _lm_pieces_mm(par)
    chain = ArcChain(pieces)
    if prw_datum:
        return chain
    return ArcChain(_shifted(pieces, -float(chain(0.0))))


#: z shift (mm) from the LM.prw datum to our frame (z(0) = 0): z_ours = z_prw + LM_DATUM_SHIFT_MM.
LM_DATUM_SHIFT_MM = float(-lm_chain_mm(prw_datum=True)(0.0))

_LM_NOTES = f"""\
LM wheel (TB/T 449), RECONSTRUCTED. TB/T 449 defines LM by a dimensioned drawing that is not public.
This profile is a tangent-continuous arc chain fitted to SIMPACK's example wheel profile LM.prw (the
likely profile of Yu et al. 2022), as republished in wenquantongxin/OpenRailVehicleDynamics; the arc
radii below come from circle fits to that table. Wheel frame: y from the nominal rolling circle, + toward the rim face, flange at -y;
z = radius minus nominal radius, shifted by +{LM_DATUM_SHIFT_MM:.4f} mm from the LM.prw datum so that
z(0) = 0.
Pieces (y toward +), source, confidence:
- flange back rounding R{LM_PARAMS_MM['back_r']}, tangent to a vertical back face at y = -70 mm and to
  the tip arc; profile starts at y = {LM_PARAMS_MM['y_start']} mm. Radius fitted to 2 data points
  (y = -64.5, -62); the data say "not one arc". ASSUMED shape; never in contact with the rail head.
- flange tip R12, centre (-54.00, 15.70 mm, LM.prw datum): data [clean fit, sure].
- flange face R{LM_PARAMS_MM['face_r']} (data ~R20.1), internally tangent to the tip: fitted [fairly sure].
- straight flank at {LM_PARAMS_MM['flank_deg']} deg, ~1.1 mm long in y: fitted. the circle fits show
  "no straight flank" but a direct R20/R14 tangency gives 74 deg and misfits by 0.3 mm; the short flank
  reproduces the measured maximum flange angle (69.6 deg) [fairly sure about the angle].
- flange root R{LM_PARAMS_MM['root_r']} concave (data ~R14, "not a clean arc"): fitted [least sure;
  deviation up to 0.046 mm at y = -37 mm].
- tread R100 concave, centre y = 0: data [sure]; internally tangent to R380.
- tread R380 concave, centre y = +25 (horizontal tangent at +25): data [sure]; slope 1:15 at y = 0.
- R150 convex from y = +25 (inflection): data to y = +34.5 [sure]; continued to y = +43.6 where its
  slope reaches 1:8 [ASSUMED].
- outer tread 1:8 straight to the rim face at y = +65 mm (rim width 135 mm): ASSUMED (recollection of
  the LM drawing, unverified). Never in contact in normal running: on UIC60 1:40 / 1435 mm the contact
  reaches y = +34.5 mm only at ~38 mm lateral shift (late derailment phase, rigid-contact scan).
- back face y = -70 mm (rolling circle 70 mm from the back face): secondary sources (1493 - 1353)/2.
Derived (measured on this profile): flange height 27.79 mm over z(0); flange thickness from the back
face 33.51 / 32.37 / 31.95 / 31.20 mm at 10 / 12 / 13 / 15 mm above z(0) (33.45 / 32.32 / 31.91 / 31.16
above the LM.prw z = 0 line; the LM.prw table itself gives 33.4 / 32.3 / 31.9 / 31.2); max flange angle
69.36 deg; slope -0.066 (1:15) at y = 0.
Check against the 34-point LM.prw extract: max deviation 0.046 mm (y = -37, flange root), RMS 0.012 mm,
tread (y >= -28 mm) 0.0006 mm, flange tip and face 0.013 mm, flange back 0.003 mm.
The common quotes "27 mm flange, 32 mm thick, R100/R500/R220" are not this file (R380, R150)."""


@lru_cache(maxsize=None)
def lm() -> Profile:
    """LM wheel reconstructed from the arc fits of SIMPACK's LM.prw (see notes/docs): y from
    y_start = -69.5 mm to the rim face at +65 mm, z(0) = 0."""
    return _from_chain("LM (reconstructed)", "wheel", lm_chain_mm(),
                       "TB/T 449 LM, reconstructed: arcs fitted to SIMPACK example LM.prw as "
                       "republished in wenquantongxin/OpenRailVehicleDynamics; outer tread and back "
                       "rounding assumed", _LM_NOTES)
