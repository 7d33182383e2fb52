"""The ROS 2 interface of railderail: topics, QoS, core rows -> messages, messages -> dicts, time
stamps and the one way every railderail node is run (`run_node`); the nodes' parameter tables are
node_parameters.py.

The simulator node (railderail_sim/ros/node.py) publishes on these topics; the monitor, recorder,
replay, viewer, demo and benchmark of railderail_monitor use them through this module, so that
railderail_sim never imports railderail_monitor. Topics (all under /railderail/ except the clock):

| topic                            | type                             | QoS                                    |
| -------------------------------- | -------------------------------- | -------------------------------------- |
| /railderail/wheelset_states      | railderail_msgs/WheelsetStates   | samples (reliable, volatile, 5000)     |
| /railderail/contact_forces       | railderail_msgs/ContactForces    | samples                                |
| /railderail/vehicle_status       | railderail_msgs/VehicleStatus    | samples                                |
| /railderail/final_status         | railderail_msgs/VehicleStatus    | reliable, transient local, depth 1     |
| /railderail/derailment           | railderail_msgs/DerailmentEvent  | reliable, transient local, depth 1     |
| /railderail/alerts               | railderail_msgs/Alert            | reliable, transient local, depth 1000  |
| /railderail/onboard_alerts       | railderail_msgs/Alert            | the same (the monitor in measured mode)|
| /railderail/onboard_estimates    | railderail_msgs/OnboardEstimate  | samples (its estimator's)              |
| /railderail/brake_command        | railderail_msgs/BrakeCommand     | reliable, volatile, depth 10 (the      |
|                                  |                                  | speed supervision's intervention)      |
| /railderail/supervision          | std_msgs/String (JSON)           | reliable, transient local, depth 1     |
|                                  |                                  | (what the speed supervision supervises)|
| /railderail/supervision_status   | std_msgs/Float64MultiArray       | sensor data (SupervisionStatus, each   |
|                                  |                                  | sample the supervision steps)          |
| /railderail/braking_curves       | std_msgs/Float64MultiArray       | sensor data (BrakingCurves: the curves |
|                                  |                                  | to the target, about once a second)    |
| /clock                           | rosgraph_msgs/Clock              | clock QoS (best effort, depth 1); only |
|                                  |                                  | when not running at real time          |

With the simulator's `sensors` on, the on-board sensors (railderail_sim/sensors, docs/onboard.md) publish under
/railderail/sensors/ (SENSORS_NS) with the samples' QoS: their topics and messages are
railderail_sim/ros/sensor_messages.py.

The samples' QoS (SENSOR, SENSOR_SUBSCRIBER: one profile) is reliable with a deep queue, so that neither the
transport under load nor a burst before a callback runs loses a sample.
"""
from __future__ import annotations

import array
import contextlib
import importlib
import json
import signal
import sys

import numpy as np
import rclpy
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Float64MultiArray, MultiArrayDimension, String

import railderail_msgs.msg as msgs
from railderail_msgs.msg import (Alert, BrakeCommand, ContactForces, DerailmentEvent, OnboardEstimate, VehicleStatus,
                                 WheelsetStates)

from railderail_sim.record import Record
from railderail_sim.vehicle.layout import BOGIES, WHEELSETS, Body, Dof

from .. import jsonout

NS = "/railderail"
STATES = f"{NS}/wheelset_states"
FORCES = f"{NS}/contact_forces"
STATUS = f"{NS}/vehicle_status"
FINAL_STATUS = f"{NS}/final_status"
DERAILMENT = f"{NS}/derailment"
ALERTS = f"{NS}/alerts"
# the measured-mode monitor's alerts (from the on-board sensors only): a topic of their own, so that what reads
# /railderail/alerts as the ground-truth criteria's (the replay's review, the warning quality) sees only those
ONBOARD_ALERTS = f"{NS}/onboard_alerts"
# its estimator's running-gear loads, unloading and Q/P from the sensors (one message per decided stamp)
ONBOARD_ESTIMATES = f"{NS}/onboard_estimates"
# the speed supervision's emergency brake command (the monitor's), which the simulator obeys
BRAKE = f"{NS}/brake_command"
# what the speed supervision supervises (its targets, the survey's curves, its braking model and live inputs;
# supervision_setup_message), latched, sent again whenever a live input moves the targets: a recording holds it
SUPERVISION = f"{NS}/supervision"
# the speed supervision at each sample it steps (SupervisionStatus), for the driver's planning area of the views
SUPERVISION_STATUS = f"{NS}/supervision_status"
# the braking curves to the target the train must brake for, along the line (BrakingCurves), for a planning area
# that computes nothing itself (Foxglove's): sent when the target changes and about once a simulated second
BRAKING_CURVES = f"{NS}/braking_curves"
CLOCK = "/clock"

