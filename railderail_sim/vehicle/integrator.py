"""Adaptive Dormand-Prince 5(4) stepper with outputs, derailment detection and divergence guard (numba).

Why this integrator: the stiffest motions are the bounce and roll of a wheelset on its elastic Hertzian
contacts (about 200 Hz on the rigid track, damped by the contact's Hunt-Crossley term) and the flange
impacts; the motions that matter (hunting, curving, climbing) are below 20 Hz. An explicit embedded
Runge-Kutta pair with error control takes long steps (up to the stability limit, ~2 ms) in steady
running and short ones through impacts and contact changes, with the local error held below the
tolerances per state (docs/vehicle-model.md shows the tolerance study). It needs no Jacobian, and the
algorithm is deterministic: the same inputs give bit-identical outputs. Steps are shortened to land on
every output instant, so the simulator node can advance the core by exactly one publication period.

`advance` is the one stepper: the batch API runs it to the end of the line, the ROS node calls it once
per publication period with the same buffers.
"""
from collections import namedtuple
import math

import numpy as np

from ..jit import core
from ..contact import wheelset as ws
from ..loads.aerodynamics import aerodynamic_load
from ..loads.layout import AeroLoad
from ..record import Record
from ..track import alignment as trk, rails
from ..track import elastic as track_elastic
from ..track.layout import N_RAIL_DOF, RailDof
from . import dynamics as dyn
from .dynamics import Kinematics
from .layout import (BodyMotion, BodyTable, Dof, N_BODY, N_DAMPER, N_DOF, N_STATE, N_WHEEL, N_WHEELSET, OutputRow,
                     State, Vector, VehicleConstants, WheelsetOutput, WHEELSETS)
from ..contact.layout import W_SIZE, WP_SIZE, Wheel, WheelPatch

RUNNING, DERAILED, DIVERGED, END_OF_LINE = 0, 1, 2, 3
MECH_FLANGE_CLIMBING, MECH_WHEEL_UNLOADING = 1, 2


class Event(Record):
    """What happened when `advance` stopped (DERAILED: the derailment; DIVERGED: the runaway state)."""
    time = "s", "simulated time"
    position = "m", "track position: of the derailed wheelset, or of the car-body centre"
    wheelset = "-", "derailed wheelset (0..3 from the front)"
    side = "-", "derailed wheel: 0 left, 1 right"
    mechanism = "-", "MECH_FLANGE_CLIMBING or MECH_WHEEL_UNLOADING"
    wheel_lift = "m", "the wheel's lift"
    lateral_displacement = "m", "the wheelset's lateral displacement from the derailed wheel's rail position"
    attack_angle = "rad", "the wheelset's attack angle to the derailed wheel's rail, + front toward the outer rail"
    contact_position = "m", "where the wheel last touched its rail (LastContact)"
    speed = "m/s", "forward speed"
    state_index = "-", "DIVERGED: index of the runaway state in the state vector (-1: the step size fell)"
    state_value = "-", "DIVERGED: its value (or the step size, s)"


class LastContact(Record):
    """Where a wheel last touched its rail (kept while it is off the rail, `_follow_contact`)."""
    on_flange = "-", ("1 if the wheel was on its flange: a loaded patch steeper than the flange_contact_angle, or "
                      "still loaded and lifted by more than the lift_tolerance since it was")
    contact_position = "m", "the main patch's point on the rail, from the head axis, + field side"


class Stepper(Record):
    """The step control's state, kept between calls of `advance`."""
    step = "s", "the step size to try next"
    accepted = "-", "steps accepted"
    rejected = "-", "steps rejected"


EV_SIZE = Event.size()
WS_SIZE = WheelsetOutput.size()
BM_SIZE = BodyMotion.size()

# limits beyond which the integration has run away (not a physical state of a car on or near the track)
LIMIT_DISPLACEMENT = 0.5       # m, any lateral/vertical body displacement
LIMIT_ANGLE = 0.5              # rad
LIMIT_VELOCITY = 30.0          # m/s, lateral/vertical
LIMIT_RATE = 60.0              # rad/s
LIMIT_DAMPER = 0.5             # m
LIMIT_RAIL = 0.05              # m, a rail's deflection (track.elastic; some mm in service)
LIMIT_SPIN = 1000.0            # rad/s, a wheelset's spin (about 240 rad/s at 400 km/h)

