"""Wheel-rail contact geometry: where a wheel of a displaced, rolled and yawed wheelset touches its rail.

Method (exact for a prismatic rail). The rail is a prism along the track, so every wheel surface point can
be projected along x onto the track cross-section, and the wheel touches the rail where the vertical gap
between the lower envelope of that projection and the rail profile is smallest. The envelope is traced by
the wheel's *contact trace line*: on each circle of the wheel (profile point y_p, radius r) the point whose
surface normal has no component along the rail, which is where the rail's own normal (always in the
cross-section) can be met. For a wheelset yawed by psi and rolled by phi (rotation Rz(psi) Rx(phi)) the
angular position theta of that point solves

    cos(psi) sin(theta) - sin(psi) sin(phi) cos(theta) = -r'(y_p) sin(psi) cos(phi),

(r' = dr/dy_p, the profile slope), solved in closed form below. At large yaw and steep flange slopes the
trace point leads the axle by tens of millimetres and sits higher than the bottom of the wheel, which is
what makes flange contact depend on the angle of attack (Wang 1984; Shabana, Zaazaa & Sugiyama,
*Railroad Vehicle Dynamics*, 2008, ch. 5).

The gap g(y_p) = Z_wheel - Z_rail(Y) is evaluated along the trace line on the wheel profile grid.
Contact patches are the connected runs where g < 0 (interpenetration: the normal contact is elastic); each
run is one patch (two runs = two-point contact, e.g. tread and flange), located at its deepest point,
refined by a parabola. A wheel with g > 0 everywhere is lifted: it has no patch and its smallest gap is
reported. No single-point or rigid-contact assumption is made in the dynamics; rigid contact (for tables,
Delta-r and conicity) is the special case solved by `rigid_contact`.

Only the left wheel is computed here; the right wheel is the left wheel of the wheelset mirrored about the
track's x-z plane (y, roll and yaw change sign), so both rails use the same left-rail table and mirror
symmetry holds by construction.

Frames and the packed array `cg` are described in `pack_contact_geometry`.
"""
import math

import numpy as np

from .. import scalarmath
from ..jit import core, core_inline
from .layout import H_SIZE, MAX_CANDIDATES, MAX_PATCHES, Candidates, GeometryHeader, HertzShape, Patch


COARSE_STRIDE = 8                    # coarse search every 8th wheel grid point (1 mm on the 0.125 mm grid)
COARSE_WINDOW_GAP = 1.5e-3           # m; coarse minima below this are searched on the fine grid (the
                                     # vertical gap can dip ~0.5 mm between coarse samples on a steep flange)
NO_RAIL_GAP = 1.0                    # m; gap reported where there is no rail under the wheel
TRACK_GAP = 1.0e-3                   # m; near-contacts below this are followed during a time step
RUN_BLOCK = 16                       # grid points scanned at a time when a patch's extent is walked out
PROMINENCE_FULL = 0.5                # see _set_weights


