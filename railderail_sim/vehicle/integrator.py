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
import math

import numpy as np

from ..jit import core
from ..contact import geometry as geo
from ..contact import kik_piotrowski as kp
from ..contact import wheelset as ws
from ..track import alignment as trk
from . import dynamics as dyn
from . import layout as L

RUNNING, DERAILED, DIVERGED, END_OF_LINE = 0, 1, 2, 3
MECH_FLANGE_CLIMBING, MECH_WHEEL_UNLOADING = 1, 2

# event array: what happened when advance stopped
EV_T, EV_S, EV_WHEELSET, EV_SIDE, EV_MECH, EV_LIFT, EV_LATERAL, EV_SPEED, EV_INDEX, EV_VALUE = range(10)
EV_SIZE = 10

# limits beyond which the integration has run away (not a physical state of a car on or near the track)
LIMIT_DISPLACEMENT = 0.5       # m, any lateral/vertical body displacement
LIMIT_ANGLE = 0.5              # rad
LIMIT_VELOCITY = 30.0          # m/s, lateral/vertical
LIMIT_RATE = 60.0              # rad/s
LIMIT_DAMPER = 0.5             # m
LIMIT_SPIN = 1000.0            # rad/s, a wheelset's spin (about 240 rad/s at 400 km/h)

N_OUT = L.O_WHEEL + 8 * ws.W_SIZE


def workspace(cg):
    """Preallocated work arrays of `advance` (reused between calls)."""
    nw = int(cg[geo.H_NW])
    return dict(ks=np.zeros((7, L.N_STATE)), xt=np.zeros(L.N_STATE), hstate=np.array([1e-4, 0.0, 0.0]),
                cand_save=np.zeros((8, 1 + geo.MAX_CANDIDATES)), kin=np.zeros((L.N_BODY, dyn.K_COLS)),
                gap=np.zeros(nw), ys=np.zeros(nw), patches=np.zeros((geo.MAX_PATCHES, geo.P_COLS)),
                cands=np.zeros((8, 1 + geo.MAX_CANDIDATES)), kpbuf=np.zeros((4, nw)),
                kpid=np.zeros(nw, dtype=np.int64), kprow=np.zeros((1, kp.NPROP)),
                recs=np.zeros((8, ws.W_SIZE)),
                event=np.zeros(EV_SIZE))


@core
def _rhs(x, dx, bodies, vp, bush, damp, bump, arb, track, sp, cg, cp, kin, gap, ys, patches, cands,
         tracked, kpbuf, kpid, kprow, recs):
    return dyn.rhs(x, dx, bodies, vp, bush, damp, bump, arb, track, sp, cg, cp, kin, gap, ys, patches,
                   cands, tracked, kpbuf, kpid, kprow, recs)


@core
def fill_row(row, t, x, v, bodies, vp, track, recs):
    """One output row from the state and the wheel records of the same instant."""
    s = x[L.I_S]
    kap, _ = trk.curvature(track, s)
    roll, _ = trk.cant(track, s)
    direction = track[trk.I_DIR]
    row[L.O_T] = t
    row[L.O_S] = s
    row[L.O_V] = v
    row[L.O_SECTION] = trk.section(track, s)
    row[L.O_CURV] = kap
    row[L.O_CANT] = abs(roll)
    # uncompensated lateral acceleration in the track plane, + toward the outside of the curve
    row[L.O_ANC] = direction * (v * v * kap * math.cos(roll) + vp[L.V_G] * math.sin(roll))
    for i in range(L.N_BODY * L.N_DOF):
        row[L.O_BODY + i] = x[i]
    for w in range(4):
        b = L.WHEELSETS[w]
        o = L.N_DOF * b
        yd, dyd = trk.lateral_defect(track, s + bodies[b, L.B_STATION])
        row[L.O_WS + 3 * w] = x[o] - yd
        # attack angle: + when the front of the wheelset points toward the outer rail
        row[L.O_WS + 3 * w + 1] = -direction * (x[o + 4] - dyd)
        row[L.O_WS + 3 * w + 2] = x[o + 2]
    for k in range(8):
        o = L.O_WHEEL + k * ws.W_SIZE
        for q in range(ws.W_SIZE):
            row[o + q] = recs[k, q]


@core
def _check_derailment(x, v, t, vp, bodies, recs, event):
    """The paper's geometric criterion, per wheel (docs/methods.md): True and `event` filled if met.

    flange climbing: lift >= flange height - tolerance and the wheelset displaced toward that wheel's rail
    by at least the displacement that puts the flange tip over the rail's highest point;
    wheel unloading (lift-off / overturning): lift >= flange height on a wheel not climbing its rail.
    """
    hf = vp[L.V_FLANGE_HEIGHT]
    tol = vp[L.V_LIFT_TOLERANCE]
    yclimb = vp[L.V_CLIMB_DISPLACEMENT]
    for w in range(4):
        b = L.WHEELSETS[w]
        y = x[L.N_DOF * b]
        for side in range(2):
            lift = recs[2 * w + side, ws.W_LIFT]
            toward = y if side == 0 else -y
            mech = 0
            if lift >= hf - tol and toward >= yclimb:
                mech = MECH_FLANGE_CLIMBING
            elif lift >= hf:
                mech = MECH_WHEEL_UNLOADING
            if mech > 0:
                event[EV_T] = t
                event[EV_S] = x[L.I_S] + bodies[b, L.B_STATION]
                event[EV_WHEELSET] = w
                event[EV_SIDE] = side
                event[EV_MECH] = mech
                event[EV_LIFT] = lift
                event[EV_LATERAL] = y
                event[EV_SPEED] = v
                return True
    return False


