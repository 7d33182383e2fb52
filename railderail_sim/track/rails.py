"""Where each rail actually is: its lateral and vertical offset from the ideal alignment (`alignment`).

A track irregularity (a measured or generated geometry record, a single defect such as the limit cycle's
lateral kink) is carried to the core as one float64 array `rails` (`pack_rails`): a header and one node
per station s with, for each rail, the lateral offset (+ to the left, track axes) and the vertical offset
(+ up) and their slopes d/ds. Between nodes the offsets are linear in s (`LINEAR`, a recorded file whose
slopes are those of the straight pieces) or cubic Hermite (`HERMITE`, a generated or analytic shape whose
exact slopes are known at the nodes). Before the first and after the last node the rails are ideal.

What the wheels see (Iwnicki (ed.), Handbook of Railway Vehicle Dynamics, ch. on track irregularities:
the rails are moved rigidly, their profiles, inclination and stiffness unchanged): each wheel meets its own
rail, so the wheelset's pose is taken relative to that rail, the lateral and vertical positions minus the
offsets, the yaw minus the lateral slope (the rail's own direction); the wheelset's velocity is resolved
along that direction (the rail does not move, so nothing is subtracted from the angular velocity) and the
forces are turned back into track axes (`vehicle.dynamics.rhs`). Rail bending under load is not here.
"""
import numpy as np

from ..jit import core
from ..record import Record

LINEAR, HERMITE = 0, 1
N_RAIL_VALUES = 4               # left lateral, left vertical, right lateral, right vertical


class RailValues(Record):
    """The offsets of both rails at one station (the order of the irregularity files' columns)."""
    left_lateral = "m", "lateral offset of the left rail, + to the left"
    left_vertical = "m", "vertical offset of the left rail, + up"
    right_lateral = "m", "lateral offset of the right rail, + to the left"
    right_vertical = "m", "vertical offset of the right rail, + up"


class RailsHeader(Record):
    """Header of the packed `rails` array; `nodes` RailNode rows follow it."""
    nodes = "-", "number of stations (0: ideal rails everywhere)"
    interpolation = "-", "between the stations: 0 linear, 1 cubic Hermite"


class RailNode(Record):
    """One station of the rails array."""
    s = "m", "distance along the line (strictly increasing)"
    offset = "m", "the rails' offsets", (1,), RailValues
    slope = "-", "d(offset)/ds", (1,), RailValues


R_HEAD = RailsHeader.size()
R_NODE = RailNode.size()


def pack_rails(s=(), offsets=np.zeros((0, N_RAIL_VALUES)), slopes=None, interpolation=LINEAR):
    """The `rails` array of the stations s (m, strictly increasing) with the offsets (n x 4, m, the order
    of RailValues) and their slopes (n x 4; with `LINEAR` left None: those of the straight pieces).
    With no stations: ideal rails."""
    s = np.asarray(s, dtype=float)
    offsets = np.asarray(offsets, dtype=float).reshape(len(s), N_RAIL_VALUES)
    if len(s) and not (np.all(np.isfinite(s)) and np.all(np.isfinite(offsets))):
        raise ValueError("rail offsets: the stations and offsets must be finite numbers")
    if len(s) == 1:
        raise ValueError("rail offsets: one station is not a shape (give none, or two or more)")
    if np.any(np.diff(s) <= 0.0):
        k = int(np.argmax(np.diff(s) <= 0.0))
        raise ValueError(f"rail offsets: the stations must increase strictly (s = {s[k]:g} m is followed by "
                         f"{s[k + 1]:g} m)")
    if interpolation == LINEAR:
        if slopes is not None:
            raise ValueError("rail offsets: linear interpolation takes its slopes from the offsets")
        slopes = np.zeros_like(offsets)
        if len(s) > 1:   # each node carries the slope of the piece that starts at it
            slopes[:-1] = np.diff(offsets, axis=0) / np.diff(s)[:, None]
    elif interpolation == HERMITE:
        slopes = np.asarray(slopes, dtype=float).reshape(offsets.shape)
        if not np.all(np.isfinite(slopes)):
            raise ValueError("rail offsets: the slopes must be finite numbers")
    else:
        raise ValueError(f"rail offsets: interpolation {interpolation} is not {LINEAR} (linear) or "
                         f"{HERMITE} (cubic Hermite)")
    nodes = np.zeros((len(s), R_NODE))
    nodes[:, RailNode.s] = s
    nodes[:, RailNode.offset.columns] = offsets
    nodes[:, RailNode.slope.columns] = slopes
    return np.concatenate((RailsHeader.pack(nodes=len(s), interpolation=interpolation), nodes.ravel()))


