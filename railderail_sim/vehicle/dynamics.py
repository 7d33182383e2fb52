"""Equations of motion of the car on the track (numba core): rhs(x) -> dx/dt.

Formulation (details and assumptions in docs/vehicle-model.md):
- Each body moves relative to the track frame at its own station s_b = s + xi_b (moving-trihedron
  formulation): lateral y, vertical z, roll, pitch, yaw. Rotation matrices are exact; the map from
  relative angle rates to angular velocity is linearised (relative angles stay below ~0.1 rad).
- Velocity states are absolute (inertial) velocities expressed in the rotating track axes, so the kinks of
  the alignment (curvature rate and cant rate jump at the ends of the transitions) enter only the
  kinematic relations and never as impulses:
      dV/dt = F/m + g_T - omega_T x V,      I domega/dt = M - omega x I omega - gyroscopic spin term,
  and for each wheelset its spin about the axle, driven by the contact forces' moment about the axle
  (so that each wheelset rolls freely: no net longitudinal creep force but the one that steers it),
      dy/dt = V_y + omega_T,x (h + z),  dz/dt = V_z - omega_T,x y,  d(angle)/dt = omega - omega_T,
  with omega_T = (v dcant/ds, v kappa sin(cant), v kappa cos(cant)) the track frame's angular velocity.
- Suspension forces come from the ground-frame positions and velocities of the attachment points (each
  body placed with its own station's track frame), so curving offsets between bodies (versines, relative
  yaw), large body roll and cant changes along the car are exact.
- Wheel-rail forces from `contact.wheelset` at each wheelset's pose relative to the rails (including the
  optional lateral alignment defect).
"""
import math

from ..jit import core
from ..contact import wheelset as ws
from ..track import alignment as trk
from . import layout as L


@core
def speed_at(sp, s):
    """Forward speed v (m/s) and dv/ds at s from the piecewise-linear speed table sp[:, (s, v)]."""
    n = sp.shape[0]
    if s <= sp[0, 0]:
        return sp[0, 1], 0.0
    if s >= sp[n - 1, 0]:
        return sp[n - 1, 1], 0.0
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if sp[mid, 0] <= s:
            lo = mid
        else:
            hi = mid
    ds = sp[hi, 0] - sp[lo, 0]
    slope = (sp[hi, 1] - sp[lo, 1]) / ds
    return sp[lo, 1] + slope * (s - sp[lo, 0]), slope


@core
def _track_rotation(out, o, heading, roll):
    """out[o:o+9] = Rz(heading) Rx(roll), row-major: ground <- track axes."""
    ch, sh = math.cos(heading), math.sin(heading)
    cr, sr = math.cos(roll), math.sin(roll)
    out[o + 0] = ch
    out[o + 1] = -sh * cr
    out[o + 2] = sh * sr
    out[o + 3] = sh
    out[o + 4] = ch * cr
    out[o + 5] = -ch * sr
    out[o + 6] = 0.0
    out[o + 7] = sr
    out[o + 8] = cr


@core
def _compose(out, o, ot, yaw, pitch, rel_roll):
    """out[o:o+9] = out[ot:ot+9] Rz(yaw) Ry(pitch) Rx(rel_roll) (the track rotation already in place)."""
    cy, sy = math.cos(yaw), math.sin(yaw)
    cp, spt = math.cos(pitch), math.sin(pitch)
    cx, sx = math.cos(rel_roll), math.sin(rel_roll)
    q00 = cy * cp
    q01 = cy * spt * sx - sy * cx
    q02 = cy * spt * cx + sy * sx
    q10 = sy * cp
    q11 = sy * spt * sx + cy * cx
    q12 = sy * spt * cx - cy * sx
    q20 = -spt
    q21 = cp * sx
    q22 = cp * cx
    for r in range(3):
        t0 = out[ot + 3 * r]
        t1 = out[ot + 3 * r + 1]
        t2 = out[ot + 3 * r + 2]
        out[o + 3 * r] = t0 * q00 + t1 * q10 + t2 * q20
        out[o + 3 * r + 1] = t0 * q01 + t1 * q11 + t2 * q21
        out[o + 3 * r + 2] = t0 * q02 + t1 * q12 + t2 * q22


