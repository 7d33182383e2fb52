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
- Low speeds: the spin's own mode is real, its rate proportional to the longitudinal creep stiffness over
  I_spin v (the creepages are normalised by v), so below about 100 km/h it, not the wheelsets' bounce, would
  set the explicit step (0.98 ms at 50 km/h against 1.8-2.4 ms; docs/performance.md). Below SPIN_HELD_SPEED
  the spin's equation takes its inertia as I_spin SPIN_HELD_SPEED / v, which holds that mode at its rate of
  SPIN_HELD_SPEED; the traction torque takes the same inertia, so the spin's steady rolling and the creep
  forces it leaves are unchanged, only its relaxation (under a millisecond) is slower. The gyroscopic
  term keeps the true angular momentum. Above SPIN_HELD_SPEED nothing changes.
- Wheel-rail forces from `contact.wheelset` at each wheelset's pose relative to the rails (including the
  optional lateral alignment defect).
"""
from collections import namedtuple
import math

from ..jit import core
from ..contact import wheelset as ws
from ..loads.aerodynamics import aerodynamic_load
from ..record import Record
from ..track import alignment as trk, rails
from ..track import elastic as track_elastic
from ..loads.layout import AeroHeader
from ..track.layout import N_RAIL_DOF, ElasticTrack, RailDof
from .layout import (CAR_BODY, LATERAL, AntiRollBar, BodyTable, BumpStop, Bushing, Damper, Dof, N_BODY, N_DOF,
                     State, Vector, VehicleConstants, WHEELSETS)

# the model's arrays (built by vehicle.assemble), as the core's functions take them
ModelArrays = namedtuple("ModelArrays", "bodies vp bush damp bump arb track rails support aero cg cp")
# buffers of one right-hand side: per-body kinematics, one wheel's contact scratch, each wheel's contact
# candidates (contact.layout.Candidates) and wheel record (contact.layout.Wheel)
RhsBuffers = namedtuple("RhsBuffers", "kin contact cands recs")


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
def _track_rotation(out, o, heading, cr, sr):
    """out[o:o+9] = Rz(heading) Rx(roll), row-major: ground <- track axes (cr, sr: the roll's cosine and
    sine)."""
    ch, sh = math.cos(heading), math.sin(heading)
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


class Kinematics(Record):
    """A row of the per-body kinematics scratch array `kin` (one per body), filled by `kinematics`."""
    position = "m", "ground position of the reference point", (), Vector
    rotation = "-", "body rotation matrix, ground <- body, row-major", (3, 3)
    velocity = "m/s", "ground velocity of the reference point", (), Vector
    angular_velocity = "rad/s", "ground angular velocity", (), Vector
    track_rotation = "-", "track rotation matrix at the body's station, ground <- track, row-major", (3, 3)
    track_angular_velocity = "rad/s", "the track frame's angular velocity, track axes", (), Vector
    track_velocity = "m/s", "absolute velocity of the reference point, track axes", (), Vector
    force = "N", "force accumulator, ground axes", (), Vector
    moment = "N m", "moment accumulator about the reference point, ground axes", (), Vector


K_COLS = Kinematics.size()
MATRIX = Kinematics.rotation.width
VECTOR = Vector.size()


@core
def _vector(row, o):
    """The Vector at offset o of a row."""
    return row[o + Vector.x], row[o + Vector.y], row[o + Vector.z]


@core
def _point(kin, b, p0, p1, p2):
    """Ground position, ground velocity and ground-axes arm of a body-fixed point."""
    R = kin[b, Kinematics.rotation:Kinematics.rotation + MATRIX]
    ax = R[0] * p0 + R[1] * p1 + R[2] * p2
    ay = R[3] * p0 + R[4] * p1 + R[5] * p2
    az = R[6] * p0 + R[7] * p1 + R[8] * p2
    w = kin[b, Kinematics.angular_velocity:Kinematics.angular_velocity + VECTOR]
    px = kin[b, Kinematics.position + Vector.x] + ax
    py = kin[b, Kinematics.position + Vector.y] + ay
    pz = kin[b, Kinematics.position + Vector.z] + az
    vx = kin[b, Kinematics.velocity + Vector.x] + w[1] * az - w[2] * ay
    vy = kin[b, Kinematics.velocity + Vector.y] + w[2] * ax - w[0] * az
    vz = kin[b, Kinematics.velocity + Vector.z] + w[0] * ay - w[1] * ax
    return px, py, pz, vx, vy, vz, ax, ay, az


@core
def _apply(kin, b, fx, fy, fz, ax, ay, az):
    """Add a ground-axes force acting at arm (ax, ay, az) from body b's reference point."""
    kin[b, Kinematics.force + Vector.x] += fx
    kin[b, Kinematics.force + Vector.y] += fy
    kin[b, Kinematics.force + Vector.z] += fz
    kin[b, Kinematics.moment + Vector.x] += ay * fz - az * fy
    kin[b, Kinematics.moment + Vector.y] += az * fx - ax * fz
    kin[b, Kinematics.moment + Vector.z] += ax * fy - ay * fx


