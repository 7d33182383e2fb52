"""`Profile` (points + C2 shape), `ProfileTable` (uniform resampling for the hot loop) and the
derived dimensions (flange height/thickness/angle, head width). Frames: see the package docstring."""
from __future__ import annotations

from dataclasses import dataclass, field

import math

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq, minimize_scalar

from .. import scalarmath

__all__ = ["Profile", "ProfileTable", "ProfileError", "DEFAULT_DY", "BACK_FACE_Y"]

#: Default spacing of a ProfileTable (m): 0.05 mm.
DEFAULT_DY = 5.0e-5
#: Lateral position of the wheel's flange back (inner) face for LM and S1002 (m).
BACK_FACE_Y = -0.070

_KINDS = ("wheel", "rail")


class ProfileError(ValueError):
    """A profile file (or array) that cannot be used. The message names the file, the line and the
    offending value; the same are available as ``path``, ``line`` and ``value``."""

    def __init__(self, message: str, *, path=None, line=None, value=None) -> None:
        super().__init__(message)
        self.path = path
        self.line = line
        self.value = value


class _CubicShape:
    """Interpolating not-a-knot cubic spline: the default C2 shape of a Profile built from arrays."""

    def __init__(self, y, z):
        self._cs = CubicSpline(y, z, bc_type="not-a-knot")

    def __call__(self, y, nu=0):
        return self._cs(y, nu)