@core
def _check_divergence(x, t, event):
    bad = -1
    for i in range(L.N_STATE):
        if not math.isfinite(x[i]):
            bad = i
            break
    if bad < 0:
        for b in range(L.N_BODY):
            o = L.N_DOF * b
            ov = L.I_VEL + o
            for k in range(L.N_DOF):
                lim_p = LIMIT_DISPLACEMENT if k < 2 else LIMIT_ANGLE
                lim_v = LIMIT_VELOCITY if k < 2 else LIMIT_RATE
                if k == 3 and b >= L.WHEELSETS[0]:
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
        for i in range(L.I_DAMPER, L.I_DAMPER + L.N_DAMPER):
            if abs(x[i]) > LIMIT_DAMPER:
                bad = i
                break
    if bad < 0:
        return False
    event[EV_T] = t
    event[EV_S] = x[L.I_S]
    event[EV_INDEX] = bad
    event[EV_VALUE] = x[bad]
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
def advance(x, t, duration, out_dt, first_row, hstate, s_end, stop_on_derailment, atol, rtol, h_min, h_max,
            bodies, vp,
            bush, damp, bump, arb, track, sp, cg, cp, ks, xt, cand_save, kin, gap, ys, patches, cands, kpbuf,
            kpid, kprow, recs, event, out):
    """Advance x in place over `duration` s from time t (a multiple of out_dt) with Dormand-Prince 5(4).

    Adaptive steps under the error control (atol per state, rtol) land exactly on every output instant;
    a row is written after every output interval, and at the start if `first_row` (the state and wheel
    records of that instant). The last stage of each step (FSAL) searches the wheel-rail contact in full at the new
    state; the inner stages follow the contacts found there (`geometry.track_patches`). hstate keeps the
    step size between calls and counts the accepted and rejected steps. Stops early at END_OF_LINE, DERAILED (if stop_on_derailment) or
    DIVERGED (state out of bounds, not finite, or step below h_min); `event` says when, where, what.
    Returns (status, rows_written, t).
    """
    n = x.shape[0]
    rows = 0
    nout = out.shape[0]
    k0 = ks[0]
    v = _rhs(x, k0, bodies, vp, bush, damp, bump, arb, track, sp, cg, cp, kin, gap, ys, patches, cands,
             False, kpbuf, kpid, kprow, recs)
    n_intervals = int(round(duration / out_dt))
    h_prop = hstate[0]
    for interval in range(n_intervals + 1):
        if (interval > 0 or first_row) and rows < nout:
            fill_row(out[rows], t, x, v, bodies, vp, track, recs)
            rows += 1
        if stop_on_derailment and _check_derailment(x, v, t, vp, bodies, recs, event):
            hstate[0] = h_prop
            return DERAILED, rows, t
        if x[L.I_S] >= s_end:
            hstate[0] = h_prop
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
                for i in range(n):
                    acc = 0.0
                    for j in range(st):
                        acc += _A[st, j] * ks[j, i]
                    xt[i] = x[i] + h * acc
                full = st == 6
                vt = _rhs(xt, ks[st], bodies, vp, bush, damp, bump, arb, track, sp, cg, cp, kin, gap, ys,
                          patches, cands, not full, kpbuf, kpid, kprow, recs)
            # xt holds the 5th-order solution (stage 7 is evaluated there: FSAL)
            err = 0.0
            for i in range(n):
                e = 0.0
                for j in range(7):
                    e += _E[j] * ks[j, i]
                sc = atol[i] + rtol * max(abs(x[i]), abs(xt[i]))
                r = h * e / sc
                err += r * r
            err = math.sqrt(err / n)
            if err <= 1.0 and math.isfinite(err):
                hstate[1] += 1.0
                for i in range(n):
                    x[i] = xt[i]
                    k0[i] = ks[6, i]
                t = t_target if clipped else t + h
                v = vt
                if _check_divergence(x, t, event):
                    hstate[0] = h_prop
                    return DIVERGED, rows, t
                fac = 5.0 if err < 1e-10 else min(5.0, 0.9 * err ** -0.2)
                # a step shortened to land on the output instant says nothing against the longer one
                h_prop = min(h_max, max(h * fac, h_prop) if clipped else h * fac)
            else:
                hstate[2] += 1.0
                for i in range(cands.shape[0]):
                    for j in range(cands.shape[1]):
                        cands[i, j] = cand_save[i, j]
                fac = 0.2 if not math.isfinite(err) else max(0.2, 0.9 * err ** -0.2)
                h_prop = h * fac
                if h_prop < h_min:
                    event[EV_T] = t
                    event[EV_S] = x[L.I_S]
                    event[EV_INDEX] = -1
                    event[EV_VALUE] = h_prop
                    hstate[0] = h_prop
                    return DIVERGED, rows, t
    hstate[0] = h_prop
    return RUNNING, rows, t