# the stepper's buffers: the right-hand side's (dynamics.RhsBuffers), the seven stage derivatives, the
# trial state, the contact candidates saved before a step (restored when it is rejected), the Event, the
# Stepper record and, per wheel, its LastContact
Workspace = namedtuple("Workspace", "rhs stages trial cand_save event stepper last_contact")
# error control and the stopping rules
StepControl = namedtuple("StepControl", "atol rtol h_min h_max s_end stop_on_derailment")


def workspace(cg):
    """Preallocated buffers of `advance` (reused between calls)."""
    stepper = np.zeros(Stepper.size())
    stepper[Stepper.step] = 1e-4
    buffers = dyn.RhsBuffers(kin=np.zeros((N_BODY, dyn.K_COLS)), contact=ws.contact_scratch(cg),
                             cands=ws.candidates(N_WHEEL), recs=np.zeros((N_WHEEL, W_SIZE)))
    return Workspace(rhs=buffers, stages=np.zeros((7, N_STATE)), trial=np.zeros(N_STATE),
                     cand_save=ws.candidates(N_WHEEL), event=np.zeros(EV_SIZE), stepper=stepper,
                     last_contact=np.zeros((N_WHEEL, LastContact.size())))


@core
def fill_row(row, t, x, dx, v, model, sp, buffers):
    """One output row (OutputRow) from the state, its rate dx and the right-hand side's buffers (the wheel
    records and the per-body kinematics) of the same instant."""
    bodies, vp, track = model.bodies, model.vp, model.track
    recs, kin = buffers.recs, buffers.kin
    s = x[State.s]
    kap, _ = trk.curvature(track, s)
    roll, _ = trk.cant(track, s)
    direction = track[trk.TrackHeader.direction]
    row[OutputRow.time] = t
    row[OutputRow.position] = s
    row[OutputRow.speed] = v
    row[OutputRow.section] = trk.section(track, s)
    row[OutputRow.curvature] = kap
    row[OutputRow.cant] = abs(roll)
    # uncompensated lateral acceleration in the track plane, + toward the outside of the curve
    row[OutputRow.uncompensated_acceleration] = direction * (v * v * kap * math.cos(roll)
                                                             + vp[VehicleConstants.gravity] * math.sin(roll))
    for i in range(N_BODY * N_DOF):
        row[OutputRow.body_states + i] = x[State.positions + i]
    for w in range(N_WHEELSET):
        b = WHEELSETS[w]
        o = State.positions + N_DOF * b
        # relative to the track's actual centre line and direction: the mean of the two rails
        yl, _, al, _ = rails.rail_deviation(model.rails, 0, s + bodies[b, BodyTable.station])
        yr, _, ar, _ = rails.rail_deviation(model.rails, 1, s + bodies[b, BodyTable.station])
        # and their elastic deflection (zero on rigid track)
        yl += track_elastic.head_shift(model.support, x, State.rail_deflections + 2 * w * N_RAIL_DOF)
        yr += track_elastic.head_shift(model.support, x, State.rail_deflections + (2 * w + 1) * N_RAIL_DOF)
        r = OutputRow.wheelsets + w * WS_SIZE
        row[r + WheelsetOutput.wheelset_lateral] = x[o + Dof.lateral] - 0.5 * (yl + yr)
        # attack angle: + when the front of the wheelset points toward the outer rail
        row[r + WheelsetOutput.attack_angle] = -direction * (x[o + Dof.yaw] - 0.5 * (al + ar))
        row[r + WheelsetOutput.wheelset_roll] = x[o + Dof.roll]
    for k in range(N_WHEEL):
        o = OutputRow.wheels + k * W_SIZE
        for q in range(W_SIZE):
            row[o + q] = recs[k, q]
    for i in range(N_WHEEL * N_RAIL_DOF):
        row[OutputRow.rails + i] = x[State.rail_deflections + i]
    w, beta, fy, fz, mx, my, mz = aerodynamic_load(model.aero, s, v)
    a = OutputRow.aerodynamics
    row[a + AeroLoad.wind_speed] = w
    row[a + AeroLoad.yaw_angle] = beta
    row[a + AeroLoad.side_force] = fy
    row[a + AeroLoad.lift] = fz
    row[a + AeroLoad.rolling_moment] = mx
    row[a + AeroLoad.pitching_moment] = my
    row[a + AeroLoad.yawing_moment] = mz
    _fill_motion(row, x, dx, v, vp, sp, bodies, kin)


