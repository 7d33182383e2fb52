"""Wheel-rail forces of one wheel from the wheelset's pose and velocities (numba core).

For each interpenetration patch found by `geometry.find_patches`:
  - normal: the normal approach d = -gap cos(delta) (delta the contact angle); equivalent-elliptic Hertz
    N = C d^1.5 from the patch's principal relative curvatures (`hertz.hertz_shape`), or the discrete
    non-elliptic Kik-Piotrowski patch from the gap along the patch (`kik_piotrowski`); Hunt-Crossley
    damping multiplies the elastic force by (1 + chi d'), and N >= 0 (no adhesion);
  - creepages from the velocity of the wheel material point at the contact (translation, rotation and
    spin of the wheelset, the rail being fixed): longitudinal and lateral along the contact plane,
    spin about the contact normal, each divided by the forward speed;
  - creep forces by the selected law (`creep.creep_forces`) on the Hertz ellipse (or the discrete
    patch's equivalent ellipse).
The force and its moment about the wheelset centre are returned in the wheelset's track axes.

Only the left wheel is written out; `wheel_forces` mirrors the pose for the right wheel.
"""
import math

from ..jit import core, core_inline
from . import geometry as geo
from .creep import creep_forces
from .hertz import hertz_shape
from . import kik_piotrowski as kp
from . import table as tab

# Contact parameter array cp
C_ESTAR, C_G, C_NU, C_MU, C_CHI, C_NORMAL, C_CREEP = 0, 1, 2, 3, 4, 5, 6
C_QP_MIN_LOAD = 7     # vertical load below which Q/P is not evaluated (N): an unloaded wheel's ratio means nothing
C_ESTAR_CBRT = 8      # E*^(1/3): scales the contact table's Hertz shape (given at E* = 1 Pa)
C_SIZE = 9
NORMAL_HERTZ, NORMAL_DISCRETE = 0, 1
KP_MIN_STRIPS = 24    # strips across a Kik-Piotrowski patch at least (a flange patch spans 4-6 grid points)

# Per-wheel output record
W_LIFT = 0            # wheel lift hp (m)
W_Q = 1               # lateral force on the rail, + toward the rail's field side (N)
W_P = 2               # vertical force on the rail, + down (N)
W_FX = 3              # longitudinal force on the rail (N)
W_QP = 4              # derailment coefficient Q/P (0 when the load is below C_QP_MIN_LOAD)
W_CPOS = 5            # main patch: lateral position on the rail from the head axis, + field side (m)
W_CANGLE = 6          # main patch contact angle (rad)
W_LEN = 7             # main patch length 2a (m)
W_WID = 8             # main patch width 2b (m)
W_COUNT = 9           # number of patches
W_GAP = 10            # smallest wheel-rail gap (m, negative when in contact)
W_PATCH0 = 11         # per patch: lateral position, lead x, length, width, normal force, contact angle
W_PATCH_COLS = 6
W_SIZE = W_PATCH0 + geo.MAX_PATCHES * W_PATCH_COLS