def pack_contact_geometry(wheel, rail, nominal_radius, rolling_circle_half_distance, gauge, gauge_depth,
                          rail_inclination, rail_step=1.0e-4):
    """Pack wheel and rail tables into the array used by the numba core.

    `wheel` and `rail` are objects with uniform-grid arrays `y0`, `dy`, `z`, `slope`, `curvature`
    (a `ProfileTable`, in the profile frames of `railderail_sim.profiles`). The rail is inclined by
    `rail_inclination` (rad, top turned toward the track centre), its gauge point (the gauge-side point
    `gauge_depth` below the crown) is placed at Y = gauge / 2 and its highest point at Z = 0.
    """
    # Rail: dense sample of the un-inclined profile, rotated (field side up for the left rail), placed.
    y_fine = np.linspace(rail.y0, rail.y0 + (len(rail.z) - 1) * rail.dy, 20 * len(rail.z))
    z_fine = np.interp(y_fine, rail.y0 + rail.dy * np.arange(len(rail.z)), rail.z)
    ang_fine = scalarmath.arctan(np.interp(y_fine, rail.y0 + rail.dy * np.arange(len(rail.z)), rail.slope))
    kap_fine = np.interp(y_fine, rail.y0 + rail.dy * np.arange(len(rail.z)), rail.curvature)
    cb, sb = math.cos(rail_inclination), math.sin(rail_inclination)
    yr = y_fine * cb - z_fine * sb
    zr = y_fine * sb + z_fine * cb
    if np.any(np.diff(yr) <= 0):
        raise ValueError("rail profile is not single-valued after inclination; its side faces are too steep")
    top = int(np.argmax(zr))
    z_top = zr[top]
    zr = zr - z_top
    # gauge point: gauge-side (left of the top) point gauge_depth below the top
    gauge_side = slice(0, top + 1)
    y_gauge_local = np.interp(-gauge_depth, zr[gauge_side], yr[gauge_side])
    shift = 0.5 * gauge - y_gauge_local
    yr = yr + shift
    axis_y = shift  # the head axis (profile y = 0) passes through the rotated origin at the crown
    y_uniform = np.arange(yr[0], yr[-1], rail_step)
    z_uniform = np.interp(y_uniform, yr, zr)
    slope_uniform = scalarmath.tan(np.interp(y_uniform, yr, ang_fine + rail_inclination))
    kap_uniform = np.interp(y_uniform, yr, kap_fine)
    head_width = _head_width(rail, gauge_depth)

    nw = len(wheel.z)
    nr = len(y_uniform)
    cg = np.zeros(H_SIZE + 3 * nw + 3 * nr)
    i0 = int(round(-wheel.y0 / wheel.dy))
    tip = int(np.argmax(wheel.z))
    H = GeometryHeader
    for field, value in ((H.wheel_points, nw), (H.wheel_y0, wheel.y0), (H.wheel_step, wheel.dy),
                         (H.rail_points, nr), (H.rail_y0, y_uniform[0]), (H.rail_step, rail_step),
                         (H.nominal_radius, nominal_radius), (H.rolling_circle_distance, rolling_circle_half_distance),
                         (H.rail_top_y, yr[top]), (H.rail_axis_y, axis_y),
                         (H.flange_height, wheel.z[tip] - wheel.z[i0]), (H.flange_tip_y, wheel.y0 + tip * wheel.dy),
                         (H.rail_head_width, head_width), (H.gauge_y, 0.5 * gauge)):
        cg[field] = value
    wheel_z, wheel_slope, wheel_curvature = wheel_table(cg)
    wheel_z[:], wheel_slope[:], wheel_curvature[:] = wheel.z, wheel.slope, wheel.curvature
    rail_z, rail_slope, rail_curvature = rail_table(cg)
    rail_z[:], rail_slope[:], rail_curvature[:] = z_uniform, slope_uniform, kap_uniform
    return cg


def wheel_table(cg):
    """Views of the wheel table in cg: (z, slope, curvature) on the wheel grid (profile frame)."""
    nw = int(cg[GeometryHeader.wheel_points])
    o = H_SIZE
    return cg[o:o + nw], cg[o + nw:o + 2 * nw], cg[o + 2 * nw:o + 3 * nw]


def rail_table(cg):
    """Views of the left rail's table in cg: (Z, slope dZ/dY, curvature) on the rail grid (track frame)."""
    nw = int(cg[GeometryHeader.wheel_points])
    nr = int(cg[GeometryHeader.rail_points])
    o = H_SIZE + 3 * nw
    return cg[o:o + nr], cg[o + nr:o + 2 * nr], cg[o + 2 * nr:o + 3 * nr]


def _head_width(rail, depth):
    """Width of the un-inclined rail head `depth` below its crown (m)."""
    y = rail.y0 + rail.dy * np.arange(len(rail.z))
    z = rail.z - rail.z.max()
    top = int(np.argmax(z))
    left = np.interp(-depth, z[:top + 1], y[:top + 1])
    right = np.interp(-depth, z[top:][::-1], y[top:][::-1])
    return right - left