# the samples' topics (states, forces, status, the on-board sensors), publishers and subscribers alike. Reliable:
# best effort lost what the transport dropped while a reader's process waited for a core (46 of 22 765 states in a
# demo's recording; a reader held still for 1.5 s lost a tenth of what came meanwhile, reliable none); keep last,
# deep: a reader's queue holds 25 s at 200 Hz, or a short run published as fast as possible (about 2500 samples a
# second), so that a Python callback that falls behind for a while loses nothing, and the writer keeps as many to
# send again; a reader that stops reading loses the oldest instead of holding the simulator up (keep all would
# block it). Best-effort subscribers (another tool's sensor-data QoS) still match.
SENSOR = SENSOR_SUBSCRIBER = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=5000,
                                        reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
LATCHED = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
ALERT_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.TRANSIENT_LOCAL)
# a command is not latched: a node that joins later must not brake on an old one
BRAKE_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10, reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.VOLATILE)
CLOCK_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)   # what rclpy's time source subscribes with

# topic -> (ROS type name, message class, publisher QoS, subscriber QoS)
TOPICS = {
    STATES: ("railderail_msgs/msg/WheelsetStates", WheelsetStates, SENSOR, SENSOR_SUBSCRIBER),
    FORCES: ("railderail_msgs/msg/ContactForces", ContactForces, SENSOR, SENSOR_SUBSCRIBER),
    STATUS: ("railderail_msgs/msg/VehicleStatus", VehicleStatus, SENSOR, SENSOR_SUBSCRIBER),
    FINAL_STATUS: ("railderail_msgs/msg/VehicleStatus", VehicleStatus, LATCHED, LATCHED),
    DERAILMENT: ("railderail_msgs/msg/DerailmentEvent", DerailmentEvent, LATCHED, LATCHED),
    ALERTS: ("railderail_msgs/msg/Alert", Alert, ALERT_QOS, ALERT_QOS),
    BRAKE: ("railderail_msgs/msg/BrakeCommand", BrakeCommand, BRAKE_QOS, BRAKE_QOS),
    SUPERVISION: ("std_msgs/msg/String", String, LATCHED, LATCHED),
    SUPERVISION_STATUS: ("std_msgs/msg/Float64MultiArray", Float64MultiArray, SENSOR, SENSOR_SUBSCRIBER),
    BRAKING_CURVES: ("std_msgs/msg/Float64MultiArray", Float64MultiArray, SENSOR, SENSOR_SUBSCRIBER),
}
# of TOPICS, those the monitor publishes (the simulator the others)
MONITOR_TOPICS = (ALERTS, BRAKE, SUPERVISION, SUPERVISION_STATUS, BRAKING_CURVES)
CLOCK_TOPIC = ("rosgraph_msgs/msg/Clock", Clock, CLOCK_QOS, CLOCK_QOS)
ONBOARD_ALERTS_TOPIC = ("railderail_msgs/msg/Alert", Alert, ALERT_QOS, ALERT_QOS)
ONBOARD_ESTIMATES_TOPIC = ("railderail_msgs/msg/OnboardEstimate", OnboardEstimate, SENSOR, SENSOR_SUBSCRIBER)


SENSORS_NS = f"{NS}/sensors"


def count_as_subscriber(node):
    """Subscribe `node` to the wheelset states and contact forces (raw, ignored), so that a simulator
    started with `wait_for_subscribers` counts it: its latched derailment event and final status reach
    only the subscribers it knows before it ends, and at full speed it can end within a second."""
    for cls, topic in ((WheelsetStates, STATES), (ContactForces, FORCES)):
        node.create_subscription(cls, topic, lambda data: None, SENSOR, raw=True)


def message_class(type_name):
    """The Python class of a ROS type name such as 'railderail_msgs/msg/Alert'."""
    package, kind, name = type_name.split("/")
    return getattr(importlib.import_module(f"{package}.{kind}"), name)