@dataclass(frozen=True, eq=False)
class Profile:
    """A wheel or rail profile z(y) in the frames of the package docstring (SI units).

    ``y``/``z`` are the defining points (float64, metres, ``y`` strictly increasing; read-only).
    ``shape`` is the C2 (or exact piecewise-arc) representation used for every derived quantity and for
    :meth:`table`; if omitted, an interpolating cubic spline through the points is used.
    """

    name: str
    kind: str
    y: np.ndarray
    z: np.ndarray
    source: str = ""
    notes: str = ""
    shape: object = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if self.kind not in _KINDS:
            raise ValueError(f"profile kind {self.kind!r} is not accepted; use 'wheel' or 'rail'")
        y = np.array(self.y, dtype=np.float64).ravel()
        z = np.array(self.z, dtype=np.float64).ravel()
        if y.shape != z.shape:
            raise ProfileError(f"profile {self.name!r}: y and z have different lengths "
                               f"({y.size} and {z.size}); they must match", value=(y.size, z.size))
        if y.size < 4:
            raise ProfileError(f"profile {self.name!r} has {y.size} points; at least 4 are needed",
                               value=y.size)
        bad = ~(np.isfinite(y) & np.isfinite(z))
        if bad.any():
            i = int(np.argmax(bad))
            raise ProfileError(f"profile {self.name!r}: point {i} ({y[i]!r}, {z[i]!r}) is not finite; "
                               "all coordinates must be finite numbers", value=(y[i], z[i]))
        dy = np.diff(y)
        if np.any(dy <= 0.0):
            i = int(np.argmax(dy <= 0.0)) + 1
            raise ProfileError(f"profile {self.name!r}: y is not strictly increasing at point {i} "
                               f"(y={y[i]!r} after {y[i - 1]!r})", value=y[i])
        y.setflags(write=False)
        z.setflags(write=False)
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)
        if self.shape is None:
            object.__setattr__(self, "shape", _CubicShape(y, z))

    # ------------------------------------------------------------------ evaluation
    @property
    def y_min(self) -> float:
        return float(self.y[0])

    @property
    def y_max(self) -> float:
        return float(self.y[-1])

    def eval(self, y, nu: int = 0):
        """z (nu=0), dz/dy (nu=1) or d2z/dy2 (nu=2) at ``y`` (m) from the C2 shape.

        Raises ValueError for y outside [y_min, y_max] (no extrapolation)."""
        ya = np.asarray(y, dtype=np.float64)
        tol = 1e-12 + 1e-9 * (self.y_max - self.y_min)
        if np.any(ya < self.y_min - tol) or np.any(ya > self.y_max + tol):
            lo, hi = float(np.min(ya)), float(np.max(ya))
            raise ValueError(f"y range {lo:.6g}..{hi:.6g} m is outside profile {self.name!r}, "
                             f"which covers {self.y_min:.6g}..{self.y_max:.6g} m")
        return self.shape(np.clip(ya, self.y_min, self.y_max), nu)

    def curvature(self, y):
        """Signed curvature z''/(1+z'^2)^1.5 (1/m) at ``y``; sign convention in the package docstring."""
        d1 = self.eval(y, 1)
        return self.eval(y, 2) / scalarmath.power(1.0 + d1 * d1, 1.5)

    def table(self, dy: float = DEFAULT_DY) -> "ProfileTable":
        """Uniform resampling for the hot loop (see :class:`ProfileTable`)."""
        return ProfileTable.from_profile(self, dy)

    # ------------------------------------------------------------------ wheel dimensions
    def _need(self, kind: str, what: str) -> None:
        if self.kind != kind:
            raise ValueError(f"{what} is defined for a {kind} profile; {self.name!r} is a {self.kind}")

    def _z0(self) -> float:
        if not (self.y_min <= 0.0 <= self.y_max):
            raise ValueError(f"profile {self.name!r} does not cover y = 0 (the nominal rolling circle)")
        return float(self.eval(0.0))

    def _argmax_z(self, lo: float, hi: float) -> float:
        ys = np.linspace(lo, hi, max(200, int((hi - lo) / 2e-5)))
        i = int(np.argmax(self.eval(ys)))
        a, b = ys[max(i - 1, 0)], ys[min(i + 1, len(ys) - 1)]
        if b <= a:
            return float(ys[i])
        res = minimize_scalar(lambda t: -float(self.eval(t)), bounds=(a, b), method="bounded",
                              options={"xatol": 1e-10})
        return float(res.x)

    def flange_tip_y(self) -> float:
        """Wheel: y (m) of the flange tip (the highest point, searched at y < 0)."""
        self._need("wheel", "flange_tip_y")
        return self._argmax_z(self.y_min, min(0.0, self.y_max))

    def flange_height(self) -> float:
        """Wheel: flange height (m) = max z minus z at y = 0 (the nominal rolling circle)."""
        self._need("wheel", "flange_height")
        return float(self.eval(self.flange_tip_y())) - self._z0()

    def flange_face_y(self, height_above_rolling_line: float) -> float:
        """Wheel: y (m) of the active flange face (tread side of the tip) at the given height above
        z(0)."""
        self._need("wheel", "flange_face_y")
        h = float(height_above_rolling_line)
        tip = self.flange_tip_y()
        z0 = self._z0()
        ztip = float(self.eval(tip))
        if not (0.0 < h < ztip - z0):
            raise ValueError(f"height_above_rolling_line={h:.6g} m is outside the flange; use a value "
                             f"between 0 and the flange height {ztip - z0:.6g} m")
        ys = np.linspace(tip, 0.0, 4000)
        zs = self.eval(ys) - z0 - h
        j = int(np.argmax(zs < 0.0))
        return float(brentq(lambda t: float(self.eval(t)) - z0 - h, ys[j - 1], ys[j], xtol=1e-12))

    def flange_thickness(self, height_above_rolling_line: float = 0.010,
                         back_face_y: float = BACK_FACE_Y) -> float:
        """Wheel: flange thickness (m): from the back (inner) face at ``back_face_y`` to the flange face
        at ``height_above_rolling_line`` above z(0). EN 15313 measures S1002's Sd at 10 mm."""
        return self.flange_face_y(height_above_rolling_line) - float(back_face_y)

    def max_flange_angle(self) -> float:
        """Wheel: maximum flange angle (rad) = max of atan(-dz/dy) between the flange tip and y = 0."""
        self._need("wheel", "max_flange_angle")
        tip = self.flange_tip_y()
        ys = np.linspace(tip, 0.0, max(2000, int(-tip / 1e-5)))
        s = -self.eval(ys, 1)
        i = int(np.argmax(s))
        a, b = ys[max(i - 1, 0)], ys[min(i + 1, len(ys) - 1)]
        res = minimize_scalar(lambda t: float(self.eval(t, 1)), bounds=(a, b), method="bounded",
                              options={"xatol": 1e-10})
        return math.atan(max(float(s[i]), -float(self.eval(res.x, 1))))

    def flange_length(self, within: float = math.radians(1.0)) -> float:
        """Wheel: length (m, along the profile) of the flange face whose angle is within `within` (rad) of
        the maximum flange angle: the flange length Len of TCRP Report 71's climb-distance criterion."""
        self._need("wheel", "flange_length")
        tip = self.flange_tip_y()
        ys = np.linspace(tip, 0.0, max(4000, int(-tip / 1e-6)))
        slope = -self.eval(ys, 1)
        face = scalarmath.arctan(slope) >= self.max_flange_angle() - within
        i = int(np.argmax(slope))
        lo, hi = i, i
        while lo > 0 and face[lo - 1]:
            lo -= 1
        while hi < len(ys) - 1 and face[hi + 1]:
            hi += 1
        return float(np.sum(np.hypot(np.diff(ys[lo:hi + 1]), np.diff(self.eval(ys[lo:hi + 1])))))

    # ------------------------------------------------------------------ rail dimensions
    def top_y(self) -> float:
        """Rail: y (m) of the highest point of the head (the crown top)."""
        self._need("rail", "top_y")
        return self._argmax_z(self.y_min, self.y_max)

    def head_sides_y(self, depth_below_top: float) -> tuple[float, float]:
        """Rail: (gauge-side y, field-side y) where the head is ``depth_below_top`` below the top."""
        self._need("rail", "head_sides_y")
        d = float(depth_below_top)
        yt = self.top_y()
        zt = float(self.eval(yt))
        target = zt - d
        if d <= 0.0 or self.z[0] > target or self.z[-1] > target:
            reach = zt - max(self.z[0], self.z[-1])
            raise ValueError(f"depth_below_top={d:.6g} m is outside the head of {self.name!r}; "
                             f"use a value between 0 and {reach:.6g} m")
        f = lambda t: float(self.eval(t)) - target  # noqa: E731
        left = np.linspace(self.y_min, yt, 4000)
        jl = int(np.nonzero(self.eval(left) - target < 0.0)[0][-1])
        right = np.linspace(yt, self.y_max, 4000)
        jr = int(np.argmax(self.eval(right) - target < 0.0))
        return (float(brentq(f, left[jl], left[jl + 1], xtol=1e-13)),
                float(brentq(f, right[jr - 1], right[jr], xtol=1e-13)))

    def head_width(self, depth_below_top: float = 0.014) -> float:
        """Rail: head width (m) at ``depth_below_top`` below the crown top (14 mm: gauge point)."""
        a, b = self.head_sides_y(depth_below_top)
        return b - a