@core
def rail_height(cg, Y):
    """Left-rail surface height Z (m) and slope dZ/dY at track-frame Y; -1 m (no rail) outside the head.

    Cubic Hermite interpolation of the tabulated height and slope, so the gap's curvature is not spoiled
    by the table step.
    """
    nw = int(cg[GeometryHeader.wheel_points])
    nr = int(cg[GeometryHeader.rail_points])
    y0 = cg[GeometryHeader.rail_y0]
    h = cg[GeometryHeader.rail_step]
    u = (Y - y0) / h
    if u < 0.0 or u >= nr - 1:
        return -1.0, 0.0
    i = int(u)
    t = u - i
    o = H_SIZE + 3 * nw
    z0 = cg[o + i]
    z1 = cg[o + i + 1]
    m0 = cg[o + nr + i] * h
    m1 = cg[o + nr + i + 1] * h
    t2 = t * t
    t3 = t2 * t
    z = (2 * t3 - 3 * t2 + 1) * z0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * z1 + (t3 - t2) * m1
    dz = ((6 * t2 - 6 * t) * z0 + (3 * t2 - 4 * t + 1) * m0 + (-6 * t2 + 6 * t) * z1 + (3 * t2 - 2 * t) * m1) / h
    return z, dz


@core
def _rail_curvature(cg, Y):
    nw = int(cg[GeometryHeader.wheel_points])
    nr = int(cg[GeometryHeader.rail_points])
    u = (Y - cg[GeometryHeader.rail_y0]) / cg[GeometryHeader.rail_step]
    if u < 0.0 or u >= nr - 1:
        return 0.0
    i = int(u)
    t = u - i
    o = H_SIZE + 3 * nw + 2 * nr
    return (1.0 - t) * cg[o + i] + t * cg[o + i + 1]


@core
def _wheel_at(cg, yp):
    """Wheel radius increase z_w, slope and curvature at profile coordinate yp (linear interpolation)."""
    nw = int(cg[GeometryHeader.wheel_points])
    u = (yp - cg[GeometryHeader.wheel_y0]) / cg[GeometryHeader.wheel_step]
    if u < 0.0:
        u = 0.0
    if u > nw - 1.000001:
        u = nw - 1.000001
    i = int(u)
    t = u - i
    o = H_SIZE
    z = (1.0 - t) * cg[o + i] + t * cg[o + i + 1]
    s = (1.0 - t) * cg[o + nw + i] + t * cg[o + nw + i + 1]
    k = (1.0 - t) * cg[o + 2 * nw + i] + t * cg[o + 2 * nw + i + 1]
    return z, s, k


@core
def pose_constants(cg, y, z, phi, psi):
    """Per-wheel constants of the trace-line transform for a left-wheel pose (see `trace_gap`)."""
    cphi = math.cos(phi)
    sphi = math.sin(phi)
    cpsi = math.cos(psi)
    spsi = math.sin(psi)
    inv_rho = 1.0 / math.sqrt(cpsi * cpsi + spsi * spsi * sphi * sphi)
    return (y, cg[GeometryHeader.nominal_radius] + z, cphi, sphi, cpsi, spsi, cpsi * inv_rho, spsi * sphi * inv_rho,
            -spsi * cphi * inv_rho)


@core_inline
def trace_offset(r, eta, slope, an, bn, k1, cphi, sphi):
    """(qx, qy, qz): the contact trace line's point of the wheel profile point of radius r, slope r' and
    lateral coordinate eta from the wheelset centre, from the wheelset centre in its yawed, unrolled axes
    (turned by the yaw: X = cpsi qx - spsi qy, Y = y + spsi qx + cpsi qy; Z = zc + qz). The trace angle theta
    has sin(theta) = bn cos(b) + an sin(b), cos(theta) = an cos(b) - bn sin(b), sin(b) = r' k1 (the module
    docstring's trace-line equation; an, bn, k1 from `pose_constants`). Inlined: `_scan`'s and the Kik-
    Piotrowski strips' inner loops take it per profile point."""
    c = min(1.0, max(-1.0, slope * k1))
    cb = math.sqrt(1.0 - c * c)
    rct = r * (an * cb - bn * c)
    qx = r * (bn * cb + an * c)
    return qx, eta * cphi + rct * sphi, eta * sphi - rct * cphi