# columns of the per-body kinematics scratch array
K_P = 0          # ground position of the reference point (3)
K_R = 3          # body rotation matrix, ground <- body (9)
K_V = 12         # ground velocity of the reference point (3)
K_W = 15         # ground angular velocity (3)
K_RT = 18        # track rotation matrix, ground <- track (9)
K_WT = 27        # track-frame angular velocity in track axes (3)
K_VT = 30        # absolute velocity in track axes (3)
K_F = 33         # force accumulator, ground axes (3)
K_M = 36         # moment accumulator about the reference point, ground axes (3)
K_COLS = 39


@core
def _point(kin, b, p0, p1, p2):
    """Ground position, ground velocity and ground-axes arm of a body-fixed point."""
    R = kin[b, K_R:K_R + 9]
    ax = R[0] * p0 + R[1] * p1 + R[2] * p2
    ay = R[3] * p0 + R[4] * p1 + R[5] * p2
    az = R[6] * p0 + R[7] * p1 + R[8] * p2
    w = kin[b, K_W:K_W + 3]
    px = kin[b, K_P] + ax
    py = kin[b, K_P + 1] + ay
    pz = kin[b, K_P + 2] + az
    vx = kin[b, K_V] + w[1] * az - w[2] * ay
    vy = kin[b, K_V + 1] + w[2] * ax - w[0] * az
    vz = kin[b, K_V + 2] + w[0] * ay - w[1] * ax
    return px, py, pz, vx, vy, vz, ax, ay, az


@core
def _apply(kin, b, fx, fy, fz, ax, ay, az):
    """Add a ground-axes force acting at arm (ax, ay, az) from body b's reference point."""
    kin[b, K_F] += fx
    kin[b, K_F + 1] += fy
    kin[b, K_F + 2] += fz
    kin[b, K_M] += ay * fz - az * fy
    kin[b, K_M + 1] += az * fx - ax * fz
    kin[b, K_M + 2] += ax * fy - ay * fx


@core
def _to_body_axes(kin, a, dx, dy, dz):
    R = kin[a, K_R:K_R + 9]
    return (R[0] * dx + R[3] * dy + R[6] * dz, R[1] * dx + R[4] * dy + R[7] * dz,
            R[2] * dx + R[5] * dy + R[8] * dz)


@core
def _to_ground(kin, a, lx, ly, lz):
    R = kin[a, K_R:K_R + 9]
    return (R[0] * lx + R[1] * ly + R[2] * lz, R[3] * lx + R[4] * ly + R[5] * lz,
            R[6] * lx + R[7] * ly + R[8] * lz)


@core
def damper_force(v, knee, c1, c2):
    """Two-stage (blow-off) damper force (N) at elongation rate v (m/s)."""
    av = abs(v)
    if av <= knee:
        return c1 * v
    f = c1 * knee + c2 * (av - knee)
    return f if v > 0.0 else -f


@core
def damper_rate(f, knee, c1, c2):
    """Inverse of damper_force: elongation rate (m/s) of the damper carrying force f (N)."""
    fk = c1 * knee
    af = abs(f)
    if af <= fk:
        return f / c1
    v = knee + (af - fk) / c2
    return v if f > 0.0 else -v


@core
def bump_force(vp, u):
    """Bump-stop force magnitude (N) at lateral deflection magnitude u (m)."""
    clear = vp[L.V_BUMP_CLEARANCE]
    if u <= clear:
        return 0.0
    n = int(vp[L.V_BUMP_N])
    u0 = clear
    f0 = 0.0
    for i in range(n):
        u1 = vp[L.V_BUMP_TRAVEL + i]
        f1 = vp[L.V_BUMP_FORCE + i]
        if u <= u1 or i == n - 1:
            return f0 + (f1 - f0) * (u - u0) / (u1 - u0)
        u0 = u1
        f0 = f1
    return f0


