"""Where each rail actually is: its lateral and vertical deviation from the ideal alignment (`alignment`).

A track irregularity (a measured record, a random sample of a spectrum, a single defect such as the limit
cycle's lateral kink; `irregularity`) reaches the core as one float64 array `rails` (`pack_rails`): an
IrregularityHeader and one IrregularityPoint per point s with the four rail channels (left and right rail,
lateral + to the left and vertical + up, track frame) and their slopes d/ds. Between points the
deviations are linear in s (`LINEAR`: a file) or cubic Hermite (`HERMITE`: a generated or analytic shape
whose exact slopes are known). Before the first and after the last point the rails are ideal.

What the wheels see (the rails are moved rigidly: their profiles, inclination and stiffness unchanged;
Iwnicki (ed.), Handbook of Railway Vehicle Dynamics, on track irregularities as a wheelset input): each
wheel meets its own rail, so the wheelset's pose is taken relative to that rail (the lateral and vertical
positions minus the rail's deviations, the yaw minus its lateral slope, i.e. the rail's own direction), its
velocities are resolved in the rail's axes (turned by the slopes; the rail does not move, so no rail
velocity is subtracted) and the wheel's force and moment are turned back into track axes
(`vehicle.dynamics.rhs`).
"""
import numpy as np

from ..jit import core
from ..lookup import interval
from ..record import Record

LINEAR, HERMITE = 0, 1
N_CHANNELS = 4                  # left lateral, left vertical, right lateral, right vertical


class IrregularityHeader(Record):
    """Header of the packed rails array (`pack_rails`); `points` IrregularityPoint rows follow."""
    points = "-", "number n of points (0: ideal rails everywhere)"
    interpolation = "-", "0 linear between the points (a file), 1 cubic Hermite with the points' slopes"


class RailDeviation(Record):
    """The four rail channels at a point, track frame (the order of the irregularity file's columns)."""
    left_lateral = "m", "left rail lateral deviation, + to the left"
    left_vertical = "m", "left rail vertical deviation, + up"
    right_lateral = "m", "right rail lateral deviation, + to the left"
    right_vertical = "m", "right rail vertical deviation, + up"


class IrregularityPoint(Record):
    """One point of the packed rails array."""
    s = "m", "distance along the line, strictly increasing from point to point"
    deviation = "m", "the rail channels at s", (), RailDeviation
    slope = "m/m", "their d/ds at s (linear: of the piece that starts at the point)", (), RailDeviation


R_HEAD = IrregularityHeader.size()
R_POINT = IrregularityPoint.size()


def pack_rails(s=(), deviations=np.zeros((0, N_CHANNELS)), slopes=None, interpolation=LINEAR):
    """The `rails` array of the points s (m, strictly increasing) with the deviations (n x 4, m, the order of
    RailDeviation) and, for `HERMITE`, their slopes (n x 4; `LINEAR` takes those of the straight pieces).
    No points: ideal rails."""
    s = np.asarray(s, dtype=float)
    deviations = np.asarray(deviations, dtype=float).reshape(len(s), N_CHANNELS)
    if not (np.all(np.isfinite(s)) and np.all(np.isfinite(deviations))):
        raise ValueError("rail deviations: the points and deviations must be finite numbers")
    if len(s) == 1:
        raise ValueError("rail deviations: one point is not a shape (give none, or two or more)")
    if np.any(np.diff(s) <= 0.0):
        k = int(np.argmax(np.diff(s) <= 0.0))
        raise ValueError(f"rail deviations: s must increase strictly (s = {s[k]:g} m is followed by {s[k + 1]:g} m)")
    if interpolation == LINEAR:
        if slopes is not None:
            raise ValueError("rail deviations: linear interpolation takes its slopes from the deviations")
        slopes = np.zeros_like(deviations)
        if len(s):
            slopes[:-1] = np.diff(deviations, axis=0) / np.diff(s)[:, None]
    elif interpolation == HERMITE:
        slopes = np.asarray(slopes, dtype=float).reshape(deviations.shape)
        if not np.all(np.isfinite(slopes)):
            raise ValueError("rail deviations: the slopes must be finite numbers")
    else:
        raise ValueError(f"rail deviations: interpolation {interpolation} is not {LINEAR} (linear) or "
                         f"{HERMITE} (cubic Hermite)")
    points = np.zeros((len(s), R_POINT))
    points[:, IrregularityPoint.s] = s
    points[:, IrregularityPoint.deviation.columns] = deviations
    points[:, IrregularityPoint.slope.columns] = slopes
    return np.concatenate((IrregularityHeader.pack(points=len(s), interpolation=interpolation), points.ravel()))