@core
def _scan(cg, pose, j0, j1, stride, gap, ys):
    """Vertical gap along the contact trace line (`trace_offset`) at wheel grid points j0, j0+stride, ... < j1.
    The rail height is a cubic Hermite interpolation of the tabulated height and slope."""
    nw = int(cg[GeometryHeader.wheel_points])
    wy0 = cg[GeometryHeader.wheel_y0]
    dw = cg[GeometryHeader.wheel_step]
    nr = int(cg[GeometryHeader.rail_points])
    ry0 = cg[GeometryHeader.rail_y0]
    dr = cg[GeometryHeader.rail_step]
    r0 = cg[GeometryHeader.nominal_radius]
    lw = cg[GeometryHeader.rolling_circle_distance]
    y, zc, cphi, sphi, cpsi, spsi, an, bn, k1 = pose
    inv_dr = 1.0 / dr
    ow = H_SIZE
    oz = H_SIZE + 3 * nw
    osl = oz + nr
    umax = nr - 1.0
    for j in range(j0, j1, stride):
        eta = lw + wy0 + j * dw
        qx, qy, qz = trace_offset(r0 + cg[ow + j], eta, cg[ow + nw + j], an, bn, k1, cphi, sphi)
        Y = y + spsi * qx + cpsi * qy
        u = (Y - ry0) * inv_dr
        if u < 0.0 or u >= umax:
            gap[j] = NO_RAIL_GAP
        else:
            i = int(u)
            t = u - i
            z0 = cg[oz + i]
            d = cg[oz + i + 1] - z0
            m0 = cg[osl + i] * dr
            m1 = cg[osl + i + 1] * dr
            zr = z0 + t * (m0 + t * (3.0 * d - 2.0 * m0 - m1 + t * (m0 + m1 - 2.0 * d)))
            gap[j] = zc + qz - zr
        ys[j] = Y


@core
def _trace_point(cg, pose, yp):
    """Trace-line point (X, Y, Z) of the wheel at continuous profile coordinate yp, with its wheel data."""
    y, zc, cphi, sphi, cpsi, spsi, an, bn, k1 = pose
    zw, sw, kw = _wheel_at(cg, yp)
    r = cg[GeometryHeader.nominal_radius] + zw
    qx, qy, qz = trace_offset(r, cg[GeometryHeader.rolling_circle_distance] + yp, sw, an, bn, k1, cphi, sphi)
    return cpsi * qx - spsi * qy, y + spsi * qx + cpsi * qy, zc + qz, r, sw, kw


@core
def wheel_range(cg, pose):
    """Wheel grid indices [j0, j1) that can lie over the rail head (3 mm margin)."""
    y, zc, cphi, sphi, cpsi, spsi, an, bn, k1 = pose
    dw = cg[GeometryHeader.wheel_step]
    ry0 = cg[GeometryHeader.rail_y0]
    ry1 = ry0 + (cg[GeometryHeader.rail_points] - 1) * cg[GeometryHeader.rail_step]
    base = (y + cg[GeometryHeader.rolling_circle_distance] * cphi + cg[GeometryHeader.nominal_radius] * sphi
            + cg[GeometryHeader.wheel_y0])
    nw = int(cg[GeometryHeader.wheel_points])
    j0 = int(math.floor((ry0 - base) / (dw * cphi) - 3e-3 / dw))
    j1 = int(math.ceil((ry1 - base) / (dw * cphi) + 3e-3 / dw)) + 1
    # 0 <= j0 <= j1 <= nw: empty when no part of the wheel lies over the rail (a wheel pushed far off it)
    j0 = min(max(j0, 0), nw)
    return j0, max(min(j1, nw), j0)


