"""Wheel-rail forces of one wheel from the wheelset's pose and velocities (numba core).

For each interpenetration patch found by `geometry.find_patches`:
  - normal: the normal approach d = -gap cos(delta) (delta the contact angle); equivalent-elliptic Hertz
    N = C d^1.5 from the patch's principal relative curvatures (`hertz.hertz_shape`), or the discrete
    non-elliptic Kik-Piotrowski patch from the gap along the patch (`kik_piotrowski`); Hunt-Crossley
    damping multiplies the elastic force by (1 + chi d'), and N >= 0 (no adhesion);
  - creepages from the velocity of the wheel material point at the contact (translation, rotation and
    spin of the wheelset, the rail being fixed): longitudinal and lateral along the contact plane,
    spin about the contact normal, each divided by the forward speed;
  - creep forces by the selected law (`creep.creep_law`, as `creep.creep_forces` with Kalker's coefficients
    from the model's table, `creep.tabulated_coefficients`) on the Hertz ellipse (or the discrete patch's
    equivalent ellipse).
The force and its moment about the wheelset centre are returned in the wheelset's track axes.

Only the left wheel is written out; `wheel_forces` mirrors the pose for the right wheel.

Arguments come in groups: `pose` = (y, z, phi, psi), the wheelset's lateral and vertical displacement
(m) and roll and yaw (rad) relative to the rails; `motion` = (vx, vy, vz, ox, oy, oz, spin, speed), the
absolute velocity of the wheelset centre and its angular velocity without spin (track axes), the spin
about the axle (rad/s) and the forward speed that normalises the creepages (m/s); `scratch` the
`ContactScratch` buffers (`contact_scratch(cg)`).
"""
from collections import namedtuple
import math

import numpy as np

from ..jit import core, core_inline
from ..record import Record
from . import geometry as geo
from .creep import creep_law, tabulated_coefficients
from .hertz import combined_modulus, hertz_shape
from . import kik_piotrowski as kp
from . import table as tab
from .layout import (H_SIZE, MAX_PATCHES, P_COLS, WP_SIZE, Candidates, ContactConstants, GeometryHeader, HertzShape, Patch,
                     Wheel, WheelPatch)

NORMAL_HERTZ, NORMAL_DISCRETE = 0, 1
SMALL_ANGLE = 0.05    # rad; `sin_cos` by its Taylor polynomials up to here (within an ulp of libm's), libm beyond
KP_STRIPS = 16        # strips across a Kik-Piotrowski patch, at fixed fractions of its extent (`_discrete_normal`)
KP_WALK = 6           # coarse steps from a KP patch's deepest point to its edge, about (`_kp_extent`)
KP_MAX_STRIDE = 8     # grid points (1 mm on the 0.125 mm grid) per coarse step at most




class Strip(Record):
    """Rows of the discrete (Kik-Piotrowski) patch's strip buffer `ContactScratch.kpbuf`."""
    gap = "m", "KP's virtual interpenetration f = eps delta - (gap - gmin) at the strip's centre"
    radius = "m", "the wheel's longitudinal radius in the contact plane"
    half_length = "m", "strip half-length x_L (kik_piotrowski.kp_normal's output)"


# buffers of one wheel's contact evaluation (allocated by `contact_scratch`): gap and trace-point Y on the
# wheel grid, the patch rows, the discrete patch's strips
ContactScratch = namedtuple("ContactScratch", "gap ys patches kpbuf")


def contact_scratch(cg):
    """Buffers of `wheel_forces` for the packed geometry cg."""
    nw = int(cg[GeometryHeader.wheel_points])
    return ContactScratch(gap=np.zeros(nw), ys=np.zeros(nw), patches=np.zeros((MAX_PATCHES, P_COLS)),
                          kpbuf=np.zeros((Strip.size(), KP_STRIPS)))


def candidates(count=1):
    """Candidate lists (`Candidates`) of `count` wheels."""
    return np.zeros((count, Candidates.size()))