# --- time stamps: simulation time in seconds <-> builtin_interfaces/Time ----------------------

def set_time(time_msg, seconds):
    """Set a builtin_interfaces/Time to a simulation time in seconds (exact to the nanosecond)."""
    time_msg.sec, time_msg.nanosec = divmod(int(round(seconds * 1e9)), 1_000_000_000)
    return time_msg


def stamp(message, seconds):
    """Set header.stamp of a message to a simulation time in seconds."""
    set_time(message.header.stamp, seconds)
    return message


def seconds(time_msg):
    """builtin_interfaces/Time (or anything with sec and nanosec) -> seconds."""
    return time_msg.sec + 1e-9 * time_msg.nanosec


def stamp_ns(time_msg):
    """builtin_interfaces/Time -> integer nanoseconds (what `set_time` wrote: round(seconds * 1e9))."""
    return time_msg.sec * 1_000_000_000 + time_msg.nanosec


# --- core rows -> messages --------------------------------------------------------------------

class RowConverter:
    """Messages of one output sample from the named arrays of `vehicle.simulate.output_arrays`
    (a batch of rows; `i` the row, `sample` the running sample index)."""

    def __init__(self, frame_id="track"):
        self.frame_id = frame_id

    def _header(self, message, t):
        stamp(message, t)
        message.header.frame_id = self.frame_id
        return message

    def states(self, a, i, sample):
        m = self._header(WheelsetStates(), a["time"][i])
        m.sample = sample
        m.track_position = float(a["position"][i])
        m.speed = float(a["speed"][i])
        m.curvature = float(a["curvature"][i])
        bodies = a["body_states"][i]
        m.lateral_displacement = np.ascontiguousarray(a["wheelset_lateral"][i])
        m.vertical_displacement = np.ascontiguousarray(bodies[WHEELSETS, Dof.vertical])
        m.roll = np.ascontiguousarray(a["wheelset_roll"][i])
        m.yaw = np.ascontiguousarray(bodies[WHEELSETS, Dof.yaw])
        m.attack_angle = np.ascontiguousarray(a["attack_angle"][i])
        m.wheel_lift = np.ascontiguousarray(a["wheel_lift"][i])
        return m

    def forces(self, a, i, sample):
        m = self._header(ContactForces(), a["time"][i])
        m.sample = sample
        m.track_position = float(a["position"][i])
        m.speed = float(a["speed"][i])
        m.curvature = float(a["curvature"][i])
        m.lateral_force = np.ascontiguousarray(a["lateral_force"][i])
        m.vertical_force = np.ascontiguousarray(a["vertical_force"][i])
        m.longitudinal_force = np.ascontiguousarray(a["longitudinal_force"][i])
        m.derailment_coefficient = np.ascontiguousarray(a["derailment_coefficient"][i])
        m.contact_position = np.ascontiguousarray(a["contact_position"][i])
        m.contact_angle = np.ascontiguousarray(a["contact_angle"][i])
        m.patch_length = np.ascontiguousarray(a["patch_length"][i])
        m.patch_width = np.ascontiguousarray(a["patch_width"][i])
        m.contact_count = np.ascontiguousarray(a["contact_count"][i], dtype=np.uint8)
        return m

    def status(self, a, i, sample, state=VehicleStatus.STATE_RUNNING, message=""):
        m = self._header(VehicleStatus(), a["time"][i])
        m.sample = sample
        m.track_position = float(a["position"][i])
        m.speed = float(a["speed"][i])
        m.section = int(a["section"][i])
        m.curvature = float(a["curvature"][i])
        m.cant = float(a["cant"][i])
        m.uncompensated_lateral_acceleration = float(a["uncompensated_acceleration"][i])
        b = a["body_states"][i]
        body = b[Body.car_body]
        m.car_body_lateral_displacement = float(body[Dof.lateral])
        m.car_body_vertical_displacement = float(body[Dof.vertical])
        m.car_body_roll = float(body[Dof.roll])
        m.car_body_yaw = float(body[Dof.yaw])
        m.bogie_lateral_displacement = np.ascontiguousarray(b[BOGIES, Dof.lateral])
        m.bogie_roll = np.ascontiguousarray(b[BOGIES, Dof.roll])
        m.bogie_yaw = np.ascontiguousarray(b[BOGIES, Dof.yaw])
        m.state = state
        m.message = message
        return m