@core
def _fill_motion(row, x, dx, v, vp, sp, bodies, kin):
    """Each body's BodyMotion: from dV/dt = F/m + g_T - omega_T x V (dynamics.rhs) the specific force
    F/m = dV/dt - g_T + omega_T x V, and the inertial angular acceleration d(omega)/dt + omega_T x omega, in
    track axes. V_x is not a state (the body keeps its station): its rate is taken as the forward
    acceleration v dv/ds, without the small rates of the track's turn and of the body's offsets; so is
    the rate of the wheelsets' non-spinning pitch, the track's own."""
    g = vp[VehicleConstants.gravity]
    _, dvds = dyn.speed_at(sp, x[State.s])
    for b in range(N_BODY):
        ov = State.velocities + N_DOF * b
        w_t = Kinematics.track_angular_velocity
        wtx, wty, wtz = kin[b, w_t + Vector.x], kin[b, w_t + Vector.y], kin[b, w_t + Vector.z]
        v_t = Kinematics.track_velocity
        vtx, vty, vtz = kin[b, v_t + Vector.x], kin[b, v_t + Vector.y], kin[b, v_t + Vector.z]
        # the track's roll at the body's station (its rotation matrix: ground <- track, row-major)
        roll_t = math.atan2(kin[b, Kinematics.track_rotation + 7], kin[b, Kinematics.track_rotation + 8])
        is_ws = bodies[b, BodyTable.is_wheelset] > 0.5
        wx, wz = x[ov + Dof.roll], x[ov + Dof.yaw]
        wy = wty if is_ws else x[ov + Dof.pitch]
        dwy = 0.0 if is_ws else dx[ov + Dof.pitch]
        r = OutputRow.body_motion + b * BM_SIZE
        row[r + BodyMotion.specific_force + Vector.x] = v * dvds + wty * vtz - wtz * vty
        row[r + BodyMotion.specific_force + Vector.y] = dx[ov + Dof.lateral] + g * math.sin(roll_t) + wtz * vtx \
            - wtx * vtz
        row[r + BodyMotion.specific_force + Vector.z] = dx[ov + Dof.vertical] + g * math.cos(roll_t) + wtx * vty \
            - wty * vtx
        row[r + BodyMotion.angular_velocity + Vector.x] = wx
        row[r + BodyMotion.angular_velocity + Vector.y] = wy
        row[r + BodyMotion.angular_velocity + Vector.z] = wz
        row[r + BodyMotion.angular_acceleration + Vector.x] = dx[ov + Dof.roll] + wty * wz - wtz * wy
        row[r + BodyMotion.angular_acceleration + Vector.y] = dwy + wtz * wx - wtx * wz
        row[r + BodyMotion.angular_acceleration + Vector.z] = dx[ov + Dof.yaw] + wtx * wy - wty * wx


@core
def _follow_contact(recs, vp, last):
    """Per wheel in contact: its LastContact, on the flange when a loaded patch's contact angle is above the
    `flange_contact_angle`; unchanged while the wheel is off the rail, so that a wheel that has lifted
    remembers where it touched before.

    A wheel that climbs stays on its flange while it is loaded and lifted by more than the lift tolerance:
    near the flange tip the contact angle falls below the threshold (to 0 at the tip) although the wheel
    is still riding up its flange, and on the tread a loaded wheel's lift stays below a millimetre."""
    limit = vp[VehicleConstants.flange_contact_angle]
    riding = vp[VehicleConstants.lift_tolerance]
    for k in range(N_WHEEL):
        loaded = False
        on_flange = False
        for q in range(int(recs[k, Wheel.contact_count])):
            o = Wheel.patches + q * WP_SIZE
            if recs[k, o + WheelPatch.normal_force] > 0.0:
                loaded = True
                if recs[k, o + WheelPatch.contact_angle] > limit:
                    on_flange = True
        if loaded:
            climbing = last[k, LastContact.on_flange] > 0.5 and recs[k, Wheel.wheel_lift] > riding
            last[k, LastContact.on_flange] = 1.0 if on_flange or climbing else 0.0
            last[k, LastContact.contact_position] = recs[k, Wheel.contact_position]