@core
def _apply_pair(kin, a, b, gx, gy, gz, aax, aay, aaz, abx, aby, abz, sx, sy, sz):
    """Add the ground-axes force g on body b and -g on body a, both at the one point halfway between the
    element's attachment points (at arms aa from a's and ab from b's reference point, b's point s = pb - pa
    from a's). Applied each at its own body's point, the pair would make a couple s x g that nothing reacts:
    a zero-length spring carrying a quarter of the car body (78.5 kN) sheared by 30 mm would roll the whole
    car with 2.4 kN m of its own."""
    _apply(kin, b, gx, gy, gz, abx - 0.5 * sx, aby - 0.5 * sy, abz - 0.5 * sz)
    _apply(kin, a, -gx, -gy, -gz, aax + 0.5 * sx, aay + 0.5 * sy, aaz + 0.5 * sz)


@core
def _to_body_axes(kin, a, dx, dy, dz):
    R = kin[a, Kinematics.rotation:Kinematics.rotation + MATRIX]
    return (R[0] * dx + R[3] * dy + R[6] * dz, R[1] * dx + R[4] * dy + R[7] * dz,
            R[2] * dx + R[5] * dy + R[8] * dz)


@core
def _to_ground(kin, a, lx, ly, lz):
    R = kin[a, Kinematics.rotation:Kinematics.rotation + MATRIX]
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
def bump_force(stop, u, clear):
    """Force magnitude (N) of the bump stop `stop` (a layout.BumpStop row) at travel magnitude u (m) on the
    side whose clearance is `clear` (m)."""
    if u <= clear:
        return 0.0
    n = int(stop[BumpStop.points])
    u0 = clear
    f0 = 0.0
    for i in range(n):
        u1 = stop[BumpStop.travel + i]
        f1 = stop[BumpStop.force + i]
        if u <= u1 or i == n - 1:
            return f0 + (f1 - f0) * (u - u0) / (u1 - u0)
        u0 = u1
        f0 = f1
    return f0


@core
def kinematics(x, bodies, track, sp, kin):
    """Fill the per-body kinematics scratch array; returns (v, dv/ds)."""
    s = x[State.s]
    v, dvds = speed_at(sp, s)
    for b in range(N_BODY):
        o = State.positions + N_DOF * b
        ov = State.velocities + N_DOF * b
        sb = s + bodies[b, BodyTable.station]
        X, Y, heading, roll, kap, droll = trk.body_frame(track, sb)
        cr, sr = math.cos(roll), math.sin(roll)
        y = x[o + Dof.lateral]
        z = x[o + Dof.vertical]
        h = bodies[b, BodyTable.height] + z
        wtx = v * droll
        wty = v * kap * sr
        wtz = v * kap * cr
        kin[b, Kinematics.track_angular_velocity + Vector.x] = wtx
        kin[b, Kinematics.track_angular_velocity + Vector.y] = wty
        kin[b, Kinematics.track_angular_velocity + Vector.z] = wtz
        _track_rotation(kin[b], Kinematics.track_rotation, heading, cr, sr)
        _compose(kin[b], Kinematics.rotation, Kinematics.track_rotation, x[o + Dof.yaw], x[o + Dof.pitch],
                 x[o + Dof.roll])
        RT = kin[b, Kinematics.track_rotation:Kinematics.track_rotation + MATRIX]
        kin[b, Kinematics.position + Vector.x] = X + RT[1] * y + RT[2] * h
        kin[b, Kinematics.position + Vector.y] = Y + RT[4] * y + RT[5] * h
        kin[b, Kinematics.position + Vector.z] = RT[7] * y + RT[8] * h
        # absolute velocity in track axes; V_x keeps the body at its station
        vtx = v + wty * h - wtz * y
        vty = x[ov + Dof.lateral]
        vtz = x[ov + Dof.vertical]
        kin[b, Kinematics.track_velocity + Vector.x] = vtx
        kin[b, Kinematics.track_velocity + Vector.y] = vty
        kin[b, Kinematics.track_velocity + Vector.z] = vtz
        kin[b, Kinematics.velocity + Vector.x] = RT[0] * vtx + RT[1] * vty + RT[2] * vtz
        kin[b, Kinematics.velocity + Vector.y] = RT[3] * vtx + RT[4] * vty + RT[5] * vtz
        kin[b, Kinematics.velocity + Vector.z] = RT[6] * vtx + RT[7] * vty + RT[8] * vtz
        wx = x[ov + Dof.roll]
        wy = wty if bodies[b, BodyTable.is_wheelset] > 0.5 else x[ov + Dof.pitch]
        wz = x[ov + Dof.yaw]
        kin[b, Kinematics.angular_velocity + Vector.x] = RT[0] * wx + RT[1] * wy + RT[2] * wz
        kin[b, Kinematics.angular_velocity + Vector.y] = RT[3] * wx + RT[4] * wy + RT[5] * wz
        kin[b, Kinematics.angular_velocity + Vector.z] = RT[6] * wx + RT[7] * wy + RT[8] * wz
        for k in range(VECTOR):
            kin[b, Kinematics.force + k] = 0.0
            kin[b, Kinematics.moment + k] = 0.0
    return v, dvds