@core
def left_wheel(cg, cp, y, z, phi, psi, vx0, vy0, vz0, ox, oy, oz, spin, speed, gap, ys, patches, cand, tracked,
               kpbuf, kpid, kprow, rec):
    """Contact forces of the left wheel of a wheelset.

    y, z, phi, psi: pose relative to the rails (m, rad); vx0, vy0, vz0: absolute velocity of the wheelset
    centre, ox, oy, oz: its absolute angular velocity without spin (track axes); spin: rolling angular
    speed (rad/s) about the axle; speed: forward speed for the creepages (m/s). Returns the force on the
    wheel and its moment about the wheelset centre, (Fx, Fy, Fz, Mx, My, Mz) in track axes (scalars, not
    arrays: this runs 48 times per time step); fills the output record `rec` on full searches.
    The patches come from the contact table when cg carries one and the pose is inside it
    (`contact.table`); otherwise from the exact search: `tracked` then follows the minima listed in `cand`
    by the last full search (inside a time step) instead of searching the whole profile
    (`geometry.track_patches`).
    """
    count, gmin = tab.table_patches(cg, y, z, phi, psi, patches, cand)
    if count < 0:                       # no table, or the pose is outside it: exact online search
        if tracked:
            count = geo.track_patches(cg, y, z, phi, psi, gap, ys, patches, cand)
            gmin = 0.0
            for k in range(count):
                gmin = min(gmin, patches[k, geo.P_GAP])
        else:
            count, gmin = geo.find_patches(cg, y, z, phi, psi, gap, ys, patches, cand)
    r0 = cg[geo.H_R0]
    cphi = math.cos(phi)
    sphi = math.sin(phi)
    cpsi = math.cos(psi)
    spsi = math.sin(psi)
    # axle direction (track axes) and total angular velocity of the wheel
    ax_x = -spsi * cphi
    ax_y = cpsi * cphi
    ax_z = sphi
    wx = ox + spin * ax_x
    wy = oy + spin * ax_y
    wz = oz + spin * ax_z
    estar = cp[C_ESTAR]
    shear = cp[C_G]
    nu = cp[C_NU]
    mu = cp[C_MU]
    chi = cp[C_CHI]
    model = int(cp[C_CREEP])
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
        rec[W_LIFT] = geo.wheel_lift(cg, z, phi)
        rec[W_GAP] = gmin
        rec[W_COUNT] = count
    for k in range(count):
        patches[k, geo.P_NORMAL] = 0.0
        slope = patches[k, geo.P_SLOPE]
        cd = 1.0 / math.sqrt(1.0 + slope * slope)
        sd = slope * cd
        d = -patches[k, geo.P_GAP] * cd
        if d <= 0.0:
            continue
        # contact frame: normal n (rail into wheel), lateral tangent t, longitudinal e_x
        nY, nZ = -sd, cd
        tY, tZ = cd, sd
        rx = patches[k, geo.P_X]
        ry = patches[k, geo.P_Y] - y
        rz = patches[k, geo.P_Z] - (r0 + z)
        # velocity of the wheel material point at the contact
        vx = vx0 + wy * rz - wz * ry
        vy = vy0 + wz * rx - wx * rz
        vz = vz0 + wx * ry - wy * rx
        approach_rate = -(vy * nY + vz * nZ)
        discrete = int(cp[C_NORMAL]) == NORMAL_DISCRETE
        if discrete:
            n_el, a, b, a_eq, b_eq = _discrete_normal(cg, y, z, phi, psi, int(patches[k, geo.P_JM]),
                                                      patches[k, geo.P_GAP], cd, gap, ys, kpbuf, kpid,
                                                      kprow, cp[C_ESTAR], nu)
        if not discrete or record:
            if patches[k, geo.P_HERTZ_C1 + 2] > 0.0:     # from the contact table, at E* = 1 Pa
                ac = patches[k, geo.P_HERTZ_C1] / cp[C_ESTAR_CBRT]
                bc = patches[k, geo.P_HERTZ_C1 + 1] / cp[C_ESTAR_CBRT]
                stiff = patches[k, geo.P_HERTZ_C1 + 2] * estar
            else:
                ac, bc, stiff = hertz_shape(patches[k, geo.P_A], patches[k, geo.P_B], estar)
        if not discrete:
            # a part of a wider contact carries its share only (geometry._set_weights)
            n_el = patches[k, geo.P_WEIGHT] * stiff * d * math.sqrt(d)
            cube_root = n_el ** (1.0 / 3.0)
            a = ac * cube_root
            b = bc * cube_root
            a_eq = a
            b_eq = b
        # Hunt-Crossley damping scales the load; the patch is the elastic one
        normal = n_el * (1.0 + chi * approach_rate)
        if normal <= 0.0:
            continue
        xi_x = vx / speed
        xi_y = (vy * tY + vz * tZ) / speed
        phi_s = (wy * nY + wz * nZ) / speed
        fx, ft, mz = creep_forces(model, xi_x, xi_y, phi_s, a_eq, b_eq, normal, mu, shear, nu)
        if record:
            row = patches[k]
            row[geo.P_NORMAL] = normal
            row[geo.P_APPROACH] = d
            row[geo.P_HALF_LENGTH] = a
            row[geo.P_HALF_WIDTH] = b
            row[geo.P_AEQ] = a_eq
            row[geo.P_BEQ] = b_eq
            cube_root = normal ** (1.0 / 3.0)
            row[geo.P_HERTZ_A] = ac * cube_root
            row[geo.P_HERTZ_B] = bc * cube_root
            row[geo.P_XI_X] = xi_x
            row[geo.P_XI_Y] = xi_y
            row[geo.P_SPIN] = phi_s
            row[geo.P_FX] = fx
            row[geo.P_FT] = ft
            row[geo.P_MZ] = mz
        Fx = fx
        Fy = normal * nY + ft * tY
        Fz = normal * nZ + ft * tZ
        # moment of the force about the wheelset centre, plus the spin moment about the normal
        mx_tot += ry * Fz - rz * Fy
        my_tot += rz * Fx - rx * Fz + mz * nY
        mz_tot += rx * Fy - ry * Fx + mz * nZ
        fx_tot += Fx
        fy_tot += Fy
        fz_tot += Fz
        if record:
            o = W_PATCH0 + k * W_PATCH_COLS
            rec[o] = patches[k, geo.P_Y] - cg[geo.H_RAIL_AXIS_Y]
            rec[o + 1] = rx
            rec[o + 2] = 2.0 * a
            rec[o + 3] = 2.0 * b
            rec[o + 4] = normal
            rec[o + 5] = math.atan(slope)
            if normal > nmax:           # the main patch: the most loaded one
                nmax = normal
                rec[W_CPOS] = rec[o]
                rec[W_CANGLE] = rec[o + 5]
                rec[W_LEN] = rec[o + 2]
                rec[W_WID] = rec[o + 3]
    if not record:
        return fx_tot, fy_tot, fz_tot, mx_tot, my_tot, mz_tot
    # forces on the rail: Q toward the left rail's field side (+Y), P downward
    rec[W_Q] = -fy_tot
    rec[W_P] = fz_tot
    rec[W_FX] = -fx_tot
    rec[W_QP] = rec[W_Q] / rec[W_P] if rec[W_P] > cp[C_QP_MIN_LOAD] else 0.0
    return fx_tot, fy_tot, fz_tot, mx_tot, my_tot, mz_tot