@core_inline
def sin_cos(x):
    """(sin x, cos x). For |x| <= SMALL_ANGLE (a wheelset's roll and yaw relative to its rails: a few mrad) by
    the Taylor polynomials to x^7 and x^8, whose truncation (x^9/9!, x^10/10!) is below 2e-17 relative there:
    they differ from libm's sin and cos by at most one rounding (tests/test_contact_geometry.py); libm beyond.

    Hand-written in the core: a libm sin and cos cost about 16 ns per pair, the polynomials 2 ns, and
    `wheel_forces` needs two pairs per wheel and right-hand side.
    """
    if abs(x) <= SMALL_ANGLE:
        x2 = x * x
        s = x + x * x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0)))
        c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0))))
        return s, c
    return math.sin(x), math.cos(x)


@core
def wheel_forces(cg, cp, side, pose, motion, scratch, cand, tracked, rec):
    """Contact force and moment of wheel `side` (0 left, 1 right) of a wheelset at `pose` with `motion`
    (module docstring): (Fx, Fy, Fz, Mx, My, Mz) on the wheel, about the wheelset centre, track axes.

    Scalars, not arrays: this runs 48 times per time step. On full searches (not `tracked`) it fills the
    `Wheel` record `rec` and the patch rows. The right wheel is the left wheel of the wheelset mirrored in
    the x-z plane: y, phi, psi, the lateral velocity and the x and z angular velocities change sign on the
    way in, the lateral force and the x and z moments on the way out (one function, not a wrapper: each
    call copies a dozen array descriptors). The patches come from the contact table when cg carries one
    and the pose is inside it (`contact.table`); otherwise from the exact search: `tracked` then follows
    the minima listed in `cand` by the last full search (inside a time step) instead of searching the
    whole profile (`geometry.track_patches`).
    """
    mirror = 1.0 if side == 0 else -1.0
    y, z, phi, psi = pose
    y, phi, psi = mirror * y, mirror * phi, mirror * psi
    vx0, vy0, vz0, ox, oy, oz, spin, speed = motion
    vy0, ox, oz = mirror * vy0, mirror * ox, mirror * oz
    gap, ys, patches = scratch.gap, scratch.ys, scratch.patches
    count, gmin = tab.table_patches(cg, y, z, phi, psi, patches, cand)
    if count < 0:                       # no table, or the pose is outside it: exact online search
        if tracked:
            count = geo.track_patches(cg, y, z, phi, psi, gap, ys, patches, cand)
            gmin = 0.0
            for k in range(count):
                gmin = min(gmin, patches[k, Patch.gap])
        else:
            count, gmin = geo.find_patches(cg, y, z, phi, psi, gap, ys, patches, cand)
    r0 = cg[GeometryHeader.nominal_radius]
    sphi, cphi = sin_cos(phi)
    spsi, cpsi = sin_cos(psi)
    # axle direction (track axes) and total angular velocity of the wheel
    ax_x = -spsi * cphi
    ax_y = cpsi * cphi
    ax_z = sphi
    wx = ox + spin * ax_x
    wy = oy + spin * ax_y
    wz = oz + spin * ax_z
    estar = cp[ContactConstants.combined_modulus]
    shear = cp[ContactConstants.shear_modulus]
    nu = cp[ContactConstants.poisson_ratio]
    mu = cp[ContactConstants.friction]
    chi = cp[ContactConstants.contact_damping]
    model = int(cp[ContactConstants.creep_model])
    discrete = int(cp[ContactConstants.normal_model]) == NORMAL_DISCRETE
    inv_speed = 1.0 / speed
    inv_estar_cbrt = 1.0 / cp[ContactConstants.combined_modulus_cbrt]
    fy_tot = 0.0
    fz_tot = 0.0
    fx_tot = 0.0
    mx_tot = 0.0
    my_tot = 0.0
    mz_tot = 0.0
    nmax = -1.0
    # the output record is written on full searches only (the states that are output or checked)
    record = not tracked
    if record:
        for q in range(rec.shape[0]):
            rec[q] = 0.0
        rec[Wheel.wheel_lift] = geo.wheel_lift(cg, z, phi)
        rec[Wheel.min_gap] = gmin
        rec[Wheel.contact_count] = count
    for k in range(count):
        patches[k, Patch.normal_force] = 0.0
        slope = patches[k, Patch.slope]
        cd = 1.0 / math.sqrt(1.0 + slope * slope)
        sd = slope * cd
        d = -patches[k, Patch.gap] * cd
        if d <= 0.0:
            continue
        # contact frame: normal n (rail into wheel), lateral tangent t, longitudinal e_x
        nY, nZ = -sd, cd
        tY, tZ = cd, sd
        rx = patches[k, Patch.x]
        ry = patches[k, Patch.y] - y
        rz = patches[k, Patch.z] - (r0 + z)
        # velocity of the wheel material point at the contact
        vx = vx0 + wy * rz - wz * ry
        vy = vy0 + wz * rx - wx * rz
        vz = vz0 + wx * ry - wy * rx
        approach_rate = -(vy * nY + vz * nZ)
        if discrete:
            n_el, a, b, a_eq, b_eq = _discrete_normal(cg, (y, z, phi, psi), int(patches[k, Patch.grid_index]),
                                                      patches[k, Patch.gap], cd, scratch,
                                                      cp[ContactConstants.youngs_modulus], nu)
        if not discrete or record:
            shape = Patch.hertz_shape
            if patches[k, shape + HertzShape.stiffness] > 0.0:     # from the contact table, at E* = 1 Pa
                ac = patches[k, shape + HertzShape.a_coefficient] * inv_estar_cbrt
                bc = patches[k, shape + HertzShape.b_coefficient] * inv_estar_cbrt
                stiff = patches[k, shape + HertzShape.stiffness] * estar
            else:
                ac, bc, stiff = hertz_shape(patches[k, Patch.curvature_a], patches[k, Patch.curvature_b], estar)
        if not discrete:
            # a part of a wider contact carries its share only (geometry._set_weights)
            n_el = patches[k, Patch.weight] * stiff * d * math.sqrt(d)
            cube_root = n_el ** (1.0 / 3.0)
            a = ac * cube_root
            b = bc * cube_root
            a_eq = a
            b_eq = b
        # Hunt-Crossley damping scales the load; the patch is the elastic one
        normal = n_el * (1.0 + chi * approach_rate)
        if normal <= 0.0:
            continue
        xi_x = vx * inv_speed
        xi_y = (vy * tY + vz * tZ) * inv_speed
        phi_s = (wy * nY + wz * nZ) * inv_speed
        if a_eq > 0.0 and b_eq > 0.0:      # Kalker's coefficients from the model's table (creep.py)
            C11, C22, C23, C33 = tabulated_coefficients(cp, a_eq, b_eq)
            fx, ft, mz = creep_law(model, xi_x, xi_y, phi_s, a_eq, b_eq, normal, mu, shear, C11, C22, C23, C33)
        else:
            fx, ft, mz = 0.0, 0.0, 0.0
        if record:
            row = patches[k]
            row[Patch.normal_force] = normal
            row[Patch.approach] = d
            row[Patch.half_length] = a
            row[Patch.half_width] = b
            row[Patch.creep_a] = a_eq
            row[Patch.creep_b] = b_eq
            cube_root = normal ** (1.0 / 3.0)
            row[Patch.hertz_a] = ac * cube_root
            row[Patch.hertz_b] = bc * cube_root
            row[Patch.creepage_x] = xi_x
            row[Patch.creepage_y] = xi_y
            row[Patch.spin_creepage] = phi_s
            row[Patch.creep_force_x] = fx
            row[Patch.creep_force_lateral] = ft
            row[Patch.spin_moment] = mz
        Fx, Fy, Fz, Mx, My, Mz = patch_load(nY, nZ, rx, ry, rz, normal, fx, ft, mz)
        mx_tot += Mx
        my_tot += My
        mz_tot += Mz
        fx_tot += Fx
        fy_tot += Fy
        fz_tot += Fz
        if record:
            o = Wheel.patches + k * WP_SIZE
            rec[o + WheelPatch.lateral_position] = patches[k, Patch.y] - cg[GeometryHeader.rail_axis_y]
            rec[o + WheelPatch.lead] = rx
            rec[o + WheelPatch.length] = 2.0 * a
            rec[o + WheelPatch.width] = 2.0 * b
            rec[o + WheelPatch.normal_force] = normal
            rec[o + WheelPatch.contact_angle] = math.atan(slope)
            if normal > nmax:           # the main patch: the most loaded one
                nmax = normal
                rec[Wheel.contact_position] = rec[o + WheelPatch.lateral_position]
                rec[Wheel.contact_angle] = rec[o + WheelPatch.contact_angle]
                rec[Wheel.patch_length] = rec[o + WheelPatch.length]
                rec[Wheel.patch_width] = rec[o + WheelPatch.width]
    if not record:
        return fx_tot, mirror * fy_tot, fz_tot, mirror * mx_tot, my_tot, mirror * mz_tot
    # forces on the rail: Q toward the left rail's field side (+Y), P downward
    rec[Wheel.lateral_force] = -fy_tot
    rec[Wheel.vertical_force] = fz_tot
    rec[Wheel.longitudinal_force] = -fx_tot
    loaded = rec[Wheel.vertical_force] > cp[ContactConstants.qp_min_load]
    rec[Wheel.derailment_coefficient] = rec[Wheel.lateral_force] / rec[Wheel.vertical_force] if loaded else 0.0
    return fx_tot, mirror * fy_tot, fz_tot, mirror * mx_tot, my_tot, mirror * mz_tot