@core
def kinematics(x, bodies, track, sp, kin):
    """Fill the per-body kinematics scratch array; returns (v, dv/ds)."""
    s = x[L.I_S]
    v, dvds = speed_at(sp, s)
    for b in range(L.N_BODY):
        o = L.N_DOF * b
        ov = L.I_VEL + o
        sb = s + bodies[b, L.B_STATION]
        X, Y, heading, roll = trk.frame(track, sb)
        kap, _ = trk.curvature(track, sb)
        _, droll = trk.cant(track, sb)
        y = x[o]
        z = x[o + 1]
        h = bodies[b, L.B_HEIGHT] + z
        wtx = v * droll
        wty = v * kap * math.sin(roll)
        wtz = v * kap * math.cos(roll)
        kin[b, K_WT] = wtx
        kin[b, K_WT + 1] = wty
        kin[b, K_WT + 2] = wtz
        _track_rotation(kin[b], K_RT, heading, roll)
        _compose(kin[b], K_R, K_RT, x[o + 4], x[o + 3], x[o + 2])
        RT = kin[b, K_RT:K_RT + 9]
        kin[b, K_P] = X + RT[1] * y + RT[2] * h
        kin[b, K_P + 1] = Y + RT[4] * y + RT[5] * h
        kin[b, K_P + 2] = RT[7] * y + RT[8] * h
        # absolute velocity in track axes; V_x keeps the body at its station
        vtx = v + wty * h - wtz * y
        vty = x[ov]
        vtz = x[ov + 1]
        kin[b, K_VT] = vtx
        kin[b, K_VT + 1] = vty
        kin[b, K_VT + 2] = vtz
        kin[b, K_V] = RT[0] * vtx + RT[1] * vty + RT[2] * vtz
        kin[b, K_V + 1] = RT[3] * vtx + RT[4] * vty + RT[5] * vtz
        kin[b, K_V + 2] = RT[6] * vtx + RT[7] * vty + RT[8] * vtz
        wx = x[ov + 2]
        wy = wty if bodies[b, L.B_WHEELSET] > 0.5 else x[ov + 3]
        wz = x[ov + 4]
        kin[b, K_W] = RT[0] * wx + RT[1] * wy + RT[2] * wz
        kin[b, K_W + 1] = RT[3] * wx + RT[4] * wy + RT[5] * wz
        kin[b, K_W + 2] = RT[6] * wx + RT[7] * wy + RT[8] * wz
        for k in range(6):
            kin[b, K_F + k] = 0.0
    return v, dvds


