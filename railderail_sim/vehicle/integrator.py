"""Adaptive Dormand-Prince 5(4) stepper with dense output, derailment detection and divergence guard (numba).

Why this integrator: the stiffest motions are the bounce and roll of a wheelset on its elastic Hertzian
contacts (about 200 Hz on the rigid track, damped by the contact's Hunt-Crossley term) and the flange
impacts; the motions that matter (hunting, curving, climbing) are below 20 Hz. An explicit embedded
Runge-Kutta pair with error control takes long steps (up to the stability limit, ~1.8 ms) in steady
running and short ones through impacts and contact changes, with the local error held below the
tolerances per state (docs/vehicle-model.md shows the tolerance study). It needs no Jacobian, and the
algorithm is deterministic: the same inputs give bit-identical outputs.

The steps do not stop at the output instants: each output row is the state of Dormand-Prince's continuous
extension (the 4th-order interpolant of the step's stage derivatives, `_DENSE`) at its instant, and the
right-hand side is evaluated there once more (full contact search, buffers of its own) for the row's forces,
contact records and accelerations and for the derailment check, which stays on the output instants. The
step sequence therefore depends neither on the output rate nor on how a run is cut into calls: the
stepper's own time and the last step's interpolant live in the Workspace between calls, and the state x
is the stepper's (at or up to one step past the last output instant).

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
from ..track.layout import N_RAIL_DOF
from . import dynamics as dyn
from .dynamics import Kinematics
from .layout import (BodyMotion, BodyTable, Dof, N_BODY, N_DOF, N_STATE, N_WHEEL, N_WHEELSET, OutputRow,
                     State, Vector, VehicleConstants, WheelsetOutput, WHEELSETS)
from ..contact.layout import W_SIZE
from .run_end import Event, LastContact, check_derailment, check_divergence, follow_contact

RUNNING, DERAILED, DIVERGED, END_OF_LINE = 0, 1, 2, 3


class Stepper(Record):
    """The step control's state, kept between calls of `advance`."""
    step = "s", "the step size to try next"
    accepted = "-", "steps accepted"
    rejected = "-", "steps rejected"
    time = "s", "the stepper's own time, where the state x is (at or past the last output instant)"
    last_step = "s", "the last accepted step, the one `Workspace.dense` interpolates (0: none yet)"
    start_rate_time = "s", ("the stepper's time at which the first stage derivative (`Workspace.stages` row 0) was "
                            "left by the last call, as of `Workspace.seen_state`, `seen_speeds` and `seen_candidates` "
                            "(NaN: none; `advance` evaluates it afresh)")


class Dense(Record):
    """The rows of `Workspace.dense` (each N_STATE long): the last accepted step's continuous extension,
    x(t_old + theta h) = y0 + theta (dy + (1 - theta) (c3 + theta (c4 + (1 - theta) c5))) (Hairer, Norsett
    and Wanner, Solving Ordinary Differential Equations I, 2nd ed., II.6, the DOPRI5 code's CONTD5),
    and the state and rates at an output instant."""
    y0 = "-", "the state at the step's start"
    dy = "-", "the step's change of the state"
    c3 = "-", "h k1 - dy"
    c4 = "-", "dy - h k7 - c3"
    c5 = "-", "h (d1 k1 + d3 k3 + ... + d7 k7)"
    state = "-", "the interpolated state at the output instant"
    rate = "-", "its rate, from the right-hand side at that state"


EV_SIZE = Event.size()
WS_SIZE = WheelsetOutput.size()
BM_SIZE = BodyMotion.size()

# the stepper's buffers: the right-hand side's (dynamics.RhsBuffers), the seven stage derivatives, the
# trial state, the contact candidates saved before a step (restored when it is rejected), the Event, the
# Stepper record and, per wheel, its LastContact; for the output instants: the last step's continuous
# extension (Dense), the right-hand side's own buffers (the stepper's contact candidates stay untouched)
# and each wheel's LastContact as of the instant; what the last call left the first stage's derivative at
# (the state, the speed table and the contact candidates: `advance` reuses it if none has changed)
Workspace = namedtuple("Workspace", "rhs stages trial cand_save event stepper last_contact dense out_rhs "
                                    "out_contact seen_state seen_speeds seen_candidates")
# error control and the stopping rules
StepControl = namedtuple("StepControl", "atol rtol h_min h_max s_end stop_on_derailment")