def derailment_message(event, car_body_position, frame_id="track"):
    """DerailmentEvent from `Simulation.derailment()` (track_position: the car-body centre)."""
    m = DerailmentEvent()
    stamp(m, event["time_s"])
    m.header.frame_id = frame_id
    m.wheelset = event["wheelset"]
    m.wheel_side = event["wheel_side"]
    m.rail_side = event["rail_side"]
    m.mechanism = event["mechanism"]
    m.track_position = float(car_body_position)
    m.speed = event["speed_kmh"] / 3.6
    m.wheel_lift = event["wheel_lift_m"]
    m.lateral_displacement = event["lateral_displacement_m"]
    m.attack_angle = event["attack_angle_rad"]
    m.contact_position = event["contact_position_m"]
    return m


# --- messages -> dicts ------------------------------------------------------------------------

class SupervisionStatus(Record):
    """The speed supervision at one sample, as a driver's planning area shows it (a display's record: its speeds
    in km/h, as the driver reads them). The target is the one the train must brake for now: the one whose last
    braking point at this speed comes first (0 s inside it), or, when the train needs to brake for none, the
    next one ahead below the limit in force."""
    time_s = "s", "the sample's time"
    front_m = "m", "the train's front (its leading wheelset) along the line as supervised (the odometer's estimate)"
    position_error_m = "m", "half the odometer's confidence interval of the front (0 on ground truth)"
    speed_kmh = "km/h", "the speed supervised"
    level = "-", "0 none, 1 indication, 2 warning, 3 intervention (the emergency brake command)"
    limit_kmh = "km/h", "the lowest target speed in force at the front (NaN: none)"
    target_start_m = "m", "the target's start (NaN: no target ahead)"
    target_end_m = "m", "the target's end"
    target_speed_kmh = "km/h", "the target's speed limit"
    margin_kmh = "km/h", "the target's speed limit less the speed (negative: over it)"
    time_to_intervention_s = "s", "to the target's last braking point (EBI) at this speed; 0 inside it; inf: none"
    braking = "-", "1 while the emergency brake is commanded, else 0"


def supervision_status_message(row):
    """A SupervisionStatus row (float64 array) as its Float64MultiArray, the dimension labelled with the fields."""
    message = Float64MultiArray()
    message.layout.dim = [MultiArrayDimension(label=",".join(SupervisionStatus.names()), size=len(row), stride=len(row))]
    message.data = [float(x) for x in row]
    return message


def supervision_status_dict(message):
    """{field: value} of a SupervisionStatus message."""
    return {name: float(v) for name, v in zip(SupervisionStatus.names(), message.data)}


class BrakingCurves(Record):
    """The braking curves to SupervisionStatus's target (the one the train must brake for) as a driver's planning
    area draws them: a row of samples along the line per field (speeds in km/h, as the driver reads them), the
    same number in each; no samples once no target is ahead. From the target's start on, each curve is its
    ceiling (ETCS's ceiling supervision inside a target); NaN: above the area's top speed. The curves are the
    supervisor's (railderail_monitor/supervision/curves.py, docs/supervision.md), without the odometer's speed
    error."""
    position_m = "m", ("the front along the line: from where it is now (the first sample) to the target's start, "
                       "closer together towards it, then over the target to its end (its start twice)")
    speed_kmh = "km/h", "the speed supervised at the first sample (the train now); NaN at the others"
    ebd_kmh = "km/h", "the emergency brake deceleration curve (EBD), down to the target's speed plus dV_ebi"
    ebi_kmh = "km/h", "the emergency brake intervention (EBI): the EBD less the brake build-up's run"
    sbi_kmh = "km/h", "the service brake intervention (SBI): T_bs ahead of the EBI"
    warning_kmh = "km/h", "the warning: T_warning ahead of the SBI"
    permitted_kmh = "km/h", "the permitted speed (the driver's curve): T_driver ahead of the SBI"
    indication_kmh = "km/h", "the indication: T_indication ahead of the permitted speed"


def braking_curves_message(rows):
    """BrakingCurves rows (a float array, fields x samples) as their Float64MultiArray: data row after row, the
    first dimension labelled with the fields, the second `sample`."""
    fields, n = rows.shape
    message = Float64MultiArray()
    message.layout.dim = [MultiArrayDimension(label=",".join(BrakingCurves.names()), size=fields, stride=fields * n),
                          MultiArrayDimension(label="sample", size=n, stride=n)]
    message.data = array.array("d", np.ascontiguousarray(rows, dtype=float).tobytes())
    return message


