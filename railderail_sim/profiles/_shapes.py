"""C2 (or piecewise-exact) representations z(y) behind a :class:`~railderail_sim.profiles.Profile`.

Two kinds of shape are used:

* :class:`ArcChain` -- an exact chain of circular arcs and straight lines, joined tangentially
  (C1 everywhere, exact z, z' and z'' on each piece; the curvature jumps at the joints as it does on
  the drawing). Used by the arc-built profiles (UIC60 / 60E1 and the LM reconstruction).
* :class:`SplineShape` -- a cubic spline z(y) (C2) through or near point data. Used for profiles read
  from files (S1002, the MBench UIC60, user files).

Both are called as ``shape(y, nu)`` with ``nu`` = 0, 1, 2 for z, dz/dy, d2z/dy2 (SI units).
Plain numpy/scipy: profile building is not in the simulation hot loop.
"""
from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np
from scipy.interpolate import UnivariateSpline

from .. import scalarmath

__all__ = ["Arc", "Line", "ArcChain", "SplineShape"]


@dataclass(frozen=True)
class Arc:
    """Circular arc z = zc + branch * sqrt(R^2 - (y - yc)^2) on ya <= y <= yb.

    ``branch = +1``: upper half (z'' < 0, bulging toward +z); ``branch = -1``: lower half (z'' > 0).
    """

    yc: float
    zc: float
    r: float
    branch: int
    ya: float
    yb: float

    def eval(self, y: np.ndarray, nu: int) -> np.ndarray:
        u = y - self.yc
        w = np.sqrt(np.maximum(self.r * self.r - u * u, 0.0))
        if nu == 0:
            return self.zc + self.branch * w
        with np.errstate(divide="ignore", invalid="ignore"):
            if nu == 1:
                return -self.branch * u / w
            if nu == 2:
                return -self.branch * self.r * self.r / scalarmath.power(w, 3.0)   # libm's, as on any CPU
        raise ValueError(f"derivative order nu={nu} is not supported; use 0, 1 or 2")

    def describe(self, scale: float = 1e3) -> str:
        kind = "convex (bulges toward +z)" if self.branch > 0 else "concave (hollow toward +z)"
        return (f"arc R{self.r * scale:.3f} {kind}, centre ({self.yc * scale:.4f}, {self.zc * scale:.4f}), "
                f"y {self.ya * scale:.4f} .. {self.yb * scale:.4f}")


@dataclass(frozen=True)
class Line:
    """Straight line z = z0 + m (y - y0) on ya <= y <= yb."""

    y0: float
    z0: float
    m: float
    ya: float
    yb: float

    def eval(self, y: np.ndarray, nu: int) -> np.ndarray:
        if nu == 0:
            return self.z0 + self.m * (y - self.y0)
        if nu == 1:
            return np.full_like(y, self.m)
        if nu == 2:
            return np.zeros_like(y)
        raise ValueError(f"derivative order nu={nu} is not supported; use 0, 1 or 2")

    def describe(self, scale: float = 1e3) -> str:
        ang = np.degrees(np.arctan(abs(self.m)))
        return (f"line slope {self.m:+.5f} ({ang:.3f} deg), through ({self.y0 * scale:.4f}, "
                f"{self.z0 * scale:.4f}), y {self.ya * scale:.4f} .. {self.yb * scale:.4f}")