def workspace(cg, speed_rows=2):
    """Preallocated buffers of `advance` (reused between calls); `speed_rows`: the speed table's rows (a table
    of another length is compared with `seen_speeds` of its own, `seen_speeds_for`)."""
    stepper = np.zeros(Stepper.size())
    stepper[Stepper.step] = 1e-4
    stepper[Stepper.start_rate_time] = math.nan
    scratch = ws.contact_scratch(cg)
    buffers = dyn.RhsBuffers(kin=np.zeros((N_BODY, dyn.K_COLS)), contact=scratch,
                             cands=ws.candidates(N_WHEEL), recs=np.zeros((N_WHEEL, W_SIZE)))
    out_buffers = dyn.RhsBuffers(kin=np.zeros((N_BODY, dyn.K_COLS)), contact=scratch,
                                 cands=ws.candidates(N_WHEEL), recs=np.zeros((N_WHEEL, W_SIZE)))
    return Workspace(rhs=buffers, stages=np.zeros((7, N_STATE)), trial=np.zeros(N_STATE),
                     cand_save=ws.candidates(N_WHEEL), event=np.zeros(EV_SIZE), stepper=stepper,
                     last_contact=np.zeros((N_WHEEL, LastContact.size())), dense=np.zeros((Dense.size(), N_STATE)),
                     out_rhs=out_buffers, out_contact=np.zeros((N_WHEEL, LastContact.size())),
                     seen_state=np.zeros(N_STATE), seen_speeds=seen_speeds_for(speed_rows),
                     seen_candidates=ws.candidates(N_WHEEL))


def seen_speeds_for(rows):
    """A Workspace's `seen_speeds` for a speed table of `rows` rows: NaN, never equal to a table (the first
    call with it evaluates the first stage afresh)."""
    return np.full((rows, 2), math.nan)


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
# the continuous extension's last term (Dense.c5; Hairer, Norsett and Wanner, II.6; Shampine, Math. Comp. 46
# (1986) 135-150): 4th order at every theta in the step
_DENSE = np.array([-12715105075.0 / 11282082432.0, 0.0, 87487479700.0 / 32700410799.0,
                   -10690763975.0 / 1880347072.0, 701980252875.0 / 199316789632.0,
                   -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0])


@core
def _output_row(row, t, theta, n, model, sp, work):
    """The output row at time t, theta of the way through the last accepted step (Dense), and the
    derailment check there: the state from the continuous extension, the right-hand side at it (full
    contact search, `work.out_rhs`) for the row's forces and contact records, and each wheel's last contact
    as of t (`work.out_contact`: the stepper's as of the step's start, followed through the step's output
    instants up to t; nothing after t). Returns (True if derailed, the interpolated state's track
    position)."""
    dense = work.dense
    xo, dxo = dense[Dense.state], dense[Dense.rate]
    t1 = 1.0 - theta
    for i in range(n):
        xo[i] = dense[Dense.y0, i] + theta * (dense[Dense.dy, i] + t1 * (dense[Dense.c3, i] + theta * (
            dense[Dense.c4, i] + t1 * dense[Dense.c5, i])))
    return _row_at(row, t, xo, dxo, model, sp, work)


@core
def _row_at(row, t, xo, dxo, model, sp, work):
    """The output row of state xo at time t and the derailment check there (`_output_row`)."""
    buffers = work.out_rhs
    v = dyn.rhs(xo, dxo, model, sp, buffers, False)
    fill_row(row, t, xo, dxo, v, model, sp, buffers)
    follow_contact(buffers.recs, model.vp, work.out_contact)
    return check_derailment(xo, v, t, model, buffers.recs, work.out_contact, work.event), xo[State.s]


@core
def _copy_rows(source, target):
    for k in range(source.shape[0]):
        for q in range(source.shape[1]):
            target[k, q] = source[k, q]


@core
def advance(x, t, duration, out_dt, first_row, model, sp, control, work, out):
    """Advance the run (`_advance`, whose docstring says how), reusing the first stage's derivative that the
    last call left if nothing it depends on has changed since (`_start_rate_kept`)."""
    fresh = not _start_rate_kept(x, sp, work)
    result = _advance(x, t, duration, out_dt, first_row, model, sp, control, work, out, fresh)
    _keep_start_rate(x, sp, work)
    return result


@core
def _start_rate_kept(x, sp, work):
    """True if the first stage's derivative (`Workspace.stages` row 0) is the right-hand side at x with a full
    contact search, bit for bit: a call left it (Stepper.start_rate_time is the stepper's time) and the state,
    the speed table and the contact candidates are those it left (`Workspace.seen_*`). Each call ends with it
    so: its last accepted step's last stage is that full right-hand side at the new state (FSAL), and the
    stepper's candidates are that search's (a rejected step restores them); a call without a step keeps the
    one it started with. A caller that changes the state or the speed table (`closed_loop.apply_brake`), or
    searches the contact with the stepper's buffers, gets it evaluated afresh. The rest of the right-hand
    side's inputs (the model's arrays) are a run's constants."""
    stepper = work.stepper
    if not stepper[Stepper.start_rate_time] == stepper[Stepper.time]:
        return False
    seen = work.seen_state
    for i in range(x.shape[0]):
        if not x[i] == seen[i]:
            return False
    return _same_rows(sp, work.seen_speeds) and _same_rows(work.rhs.cands, work.seen_candidates)


