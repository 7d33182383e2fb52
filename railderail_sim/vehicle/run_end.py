"""What ends a run of the stepper (`integrator.advance`) before its line does, checked at each output instant
and each accepted step: the derailment (the paper's geometric criterion, per wheel, `check_derailment`, with
where each wheel last touched its rail, `follow_contact`) and the divergence guard (a state beyond what a car
on or near the track can reach, `check_divergence`); the Event record that says what happened."""
import math

from ..contact.layout import WP_SIZE, Wheel, WheelPatch
from ..jit import core
from ..record import Record
from ..track import alignment as trk, rails
from ..track import elastic as track_elastic
from ..track.layout import N_RAIL_DOF, RailDof
from .layout import BodyTable, Dof, N_BODY, N_DAMPER, N_DOF, N_STATE, N_WHEEL, N_WHEELSET, State, VehicleConstants, WHEELSETS

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
    """Where a wheel last touched its rail (kept while it is off the rail, `follow_contact`)."""
    on_flange = "-", ("1 if the wheel was on its flange: a loaded patch steeper than the flange_contact_angle, or "
                      "still loaded and lifted by more than the lift_tolerance since it was")
    contact_position = "m", "the main patch's point on the rail, from the head axis, + field side"


# limits beyond which the integration has run away (not a physical state of a car on or near the track)
LIMIT_DISPLACEMENT = 0.5       # m, any lateral/vertical body displacement
LIMIT_ANGLE = 0.5              # rad
LIMIT_VELOCITY = 30.0          # m/s, lateral/vertical
LIMIT_RATE = 60.0              # rad/s
LIMIT_DAMPER = 0.5             # m
LIMIT_RAIL = 0.05              # m, a rail's deflection (track.elastic; some mm in service)
LIMIT_SPIN = 1000.0            # rad/s, a wheelset's spin (about 240 rad/s at 400 km/h)


@core
def follow_contact(recs, vp, last):
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
def check_derailment(x, v, t, model, recs, last, event):
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
def check_divergence(x, t, event):
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