@core
def trace_gap(cg, y, z, phi, psi, gap, ys):
    """Gap along the whole trace line of the left wheel (every grid point over the rail).

    y, z: lateral (+ left) and vertical displacement of the wheelset centre from its nominal position
    (centre at height r0 above the rail-top plane); phi, psi: roll and yaw relative to the track (rad).
    Fills gap[j] and the trace point's track-frame Y in ys[j] for j0 <= j < j1; returns (j0, j1).
    """
    pose = pose_constants(cg, y, z, phi, psi)
    j0, j1 = wheel_range(cg, pose)
    _scan(cg, pose, j0, j1, 1, gap, ys)
    return j0, j1


@core
def find_patches(cg, y, z, phi, psi, gap, ys, patches, cand):
    """Interpenetration patches of the left wheel; returns (count, smallest coarse gap).

    Coarse-to-fine search: the gap is sampled every COARSE_STRIDE grid points; around each coarse local
    minimum below COARSE_WINDOW_GAP the fine grid is searched for the true local minimum (the threshold
    covers the dip that can hide between two coarse samples on these profiles). Minima with a negative gap
    are patches, in order across the wheel; each gets its share weight (`_set_weights`). Each patch row gets
    the contact point, its gap, rail slope, wheel profile coordinate and radius, the Hertz half relative
    curvatures A and B, the fine grid index of its minimum (Patch.grid_index) and the weight (Patch.weight).

    `cand` receives the fine minima worth following within the next integration step (patches and
    near-contacts below TRACK_GAP), a `Candidates` record (see `track_patches`).
    """
    pose = pose_constants(cg, y, z, phi, psi)
    j0, j1 = wheel_range(cg, pose)
    S = COARSE_STRIDE
    _scan(cg, pose, j0, j1, S, gap, ys)
    jl = j0 + ((j1 - 1 - j0) // S) * S   # last coarse point
    gmin = NO_RAIL_GAP
    count = 0
    ncand = 0
    prev_min = -1                        # fine index of the previous patch
    j = j0
    while j <= jl:
        g = gap[j]
        if g < gmin:
            gmin = g
        left = gap[j - S] if j - S >= j0 else NO_RAIL_GAP
        right = gap[j + S] if j + S <= jl else NO_RAIL_GAP
        if g < COARSE_WINDOW_GAP and g <= left and g < right:
            jm = local_minimum(cg, pose, j, j0, j1, S, gap, ys)
            if gap[jm] < 0.0:
                if jm != prev_min and count < MAX_PATCHES:
                    _fill_patch(cg, pose, jm, j0, j1, gap, patches, count)
                    count += 1
                    prev_min = jm
                    if ncand < MAX_CANDIDATES:
                        cand[Candidates.indices + ncand] = jm
                        ncand += 1
            elif gap[jm] < TRACK_GAP and ncand < MAX_CANDIDATES:
                cand[Candidates.indices + ncand] = jm
                ncand += 1
        j += S
    cand[Candidates.count] = ncand
    _set_weights(cg, pose, patches, count, gap, ys)
    return count, gmin


@core
def track_patches(cg, y, z, phi, psi, gap, ys, patches, cand):
    """Patches near the minima listed in `cand` by the last `find_patches` (a cheap local search).

    Used inside one integration step, where the wheelset moves by a fraction of a millimetre: each
    listed minimum is followed downhill on the fine grid (`local_minimum`) and refined as in
    `find_patches`; minima that meet are counted once.
    """
    pose = pose_constants(cg, y, z, phi, psi)
    j0, j1 = wheel_range(cg, pose)
    count = 0
    prev = -10
    for c in range(int(cand[Candidates.count])):
        jc = int(cand[Candidates.indices + c])
        if jc < j0 or jc >= j1:
            continue
        jm = local_minimum(cg, pose, jc, j0, j1, 2, gap, ys)
        if gap[jm] < 0.0 and abs(jm - prev) > 1 and count < MAX_PATCHES:
            _fill_patch(cg, pose, jm, j0, j1, gap, patches, count)
            count += 1
            prev = jm
    _set_weights(cg, pose, patches, count, gap, ys)
    return count


@core
def local_minimum(cg, pose, jc, j0, j1, half, gap, ys):
    """Fine-grid local minimum within `half` grid steps of jc, walking downhill beyond that window if
    needed; its two neighbours are scanned too (for the parabola of `_fill_patch`)."""
    a = max(jc - half, j0)
    b = min(jc + half + 1, j1)
    _scan(cg, pose, a, b, 1, gap, ys)
    jm = a
    for k in range(a, b):
        if gap[k] < gap[jm]:
            jm = k
    while jm == a and a > j0:
        a -= 1
        _scan(cg, pose, a, a + 1, 1, gap, ys)
        if gap[a] < gap[jm]:
            jm = a
        else:
            break
    while jm == b - 1 and b < j1:
        _scan(cg, pose, b, b + 1, 1, gap, ys)
        if gap[b] < gap[jm]:
            jm = b
            b += 1
        else:
            break
    # make sure both fine neighbours exist for the parabola
    if jm - 1 >= j0:
        _scan(cg, pose, jm - 1, jm, 1, gap, ys)
    if jm + 1 < j1:
        _scan(cg, pose, jm + 1, jm + 2, 1, gap, ys)
    return jm


@core
def _set_weights(cg, pose, patches, count, gap, ys):
    """Share weight of each patch (Patch.weight) for equivalent-elliptic normal contact.

    Neighbouring minima of the gap are separate patches (tread and flange root stay two contacts, as the
    half-space solution shows them). Where the ridge between a patch and a deeper neighbour rises less
    than PROMINENCE_FULL times the patch's own interpenetration above its minimum, the two are parts of
    one contact that one ellipse cannot describe: the shallower patch's force is scaled by
    prominence / (PROMINENCE_FULL depth), from 1 down to 0 as the ridge sinks to its level. The force
    stays continuous when two minima are born or merge, and a ripple in a conformal contact is not counted
    twice. The patches are in order across the wheel (increasing Patch.grid_index).
    """
    for k in range(count):
        patches[k, Patch.weight] = 1.0
    for k in range(count - 1):
        ja = int(patches[k, Patch.grid_index])
        jb = int(patches[k + 1, Patch.grid_index])
        _scan(cg, pose, ja + 1, jb, 1, gap, ys)
        ridge = gap[ja]
        for q in range(ja + 1, jb):
            if gap[q] > ridge:
                ridge = gap[q]
        share_weight(patches, k, k + 1, ridge)


@core
def share_weight(patches, ka, kb, ridge):
    """Lower the share weight of the shallower of patches ka, kb by the prominence of the ridge (the
    highest gap) between them, as `_set_weights` describes; the contact table calls it with its ridge."""
    s = ka if patches[ka, Patch.gap] > patches[kb, Patch.gap] else kb
    depth = -patches[s, Patch.gap]
    w = (ridge - patches[s, Patch.gap]) / (PROMINENCE_FULL * depth)
    w = min(1.0, max(0.0, w))
    if w < patches[s, Patch.weight]:
        patches[s, Patch.weight] = w


@core
def run_bounds(cg, y, z, phi, psi, jm, gap, ys):
    """Fine-grid extent [ja, jb] of the patch around its minimum jm (fills gap/ys on it): the
    interpenetration run, cut at the top of a ridge (beyond it lies the next patch's minimum)."""
    pose = pose_constants(cg, y, z, phi, psi)
    j0, j1 = wheel_range(cg, pose)
    # start from the local minimum (a tabulated contact gives its grid point to within one step)
    jm = local_minimum(cg, pose, min(max(jm, j0), j1 - 1), j0, j1, 1, gap, ys)
    # walk out from the minimum; the gap is scanned RUN_BLOCK points ahead at a time (a loop over a
    # block costs a fraction of one call per point), so [lo, hi) is always scanned
    lo = jm
    hi = jm + 1
    ja = jm
    while ja - 1 >= j0:
        if ja - 1 < lo:
            new_lo = max(j0, lo - RUN_BLOCK)
            _scan(cg, pose, new_lo, lo, 1, gap, ys)
            lo = new_lo
        if gap[ja - 1] >= 0.0 or gap[ja - 1] < gap[ja]:
            break
        ja -= 1
    jb = jm
    while jb + 1 < j1:
        if jb + 1 >= hi:
            new_hi = min(j1, hi + RUN_BLOCK)
            _scan(cg, pose, hi, new_hi, 1, gap, ys)
            hi = new_hi
        if gap[jb + 1] >= 0.0 or gap[jb + 1] < gap[jb]:
            break
        jb += 1
    return ja, jb


@core
def _fill_patch(cg, pose, jm, j0, j1, gap, patches, slot):
    """Refine the deepest grid point of a run by a parabola and fill one patch row."""
    t = 0.0
    g = gap[jm]
    if jm > j0 and jm < j1 - 1:
        gl = gap[jm - 1]
        gr = gap[jm + 1]
        den = gl - 2.0 * g + gr
        if den > 0.0:
            t = min(0.5, max(-0.5, 0.5 * (gl - gr) / den))
            g = g - 0.125 * (gl - gr) * (gl - gr) / den
    yp = cg[GeometryHeader.wheel_y0] + (jm + t) * cg[GeometryHeader.wheel_step]
    X, Y, Z, radius, sw, kw = _trace_point(cg, pose, yp)
    _, slope = rail_height(cg, Y)
    kr = _rail_curvature(cg, Y)
    patches[slot, Patch.y] = Y
    patches[slot, Patch.z] = Z
    patches[slot, Patch.x] = X
    patches[slot, Patch.gap] = g
    patches[slot, Patch.slope] = slope
    patches[slot, Patch.wheel_y] = yp
    patches[slot, Patch.radius] = radius
    # relative lateral curvature: the wheel surface seen from the rail has curvature -kw
    patches[slot, Patch.curvature_b] = 0.5 * (-kw - kr)
    patches[slot, Patch.curvature_a] = 0.5 / (radius * math.sqrt(1.0 + sw * sw))
    patches[slot, Patch.grid_index] = jm
    patches[slot, Patch.hertz_shape + HertzShape.stiffness] = 0.0           # the Hertz shape is computed from A and B


@core
def wheel_lift(cg, z, phi):
    """The paper's hp for the left wheel: height of the lowest point of the nominal rolling circle above
    the rail's highest point (m). Right wheel: call with the mirrored pose (-phi)."""
    r0 = cg[GeometryHeader.nominal_radius]
    lw = cg[GeometryHeader.rolling_circle_distance]
    return r0 + z + lw * math.sin(phi) - r0 * math.cos(phi)


@core
def min_gap(cg, y, z, phi, psi, gap, ys):
    """Smallest gap of the left wheel (m) on the fine grid and the index where it occurs; (NO_RAIL_GAP, -1)
    when no part of the wheel lies over the rail."""
    j0, j1 = trace_gap(cg, y, z, phi, psi, gap, ys)
    if j1 <= j0:
        return NO_RAIL_GAP, -1
    jm = j0
    for j in range(j0, j1):
        if gap[j] < gap[jm]:
            jm = j
    return gap[jm], jm


@core
def rigid_contact(cg, y, psi, gap, ys):
    """Rigid (zero-penetration) contact of both wheels for lateral displacement y and yaw psi.

    Solves for the wheelset's vertical displacement z and roll phi at which the smallest gap of each wheel
    is zero (Newton with the exact kinematic Jacobian of a rigid wheelset). Returns (z, phi, jl, jr):
    jl, jr are the wheel grid indices of the left and right contact points.
    """
    lw = cg[GeometryHeader.rolling_circle_distance]
    z = 0.0
    phi = 0.0
    jl = 0
    jr = 0
    for _ in range(60):
        gl, jl = min_gap(cg, y, z, phi, psi, gap, ys)
        gr, jr = min_gap(cg, -y, z, -phi, -psi, gap, ys)
        dz = -0.5 * (gl + gr)
        dphi = 0.5 * (gr - gl) / lw
        z += dz
        phi += dphi
        if abs(dz) < 1e-12 and abs(dphi) < 1e-12:
            break
    return z, phi, jl, jr