@core
def suspension(x, dx, vp, bush, damp, bump, arb, kin):
    """Add all suspension forces to the kinematics accumulators; damper state rates into dx."""
    for e in range(bush.shape[0]):
        a = int(bush[e, L.E_A])
        b = int(bush[e, L.E_B])
        pax, pay, paz, vax, vay, vaz, aax, aay, aaz = _point(kin, a, bush[e, L.E_PA], bush[e, L.E_PA + 1],
                                                             bush[e, L.E_PA + 2])
        pbx, pby, pbz, vbx, vby, vbz, abx, aby, abz = _point(kin, b, bush[e, L.E_PB], bush[e, L.E_PB + 1],
                                                             bush[e, L.E_PB + 2])
        dlx, dly, dlz = _to_body_axes(kin, a, pbx - pax, pby - pay, pbz - paz)
        ddx, ddy, ddz = _to_body_axes(kin, a, vbx - vax, vby - vay, vbz - vaz)
        fx = bush[e, L.E_F0] - bush[e, L.E_K] * dlx - bush[e, L.E_C] * ddx
        fy = bush[e, L.E_F0 + 1] - bush[e, L.E_K + 1] * dly - bush[e, L.E_C + 1] * ddy
        fz = bush[e, L.E_F0 + 2] - bush[e, L.E_K + 2] * dlz - bush[e, L.E_C + 2] * ddz
        gx, gy, gz = _to_ground(kin, a, fx, fy, fz)
        _apply(kin, b, gx, gy, gz, abx, aby, abz)
        _apply(kin, a, -gx, -gy, -gz, aax, aay, aaz)
    for e in range(damp.shape[0]):
        a = int(damp[e, L.D_A])
        b = int(damp[e, L.D_B])
        pax, pay, paz, vax, vay, vaz, aax, aay, aaz = _point(kin, a, damp[e, L.D_PA], damp[e, L.D_PA + 1],
                                                             damp[e, L.D_PA + 2])
        pbx, pby, pbz, vbx, vby, vbz, abx, aby, abz = _point(kin, b, damp[e, L.D_PB], damp[e, L.D_PB + 1],
                                                             damp[e, L.D_PB + 2])
        dxl = pbx - pax
        dyl = pby - pay
        dzl = pbz - paz
        length = math.sqrt(dxl * dxl + dyl * dyl + dzl * dzl)
        ex = dxl / length
        ey = dyl / length
        ez = dzl / length
        knee = damp[e, L.D_KNEE]
        c1 = damp[e, L.D_C1]
        c2 = damp[e, L.D_C2]
        ks = damp[e, L.D_KS]
        si = int(damp[e, L.D_STATE])
        if ks > 0.0:
            f = ks * (length - damp[e, L.D_L0] - x[si])
            dx[si] = damper_rate(f, knee, c1, c2)
        else:
            rate = ex * (vbx - vax) + ey * (vby - vay) + ez * (vbz - vaz)
            f = damper_force(rate, knee, c1, c2)
            dx[si] = 0.0
        _apply(kin, b, -f * ex, -f * ey, -f * ez, abx, aby, abz)
        _apply(kin, a, f * ex, f * ey, f * ez, aax, aay, aaz)
    for e in range(bump.shape[0]):
        a = int(bump[e, L.S_A])
        b = int(bump[e, L.S_B])
        pax, pay, paz, _, _, _, aax, aay, aaz = _point(kin, a, bump[e, L.S_PA], bump[e, L.S_PA + 1],
                                                      bump[e, L.S_PA + 2])
        pbx, pby, pbz, _, _, _, abx, aby, abz = _point(kin, b, bump[e, L.S_PB], bump[e, L.S_PB + 1],
                                                      bump[e, L.S_PB + 2])
        _, dly, _ = _to_body_axes(kin, a, pbx - pax, pby - pay, pbz - paz)
        f = bump_force(vp, abs(dly))
        if f > 0.0:
            fy = -f if dly > 0.0 else f
            gx, gy, gz = _to_ground(kin, a, 0.0, fy, 0.0)
            _apply(kin, b, gx, gy, gz, abx, aby, abz)
            _apply(kin, a, -gx, -gy, -gz, aax, aay, aaz)
    for e in range(arb.shape[0]):
        a = int(arb[e, L.R_A])
        b = int(arb[e, L.R_B])
        Ra = kin[a, K_R:K_R + 9]
        Rb = kin[b, K_R:K_R + 9]
        # relative rotation Ra^T Rb: roll angle from its antisymmetric (2,1) - (1,2) part
        r21 = Ra[2] * Rb[1] + Ra[5] * Rb[4] + Ra[8] * Rb[7]
        r12 = Ra[1] * Rb[2] + Ra[4] * Rb[5] + Ra[7] * Rb[8]
        ang = 0.5 * (r21 - r12)
        mx, my, mz = _to_ground(kin, a, -arb[e, L.R_K] * ang, 0.0, 0.0)
        kin[b, K_M] += mx
        kin[b, K_M + 1] += my
        kin[b, K_M + 2] += mz
        kin[a, K_M] -= mx
        kin[a, K_M + 1] -= my
        kin[a, K_M + 2] -= mz