def lateral_kink(start, length, amplitude, step=0.25):
    """Both rails moved sideways by one period of a cosine, A/2 (1 - cos(2 pi (s - start) / L)) over
    start <= s <= start + L (m): a smooth (C1) alignment defect of peak A to the left in the middle, the
    limit-cycle method's excitation. Cubic Hermite on a `step` grid with the exact slopes (the largest
    error of the shape, A (2 pi step / L)^4 / 384, is 2e-9 m for 10 mm over 20 m)."""
    if not (length > 0.0 and step > 0.0):
        raise ValueError(f"lateral kink: length {length:g} m and step {step:g} m must be positive")
    n = max(int(round(length / step)), 2) + 1
    s = np.linspace(start, start + length, n)
    w = 2.0 * np.pi / length
    lateral = 0.5 * amplitude * (1.0 - np.cos(w * (s - start)))
    slope = 0.5 * amplitude * w * np.sin(w * (s - start))
    zero = np.zeros(n)
    return pack_rails(s, np.column_stack((lateral, zero, lateral, zero)),
                      np.column_stack((slope, zero, slope, zero)), HERMITE)


def split_rails(rails):
    """(s, offsets, slopes, interpolation) of a packed rails array: the inverse of `pack_rails`."""
    n = int(rails[RailsHeader.nodes])
    nodes = rails[R_HEAD:R_HEAD + n * R_NODE].reshape(n, R_NODE)
    return (nodes[:, RailNode.s], nodes[:, RailNode.offset.columns], nodes[:, RailNode.slope.columns],
            int(rails[RailsHeader.interpolation]))


@core
def rail_offset(rails, side, s):
    """(lateral offset, vertical offset, lateral slope, vertical slope) of rail `side` (0 left, 1 right) at s.

    By hand in the core (a bisection and one cubic): this runs for every wheelset at every evaluation of
    the equations of motion, where numpy.interp and scipy's splines cannot be called.
    """
    n = int(rails[RailsHeader.nodes])
    if n == 0:
        return 0.0, 0.0, 0.0, 0.0
    first = rails[R_HEAD + RailNode.s]
    last = rails[R_HEAD + (n - 1) * R_NODE + RailNode.s]
    if s < first or s > last:
        return 0.0, 0.0, 0.0, 0.0
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if rails[R_HEAD + mid * R_NODE + RailNode.s] <= s:
            lo = mid
        else:
            hi = mid
    a = R_HEAD + lo * R_NODE
    b = R_HEAD + hi * R_NODE
    lat = RailValues.left_lateral if side == 0 else RailValues.right_lateral
    ver = RailValues.left_vertical if side == 0 else RailValues.right_vertical
    h = rails[b + RailNode.s] - rails[a + RailNode.s]
    if int(rails[RailsHeader.interpolation]) == LINEAR:
        la = rails[a + RailNode.offset + lat]
        va = rails[a + RailNode.offset + ver]
        dla = rails[a + RailNode.slope + lat]
        dva = rails[a + RailNode.slope + ver]
        return la + dla * (s - rails[a + RailNode.s]), va + dva * (s - rails[a + RailNode.s]), dla, dva
    u = (s - rails[a + RailNode.s]) / h
    lv, ls = _hermite(rails[a + RailNode.offset + lat], rails[b + RailNode.offset + lat],
                      rails[a + RailNode.slope + lat], rails[b + RailNode.slope + lat], h, u)
    vv, vs = _hermite(rails[a + RailNode.offset + ver], rails[b + RailNode.offset + ver],
                      rails[a + RailNode.slope + ver], rails[b + RailNode.slope + ver], h, u)
    return lv, vv, ls, vs


@core
def _hermite(ya, yb, ma, mb, h, u):
    """Value and slope at u = (s - s_a) / h of the cubic with values ya, yb and slopes ma, mb at the ends."""
    u2 = u * u
    u3 = u2 * u
    value = (2.0 * u3 - 3.0 * u2 + 1.0) * ya + (u3 - 2.0 * u2 + u) * h * ma + (3.0 * u2 - 2.0 * u3) * yb \
        + (u3 - u2) * h * mb
    slope = (6.0 * u2 - 6.0 * u) * (ya - yb) / h + (3.0 * u2 - 4.0 * u + 1.0) * ma + (3.0 * u2 - 2.0 * u) * mb
    return value, slope
