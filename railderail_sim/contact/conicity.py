"""Rigid contact-geometry tables over the wheelset's lateral displacement, and equivalent conicity.

Rigid contact: for a wheelset at lateral displacement y (no yaw), the vertical position and roll at which
both wheels touch their rails without interpenetration (`geometry.rigid_contact`); from it the rolling
radius difference Delta r(y) = r_left - r_right, contact angles, contact positions, the wheelset roll and
the wheel lift.

Equivalent conicity (EN 15302:2008+A1:2010, Annex B "integration of the non-linear differential
equation"): the free wheelset's kinematic (Klingel) motion

    d^2y/dx^2 = -Delta r(y) / (2 e r0)

is integrated over one period for the amplitude A (turning points -A ... +A' found from the first
integral); its wavelength lambda defines tan(gamma_e) = e r0 (2 pi / lambda)^2, which for a coned wheelset
returns the cone angle (Klingel: lambda = 2 pi sqrt(e r0 / gamma)). e is half the distance between the
contact points of the centred wheelset. The harmonic (describing-function) value
(1 / (pi A)) integral_0^2pi Delta r(A sin t)/2 sin t dt is given beside it.
"""
from dataclasses import dataclass
import math

import numpy as np
from scipy.optimize import brentq

from ..ranges import check_range
from . import geometry as geo
from .layout import CANDIDATES_SIZE, MAX_PATCHES, P_COLS, GeometryHeader, Patch

QUADRATURE_POINTS = 20001    # trapezoidal rule in the angle variable; converged to ~1e-6
TWO_POINT_GAP = 1.0e-5       # m: a second contact this close to touching counts as two-point contact
CONVERGED_GAP = 1.0e-6       # m: rigid contact counts as found when both wheels' gaps are below this


@dataclass
class RigidTable:
    """Rigid contact over lateral displacement y (m); arrays of the left (L) and right (R) wheel."""
    y: np.ndarray
    delta_r: np.ndarray          # r_left - r_right (m)
    roll: np.ndarray             # wheelset roll (rad)
    z: np.ndarray                # wheelset vertical displacement (m)
    radius_left: np.ndarray
    radius_right: np.ndarray
    contact_angle_left: np.ndarray    # rad, + toward the flange (for each wheel its own rail)
    contact_angle_right: np.ndarray
    contact_y_left: np.ndarray   # wheel profile coordinate of the contact (m)
    contact_y_right: np.ndarray
    rail_y_left: np.ndarray      # contact position on the rail from the head axis, + field side (m)
    rail_y_right: np.ndarray
    two_point_left: np.ndarray   # bool: a second contact within TWO_POINT_GAP of touching
    two_point_right: np.ndarray
    lift_left: np.ndarray        # the paper's wheel lift hp (m)
    lift_right: np.ndarray
    r0: float
    contact_half_distance: float


def _wheel_contact(cg, y, z, phi):
    """Deepest contact of the left wheel at a rigid pose: radius, contact angle, wheel y_p, rail y and
    whether a second contact lies within TWO_POINT_GAP of touching (two-point contact)."""
    nw = int(cg[GeometryHeader.wheel_points])
    gap = np.zeros(nw)
    ys = np.zeros(nw)
    patches = np.zeros((MAX_PATCHES, P_COLS))
    n, _ = geo.find_patches(cg, y, z - TWO_POINT_GAP, phi, 0.0, gap, ys, patches,
                            np.zeros(CANDIDATES_SIZE))
    k = int(np.argmin(patches[:n, Patch.gap]))
    return (patches[k, Patch.radius], math.atan(patches[k, Patch.slope]), patches[k, Patch.wheel_y],
            patches[k, Patch.y] - cg[GeometryHeader.rail_axis_y], n > 1)


def rigid_table(cg, y_max=0.012, step=1.0e-4):
    """Rigid contact of LM-type profiles over -y_max..y_max (m)."""
    ys_grid = np.round(np.arange(-y_max, y_max + 0.5 * step, step), 12)
    nw = int(cg[GeometryHeader.wheel_points])
    gap = np.zeros(nw)
    yb = np.zeros(nw)
    rows = []
    for y in ys_grid:
        z, phi, _, _ = geo.rigid_contact(cg, y, 0.0, gap, yb)
        rl, al, ypl, ryl, tpl = _wheel_contact(cg, y, z, phi)
        rr, ar, ypr, ryr, tpr = _wheel_contact(cg, -y, z, -phi)
        rows.append((rl - rr, phi, z, rl, rr, al, ar, ypl, ypr, ryl, ryr, tpl, tpr,
                     geo.wheel_lift(cg, z, phi), geo.wheel_lift(cg, z, -phi)))
    a = np.array(rows, dtype=float)
    r0 = cg[GeometryHeader.nominal_radius]
    i0 = len(ys_grid) // 2
    half = cg[GeometryHeader.rolling_circle_distance] + a[i0, 7]
    return RigidTable(y=ys_grid, delta_r=a[:, 0], roll=a[:, 1], z=a[:, 2], radius_left=a[:, 3],
                      radius_right=a[:, 4], contact_angle_left=a[:, 5], contact_angle_right=a[:, 6],
                      contact_y_left=a[:, 7], contact_y_right=a[:, 8], rail_y_left=a[:, 9],
                      rail_y_right=a[:, 10], two_point_left=a[:, 11] > 0.5, two_point_right=a[:, 12] > 0.5,
                      lift_left=a[:, 13], lift_right=a[:, 14], r0=r0, contact_half_distance=half)