@core
def _check_derailment(x, v, t, model, recs, last, event):
    """The paper's geometric criterion, per wheel (docs/methods.md): True and `event` filled if met.

    flange climbing: the flanging wheel (its last contact on the flange, `LastContact`) has
    lifted to the flange height less the tolerance; wheel unloading (lift-off, overturning): a wheel whose
    last contact was on its tread has lifted to the flange height. The event gives the wheelset's lateral
    displacement and attack angle relative to the derailed wheel's rail and where the wheel last touched it.
    """
    vp = model.vp
    hf = vp[VehicleConstants.flange_height]
    tol = vp[VehicleConstants.lift_tolerance]
    direction = model.track[trk.TrackHeader.direction]
    for w in range(N_WHEELSET):
        b = WHEELSETS[w]
        o = State.positions + N_DOF * b
        sw = x[State.s] + model.bodies[b, BodyTable.station]
        for side in range(2):
            k = 2 * w + side
            lift = recs[k, Wheel.wheel_lift]
            mech = 0
            if last[k, LastContact.on_flange] > 0.5 and lift >= hf - tol:
                mech = MECH_FLANGE_CLIMBING
            elif lift >= hf:
                mech = MECH_WHEEL_UNLOADING
            if mech > 0:
                rail_y, _, rail_slope, _ = rails.rail_deviation(model.rails, side, sw)
                rail_y += track_elastic.head_shift(model.support, x, State.rail_deflections + k * N_RAIL_DOF)
                event[Event.time] = t
                event[Event.position] = sw
                event[Event.wheelset] = w
                event[Event.side] = side
                event[Event.mechanism] = mech
                event[Event.wheel_lift] = lift
                event[Event.lateral_displacement] = x[o + Dof.lateral] - rail_y
                event[Event.attack_angle] = -direction * (x[o + Dof.yaw] - rail_slope)
                event[Event.contact_position] = last[k, LastContact.contact_position]
                event[Event.speed] = v
                return True
    return False


@core
def _check_divergence(x, t, event):
    bad = -1
    for i in range(N_STATE):
        if not math.isfinite(x[i]):
            bad = i
            break
    if bad < 0:
        for b in range(N_BODY):
            o = State.positions + N_DOF * b
            ov = State.velocities + N_DOF * b
            for k in range(N_DOF):
                translation = k == Dof.lateral or k == Dof.vertical
                lim_p = LIMIT_DISPLACEMENT if translation else LIMIT_ANGLE
                lim_v = LIMIT_VELOCITY if translation else LIMIT_RATE
                if k == Dof.pitch and b >= WHEELSETS[0]:
                    lim_v = LIMIT_SPIN
                if abs(x[o + k]) > lim_p:
                    bad = o + k
                    break
                if abs(x[ov + k]) > lim_v:
                    bad = ov + k
                    break
            if bad >= 0:
                break
    if bad < 0:
        for i in range(State.dampers, State.dampers + N_DAMPER):
            if abs(x[i]) > LIMIT_DAMPER:
                bad = i
                break
    if bad < 0:
        for k in range(N_WHEEL * N_RAIL_DOF):
            lim_p = LIMIT_ANGLE if k % N_RAIL_DOF == RailDof.roll else LIMIT_RAIL
            lim_v = LIMIT_RATE if k % N_RAIL_DOF == RailDof.roll else LIMIT_VELOCITY
            if abs(x[State.rail_deflections + k]) > lim_p:
                bad = State.rail_deflections + k
                break
            if abs(x[State.rail_rates + k]) > lim_v:
                bad = State.rail_rates + k
                break
    if bad < 0:
        return False
    event[Event.time] = t
    event[Event.position] = x[State.s]
    event[Event.state_index] = bad
    event[Event.state_value] = x[bad]
    return True


# Dormand-Prince 5(4) coefficients (Dormand & Prince, J. Comput. Appl. Math. 6 (1980) 19-26)
_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0]])
_E = np.array([71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
               -1.0 / 40.0])