def braking_curves_dict(message):
    """{field: array of the samples} of a BrakingCurves message."""
    n = message.layout.dim[1].size
    data = np.asarray(message.data, dtype=float)
    return {name: data[k * n:(k + 1) * n] for k, name in enumerate(BrakingCurves.names())}


def supervision_setup_message(setup):
    """The speed supervision's setup (a JSON-able dict) as its std_msgs/String."""
    message = String()
    message.data = jsonout.dumps(setup)
    return message


def alert_dict(message):
    """An Alert message (rclpy's, or mcap_ros2's from a recording) as the plain dict of the
    monitor's AlertRecord."""
    return dict(time_s=seconds(message.header.stamp), sample=int(message.sample), criterion=message.criterion,
                severity=int(message.severity), value=float(message.value), threshold=float(message.threshold),
                wheelset=int(message.wheelset), wheel_side=message.wheel_side, rail_side=message.rail_side,
                track_position=float(message.track_position), speed=float(message.speed), message=message.message)


def derailment_dict(message):
    """A DerailmentEvent message as a dict (time_s, track_position_m of the car-body centre, ...)."""
    return dict(time_s=seconds(message.header.stamp), track_position_m=float(message.track_position),
                wheelset=int(message.wheelset), wheel_side=message.wheel_side, rail_side=message.rail_side,
                mechanism=message.mechanism, speed_kmh=float(message.speed) * 3.6,
                wheel_lift_m=float(message.wheel_lift), lateral_displacement_m=float(message.lateral_displacement),
                attack_angle_rad=float(message.attack_angle), contact_position_m=float(message.contact_position))


# --- the simulator's run report ------------------------------------------------------------------

RUN_REPORT = "run report: "     # the simulator node's last log line: this, then one JSON object


def run_report_line(published, achieved_rate, requested_rate):
    """The simulator's last log line: messages published per topic, achieved and requested samples per wall
    second (requested 0: as fast as possible); what a recording and a monitor are checked against."""
    return RUN_REPORT + json.dumps(dict(published=dict(sorted(published.items())),
                                        achieved_samples_per_s=round(achieved_rate, 3),
                                        requested_samples_per_s=requested_rate))


def run_report(log_text):
    """The run report of a simulator log (run_report_line's dict), or None when the log has none."""
    line = next((line for line in reversed(log_text.splitlines()) if RUN_REPORT in line), None)
    return None if line is None else json.loads(line.split(RUN_REPORT, 1)[1])


# --- running a node -------------------------------------------------------------------------------

SPIN_PERIOD_S = 0.1       # the longest a node waits for work before it looks at Ctrl-C again

# run_node's Ctrl-C and SIGTERM: None, raised at once as KeyboardInterrupt (run_node's handler outside a hold);
# False, held (`_held_signals`): noted here, not raised; True, one came while held
_held = None


def _interrupt(signum, frame):
    global _held
    if _held is None:
        raise KeyboardInterrupt
    _held = True


@contextlib.contextmanager
def _held_signals():
    """Ctrl-C and SIGTERM (run_node's handler) noted, not raised, inside the block; one that came is raised as
    KeyboardInterrupt when the block ends. Raised in a Python callback of rclpy's events executor, a
    KeyboardInterrupt leaves its C++ side inconsistent: one that landed while it took the node's entities in
    (the first entities' callbacks registered, the set not yet recorded) made its destructor abort the process
    (SIGABRT, "Destroying callback manager with callbacks remaining": the monitor in CI; 3 Ctrl-Cs in 60 just
    after the start on two busy cores)."""
    global _held
    if _held is not None:           # already held: the outer block raises
        yield
        return
    _held = False
    try:
        yield
    finally:
        came, _held = _held, None
    if came:
        raise KeyboardInterrupt


def spin_until(executor, until=None):
    """Spin until `until()` is true (default: until Ctrl-C), waiting at most SPIN_PERIOD_S at a time:
    without rclpy's signal handlers (`run_node`) a wait is not woken by a signal, so a Ctrl-C is taken
    at the next period. Under run_node a Ctrl-C or SIGTERM is held while the executor runs and raised
    (KeyboardInterrupt) between two spins, never inside the executor."""
    with _held_signals():
        while _held is not True and (until is None or not until()):
            executor.spin_once(timeout_sec=SPIN_PERIOD_S)