@core
def _discrete_normal(cg, y, z, phi, psi, jm, gmin, cos_angle, gap, ys, kpbuf, kpid, kprow, estar, nu):
    """Kik-Piotrowski normal load of one patch from the gap along its extent.

    The patch's extent on the wheel grid (`geometry.run_bounds`, one step wider on each side) is sampled
    at no fewer than KP_MIN_STRIPS points along the trace line (a flange patch spans only a few grid
    points); the vertical gap is turned into the normal separation (times cos of the contact angle) on the
    lateral tangent coordinate (Y / cos), assuming a locally plane contact; the wheel's longitudinal radius
    in the contact plane is r sqrt(1 + r'^2). Returns (N, a, b, a_eq, b_eq): half the patch's length and
    width, and the semi-axes of its equivalent ellipse for the creep forces.
    """
    ja, jb = geo.run_bounds(cg, y, z, phi, psi, jm, gap, ys)
    dw = cg[geo.H_DW]
    yp0 = cg[geo.H_WY0] + (ja - 1) * dw
    yp1 = cg[geo.H_WY0] + (jb + 1) * dw
    n = max(jb - ja + 3, KP_MIN_STRIPS)
    n = min(n, kpbuf.shape[1])
    pose = geo.pose_constants(cg, y, z, phi, psi)
    y_first = 0.0
    y_last = 0.0
    for i in range(n):
        yp = yp0 + (yp1 - yp0) * i / (n - 1)
        X, Y, Z, r, sw, kw = geo._trace_point(cg, pose, yp)
        zr, _ = geo.rail_height(cg, Y)
        kpbuf[1, i] = (Z - zr - gmin) * cos_angle
        kpbuf[2, i] = r * math.sqrt(1.0 + sw * sw)
        if i == 0:
            y_first = Y
        y_last = Y
    ds = abs(y_last - y_first) / ((n - 1) * cos_angle)
    for i in range(n):
        kpbuf[0, i] = i * ds
        if kpbuf[1, i] < 0.0:
            kpbuf[1, i] = 0.0
    # E from E* for identical materials (E* = E / (2 (1 - nu^2)))
    E = estar * 2.0 * (1.0 - nu * nu)
    count = kp.kp_normal(kpbuf[0, :n], kpbuf[1, :n], kpbuf[2, :n], -gmin * cos_angle, E, nu, kp.EPS_DEFAULT,
                         kpbuf[3, :n], kpid[:n], kprow)
    if count == 0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    return (kprow[0, kp.P_N], 0.5 * kprow[0, kp.P_LENGTH], 0.5 * kprow[0, kp.P_WIDTH], kprow[0, kp.P_AEQ],
            kprow[0, kp.P_BEQ])


@core_inline
def wheel_forces(cg, cp, side, y, z, phi, psi, vx, vy, vz, ox, oy, oz, spin, speed, gap, ys, patches, cand,
                 tracked, kpbuf, kpid, kprow, rec):
    """Contact force and moment of wheel `side` (0 left, 1 right): (Fx, Fy, Fz, Mx, My, Mz), track axes.

    The right wheel is the left wheel of the wheelset mirrored in the x-z plane: y, phi, psi, the lateral
    velocity and the x and z angular velocities change sign; the resulting lateral force and the x and z
    moments change sign back.
    """
    if side == 0:
        return left_wheel(cg, cp, y, z, phi, psi, vx, vy, vz, ox, oy, oz, spin, speed, gap, ys, patches, cand,
                          tracked, kpbuf, kpid, kprow, rec)
    fx, fy, fz, mx, my, mz = left_wheel(cg, cp, -y, z, -phi, -psi, vx, -vy, vz, -ox, oy, -oz, spin, speed, gap, ys,
                                        patches, cand, tracked, kpbuf, kpid, kprow, rec)
    return fx, -fy, fz, -mx, my, -mz