@core
def suspension(x, dx, model, kin):
    """Add all suspension forces to the kinematics accumulators; damper state rates into dx."""
    bush, damp, bump, arb = model.bush, model.damp, model.bump, model.arb
    for e in range(bush.shape[0]):
        a = int(bush[e, Bushing.body_a])
        b = int(bush[e, Bushing.body_b])
        pax, pay, paz, vax, vay, vaz, aax, aay, aaz = _point(kin, a, *_vector(bush[e], Bushing.point_a))
        pbx, pby, pbz, vbx, vby, vbz, abx, aby, abz = _point(kin, b, *_vector(bush[e], Bushing.point_b))
        dlx, dly, dlz = _to_body_axes(kin, a, pbx - pax, pby - pay, pbz - paz)
        ddx, ddy, ddz = _to_body_axes(kin, a, vbx - vax, vby - vay, vbz - vaz)
        f0x, f0y, f0z = _vector(bush[e], Bushing.preload)
        kx, ky, kz = _vector(bush[e], Bushing.stiffness)
        cx, cy, cz = _vector(bush[e], Bushing.damping)
        fx = f0x - kx * dlx - cx * ddx
        fy = f0y - ky * dly - cy * ddy
        fz = f0z - kz * dlz - cz * ddz
        gx, gy, gz = _to_ground(kin, a, fx, fy, fz)
        _apply_pair(kin, a, b, gx, gy, gz, aax, aay, aaz, abx, aby, abz, pbx - pax, pby - pay, pbz - paz)
    for e in range(damp.shape[0]):
        a = int(damp[e, Damper.body_a])
        b = int(damp[e, Damper.body_b])
        pax, pay, paz, vax, vay, vaz, aax, aay, aaz = _point(kin, a, *_vector(damp[e], Damper.point_a))
        pbx, pby, pbz, vbx, vby, vbz, abx, aby, abz = _point(kin, b, *_vector(damp[e], Damper.point_b))
        dxl = pbx - pax
        dyl = pby - pay
        dzl = pbz - paz
        length = math.sqrt(dxl * dxl + dyl * dyl + dzl * dzl)
        ex = dxl / length
        ey = dyl / length
        ez = dzl / length
        knee = damp[e, Damper.knee_velocity]
        c1 = damp[e, Damper.damping]
        c2 = damp[e, Damper.damping_after_knee]
        ks = damp[e, Damper.series_stiffness]
        si = int(damp[e, Damper.state])
        # a damper without damping (a failed one, vehicle.assemble.FAULTS) carries no force: its series
        # spring would have nothing to compress against (and damper_rate divides by the damping)
        if ks > 0.0 and c1 > 0.0:
            f = ks * (length - damp[e, Damper.length] - x[si])
            dx[si] = damper_rate(f, knee, c1, c2)
        else:
            rate = ex * (vbx - vax) + ey * (vby - vay) + ez * (vbz - vaz)
            f = damper_force(rate, knee, c1, c2)
            dx[si] = 0.0
        _apply(kin, b, -f * ex, -f * ey, -f * ez, abx, aby, abz)
        _apply(kin, a, f * ex, f * ey, f * ez, aax, aay, aaz)
    for e in range(bump.shape[0]):
        a = int(bump[e, BumpStop.body_a])
        b = int(bump[e, BumpStop.body_b])
        pax, pay, paz, _, _, _, aax, aay, aaz = _point(kin, a, *_vector(bump[e], BumpStop.point_a))
        pbx, pby, pbz, _, _, _, abx, aby, abz = _point(kin, b, *_vector(bump[e], BumpStop.point_b))
        _, dly, dlz = _to_body_axes(kin, a, pbx - pax, pby - pay, pbz - paz)
        lateral = int(bump[e, BumpStop.axis]) == LATERAL
        d = dly if lateral else dlz
        clear = bump[e, BumpStop.clearance_positive] if d > 0.0 else bump[e, BumpStop.clearance_negative]
        f = bump_force(bump[e], abs(d), clear)
        if f > 0.0:
            fd = -f if d > 0.0 else f
            gx, gy, gz = _to_ground(kin, a, 0.0, fd if lateral else 0.0, 0.0 if lateral else fd)
            _apply_pair(kin, a, b, gx, gy, gz, aax, aay, aaz, abx, aby, abz, pbx - pax, pby - pay, pbz - paz)
    for e in range(arb.shape[0]):
        a = int(arb[e, AntiRollBar.body_a])
        b = int(arb[e, AntiRollBar.body_b])
        Ra = kin[a, Kinematics.rotation:Kinematics.rotation + MATRIX]
        Rb = kin[b, Kinematics.rotation:Kinematics.rotation + MATRIX]
        # relative rotation Ra^T Rb: roll angle from its antisymmetric (2,1) - (1,2) part
        r21 = Ra[2] * Rb[1] + Ra[5] * Rb[4] + Ra[8] * Rb[7]
        r12 = Ra[1] * Rb[2] + Ra[4] * Rb[5] + Ra[7] * Rb[8]
        ang = 0.5 * (r21 - r12)
        mx, my, mz = _to_ground(kin, a, -arb[e, AntiRollBar.stiffness] * ang, 0.0, 0.0)
        kin[b, Kinematics.moment + Vector.x] += mx
        kin[b, Kinematics.moment + Vector.y] += my
        kin[b, Kinematics.moment + Vector.z] += mz
        kin[a, Kinematics.moment + Vector.x] -= mx
        kin[a, Kinematics.moment + Vector.y] -= my
        kin[a, Kinematics.moment + Vector.z] -= mz