@core
def patch_load(nY, nZ, rx, ry, rz, normal, fx, ft, mz):
    """Force and moment on the wheel of one patch (Fx, Fy, Fz, Mx, My, Mz; left-wheel track axes, about the
    wheelset centre): the normal force along n = (0, nY, nZ) (rail into wheel), the creep forces fx along x
    and ft along the lateral tangent t = (0, nZ, -nY), the spin moment mz about n, applied at the contact
    point r = (rx, ry, rz) from the wheelset centre."""
    Fx = fx
    Fy = normal * nY + ft * nZ
    Fz = normal * nZ - ft * nY
    return (Fx, Fy, Fz, ry * Fz - rz * Fy, rz * Fx - rx * Fz + mz * nY, rx * Fy - ry * Fx + mz * nZ)


@core
def _discrete_normal(cg, pose, jm, gmin, cos_angle, scratch, youngs, nu):
    """Kik-Piotrowski normal load of one patch from the gap along its extent.

    The patch's edges are found on the wheel grid: walking out from the deepest grid point jm (made a local
    minimum of the trace-line gap) to where the vertical gap reaches (1 - eps) gmin, i.e. where KP's virtual
    interpenetration f = eps delta - (gap - gmin) falls to 0 (linear interpolation between the two grid
    points around it), or to the top of a ridge (beyond it lies the next patch's minimum). The extent is
    then cut into KP_STRIPS strips at fixed fractions of it, and the gap and the wheel's longitudinal
    radius in the contact plane (r sqrt(1 + r'^2)) are evaluated at the strips' centres on the trace line:
    the strips move with the edges, which move continuously with the pose, so the load is continuous (the
    strips of the grid's cells would enter and leave one at a time). The vertical gap is turned into the
    normal separation (times cos of the contact angle) on the lateral tangent coordinate (Y / cos), assuming
    a locally plane contact; the deepest point is the parabola's vertex through jm and its neighbours.
    `kik_piotrowski.kp_strip_force` integrates the strips (its docstring; the error in docs/contact-models.md).
    Returns (N, a, b, a_eq, b_eq): half the patch's length and width, and the semi-axes of its equivalent
    ellipse for the creep forces.
    """
    y, z, phi, psi = pose
    kpbuf = scratch.kpbuf
    gap = scratch.gap
    trace = geo.pose_constants(cg, y, z, phi, psi)
    j0, j1 = geo.wheel_range(cg, trace)
    if j1 - j0 < 3 or not (gmin < 0.0):
        return 0.0, 0.0, 0.0, 0.0, 0.0
    eps = kp.EPS_DEFAULT
    edge = (1.0 - eps) * gmin               # the vertical gap at the KP patch's edge
    ua, fa, ub, fb, um, span = _kp_extent(cg, trace, min(max(jm, j0), j1 - 1), j0, j1, edge, gap, kpbuf)
    m = KP_STRIPS
    du = (ub - ua) / m
    if not (du > 0.0 and span > 0.0):
        return 0.0, 0.0, 0.0, 0.0, 0.0
    for i in range(m):
        kpbuf[Strip.gap, i] *= cos_angle            # KP's f: eps delta - (gap - gmin), normal to the contact
    ds = span / ((m - 1) * cos_angle)
    approach = -gmin * cos_angle
    N, IS, xlmax, area = kp.kp_strip_force(kpbuf[Strip.gap], kpbuf[Strip.radius], m, ds, (um - ua) / du * ds,
                                           (fa * cos_angle, fb * cos_angle), eps * approach, approach,
                                           combined_modulus(youngs, nu, youngs, nu), kpbuf[Strip.half_length])
    if not (N > 0.0):
        return 0.0, 0.0, 0.0, 0.0, 0.0
    width = m * ds
    ratio = xlmax / (0.5 * width)
    return N, xlmax, 0.5 * width, math.sqrt(area / math.pi * ratio), math.sqrt(area / (math.pi * ratio))


