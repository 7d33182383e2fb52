"""Ideal track alignment as a function of the distance s along the line.

The line is straight -> clothoid transition with a linear cant ramp -> circular curve -> transition ->
straight (Yu et al. 2022, Table 2). Before s = 0 and after the end the line continues straight. Where
the rails actually lie about this alignment (irregularities, defects) is `rails`.

Frames: the track frame at s has its origin on the track centre line at top-of-rail level, x along the
tangent, y to the left, z normal to the (canted) track plane. Cant rolls the frame about x about the
centre line; a curve to the left (positive curvature) raises the right (outer) rail, i.e. rolls the frame
by a negative angle. The cant angle of a cant height h is asin(h / e) with e the distance between the rail
centres (1.500 m for standard gauge, EN 13803).

Everything here is plain numba over one float64 array `track` packed by `pack_track` so that the vehicle
core can evaluate the alignment millions of times without Python objects.
"""
import math

import numpy as np

from .. import scalarmath
from ..jit import core
from ..record import Record

N_SEG = 5                      # straight, transition, curve, transition, straight
N_BREAKS = N_SEG + 1


class TrackHeader(Record):
    """Header of the packed track array (`pack_track`); the heading/position grid's nodes follow it."""
    breaks = "m", "the breakpoints s_0 .. s_5 of the five sections", (N_BREAKS,)
    curvature = "1/m", "curvature magnitude at the breakpoints, linear in between", (N_BREAKS,)
    cant = "rad", "cant angle magnitude at the breakpoints (linear in cant height in between)", (N_BREAKS,)
    cant_height = "m", "cant height at the breakpoints", (N_BREAKS,)
    rail_spacing = "m", "distance e between the rail centres"
    direction = "-", "+1 curve to the left, -1 to the right"
    grid_step = "m", "step of the heading/position grid"
    grid_nodes = "-", "nodes of the grid"
    grid_first = "m", "s of the first node"


class TrackNode(Record):
    """One node of the heading/position grid."""
    heading = "rad", "heading of the track tangent"
    x = "m", "ground X of the centre line"
    y = "m", "ground Y of the centre line"


T_HEAD = TrackHeader.size()
T_NODE = TrackNode.size()
GRID_STEP = 0.5                # m; Taylor expansion from the nearest node is exact to ~1e-9 m
# 4-point Gauss-Legendre abscissae and weights on [-1, 1] (the node integration's quadrature)
GAUSS_X = np.array([-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526])
GAUSS_W = np.array([0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538])


def pack_track(straight_in, transition_in, curve, transition_out, straight_out, radius, cant_height,
               direction=1, rail_spacing=1.5, margin=100.0):
    """Pack the alignment into a float64 array for the numba core (lengths in m, cant height in m);
    `margin` extends the grid beyond both ends."""
    lengths = (straight_in, transition_in, curve, transition_out, straight_out)
    breaks = np.concatenate(([0.0], np.cumsum(lengths)))
    kappa = 0.0 if math.isinf(radius) else 1.0 / radius
    curv = np.array([0.0, 0.0, kappa, kappa, 0.0, 0.0])
    cant_h = np.array([0.0, 0.0, cant_height, cant_height, 0.0, 0.0])
    cant = scalarmath.arcsin(cant_h / rail_spacing)
    head = np.zeros(T_HEAD)
    head[TrackHeader.breaks.columns] = breaks
    head[TrackHeader.curvature.columns] = curv
    head[TrackHeader.cant.columns] = cant
    head[TrackHeader.cant_height.columns] = cant_h
    head[TrackHeader.rail_spacing] = rail_spacing
    head[TrackHeader.direction] = 1.0 if direction >= 0 else -1.0
    s_first = -margin
    n = int(math.ceil((breaks[-1] + 2 * margin) / GRID_STEP)) + 1
    head[TrackHeader.grid_step], head[TrackHeader.grid_nodes], head[TrackHeader.grid_first] = GRID_STEP, n, s_first
    track = np.concatenate((head, np.zeros(T_NODE * n)))
    _integrate_nodes(track)
    return track


@core
def _piece(track, s):
    """Segment index k with breaks[k] <= s < breaks[k+1], clamped to the straight ends (-1 or 5)."""
    if s < track[TrackHeader.breaks]:
        return -1
    for k in range(N_SEG):
        if s < track[TrackHeader.breaks + k + 1]:
            return k
    return N_SEG


@core
def curvature(track, s):
    """Signed curvature (1/m, + left) and its derivative d(curvature)/ds (1/m^2)."""
    return _curvature_in(track, _piece(track, s), s)


@core
def _curvature_in(track, k, s):
    """curvature(track, s) in the section k = _piece(track, s)."""
    if k < 0 or k >= N_SEG:
        return 0.0, 0.0
    s0 = track[TrackHeader.breaks + k]
    s1 = track[TrackHeader.breaks + k + 1]
    c0 = track[TrackHeader.curvature + k]
    c1 = track[TrackHeader.curvature + k + 1]
    slope = (c1 - c0) / (s1 - s0)
    d = track[TrackHeader.direction]
    return d * (c0 + slope * (s - s0)), d * slope