@core
def wheel_on_rail(x, o, height, rails_, support, side, sw, dfl, rate, track_motion):
    """The `pose` and `motion` of `contact.wheelset.wheel_forces` for wheel `side` of the wheelset whose
    states start at x[o] (at station sw, its centre `height` above the rail tops), relative to its rail:
    the track frame moved by the rail's irregularity (track.rails: offsets ly, lz, slopes a, c) and by its
    elastic deflection `dfl` at `rate` (track.elastic: the roll centre moved by yr, zr and rolled by pr
    about it), the velocities resolved in the rail's axes. `track_motion` = (vtx, vty, vtz, wx, wy, wz,
    spin, v): the wheelset's velocity and angular velocity without spin in track axes, its spin and the
    forward speed. Also returns what turns the force back (a, c, pr) and the wheelset centre from the
    roll centre (ry, rz)."""
    vtx, vty, vtz, wx, wy, wz, spin, v = track_motion
    ly, lz, a, c = rails.rail_deviation(rails_, side, sw)
    yr, zr, pr = dfl[RailDof.lateral], dfl[RailDof.vertical], dfl[RailDof.roll]
    # the wheelset centre from the rail's roll centre
    ry = x[o + Dof.lateral] - ly - yr - (1.0 - 2.0 * side) * support[ElasticTrack.roll_centre_lateral]
    rz = height + x[o + Dof.vertical] - lz - zr + support[ElasticTrack.roll_centre_depth]
    pose = (x[o + Dof.lateral] - ly - yr + pr * rz, x[o + Dof.vertical] - lz - zr - pr * ry,
            x[o + Dof.roll] - pr, x[o + Dof.yaw] - a)
    uy = vty - rate[RailDof.lateral] + rate[RailDof.roll] * rz
    uz = vtz - rate[RailDof.vertical] - rate[RailDof.roll] * ry
    qx = wx - rate[RailDof.roll]
    motion = (vtx + a * uy + c * uz, uy - a * vtx + pr * uz, uz - c * vtx - pr * uy,
              qx + a * wy + c * wz, wy - a * qx + pr * wz, wz - c * qx - pr * wy, spin, v)
    return pose, motion, a, c, pr, ry, rz

