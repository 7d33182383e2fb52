"""Ideal track alignment as a function of the distance s along the line.

The line is straight -> clothoid transition with a linear cant ramp -> circular curve -> transition ->
straight (Yu et al. 2022, Table 2), with an optional short lateral alignment defect used to excite the
vehicle in the limit-cycle method. Before s = 0 and after the end the line continues straight.

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

from ..jit import core

# Layout of the packed track array.
N_SEG = 5                      # straight, transition, curve, transition, straight
I_BREAKS = 0                   # 6 breakpoints s_0 .. s_5 (m)
I_CURV = 6                     # curvature at the 6 breakpoints (1/m), linear in between
I_CANT = 12                    # cant angle magnitude at the 6 breakpoints (rad), linear in cant height
I_CANT_H = 18                  # cant height at the 6 breakpoints (m)
I_RAIL_SPACING = 24            # distance between rail centres e (m)
I_DIR = 25                     # +1 curve to the left, -1 to the right
I_EXC = 26                     # excitation: start s (m), length (m), amplitude (m)
I_GRID = 29                    # heading/position grid: step (m), number of nodes, first node s
I_NODES = 32                   # nodes: heading, X, Y at each grid node (3 * n)
GRID_STEP = 0.5                # m; Taylor expansion from the nearest node is exact to ~1e-9 m
# 4-point Gauss-Legendre abscissae and weights on [-1, 1] (the node integration's quadrature)
GAUSS_X = np.array([-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526])
GAUSS_W = np.array([0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538])


def pack_track(straight_in, transition_in, curve, transition_out, straight_out, radius, cant_height,
               direction=1, rail_spacing=1.5, excitation=(0.0, 0.0, 0.0), margin=100.0):
    """Pack the alignment into a float64 array for the numba core (lengths in m, cant height in m).

    `excitation` = (start s, length, amplitude) of a one-period lateral alignment defect (see
    `lateral_defect`); amplitude 0 disables it. `margin` extends the grid beyond both ends.
    """
    lengths = (straight_in, transition_in, curve, transition_out, straight_out)
    breaks = np.concatenate(([0.0], np.cumsum(lengths)))
    kappa = 0.0 if math.isinf(radius) else 1.0 / radius
    curv = np.array([0.0, 0.0, kappa, kappa, 0.0, 0.0])
    cant_h = np.array([0.0, 0.0, cant_height, cant_height, 0.0, 0.0])
    cant = np.arcsin(cant_h / rail_spacing)
    head = np.zeros(I_NODES)
    head[I_BREAKS:I_BREAKS + 6] = breaks
    head[I_CURV:I_CURV + 6] = curv
    head[I_CANT:I_CANT + 6] = cant
    head[I_CANT_H:I_CANT_H + 6] = cant_h
    head[I_RAIL_SPACING] = rail_spacing
    head[I_DIR] = 1.0 if direction >= 0 else -1.0
    head[I_EXC:I_EXC + 3] = excitation
    s_first = -margin
    n = int(math.ceil((breaks[-1] + 2 * margin) / GRID_STEP)) + 1
    head[I_GRID:I_GRID + 3] = (GRID_STEP, n, s_first)
    track = np.concatenate((head, np.zeros(3 * n)))
    _integrate_nodes(track)
    return track


@core
def _piece(track, s):
    """Segment index k with breaks[k] <= s < breaks[k+1], clamped to the straight ends (-1 or 5)."""
    if s < track[I_BREAKS]:
        return -1
    for k in range(N_SEG):
        if s < track[I_BREAKS + k + 1]:
            return k
    return N_SEG


@core
def curvature(track, s):
    """Signed curvature (1/m, + left) and its derivative d(curvature)/ds (1/m^2)."""
    k = _piece(track, s)
    if k < 0 or k >= N_SEG:
        return 0.0, 0.0
    s0 = track[I_BREAKS + k]
    s1 = track[I_BREAKS + k + 1]
    c0 = track[I_CURV + k]
    c1 = track[I_CURV + k + 1]
    slope = (c1 - c0) / (s1 - s0)
    d = track[I_DIR]
    return d * (c0 + slope * (s - s0)), d * slope


@core
def cant(track, s):
    """Track-plane roll angle (rad, signed: negative raises the right rail) and its derivative d/ds."""
    k = _piece(track, s)
    if k < 0 or k >= N_SEG:
        return 0.0, 0.0
    s0 = track[I_BREAKS + k]
    s1 = track[I_BREAKS + k + 1]
    h0 = track[I_CANT_H + k]
    h1 = track[I_CANT_H + k + 1]
    e = track[I_RAIL_SPACING]
    dh = (h1 - h0) / (s1 - s0)
    h = h0 + dh * (s - s0)
    ang = math.asin(h / e)
    dang = dh / (e * math.cos(ang))
    d = -track[I_DIR]
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
    d = track[I_DIR]
    for k in range(N_SEG):
        s0 = track[I_BREAKS + k]
        s1 = track[I_BREAKS + k + 1]
        if s <= s0:
            break
        e = min(s, s1)
        c0 = track[I_CURV + k]
        slope = (track[I_CURV + k + 1] - c0) / (s1 - s0)
        u = e - s0
        h += d * (c0 * u + 0.5 * slope * u * u)
    return h


@core
def _integrate_nodes(track):
    """Fill the heading/position grid by 4-point Gauss-Legendre quadrature of (cos h, sin h) per step."""
    step = track[I_GRID]
    n = int(track[I_GRID + 1])
    s_first = track[I_GRID + 2]
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
        j = I_NODES + 3 * i
        track[j] = _heading_exact(track, s)
        track[j + 1] = x
        track[j + 2] = y


@core
def lateral_defect(track, s):
    """Lateral alignment defect (m, + left) and its slope d/ds at s.

    One full period of a cosine-shaped lateral kink: y(s) = A/2 (1 - cos(2 pi (s - s0) / L)) for
    s0 <= s <= s0 + L. Smooth (C1), zero outside, peak amplitude A in the middle.
    """
    s0 = track[I_EXC]
    length = track[I_EXC + 1]
    amp = track[I_EXC + 2]
    if amp == 0.0 or s < s0 or s > s0 + length:
        return 0.0, 0.0
    w = 2.0 * math.pi / length
    u = s - s0
    return 0.5 * amp * (1.0 - math.cos(w * u)), 0.5 * amp * w * math.sin(w * u)


@core
def frame(track, s):
    """Track frame at s: (X, Y, heading, roll) of the origin in the ground frame.

    X, Y by a third-order expansion about the nearest grid node (error below 1e-7 m on the 0.5 m grid,
    largest next to a curvature break); the heading is exact.
    """
    step = track[I_GRID]
    n = int(track[I_GRID + 1])
    s_first = track[I_GRID + 2]
    i = int(math.floor((s - s_first) / step + 0.5))
    if i < 0:
        i = 0
    elif i > n - 1:
        i = n - 1
    j = I_NODES + 3 * i
    h0 = track[j]
    d = s - (s_first + i * step)
    kap, dkap = curvature(track, s_first + i * step)
    # heading along the step: h0 + kap d + dkap d^2/2 ; integrate cos/sin to third order in d
    c = math.cos(h0)
    sn = math.sin(h0)
    d2 = d * d
    d3 = d2 * d
    x = track[j + 1] + c * d - sn * (0.5 * kap * d2 + dkap * d3 / 6.0) - c * kap * kap * d3 / 6.0
    y = track[j + 2] + sn * d + c * (0.5 * kap * d2 + dkap * d3 / 6.0) - sn * kap * kap * d3 / 6.0
    heading = _heading_exact(track, s)
    roll, _ = cant(track, s)
    return x, y, heading, roll


def end_of_line(track):
    """Distance (m) of the end of the last straight."""
    return float(track[I_BREAKS + N_SEG])