@core_inline
def _trace_gap(cg, u, nw, nr, wy0, dw, lw, r0, ry0, inv_dr, y, zc, cphi, sphi, cpsi, spsi, an, bn, k1):
    """Vertical gap, track-frame Y and the wheel's longitudinal radius in the contact plane at continuous
    wheel grid coordinate u: `geometry._scan` and `geometry._trace_point` in one, scalars in (inlined: a call
    passing cg and the pose costs as much as the point)."""
    i = min(max(int(u), 0), nw - 2)
    t = u - i
    ow = H_SIZE
    zw = cg[ow + i] + t * (cg[ow + i + 1] - cg[ow + i])
    sw = cg[ow + nw + i] + t * (cg[ow + nw + i + 1] - cg[ow + nw + i])
    r = r0 + zw
    qx, qy, qz = geo.trace_offset(r, lw + wy0 + u * dw, sw, an, bn, k1, cphi, sphi)
    Y = y + spsi * qx + cpsi * qy
    v = (Y - ry0) * inv_dr
    if v < 0.0 or v >= nr - 1.0:
        return geo.NO_RAIL_GAP, Y, r * math.sqrt(1.0 + sw * sw)
    k = int(v)
    tr = v - k
    oz = H_SIZE + 3 * nw
    osl = oz + nr
    z0 = cg[oz + k]
    d = cg[oz + k + 1] - z0
    m0 = cg[osl + k] / inv_dr
    m1 = cg[osl + k + 1] / inv_dr
    zr = z0 + tr * (m0 + tr * (3.0 * d - 2.0 * m0 - m1 + tr * (m0 + m1 - 2.0 * d)))
    return zc + qz - zr, Y, r * math.sqrt(1.0 + sw * sw)


