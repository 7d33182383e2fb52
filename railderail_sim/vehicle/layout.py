"""Layouts of the vehicle core's arrays (`record.Record`): the state vector, the body and force-element
tables, the vehicle constants and the output row.

Bodies 0..6: the car body, the front and rear bogie frames, wheelsets 0..3 from the front. Each body
moves relative to the track frame at its own station (docs/vehicle-model.md). Wheelsets: the `pitch`
position of a wheelset is unused and stays zero; its `pitch` velocity is the wheelset's spin about
its axle (rad/s, about v / r0), a degree of freedom driven by the contact forces.
"""
import enum

from ..contact.layout import Wheel
from ..loads.layout import AeroLoad
from ..record import Record
from ..track.layout import RailDof


class Body(enum.IntEnum):
    car_body = 0
    front_bogie = 1
    rear_bogie = 2
    wheelset_0 = 3
    wheelset_1 = 4
    wheelset_2 = 5
    wheelset_3 = 6


N_BODY = len(Body)
CAR_BODY = int(Body.car_body)
BOGIES = (int(Body.front_bogie), int(Body.rear_bogie))
WHEELSETS = tuple(int(b) for b in Body if b >= Body.wheelset_0)
N_WHEELSET = len(WHEELSETS)
N_WHEEL = 2 * N_WHEELSET                 # wheel 2 i + 0 left, 2 i + 1 right of wheelset i
RUNNING_GEARS = ((0, 1), (2, 3))         # the wheelsets of the front and the rear bogie
N_DAMPER = 8                             # 4 yaw dampers + 2 lateral dampers as mirrored pairs of halves


def running_gear_sides(per_wheel):
    """The mean over each bogie's two wheels on one side of a per-wheel quantity, (..., 8) wheels
    [wheelset 0 left, wheelset 0 right, ...] -> (..., 4) [front bogie left, front right, rear left, rear
    right] (EN 14067-6 evaluates the wheel unloading of a running gear so)."""
    import numpy as np
    q = np.asarray(per_wheel, dtype=float)
    return np.stack([0.5 * (q[..., 2 * a + side] + q[..., 2 * b + side]) for a, b in RUNNING_GEARS for side in (0, 1)],
                    axis=-1)


class Dof(Record):
    """A body's degrees of freedom relative to the track frame at its station (positions), or their
    absolute rates in track axes (velocities)."""
    lateral = "m; m/s", "lateral, + left"
    vertical = "m; m/s", "vertical, + up"
    roll = "rad; rad/s", "roll about the track x axis"
    pitch = "rad; rad/s", "pitch about the track y axis (wheelsets: unused position; spin rate)"
    yaw = "rad; rad/s", "yaw about the track z axis"


N_DOF = Dof.size()


class State(Record):
    """The state vector x of the core."""
    positions = "m, rad", "each body's displacement relative to the track frame at its station", (N_BODY,), Dof
    velocities = ("m/s, rad/s", "each body's absolute velocity of its reference point and absolute angular "
                  "velocity, in track axes", (N_BODY,), Dof)
    dampers = "m", "elongation of the damper part of each series spring-damper element", (N_DAMPER,)
    s = "m", "distance of the car-body centre along the line"
    rail_deflections = ("m, rad", "each wheel's co-running rail: its deflection (track.elastic; frozen at zero on "
                        "rigid track)", (N_WHEEL,), RailDof)
    rail_rates = "m/s, rad/s", "the rates of the rail deflections", (N_WHEEL,), RailDof


N_STATE = State.size()


class Vector(Record):
    """Components of a vector (a point, a stiffness or a force) in a table or scratch row."""
    x = "-", "x component"
    y = "-", "y component"
    z = "-", "z component"


class BodyTable(Record):
    """A row of the body table."""
    mass = "kg", "mass"
    roll_inertia = "kg m^2", "inertia about the body's x axis"
    pitch_inertia = "kg m^2", "inertia about its y axis (wheelsets: about the axle)"
    yaw_inertia = "kg m^2", "inertia about its z axis"
    station = "m", "longitudinal position of the reference point from the car-body centre, + forward"
    height = "m", "height of the reference point above the rail top"
    is_wheelset = "-", "1 for a wheelset, 0 otherwise"


class Bushing(Record):
    """A spring-damper between coincident points of two bodies; stiffness and damping in body a's axes."""
    body_a = "-", "index of body a"
    body_b = "-", "index of body b"
    point_a = "m", "the point in body a's coordinates (from its reference point)", (), Vector
    point_b = "m", "the same point in body b's coordinates", (), Vector
    stiffness = "N/m", "stiffness along x, y, z", (), Vector
    damping = "N s/m", "damping along x, y, z", (), Vector
    preload = "N", "force on body b at the nominal position, in body a's axes", (), Vector