def events_executor(context=None):
    """rclpy's events executor (rclpy.experimental, its dispatch in C++): about 20 us a message against
    the single-threaded executor's 120 (an empty callback on sensor_msgs/Imu, measured here), for a node
    that takes thousands of messages a second (the measured-mode monitor: the shipped sensors send about
    3800 a second at real time). Not the recorder's: with its timers, a Ctrl-C left it spinning (13 times in 14 on
    2026-12-06; before the signals were held while it was built, it aborted, SIGABRT). A KeyboardInterrupt must not
    be raised inside it (`_held_signals`)."""
    from rclpy.experimental import EventsExecutor
    return EventsExecutor(context=context)


def run_node(prog, make_node, args=None, spin=None, executor_class=SingleThreadedExecutor):
    """Run one node as every railderail node runs, and return the process's exit status.

    rclpy.init(args); `make_node()` builds the node (a ValueError or a refused parameter: one line
    `prog: error: ...` on stderr, status 2; a RuntimeError, e.g. the model diverging on its first
    period: the same line, status 1); then `spin(node, executor)` (default: spin until shut down;
    its return value is the status). Ctrl-C or SIGTERM ends it cleanly with status 0. The node runs
    on an executor of its own (`executor_class`, rclpy's single-threaded one unless a node needs
    `events_executor`), shut down before the node and the context (rclpy's global one would be torn down
    at interpreter exit, after them); the node's `destroy_node` is where it finishes
    its work (closes its file, prints its summary).

    Signals are Python's, not rclpy's: rclpy's handlers shut the context down from a thread of their
    own while the node may still be using it, which made a Ctrl-C at start end in "rcl_shutdown already
    called" or a segmentation fault (CI, twice); here Ctrl-C and SIGTERM raise KeyboardInterrupt in the
    main thread, and the context is shut down there. They are raised at once while the node is built (a
    Ctrl-C then ends the process without the node's summary); from then on they are held while the executor
    is made and takes the node in and while `spin_until` runs it (taken between two spins, at most
    SPIN_PERIOD_S later: never inside rclpy's events executor, `_held_signals`), and ignored while the
    executor, the node and the context are torn down (a second Ctrl-C does not cut that short: a
    KeyboardInterrupt in the executor's shutdown would leave the node undestroyed)."""
    global _held
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    # SIGINT only where Python raises KeyboardInterrupt for it (not where it is ignored: a background job's)
    signals = [signal.SIGTERM] + [signal.SIGINT] * (signal.getsignal(signal.SIGINT) is signal.default_int_handler)
    previous = {signum: signal.signal(signum, _interrupt) for signum in signals}
    executor = node = None
    try:  # from here on, Ctrl-C (KeyboardInterrupt) or SIGTERM ends the node cleanly
        try:
            node = make_node()
        except (ValueError, ParameterException) as error:
            print(f"{prog}: error: {error}", file=sys.stderr)
            return 2
        except RuntimeError as error:
            print(f"{prog}: error: {error}", file=sys.stderr)
            return 1
        # the executor made after the node and Ctrl-C held while it takes the node in: with rclpy's events
        # executor made first, one Ctrl-C in ten just after the start aborted the process (SIGABRT); none of 42
        # tries so (2026-12-04, with the signals blocked in this thread). Not enough alone: the executor takes the
        # node's entities in at its first spin, where Ctrl-C is held too (`spin_until`)
        held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        try:
            with _held_signals():
                executor = executor_class()
                executor.add_node(node)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, held)
        if spin is None:
            spin_until(executor)
            return 0
        return spin(node, executor)
    except (KeyboardInterrupt, ExternalShutdownException):
        return 0
    finally:
        _held = False      # a signal from here on is noted and dropped: the teardown is not interrupted
        try:
            if executor is not None:
                executor.shutdown()
                # dropped here, while the node and the context still exist, not when run_node's frame goes
                executor = None
            if node is not None:
                node.destroy_node()
            rclpy.try_shutdown()
        finally:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
            _held = None


__all__ = ["msgs", "TOPICS", "RowConverter", "derailment_message", "alert_dict", "derailment_dict", "run_node",
           "spin_until"]