def equivalent_conicity(table: RigidTable, amplitude):
    """EN 15302 Annex B equivalent conicity tan(gamma_e) for a lateral amplitude (m)."""
    check_range("amplitude", amplitude * 1e3, 0.0, table.y[-1] * 1e3, "mm", lo_open=True)
    y = table.y
    dr = table.delta_r - np.interp(0.0, y, table.delta_r)
    e = table.contact_half_distance
    r0 = table.r0
    # S(y) = integral_0^y Delta r dy (trapezoidal on the table), "potential" of the kinematic motion
    S = np.concatenate(([0.0], np.cumsum(0.5 * (dr[1:] + dr[:-1]) * np.diff(y))))
    S -= np.interp(0.0, y, S)
    def S_at(q):
        """Exact integral of the linearly interpolated Delta r (S is piecewise quadratic)."""
        i = np.clip(np.searchsorted(y, q) - 1, 0, len(y) - 2)
        u = q - y[i]
        return S[i] + dr[i] * u + 0.5 * (dr[i + 1] - dr[i]) / (y[i + 1] - y[i]) * u * u

    level = float(S_at(amplitude))
    # other turning point: where S equals the same level on the negative side
    y_neg = brentq(lambda q: float(S_at(q)) - level, y[0], 0.0) if S[0] > level else y[0]
    # dy/dx = psi, psi^2 = (level - S(y)) / (e r0); substitution y = c + h sin(t) removes the
    # square-root singularities at the turning points
    c = 0.5 * (amplitude + y_neg)
    h = 0.5 * (amplitude - y_neg)

    t = np.linspace(-0.5 * math.pi, 0.5 * math.pi, QUADRATURE_POINTS)[1:-1]
    q = c + h * np.sin(t)
    den2 = np.maximum((level - S_at(q)) / (e * r0), 1e-300)
    half_wave = np.trapezoid(h * np.cos(t) / np.sqrt(den2), t)
    # the two end intervals (turning points), where the integrand tends to sqrt(2 h e r0 / |Delta r|)
    for end in (y_neg, amplitude):
        d = abs(float(np.interp(end, y, dr)))
        half_wave += (t[0] + 0.5 * math.pi) * math.sqrt(2.0 * h * e * r0 / d) if d > 0 else 0.0
    wavelength = 2.0 * half_wave
    return e * r0 * (2.0 * math.pi / wavelength) ** 2, wavelength


def harmonic_conicity(table: RigidTable, amplitude):
    """First-harmonic (describing-function) conicity of Delta r(y) at amplitude (m)."""
    dr = table.delta_r - np.interp(0.0, table.y, table.delta_r)
    t = np.linspace(0.0, 2.0 * math.pi, QUADRATURE_POINTS)
    val = np.trapezoid(0.5 * np.interp(amplitude * np.sin(t), table.y, dr) * np.sin(t), t)
    return val / (math.pi * amplitude)


def _buffers(cg):
    nw = int(cg[GeometryHeader.wheel_points])
    return np.zeros(nw), np.zeros(nw)


def rigid_pose(cg, y, psi):
    """Rigid contact of the wheelset at lateral shift y and yaw psi: (z, phi, both wheels touch)."""
    gap, ys = _buffers(cg)
    z, phi, _, _ = geo.rigid_contact(cg, y, psi, gap, ys)
    gl, _ = geo.min_gap(cg, y, z, phi, psi, gap, ys)
    gr, _ = geo.min_gap(cg, -y, z, -phi, -psi, gap, ys)
    return z, phi, bool(math.isfinite(z) and abs(gl) < CONVERGED_GAP and abs(gr) < CONVERGED_GAP)


def deepest_patch(cg, y, z, phi, psi):
    """(patch row of the deepest contact, patch count) of the left wheel just below touching at this
    pose; (None, 0) if it finds no rail."""
    gap, ys = _buffers(cg)
    patches = np.zeros((MAX_PATCHES, P_COLS))
    g0, _ = geo.min_gap(cg, y, z, phi, psi, gap, ys)
    n, _ = geo.find_patches(cg, y, z - g0 - 1e-7, phi, psi, gap, ys, patches,
                            np.zeros(CANDIDATES_SIZE))
    if n == 0:
        return None, 0
    return patches[int(np.argmin(patches[:n, Patch.gap]))].copy(), n


def max_contact_angle(cg, table=None):
    """The largest contact angle of the profile pair in rigid contact without yaw, and the |y| where
    it occurs: (angle rad, y m). Found on the rigid table (`rigid_table(cg)` unless one is given) and
    refined between the rows around its peak, which is sharp at the flange face. Nadal's limit of the
    pair is `nadal.nadal_limit` at this angle."""
    from scipy.optimize import minimize_scalar

    table = rigid_table(cg) if table is None else table
    angles = np.maximum(table.contact_angle_left, table.contact_angle_right)
    i = int(np.argmax(angles))
    angle_i = float(angles[i])

    def angle(yy):
        z, phi, ok = rigid_pose(cg, yy, 0.0)
        row = deepest_patch(cg, yy, z, phi, 0.0)[0] if ok else None
        return math.atan(row[Patch.slope]) if row is not None else -math.inf

    y = table.y
    yi = abs(float(y[i]))
    step = float(y[1] - y[0])
    lo, hi = max(0.0, yi - step), min(float(y[-1]), yi + step)
    if hi <= lo:
        return angle_i, yi
    grid = np.linspace(lo, hi, 41)
    values = [angle(v) for v in grid]
    k = int(np.argmax(values))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    res = minimize_scalar(lambda yy: -angle(yy), bounds=(lo, hi), method="bounded", options={"xatol": 1e-9})
    if values[k] > max(-res.fun, angle_i):
        return float(values[k]), float(grid[k])
    if -res.fun > angle_i:
        return float(-res.fun), float(res.x)
    return angle_i, yi