class Damper(Record):
    """A two-point damper: force along the line between its points, two-stage law, optional series spring."""
    body_a = "-", "index of body a"
    body_b = "-", "index of body b"
    point_a = "m", "end point in body a's coordinates", (), Vector
    point_b = "m", "end point in body b's coordinates", (), Vector
    knee_velocity = "m/s", "knee (blow-off) velocity"
    damping = "N s/m", "damping below the knee"
    damping_after_knee = "N s/m", "damping beyond the knee"
    series_stiffness = "N/m", "series stiffness of the end fittings, 0 = none"
    length = "m", "nominal length"
    state = "-", "index of its elongation state in the state vector"


BUMP_POINTS = 8                          # points of a bump stop's force law at most
LATERAL = 1                              # BumpStop.axis: body a's y axis
VERTICAL = 2                             # BumpStop.axis: body a's z axis


class BumpStop(Record):
    """A travel limit between coincident points: along one axis of body a, the relative displacement d of
    body b's point from body a's meets the stop beyond a clearance on either side (inf: no stop on that
    side); the force then follows the row's piecewise-linear law of |d|, from zero at the clearance through
    the (travel, force) points, the last slope continuing beyond the last point, and pushes d back."""
    body_a = "-", "index of body a"
    body_b = "-", "index of body b"
    point_a = "m", "the point in body a's coordinates", (), Vector
    point_b = "m", "the same point in body b's coordinates", (), Vector
    axis = "-", "the axis of the travel in body a's axes: LATERAL (1, y) or VERTICAL (2, z)"
    clearance_negative = "m", "free travel for d < 0 (inf: no stop on that side)"
    clearance_positive = "m", "free travel for d > 0 (inf: no stop on that side)"
    points = "-", "number of points of the force law"
    travel = "m", "|d| at each point of the force law (measured from the nominal position)", (BUMP_POINTS,)
    force = "N", "force at each point of the force law", (BUMP_POINTS,)


class AntiRollBar(Record):
    """An anti-roll bar: a roll moment proportional to the relative roll of two bodies."""
    body_a = "-", "index of body a"
    body_b = "-", "index of body b"
    stiffness = "N m/rad", "roll stiffness"


class VehicleConstants(Record):
    """The vehicle constants array vp of the core."""
    gravity = "m/s^2", "gravity"
    rolling_radius = "m", "nominal rolling radius"
    spin_inertia = "kg m^2", "wheelset spin inertia"
    flange_height = "m", "flange height above the nominal rolling circle"
    flange_contact_angle = "rad", "a contact steeper than this is on the flange: half the wheel's flange angle"
    lift_tolerance = "m", "wheel lift short of the flange height at which a climbing wheel counts as derailed"


class WheelsetOutput(Record):
    """What the output row gives of each wheelset."""
    wheelset_lateral = "m", "lateral displacement from the middle of the two rails, + left"
    attack_angle = "rad", "yaw to the mean direction of the two rails, + front toward the outer rail"
    wheelset_roll = "rad", "roll relative to the track"


class BodyMotion(Record):
    """What an ideal accelerometer and gyro at a body's reference point measure, in the track axes at its
    station (vehicle.motion carries them to any point of the body and into its axes)."""
    specific_force = ("m/s^2", "specific force F/m (the acceleration minus gravity: what an accelerometer reads; "
                      "+g up at rest) of the reference point", (), Vector)
    angular_velocity = "rad/s", "absolute angular velocity (wheelsets: of the axle boxes, without the spin)", (), Vector
    angular_acceleration = "rad/s^2", "absolute angular acceleration (the inertial rate of angular_velocity)", (), \
        Vector


class OutputRow(Record):
    """One output sample of the core."""
    time = "s", "simulated time"
    position = "m", "distance s of the car-body centre along the line"
    speed = "m/s", "forward speed"
    section = "-", "0 straight, 1 transition, 2 circular curve"
    curvature = "1/m", "signed curvature at the car-body centre, + left"
    cant = "rad", "cant angle (magnitude)"
    uncompensated_acceleration = "m/s^2", "in the track plane, + toward the outside of the curve"
    body_states = "m, rad", "every body's position, as in the state vector", (N_BODY,), Dof
    wheelsets = "-", "each wheelset's pose relative to the rails", (N_WHEELSET,), WheelsetOutput
    wheels = "-", "each wheel's contact record, [wheelset 0 left, wheelset 0 right, ...]", (N_WHEEL,), Wheel
    rails = "m, rad", "each wheel's rail deflection (elastic track; zero on rigid track)", (N_WHEEL,), RailDof
    aerodynamics = "-", "the wind and its load on the car body (zero without wind)", (), AeroLoad
    body_motion = "-", "every body's specific force and angular motion (ideal inertial sensors)", (N_BODY,), BodyMotion


N_OUT = OutputRow.size()