@dataclass(frozen=True, eq=False)
class ProfileTable:
    """Uniform resampling of a profile for the numba hot loop.

    Sample ``i`` is at ``y = y0 + i * dy`` (i = 0..n-1); ``z``, ``slope`` (dz/dy) and ``curvature``
    (z''/(1+z'^2)^1.5, sign convention in the package docstring) are float64 arrays of length ``n``,
    evaluated from the profile's C2 shape (exact arcs for the arc-built profiles, the smoothing spline
    for point data). At an arc joint the curvature jumps; the sample takes the value of the piece to
    its right. The arrays are fresh, C-contiguous and writable (plain numba ``float64[::1]``).
    """

    y0: float
    dy: float
    n: int
    z: np.ndarray
    slope: np.ndarray
    curvature: np.ndarray
    kind: str = "wheel"
    name: str = ""

    @classmethod
    def from_profile(cls, profile: Profile, dy: float = DEFAULT_DY) -> "ProfileTable":
        dy = float(dy)
        span = profile.y_max - profile.y_min
        if not (0.0 < dy <= span / 10.0):
            raise ValueError(f"table spacing dy={dy!r} m is not accepted; use 0 < dy <= {span / 10:.4g} m "
                             f"(a tenth of the profile width)")
        n = int(np.floor(span / dy + 1e-9)) + 1
        y = profile.y_min + dy * np.arange(n, dtype=np.float64)
        y[-1] = min(y[-1], profile.y_max)
        z = np.ascontiguousarray(profile.eval(y, 0), dtype=np.float64)
        s = np.ascontiguousarray(profile.eval(y, 1), dtype=np.float64)
        k = np.ascontiguousarray(profile.eval(y, 2) / scalarmath.power(1.0 + s * s, 1.5), dtype=np.float64)
        return cls(y0=float(profile.y_min), dy=dy, n=n, z=z, slope=s, curvature=k,
                   kind=profile.kind, name=profile.name)

    @property
    def y(self) -> np.ndarray:
        """The sample abscissae y0 + i*dy (m)."""
        return self.y0 + self.dy * np.arange(self.n, dtype=np.float64)