@core
def _kp_extent(cg, trace, jm, j0, j1, edge, gap, strips):
    """The KP patch's deepest point, edges and strips (`_discrete_normal`), from its deepest grid point jm
    (to within a step or two) within the wheel's grid range [j0, j1) and the vertical gap at the edge.

    The deepest point: the grid's local minimum reached downhill from jm, refined by the parabola through
    it and its neighbours. Walking from it to each side, the edge is the grid coordinate where the vertical
    gap reaches `edge` (linear interpolation between the two grid points around it; f = 0 there), or the
    top of a ridge (the last grid point before the gap falls again) or the range's end (f > 0 there). The
    walk takes strides of about a KP_WALK-th of the parabola's half-width (at most KP_MAX_STRIDE grid points:
    the gap's ridges are millimetres wide) and looks at the grid points in between only where the gap
    crossed `edge` (by bisection) or fell. Then the strips' edge - gap (the caller scales it to KP's f) and
    radii at their centres, at fixed fractions of the extent, into `strips`. Returns (ua, fa, ub, fb, the
    deepest point's grid coordinate, the tangent Y span of the strips' centres); ub = ua if the gap does
    not reach below `edge`."""
    y, zc, cphi, sphi, cpsi, spsi, an, bn, k1 = trace
    nw = int(cg[GeometryHeader.wheel_points])
    nr = int(cg[GeometryHeader.rail_points])
    wy0 = cg[GeometryHeader.wheel_y0]
    dw = cg[GeometryHeader.wheel_step]
    lw = cg[GeometryHeader.rolling_circle_distance]
    r0 = cg[GeometryHeader.nominal_radius]
    ry0 = cg[GeometryHeader.rail_y0]
    inv_dr = 1.0 / cg[GeometryHeader.rail_step]
    # the local minimum downhill from jm, and both its neighbours
    gm = _trace_gap(cg, float(jm), nw, nr, wy0, dw, lw, r0, ry0, inv_dr, y, zc, cphi, sphi, cpsi, spsi, an, bn, k1)[0]
    gap[jm] = gm
    for step in (-1, 1):
        while True:
            j = jm + step
            if j < j0 or j >= j1:
                break
            g = _trace_gap(cg, float(j), nw, nr, wy0, dw, lw, r0, ry0, inv_dr, y, zc, cphi, sphi, cpsi, spsi, an, bn,
                           k1)[0]
            gap[j] = g
            if not (g < gap[jm]):
                break
            jm = j
    if not (gap[jm] < edge):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    t = 0.0
    stride = 1
    if jm > j0 and jm < j1 - 1:
        den = gap[jm - 1] - 2.0 * gap[jm] + gap[jm + 1]
        if den > 0.0:
            t = min(0.5, max(-0.5, 0.5 * (gap[jm - 1] - gap[jm + 1]) / den))
            stride = min(max(int(math.sqrt(2.0 * (edge - gap[jm]) / den) / KP_WALK), 1), KP_MAX_STRIDE)
    ua = 0.0
    ub = 0.0
    fa = 0.0
    fb = 0.0
    for side in range(2):
        step = -1 if side == 0 else 1
        prev = jm
        u_edge = float(jm)
        f_edge = edge - gap[jm]
        while True:
            c = min(max(prev + step * stride, j0), j1 - 1)
            if c == prev:
                u_edge, f_edge = float(prev), edge - gap[prev]
                break
            gc = _trace_gap(cg, float(c), nw, nr, wy0, dw, lw, r0, ry0, inv_dr, y, zc, cphi, sphi, cpsi, spsi, an, bn,
                            k1)[0]
            gap[c] = gc
            if gc < gap[prev]:              # a fall within (prev, c]: walk to it (or to a crossing before it)
                j = prev
                while j != c:
                    if j + step != c:
                        gap[j + step] = _trace_gap(cg, float(j + step), nw, nr, wy0, dw, lw, r0, ry0, inv_dr, y, zc,
                                                   cphi, sphi, cpsi, spsi, an, bn, k1)[0]
                    g = gap[j + step]
                    if g >= edge:
                        u_edge, f_edge = j + step * (edge - gap[j]) / (g - gap[j]), 0.0
                        break
                    if g < gap[j]:
                        u_edge, f_edge = float(j), edge - gap[j]
                        break
                    j += step
                break
            if gc >= edge:                  # the crossing within (prev, c]: bisection for its grid interval
                lo = prev
                hi = c
                while abs(hi - lo) > 1:
                    mid = (lo + hi) // 2
                    g = _trace_gap(cg, float(mid), nw, nr, wy0, dw, lw, r0, ry0, inv_dr, y, zc, cphi, sphi, cpsi,
                                   spsi, an, bn, k1)[0]
                    gap[mid] = g
                    if g >= edge:
                        hi = mid
                    else:
                        lo = mid
                u_edge, f_edge = lo + step * (edge - gap[lo]) / (gap[hi] - gap[lo]), 0.0
                break
            prev = c
        if side == 0:
            ua, fa = u_edge, f_edge
        else:
            ub, fb = u_edge, f_edge
    m = strips.shape[1]
    du = (ub - ua) / m
    Y_first = 0.0
    Y_last = 0.0
    for i in range(m):
        g, Y, R = _trace_gap(cg, ua + (i + 0.5) * du, nw, nr, wy0, dw, lw, r0, ry0, inv_dr, y, zc, cphi, sphi, cpsi,
                             spsi, an, bn, k1)
        strips[Strip.gap, i] = edge - g
        strips[Strip.radius, i] = R
        if i == 0:
            Y_first = Y
        Y_last = Y
    return ua, fa, ub, fb, jm + t, abs(Y_last - Y_first)
