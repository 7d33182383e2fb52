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
from .hertz import hertz_shape
from . import kik_piotrowski as kp
from .kik_piotrowski import DiscretePatch
from . import table as tab
from .layout import (MAX_PATCHES, P_COLS, WP_SIZE, Candidates, ContactConstants, GeometryHeader, HertzShape, Patch,
                     Wheel, WheelPatch)

NORMAL_HERTZ, NORMAL_DISCRETE = 0, 1
SMALL_ANGLE = 0.05    # rad; `sin_cos` by its Taylor polynomials up to here (within an ulp of libm's), libm beyond
KP_MIN_STRIPS = 24    # strips across a Kik-Piotrowski patch at least (a flange patch spans 4-6 grid points)




class Strip(Record):
    """Rows of the discrete (Kik-Piotrowski) patch's strip buffer `ContactScratch.kpbuf`."""
    lateral = "m", "lateral tangent coordinate of the strip"
    gap = "m", "normal separation from the deepest point"
    radius = "m", "the wheel's longitudinal radius in the contact plane"
    half_length = "m", "strip half-length x_L (kik_piotrowski.kp_normal's output)"


# buffers of one wheel's contact evaluation (allocated by `contact_scratch`): gap and trace-point Y on the
# wheel grid, the patch rows, the discrete patch's strips, strip patch ids and its patch row
ContactScratch = namedtuple("ContactScratch", "gap ys patches kpbuf kpid kprow")


def contact_scratch(cg):
    """Buffers of `wheel_forces` for the packed geometry cg."""
    nw = int(cg[GeometryHeader.wheel_points])
    return ContactScratch(gap=np.zeros(nw), ys=np.zeros(nw), patches=np.zeros((MAX_PATCHES, P_COLS)),
                          kpbuf=np.zeros((Strip.size(), nw)), kpid=np.zeros(nw, dtype=np.int64),
                          kprow=np.zeros((1, DiscretePatch.size())))


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

    The patch's extent on the wheel grid (`geometry.run_bounds`, one step wider on each side) is sampled
    at no fewer than KP_MIN_STRIPS points along the trace line (a flange patch spans only a few grid
    points); the vertical gap is turned into the normal separation (times cos of the contact angle) on the
    lateral tangent coordinate (Y / cos), assuming a locally plane contact; the wheel's longitudinal radius
    in the contact plane is r sqrt(1 + r'^2). Returns (N, a, b, a_eq, b_eq): half the patch's length and
    width, and the semi-axes of its equivalent ellipse for the creep forces.
    """
    y, z, phi, psi = pose
    kpbuf, kprow = scratch.kpbuf, scratch.kprow
    ja, jb = geo.run_bounds(cg, y, z, phi, psi, jm, scratch.gap, scratch.ys)
    dw = cg[GeometryHeader.wheel_step]
    yp0 = cg[GeometryHeader.wheel_y0] + (ja - 1) * dw
    yp1 = cg[GeometryHeader.wheel_y0] + (jb + 1) * dw
    n = max(jb - ja + 3, KP_MIN_STRIPS)
    n = min(n, kpbuf.shape[1])
    trace = geo.pose_constants(cg, y, z, phi, psi)
    y_first = 0.0
    y_last = 0.0
    for i in range(n):
        yp = yp0 + (yp1 - yp0) * i / (n - 1)
        X, Y, Z, r, sw, kw = geo._trace_point(cg, trace, yp)
        zr, _ = geo.rail_height(cg, Y)
        kpbuf[Strip.gap, i] = (Z - zr - gmin) * cos_angle
        kpbuf[Strip.radius, i] = r * math.sqrt(1.0 + sw * sw)
        if i == 0:
            y_first = Y
        y_last = Y
    ds = abs(y_last - y_first) / ((n - 1) * cos_angle)
    for i in range(n):
        kpbuf[Strip.lateral, i] = i * ds
        if kpbuf[Strip.gap, i] < 0.0:
            kpbuf[Strip.gap, i] = 0.0
    count = kp.kp_normal(kpbuf[Strip.lateral, :n], kpbuf[Strip.gap, :n], kpbuf[Strip.radius, :n], -gmin * cos_angle,
                         youngs, nu, kp.EPS_DEFAULT, kpbuf[Strip.half_length, :n], scratch.kpid[:n], kprow)
    if count == 0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    row = kprow[0]
    return (row[DiscretePatch.normal_force], 0.5 * row[DiscretePatch.length], 0.5 * row[DiscretePatch.width],
            row[DiscretePatch.a_eq], row[DiscretePatch.b_eq])