@core
def advance(x, t, duration, out_dt, first_row, model, sp, control, work, out):
    """Advance x in place over `duration` s from time t (a multiple of out_dt) with Dormand-Prince 5(4).

    `model`: the dynamics.ModelArrays; sp: the speed table; `control`: the StepControl; `work`: the
    Workspace. Adaptive steps under the error control (atol per state, rtol) land exactly on every
    output instant; a row is written after every output interval, and at the start if `first_row` (the
    state and wheel records of that instant). The last stage of each step (FSAL) searches the wheel-rail
    contact in full at the new state; the inner stages follow the contacts found there
    (`geometry.track_patches`). work.stepper keeps the step size between calls and counts the accepted
    and rejected steps. Stops early at END_OF_LINE, DERAILED (if control.stop_on_derailment) or DIVERGED
    (state out of bounds, not finite, or step below h_min); work.event says when, where, what.
    Returns (status, rows_written, t).
    """
    atol, rtol, h_min, h_max = control.atol, control.rtol, control.h_min, control.h_max
    ks, xt, cand_save, event, stepper = work.stages, work.trial, work.cand_save, work.event, work.stepper
    buffers = work.rhs
    cands, recs = buffers.cands, buffers.recs
    # the RMS error counts the states that move: a frozen state (the rigid track's rails) has atol = inf.
    # The stages, the error and the update run over the states up to the last that moves (n): the frozen
    # ones after it keep their values (rigid track: the 48 rail states, 38 % of the state vector)
    counted = 0
    n = 0
    for i in range(x.shape[0]):
        if math.isfinite(atol[i]):
            counted += 1
            n = i + 1
    for i in range(n, x.shape[0]):
        xt[i] = x[i]
    rows = 0
    nout = out.shape[0]
    k0 = ks[0]
    v = dyn.rhs(x, k0, model, sp, buffers, False)
    n_intervals = int(round(duration / out_dt))
    h_prop = stepper[Stepper.step]
    for interval in range(n_intervals + 1):
        if (interval > 0 or first_row) and rows < nout:
            fill_row(out[rows], t, x, k0, v, model, sp, buffers)
            rows += 1
        if control.stop_on_derailment and _check_derailment(x, v, t, model, recs, work.last_contact, event):
            stepper[Stepper.step] = h_prop
            return DERAILED, rows, t
        if x[State.s] >= control.s_end:
            stepper[Stepper.step] = h_prop
            return END_OF_LINE, rows, t
        if interval == n_intervals:
            break
        t_target = t + out_dt
        while t < t_target - 1e-12:
            clipped = t + h_prop >= t_target - 1e-12
            h = t_target - t if clipped else h_prop
            for i in range(cands.shape[0]):
                for j in range(cands.shape[1]):
                    cand_save[i, j] = cands[i, j]
            for st in range(1, 7):
                # the stage sum of each state in the order j = 0.. (as one sum per state), row by row so
                # that the loops run along contiguous rows
                for i in range(n):
                    xt[i] = 0.0
                for j in range(st):
                    a = _A[st, j]
                    kj = ks[j]
                    for i in range(n):
                        xt[i] += a * kj[i]
                for i in range(n):
                    xt[i] = x[i] + h * xt[i]
                full = st == 6
                vt = dyn.rhs(xt, ks[st], model, sp, buffers, not full)
            # xt holds the 5th-order solution (stage 7 is evaluated there: FSAL)
            err = 0.0
            for i in range(n):
                e = 0.0
                for j in range(7):
                    e += _E[j] * ks[j, i]
                sc = atol[i] + rtol * max(abs(x[i]), abs(xt[i]))
                r = h * e / sc
                err += r * r
            err = math.sqrt(err / counted)
            if err <= 1.0 and math.isfinite(err):
                stepper[Stepper.accepted] += 1.0
                for i in range(n):
                    x[i] = xt[i]
                    k0[i] = ks[6, i]
                t = t_target if clipped else t + h
                v = vt
                _follow_contact(recs, model.vp, work.last_contact)
                if _check_divergence(x, t, event):
                    stepper[Stepper.step] = h_prop
                    return DIVERGED, rows, t
                fac = 5.0 if err < 1e-10 else min(5.0, 0.9 * err ** -0.2)
                # a step shortened to land on the output instant says nothing against the longer one
                h_prop = min(h_max, max(h * fac, h_prop) if clipped else h * fac)
            else:
                stepper[Stepper.rejected] += 1.0
                for i in range(cands.shape[0]):
                    for j in range(cands.shape[1]):
                        cands[i, j] = cand_save[i, j]
                fac = 0.2 if not math.isfinite(err) else max(0.2, 0.9 * err ** -0.2)
                h_prop = h * fac
                if h_prop < h_min:
                    event[Event.time] = t
                    event[Event.position] = x[State.s]
                    event[Event.state_index] = -1
                    event[Event.state_value] = h_prop
                    stepper[Stepper.step] = h_prop
                    return DIVERGED, rows, t
    stepper[Stepper.step] = h_prop
    return RUNNING, rows, t