class ArcChain:
    """Tangent-continuous chain of :class:`Arc` / :class:`Line` pieces covering [y_min, y_max].

    The constructor checks that the pieces are contiguous in y and that z and dz/dy agree at every
    joint (to 1e-9 m and 1e-7), so a chain is C1 by construction.
    """

    def __init__(self, pieces: list, *, slope_tol: float = 1e-7, z_tol: float = 1e-9) -> None:
        if not pieces:
            raise ValueError("an arc chain needs at least one piece")
        self.pieces = tuple(pieces)
        for a, b in zip(self.pieces[:-1], self.pieces[1:]):
            if abs(a.yb - b.ya) > 1e-12:
                raise ValueError(f"pieces are not contiguous: {a.yb} != {b.ya}")
            yj = np.array([a.yb])
            dz = abs(a.eval(yj, 0)[0] - b.eval(yj, 0)[0])
            ds = abs(a.eval(yj, 1)[0] - b.eval(yj, 1)[0]) / (1.0 + abs(a.eval(yj, 1)[0]))
            if dz > z_tol or ds > slope_tol:
                raise ValueError(f"pieces are not tangent-continuous at y={a.yb:.6g} m "
                                 f"(z jump {dz:.3g} m, relative slope jump {ds:.3g})")
        self.breaks = np.array([p.ya for p in self.pieces] + [self.pieces[-1].yb])
        self.y_min = float(self.breaks[0])
        self.y_max = float(self.breaks[-1])

    def __call__(self, y, nu: int = 0) -> np.ndarray:
        y = np.asarray(y, dtype=np.float64)
        flat = np.atleast_1d(y).ravel()
        idx = np.clip(np.searchsorted(self.breaks, flat, side="right") - 1, 0, len(self.pieces) - 1)
        out = np.empty_like(flat)
        for i, p in enumerate(self.pieces):
            m = idx == i
            if np.any(m):
                out[m] = p.eval(flat[m], nu)
        return out.reshape(y.shape) if y.ndim else out[0]

    def describe(self, scale: float = 1e3) -> str:
        """One line per piece; lengths multiplied by ``scale`` (1e3: a chain in metres shown in mm;
        use 1.0 for a chain built in mm)."""
        return "\n".join(p.describe(scale) for p in self.pieces)

    def sample_points(self, step: float) -> np.ndarray:
        """y values that include every joint and split each piece into equal steps of at most ``step``
        in arc length (so steep faces are sampled as densely as flat ones); for the Profile points."""
        ys = [self.breaks[:1]]
        for p in self.pieces:
            if isinstance(p, Arc):
                ta = math.asin(min(max((p.ya - p.yc) / p.r, -1.0), 1.0))
                tb = math.asin(min(max((p.yb - p.yc) / p.r, -1.0), 1.0))
                length = p.r * abs(tb - ta)
                n = max(1, int(np.ceil(length / step)))
                ys.append(p.yc + p.r * np.sin(np.linspace(ta, tb, n + 1)[1:]))  # equal angles
            else:
                length = (p.yb - p.ya) * np.hypot(1.0, p.m)
                n = max(1, int(np.ceil(length / step)))
                ys.append(np.linspace(p.ya, p.yb, n + 1)[1:])
        y = np.concatenate(ys)
        y[-1] = self.breaks[-1]
        return y


class SplineShape:
    """Cubic spline z(y) (C2) through or near point data.

    ``sigma`` (m) is the allowed RMS deviation of the points measured *normal to the profile*:
    the spline is scipy's FITPACK smoothing spline (Dierckx) with weights
    ``w_i = 1 / (sigma * sqrt(1 + z'_i^2))`` and smoothing factor ``s = n``, i.e. the weighted sum of
    squared normal residuals may reach ``n * sigma^2``; FITPACK then uses as few knots as that allows,
    which removes rounding and measurement noise from slope and curvature. ``sigma = 0`` gives the
    interpolating cubic spline (knots at all points).
    """

    def __init__(self, y: np.ndarray, z: np.ndarray, sigma: float) -> None:
        y = np.asarray(y, dtype=np.float64)
        z = np.asarray(z, dtype=np.float64)
        self.sigma = float(sigma)
        if self.sigma > 0.0:
            s_fd = np.gradient(z, y)
            w = 1.0 / (self.sigma * np.sqrt(1.0 + s_fd * s_fd))
            self._spl = UnivariateSpline(y, z, w=w, k=3, s=float(len(y)))
        else:
            self._spl = UnivariateSpline(y, z, k=3, s=0.0)
        self.y_min = float(y[0])
        self.y_max = float(y[-1])

    @property
    def n_knots(self) -> int:
        return len(self._spl.get_knots())

    def __call__(self, y, nu: int = 0) -> np.ndarray:
        if nu not in (0, 1, 2):
            raise ValueError(f"derivative order nu={nu} is not supported; use 0, 1 or 2")
        y = np.asarray(y, dtype=np.float64)
        out = self._spl(np.atleast_1d(y).ravel(), nu=nu)
        return out.reshape(y.shape) if y.ndim else float(out[0])