def split_rails(rails):
    """(s, deviations, slopes, interpolation) of a packed rails array: the inverse of `pack_rails`."""
    n = int(rails[IrregularityHeader.points])
    view = IrregularityPoint.split(rails[R_HEAD:R_HEAD + n * R_POINT].reshape(n, R_POINT))
    return view["s"], view["deviation"], view["slope"], int(rails[IrregularityHeader.interpolation])


@core
def rail_deviation(rails, side, s):
    """(lateral deviation, vertical deviation, lateral slope, vertical slope) of rail `side` (0 left, 1 right)
    at s; zero outside the points.

    By hand in the core (`lookup.interval` and one cubic): it runs for every wheel at every evaluation of
    the equations of motion, where numpy.interp and scipy's splines cannot be called.
    """
    n = int(rails[IrregularityHeader.points])
    if n == 0 or s < rails[R_HEAD + IrregularityPoint.s] or s > rails[R_HEAD + (n - 1) * R_POINT + IrregularityPoint.s]:
        return 0.0, 0.0, 0.0, 0.0
    lo = interval(rails, R_HEAD + IrregularityPoint.s, R_POINT, n, s)
    a = R_HEAD + lo * R_POINT
    b = a + R_POINT
    lat = RailDeviation.left_lateral if side == 0 else RailDeviation.right_lateral
    ver = RailDeviation.left_vertical if side == 0 else RailDeviation.right_vertical
    da = a + IrregularityPoint.deviation
    db = b + IrregularityPoint.deviation
    ma = a + IrregularityPoint.slope
    mb = b + IrregularityPoint.slope
    u = s - rails[a + IrregularityPoint.s]
    if int(rails[IrregularityHeader.interpolation]) == LINEAR:
        return rails[da + lat] + rails[ma + lat] * u, rails[da + ver] + rails[ma + ver] * u, rails[ma + lat], \
            rails[ma + ver]
    h = rails[b + IrregularityPoint.s] - rails[a + IrregularityPoint.s]
    y_lat, m_lat = _hermite(rails[da + lat], rails[db + lat], rails[ma + lat], rails[mb + lat], h, u / h)
    y_ver, m_ver = _hermite(rails[da + ver], rails[db + ver], rails[ma + ver], rails[mb + ver], h, u / h)
    return y_lat, y_ver, m_lat, m_ver


@core
def _hermite(ya, yb, ma, mb, h, u):
    """Value and slope at u = (s - s_a) / h of the cubic with values ya, yb and slopes ma, mb at the ends."""
    u2 = u * u
    u3 = u2 * u
    value = (2.0 * u3 - 3.0 * u2 + 1.0) * ya + (u3 - 2.0 * u2 + u) * h * ma + (3.0 * u2 - 2.0 * u3) * yb \
        + (u3 - u2) * h * mb
    slope = (6.0 * u2 - 6.0 * u) * (ya - yb) / h + (3.0 * u2 - 4.0 * u + 1.0) * ma + (3.0 * u2 - 2.0 * u) * mb
    return value, slope


@core
def rail_deviations(rails, s, out):
    """The four channels (RailDeviation order) at every s into out (len(s) x 4): the core's own
    interpolation, for plots and checks of what the wheels meet."""
    for i in range(s.shape[0]):
        for side in range(2):
            lateral, vertical, _, _ = rail_deviation(rails, side, s[i])
            out[i, 2 * side] = lateral
            out[i, 2 * side + 1] = vertical