@core
def _same_rows(a, b):
    """True if the 2-D arrays a and b have one shape and equal elements (NaN equals nothing)."""
    if a.shape[0] != b.shape[0] or a.shape[1] != b.shape[1]:
        return False
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            if not a[i, j] == b[i, j]:
                return False
    return True


@core
def _keep_start_rate(x, sp, work):
    """Note what the first stage's derivative is as of (`_start_rate_kept`); not with a speed table of
    another length than `seen_speeds` (the caller gives one of its length: `seen_speeds_for`)."""
    stepper = work.stepper
    seen_sp = work.seen_speeds
    if sp.shape[0] != seen_sp.shape[0] or sp.shape[1] != seen_sp.shape[1]:
        stepper[Stepper.start_rate_time] = math.nan
        return
    _copy_rows(sp, seen_sp)
    for i in range(x.shape[0]):
        work.seen_state[i] = x[i]
    _copy_rows(work.rhs.cands, work.seen_candidates)
    stepper[Stepper.start_rate_time] = stepper[Stepper.time]


@core
def _advance(x, t, duration, out_dt, first_row, model, sp, control, work, out, fresh):
    """Advance the run over `duration` s from the output instant t (a multiple of out_dt) with
    Dormand-Prince 5(4), writing a row per output instant.

    `model`: the dynamics.ModelArrays; sp: the speed table; `control`: the StepControl; `work`: the
    Workspace. x is the stepper's state at its own time (work.stepper's `time`, at or up to one step past
    t; at the start both are t). Adaptive steps under the error control (atol per state, rtol) run past the
    output instants; a row is written at every output instant after t (from the continuous extension,
    `_output_row`), and at t if `first_row` (x itself). The last stage of each step (FSAL) searches the
    wheel-rail contact in full at the new state; the inner stages follow the contacts found there
    (`geometry.track_patches`). work.stepper keeps the step size, the time and the last step between
    calls and counts the accepted and rejected steps. Stops early at END_OF_LINE or DERAILED (if
    control.stop_on_derailment; both judged at the output instants) or DIVERGED (a step's state out of
    bounds, not finite, or the step below h_min); work.event says when, where, what.
    Returns (status, rows_written, t): t the last output instant written.
    """
    atol, rtol, h_min, h_max = control.atol, control.rtol, control.h_min, control.h_max
    ks, xt, cand_save, event, stepper = work.stages, work.trial, work.cand_save, work.event, work.stepper
    dense = work.dense
    buffers = work.rhs
    cands, recs = buffers.cands, buffers.recs
    # the RMS error counts the states that move: a frozen state (the rigid track's rails) has atol = inf.
    # The stages, the error, the update and the interpolation run over the states up to the last that
    # moves (n): the frozen ones after it keep their values (rigid track: the 48 rail states, 38 % of the
    # state vector)
    counted = 0
    n = 0
    for i in range(x.shape[0]):
        if math.isfinite(atol[i]):
            counted += 1
            n = i + 1
    for i in range(n, x.shape[0]):
        xt[i] = x[i]
        dense[Dense.state, i] = x[i]
    rows = 0
    k0, k1, k2, k3, k4, k5, k6 = ks[0], ks[1], ks[2], ks[3], ks[4], ks[5], ks[6]
    if fresh:
        # the first stage: the right-hand side at x with a full contact search (unless the last call's last
        # step left it, `advance`)
        dyn.rhs(x, k0, model, sp, buffers, False)
    # as many output intervals as `out` holds rows for
    n_intervals = min(int(round(duration / out_dt)), out.shape[0] - (1 if first_row else 0))
    h_prop = stepper[Stepper.step]
    t_step = stepper[Stepper.time]
    for interval in range(n_intervals + 1):
        if interval == 0:
            if not first_row:
                continue
            # the start: the row of x itself (the stepper is there)
            _copy_rows(work.last_contact, work.out_contact)
            derailed, s_out = _row_at(out[0], t, x, dense[Dense.rate], model, sp, work)
        else:
            t_out = t + out_dt
            while t_step < t_out - 1e-12:
                h = h_prop
                for i in range(cands.shape[0]):
                    for j in range(cands.shape[1]):
                        cand_save[i, j] = cands[i, j]
                for st in range(1, 7):
                    # each state's stage sum in one pass, its terms in the order j = 0.. from 0.0 as before,
                    # written out per stage like the error and the continuous extension below: one pass over
                    # the states per term took 19 % more instructions (docs/performance.md)
                    if st == 1:
                        for i in range(n):
                            xt[i] = x[i] + h * (0.0 + _A[1, 0] * k0[i])
                    elif st == 2:
                        for i in range(n):
                            xt[i] = x[i] + h * (0.0 + _A[2, 0] * k0[i] + _A[2, 1] * k1[i])
                    elif st == 3:
                        for i in range(n):
                            xt[i] = x[i] + h * (0.0 + _A[3, 0] * k0[i] + _A[3, 1] * k1[i] + _A[3, 2] * k2[i])
                    elif st == 4:
                        for i in range(n):
                            xt[i] = x[i] + h * (0.0 + _A[4, 0] * k0[i] + _A[4, 1] * k1[i] + _A[4, 2] * k2[i]
                                                + _A[4, 3] * k3[i])
                    elif st == 5:
                        for i in range(n):
                            xt[i] = x[i] + h * (0.0 + _A[5, 0] * k0[i] + _A[5, 1] * k1[i] + _A[5, 2] * k2[i]
                                                + _A[5, 3] * k3[i] + _A[5, 4] * k4[i])
                    else:
                        for i in range(n):
                            xt[i] = x[i] + h * (0.0 + _A[6, 0] * k0[i] + _A[6, 1] * k1[i] + _A[6, 2] * k2[i]
                                                + _A[6, 3] * k3[i] + _A[6, 4] * k4[i] + _A[6, 5] * k5[i])
                    dyn.rhs(xt, ks[st], model, sp, buffers, st < 6)
                # xt holds the 5th-order solution (stage 7 is evaluated there: FSAL)
                err = 0.0
                for i in range(n):
                    e = (0.0 + _E[0] * k0[i] + _E[1] * k1[i] + _E[2] * k2[i] + _E[3] * k3[i] + _E[4] * k4[i]
                         + _E[5] * k5[i] + _E[6] * k6[i])
                    sc = atol[i] + rtol * max(abs(x[i]), abs(xt[i]))
                    r = h * e / sc
                    err += r * r
                err = math.sqrt(err / counted)
                if err <= 1.0 and math.isfinite(err):
                    stepper[Stepper.accepted] += 1.0
                    for i in range(n):
                        dy = xt[i] - x[i]
                        c3 = h * k0[i] - dy
                        dense[Dense.y0, i] = x[i]
                        dense[Dense.dy, i] = dy
                        dense[Dense.c3, i] = c3
                        dense[Dense.c4, i] = dy - h * k6[i] - c3
                        dense[Dense.c5, i] = h * (0.0 + _DENSE[0] * k0[i] + _DENSE[1] * k1[i] + _DENSE[2] * k2[i]
                                                  + _DENSE[3] * k3[i] + _DENSE[4] * k4[i] + _DENSE[5] * k5[i]
                                                  + _DENSE[6] * k6[i])
                        x[i] = xt[i]
                        k0[i] = k6[i]
                    t_step += h
                    stepper[Stepper.time] = t_step
                    stepper[Stepper.last_step] = h
                    _copy_rows(work.last_contact, work.out_contact)
                    follow_contact(recs, model.vp, work.last_contact)
                    if check_divergence(x, t_step, event):
                        stepper[Stepper.step] = h_prop
                        return DIVERGED, rows, t
                    fac = 5.0 if err < 1e-10 else min(5.0, 0.9 * err ** -0.2)
                    h_prop = min(h_max, h * fac)
                else:
                    stepper[Stepper.rejected] += 1.0
                    for i in range(cands.shape[0]):
                        for j in range(cands.shape[1]):
                            cands[i, j] = cand_save[i, j]
                    fac = 0.2 if not math.isfinite(err) else max(0.2, 0.9 * err ** -0.2)
                    h_prop = h * fac
                    if h_prop < h_min:
                        event[Event.time] = t_step
                        event[Event.position] = x[State.s]
                        event[Event.state_index] = -1
                        event[Event.state_value] = h_prop
                        stepper[Stepper.step] = h_prop
                        return DIVERGED, rows, t
            h_last = stepper[Stepper.last_step]
            theta = 1.0 - (t_step - t_out) / h_last
            t = t_out
            derailed, s_out = _output_row(out[rows], t, theta, n, model, sp, work)
        rows += 1
        if control.stop_on_derailment and derailed:
            stepper[Stepper.step] = h_prop
            return DERAILED, rows, t
        if s_out >= control.s_end:
            stepper[Stepper.step] = h_prop
            return END_OF_LINE, rows, t
    stepper[Stepper.step] = h_prop
    return RUNNING, rows, t