@core
def rhs(x, dx, bodies, vp, bush, damp, bump, arb, track, sp, cg, cp, kin, gap, ys, patches, cands, tracked,
        kpbuf, kpid, kprow, recs):
    """dx = f(x). Wheel records of the 8 wheels are left in recs (8 x W_SIZE).

    cands (8 x (1 + MAX_CANDIDATES)): contact minima per wheel, written by a full search (tracked False)
    and followed by the cheap local search when `tracked` (the later stages of one RK4 step).
    """
    v, dvds = kinematics(x, bodies, track, sp, kin)
    suspension(x, dx, vp, bush, damp, bump, arb, kin)
    g = vp[L.V_G]
    r0 = vp[L.V_R0]
    spin_i = vp[L.V_SPIN_INERTIA]
    # the motors/brakes supply the torque that keeps the wheels turning with the prescribed acceleration
    traction = spin_i * v * dvds / r0
    s = x[L.I_S]
    for b in range(L.N_BODY):
        o = L.N_DOF * b
        ov = L.I_VEL + o
        RT = kin[b, K_RT:K_RT + 9]
        F = kin[b, K_F:K_F + 3]
        M = kin[b, K_M:K_M + 3]
        # ground -> track axes
        fx = RT[0] * F[0] + RT[3] * F[1] + RT[6] * F[2]
        fy = RT[1] * F[0] + RT[4] * F[1] + RT[7] * F[2]
        fz = RT[2] * F[0] + RT[5] * F[1] + RT[8] * F[2]
        mx = RT[0] * M[0] + RT[3] * M[1] + RT[6] * M[2]
        my = RT[1] * M[0] + RT[4] * M[1] + RT[7] * M[2]
        mz = RT[2] * M[0] + RT[5] * M[1] + RT[8] * M[2]
        wtx = kin[b, K_WT]
        wty = kin[b, K_WT + 1]
        wtz = kin[b, K_WT + 2]
        vtx = kin[b, K_VT]
        vty = kin[b, K_VT + 1]
        vtz = kin[b, K_VT + 2]
        wx = x[ov + 2]
        wz = x[ov + 4]
        is_ws = bodies[b, L.B_WHEELSET] > 0.5
        wy = wty if is_ws else x[ov + 3]
        spin = x[ov + 3]                          # wheelsets: spin about the axle (rad/s)
        # wheel-rail force and moment of both wheels of a wheelset (track axes, about its centre)
        cx = cy = cz = cmx = cmy = cmz = 0.0
        if is_ws:
            yd, dyd = trk.lateral_defect(track, s + bodies[b, L.B_STATION])
            wheel = b - L.WHEELSETS[0]
            for side in range(2):
                f0, f1, f2, m0, m1, m2 = ws.wheel_forces(
                    cg, cp, side, x[o] - yd, x[o + 1], x[o + 2], x[o + 4] - dyd, vtx, vty, vtz, wx, wy, wz, spin,
                    v, gap, ys, patches, cands[2 * wheel + side], tracked, kpbuf, kpid, kprow,
                    recs[2 * wheel + side])
                cx += f0
                cy += f1
                cz += f2
                cmx += m0
                cmy += m1
                cmz += m2
            fx += cx
            fy += cy
            fz += cz
            mx += cmx
            my += cmy
            mz += cmz
        m = bodies[b, L.B_MASS]
        ix = bodies[b, L.B_IX]
        iy = bodies[b, L.B_IY]
        iz = bodies[b, L.B_IZ]
        roll_t = math.atan2(RT[7], RT[8])
        # translation: dV/dt = F/m + g_T - omega_T x V
        dx[ov] = fy / m - g * math.sin(roll_t) - (wtz * vtx - wtx * vtz)
        dx[ov + 1] = fz / m - g * math.cos(roll_t) - (wtx * vty - wty * vtx)
        # rotation: I dw/dt = M - w x (I w) - spin gyroscopic term
        gx = (iz - iy) * wy * wz
        gy = (ix - iz) * wz * wx
        gz = (iy - ix) * wx * wy
        if is_ws:
            cphi = math.cos(x[o + 2])
            ax_x = -math.sin(x[o + 4]) * cphi
            ax_y = math.cos(x[o + 4]) * cphi
            ax_z = math.sin(x[o + 2])
            hs = spin_i * spin
            gx += hs * (wy * ax_z - wz * ax_y)
            gz += hs * (wx * ax_y - wy * ax_x)
            # spin: the contact forces' moment about the axle (the axle boxes do not turn with the wheels)
            dx[ov + 3] = ((cmx * ax_x + cmy * ax_y + cmz * ax_z) + traction) / spin_i
        else:
            dx[ov + 3] = (my - gy) / iy
        dx[ov + 2] = (mx - gx) / ix
        dx[ov + 4] = (mz - gz) / iz
        # kinematics of the relative coordinates
        h = bodies[b, L.B_HEIGHT] + x[o + 1]
        dx[o] = vty + wtx * h
        dx[o + 1] = vtz - wtx * x[o]
        dx[o + 2] = wx - wtx
        dx[o + 3] = 0.0 if is_ws else x[ov + 3] - wty
        dx[o + 4] = wz - wtz
    dx[L.I_S] = v
    return v