# m/s: below it the spin's inertia in its own equation is raised as 1/v (module docstring, "Low speeds"); the
# speed at which the spin's own mode sets a Dormand-Prince limit of 1.96 ms on the straight, about the 2 ms
# step cap (docs/performance.md: lambda v = 1.69e5 km/h/s), and the root locus's lowest speed, so its scans
# are untouched. Source: own measurement (A); the choice of speed a modelling one.
SPIN_HELD_SPEED = 100.0 / 3.6


@core
def rhs(x, dx, model, sp, buffers, tracked):
    """dx = f(x) for the ModelArrays `model` and the speed table sp; the wheel records of the 8 wheels are
    left in buffers.recs (8 x W_SIZE).

    buffers.cands (one `contact.layout.Candidates` per wheel): contact minima written by a full search (tracked
    False) and followed by the cheap local search when `tracked` (the inner stages of one step).
    """
    bodies, vp, track, support = model.bodies, model.vp, model.track, model.support
    kin, cands, recs = buffers.kin, buffers.cands, buffers.recs
    v, dvds = kinematics(x, bodies, track, sp, kin)
    suspension(x, dx, model, kin)
    g = vp[VehicleConstants.gravity]
    r0 = vp[VehicleConstants.rolling_radius]
    spin_i = vp[VehicleConstants.spin_inertia]
    # the spin's own inertia, raised as 1/v below SPIN_HELD_SPEED (module docstring, "Low speeds")
    spin_m = spin_i * SPIN_HELD_SPEED / v if v < SPIN_HELD_SPEED else spin_i
    # the motors/brakes supply the torque that keeps the wheels turning with the prescribed acceleration
    traction = spin_m * v * dvds / r0
    s = x[State.s]
    for b in range(N_BODY):
        o = State.positions + N_DOF * b
        ov = State.velocities + N_DOF * b
        RT = kin[b, Kinematics.track_rotation:Kinematics.track_rotation + MATRIX]
        F = kin[b, Kinematics.force:Kinematics.force + VECTOR]
        M = kin[b, Kinematics.moment:Kinematics.moment + VECTOR]
        # ground -> track axes
        fx = RT[0] * F[0] + RT[3] * F[1] + RT[6] * F[2]
        fy = RT[1] * F[0] + RT[4] * F[1] + RT[7] * F[2]
        fz = RT[2] * F[0] + RT[5] * F[1] + RT[8] * F[2]
        mx = RT[0] * M[0] + RT[3] * M[1] + RT[6] * M[2]
        my = RT[1] * M[0] + RT[4] * M[1] + RT[7] * M[2]
        mz = RT[2] * M[0] + RT[5] * M[1] + RT[8] * M[2]
        wtx = kin[b, Kinematics.track_angular_velocity + Vector.x]
        wty = kin[b, Kinematics.track_angular_velocity + Vector.y]
        wtz = kin[b, Kinematics.track_angular_velocity + Vector.z]
        vtx = kin[b, Kinematics.track_velocity + Vector.x]
        vty = kin[b, Kinematics.track_velocity + Vector.y]
        vtz = kin[b, Kinematics.track_velocity + Vector.z]
        wx = x[ov + Dof.roll]
        wz = x[ov + Dof.yaw]
        is_ws = bodies[b, BodyTable.is_wheelset] > 0.5
        wy = wty if is_ws else x[ov + Dof.pitch]
        spin = x[ov + Dof.pitch]                          # wheelsets: spin about the axle (rad/s)
        # wheel-rail force and moment of both wheels of a wheelset (track axes, about its centre)
        cx = cy = cz = cmx = cmy = cmz = 0.0
        if is_ws:
            sw = s + bodies[b, BodyTable.station]
            for side in range(2):
                k = 2 * (b - WHEELSETS[0]) + side
                # each wheel on its own rail (wheel_on_rail); the force and moment are turned back
                dfl = x[State.rail_deflections + k * N_RAIL_DOF:State.rail_deflections + (k + 1) * N_RAIL_DOF]
                rate = x[State.rail_rates + k * N_RAIL_DOF:State.rail_rates + (k + 1) * N_RAIL_DOF]
                pose, motion, a, c, pr, ry, rz = wheel_on_rail(x, o, bodies[b, BodyTable.height], model.rails,
                                                               support, side, sw, dfl, rate,
                                                               (vtx, vty, vtz, wx, wy, wz, spin, v))
                f0, f1, f2, m0, m1, m2 = ws.wheel_forces(model.cg, model.cp, side, pose, motion, buffers.contact,
                                                         cands[k], tracked, recs[k])
                gy = f1 + a * f0 - pr * f2
                gz = f2 + c * f0 + pr * f1
                hx = m0 - a * m1 - c * m2
                cx += f0 - a * f1 - c * f2
                cy += gy
                cz += gz
                cmx += hx
                cmy += m1 + a * m0 - pr * m2
                cmz += m2 + c * m0 + pr * m1
                if support[ElasticTrack.elastic] > 0.5:
                    # the rail takes the reaction: the wheel's force, and its moment about the roll centre
                    ay, az, ar = track_elastic.rail_accelerations(support, dfl, rate, gy, gz,
                                                                  hx + ry * gz - rz * gy)
                    for q in range(N_RAIL_DOF):
                        dx[State.rail_deflections + k * N_RAIL_DOF + q] = rate[q]
                    dx[State.rail_rates + k * N_RAIL_DOF + RailDof.lateral] = ay
                    dx[State.rail_rates + k * N_RAIL_DOF + RailDof.vertical] = az
                    dx[State.rail_rates + k * N_RAIL_DOF + RailDof.roll] = ar
                else:
                    for q in range(N_RAIL_DOF):
                        dx[State.rail_deflections + k * N_RAIL_DOF + q] = 0.0
                        dx[State.rail_rates + k * N_RAIL_DOF + q] = 0.0
            fx += cx
            fy += cy
            fz += cz
            mx += cmx
            my += cmy
            mz += cmz
        elif b == CAR_BODY and model.aero[AeroHeader.active] > 0.5:
            # the wind's load about the reference point below the body (track axes), moved to the body's
            # reference point at (y, h) above it: M + (-y, -h) x F
            _, _, ay, az, amx, amy, amz = aerodynamic_load(model.aero, s, v)
            h = bodies[b, BodyTable.height] + x[o + Dof.vertical]
            fy += ay
            fz += az
            mx += amx + h * ay - x[o + Dof.lateral] * az
            my += amy
            mz += amz
        m = bodies[b, BodyTable.mass]
        ix = bodies[b, BodyTable.roll_inertia]
        iy = bodies[b, BodyTable.pitch_inertia]
        iz = bodies[b, BodyTable.yaw_inertia]
        # translation: dV/dt = F/m + g_T - omega_T x V; gravity in track axes from the track rotation's
        # entries, the track roll's sine (RT[7]) and cosine (RT[8])
        dx[ov + Dof.lateral] = fy / m - g * RT[7] - (wtz * vtx - wtx * vtz)
        dx[ov + Dof.vertical] = fz / m - g * RT[8] - (wtx * vty - wty * vtx)
        # rotation: I dw/dt = M - w x (I w) - spin gyroscopic term
        gx = (iz - iy) * wy * wz
        gy = (ix - iz) * wz * wx
        gz = (iy - ix) * wx * wy
        if is_ws:
            cphi = math.cos(x[o + Dof.roll])
            ax_x = -math.sin(x[o + Dof.yaw]) * cphi
            ax_y = math.cos(x[o + Dof.yaw]) * cphi
            ax_z = math.sin(x[o + Dof.roll])
            hs = spin_i * spin
            gx += hs * (wy * ax_z - wz * ax_y)
            gz += hs * (wx * ax_y - wy * ax_x)
            # spin: the contact forces' moment about the axle (the axle boxes do not turn with the wheels)
            dx[ov + Dof.pitch] = ((cmx * ax_x + cmy * ax_y + cmz * ax_z) + traction) / spin_m
        else:
            dx[ov + Dof.pitch] = (my - gy) / iy
        dx[ov + Dof.roll] = (mx - gx) / ix
        dx[ov + Dof.yaw] = (mz - gz) / iz
        # kinematics of the relative coordinates
        h = bodies[b, BodyTable.height] + x[o + Dof.vertical]
        dx[o + Dof.lateral] = vty + wtx * h
        dx[o + Dof.vertical] = vtz - wtx * x[o + Dof.lateral]
        dx[o + Dof.roll] = wx - wtx
        dx[o + Dof.pitch] = 0.0 if is_ws else x[ov + Dof.pitch] - wty
        dx[o + Dof.yaw] = wz - wtz
    dx[State.s] = v
    return v