@core
def cant(track, s):
    """Track-plane roll angle (rad, signed: negative raises the right rail) and its derivative d/ds."""
    return _cant_in(track, _piece(track, s), s)


@core
def _cant_in(track, k, s):
    """cant(track, s) in the section k = _piece(track, s)."""
    if k < 0 or k >= N_SEG:
        return 0.0, 0.0
    s0 = track[TrackHeader.breaks + k]
    s1 = track[TrackHeader.breaks + k + 1]
    h0 = track[TrackHeader.cant_height + k]
    h1 = track[TrackHeader.cant_height + k + 1]
    e = track[TrackHeader.rail_spacing]
    dh = (h1 - h0) / (s1 - s0)
    h = h0 + dh * (s - s0)
    ang = math.asin(h / e)
    dang = dh / (e * math.cos(ang))
    d = -track[TrackHeader.direction]
    return d * ang, d * dang


@core
def section(track, s):
    """0 straight, 1 transition, 2 circular curve (the VehicleStatus message constants)."""
    k = _piece(track, s)
    if k == 1 or k == 3:
        return 1
    if k == 2:
        return 2
    return 0


@core
def _heading_exact(track, s):
    """Heading (rad) by exact integration of the piecewise-linear curvature from s = 0."""
    h = 0.0
    d = track[TrackHeader.direction]
    for k in range(N_SEG):
        s0 = track[TrackHeader.breaks + k]
        s1 = track[TrackHeader.breaks + k + 1]
        if s <= s0:
            break
        e = min(s, s1)
        c0 = track[TrackHeader.curvature + k]
        slope = (track[TrackHeader.curvature + k + 1] - c0) / (s1 - s0)
        u = e - s0
        h += d * (c0 * u + 0.5 * slope * u * u)
    return h


@core
def _integrate_nodes(track):
    """Fill the heading/position grid by 4-point Gauss-Legendre quadrature of (cos h, sin h) per step."""
    step = track[TrackHeader.grid_step]
    n = int(track[TrackHeader.grid_nodes])
    s_first = track[TrackHeader.grid_first]
    x = s_first  # straight before s = 0 along the x axis
    y = 0.0
    for i in range(n):
        s = s_first + i * step
        if i > 0:
            sa = s - step
            for q in range(4):
                sq = sa + 0.5 * step * (GAUSS_X[q] + 1.0)
                hq = _heading_exact(track, sq)
                x += 0.5 * step * GAUSS_W[q] * math.cos(hq)
                y += 0.5 * step * GAUSS_W[q] * math.sin(hq)
        j = T_HEAD + T_NODE * i
        track[j + TrackNode.heading] = _heading_exact(track, s)
        track[j + TrackNode.x] = x
        track[j + TrackNode.y] = y


@core
def _origin(track, s):
    """Ground X, Y of the track frame's origin at s: a third-order expansion about the nearest grid node
    (error below 1e-7 m on the 0.5 m grid, largest next to a curvature break)."""
    step = track[TrackHeader.grid_step]
    n = int(track[TrackHeader.grid_nodes])
    s_first = track[TrackHeader.grid_first]
    i = int(math.floor((s - s_first) / step + 0.5))
    if i < 0:
        i = 0
    elif i > n - 1:
        i = n - 1
    j = T_HEAD + T_NODE * i
    h0 = track[j + TrackNode.heading]
    d = s - (s_first + i * step)
    kap, dkap = curvature(track, s_first + i * step)
    # heading along the step: h0 + kap d + dkap d^2/2 ; integrate cos/sin to third order in d
    c = math.cos(h0)
    sn = math.sin(h0)
    d2 = d * d
    d3 = d2 * d
    x = track[j + TrackNode.x] + c * d - sn * (0.5 * kap * d2 + dkap * d3 / 6.0) - c * kap * kap * d3 / 6.0
    y = track[j + TrackNode.y] + sn * d + c * (0.5 * kap * d2 + dkap * d3 / 6.0) - sn * kap * kap * d3 / 6.0
    return x, y


@core
def frame(track, s):
    """Track frame at s: (X, Y, heading, roll) of the origin in the ground frame (the heading exact)."""
    x, y = _origin(track, s)
    roll, _ = cant(track, s)
    return x, y, _heading_exact(track, s), roll


@core
def body_frame(track, s):
    """What a body at station s needs of the track, with one section search and one cant evaluation:
    (X, Y, heading, roll, curvature, d(roll)/ds), as frame, curvature and cant give them."""
    k = _piece(track, s)
    x, y = _origin(track, s)
    kap, _ = _curvature_in(track, k, s)
    roll, droll = _cant_in(track, k, s)
    return x, y, _heading_exact(track, s), roll, kap, droll


def end_of_line(track):
    """Distance (m) of the end of the last straight."""
    return float(track[TrackHeader.breaks + N_SEG])
