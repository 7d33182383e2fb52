"""Topics, QoS and conversions between the core's output rows and railderail_msgs.

Topics (all under /railderail/ except the clock):

| topic                            | type                             | QoS                                    |
| -------------------------------- | -------------------------------- | -------------------------------------- |
| /railderail/wheelset_states      | railderail_msgs/WheelsetStates   | sensor data (best effort, volatile, 5) |
| /railderail/contact_forces       | railderail_msgs/ContactForces    | sensor data                            |
| /railderail/vehicle_status       | railderail_msgs/VehicleStatus    | sensor data                            |
| /railderail/final_status         | railderail_msgs/VehicleStatus    | reliable, transient local, depth 1     |
| /railderail/derailment           | railderail_msgs/DerailmentEvent  | reliable, transient local, depth 1     |
| /railderail/alerts               | railderail_msgs/Alert            | reliable, transient local, depth 1000  |
| /clock                           | rosgraph_msgs/Clock              | clock QoS (best effort, depth 1); only |
|                                  |                                  | when not running at real time          |

Subscribers of the sensor-data topics use best effort with a deeper queue (SENSOR_SUBSCRIBER) so
that a burst does not overwrite samples before the callback runs.
"""
from __future__ import annotations

import numpy as np
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data

import railderail_msgs.msg as msgs
from railderail_msgs.msg import Alert, ContactForces, DerailmentEvent, VehicleStatus, WheelsetStates

from .criteria import AlertRecord

NS = "/railderail"
STATES = f"{NS}/wheelset_states"
FORCES = f"{NS}/contact_forces"
STATUS = f"{NS}/vehicle_status"
FINAL_STATUS = f"{NS}/final_status"
DERAILMENT = f"{NS}/derailment"
ALERTS = f"{NS}/alerts"
CLOCK = "/clock"

SENSOR = qos_profile_sensor_data
SENSOR_SUBSCRIBER = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=500,
                               reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE)
LATCHED = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
ALERT_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.TRANSIENT_LOCAL)
CLOCK_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)   # what rclpy's time source subscribes with

# topic -> (ROS type name, message class, publisher QoS, subscriber QoS)
TOPICS = {
    STATES: ("railderail_msgs/msg/WheelsetStates", WheelsetStates, SENSOR, SENSOR_SUBSCRIBER),
    FORCES: ("railderail_msgs/msg/ContactForces", ContactForces, SENSOR, SENSOR_SUBSCRIBER),
    STATUS: ("railderail_msgs/msg/VehicleStatus", VehicleStatus, SENSOR, SENSOR_SUBSCRIBER),
    FINAL_STATUS: ("railderail_msgs/msg/VehicleStatus", VehicleStatus, LATCHED, LATCHED),
    DERAILMENT: ("railderail_msgs/msg/DerailmentEvent", DerailmentEvent, LATCHED, LATCHED),
    ALERTS: ("railderail_msgs/msg/Alert", Alert, ALERT_QOS, ALERT_QOS),
}


def clock_topic():
    from rosgraph_msgs.msg import Clock
    return CLOCK, ("rosgraph_msgs/msg/Clock", Clock, CLOCK_QOS, CLOCK_QOS)


def declare_parameters(node, spec):
    """Declare node parameters from {name: (default, description)} and return their values.

    A float parameter also takes an integer (`-p radius:=1000`); a value of the wrong kind is a
    ValueError naming the parameter (the nodes print it as one line)."""
    from rcl_interfaces.msg import ParameterDescriptor

    values = {}
    for name, (default, text) in spec.items():
        is_float = isinstance(default, float)
        value = node.declare_parameter(name, default, ParameterDescriptor(description=text,
                                                                          dynamic_typing=is_float)).value
        if is_float:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"parameter {name} = {value!r} is not a number ({text})")
            value = float(value)
        values[name] = value
    return values


def message_class(type_name):
    """The Python class of a ROS type name such as 'railderail_msgs/msg/Alert'."""
    import importlib
    package, kind, name = type_name.split("/")
    return getattr(importlib.import_module(f"{package}.{kind}"), name)


def stamp(message, seconds):
    """Set header.stamp to a simulation time in seconds (exact to the nanosecond)."""
    ns = int(round(seconds * 1e9))
    message.header.stamp.sec, message.header.stamp.nanosec = divmod(ns, 1_000_000_000)
    return message


def seconds(time_msg):
    """builtin_interfaces/Time (or anything with sec and nanosec) -> seconds."""
    return time_msg.sec + 1e-9 * time_msg.nanosec


# --- core rows -> messages --------------------------------------------------------------------

def sample_arrays(result):
    """The named arrays of `Result.arrays()` (views of the rows): what the simulator node converts at
    every tick."""
    return result.arrays()


class RowConverter:
    """Messages of one output sample from the named arrays of `Result.arrays()` or `sample_arrays`
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
        bodies = a["body_states"][i]
        m.lateral_displacement = np.ascontiguousarray(a["wheelset_lateral"][i])
        m.vertical_displacement = np.ascontiguousarray(bodies[3:7, 1])
        m.roll = np.ascontiguousarray(a["wheelset_roll"][i])
        m.yaw = np.ascontiguousarray(bodies[3:7, 4])
        m.attack_angle = np.ascontiguousarray(a["attack_angle"][i])
        m.wheel_lift = np.ascontiguousarray(a["wheel_lift"][i])
        return m

    def forces(self, a, i, sample):
        m = self._header(ContactForces(), a["time"][i])
        m.sample = sample
        m.track_position = float(a["position"][i])
        m.speed = float(a["speed"][i])
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
        m.car_body_lateral_displacement = float(b[0, 0])
        m.car_body_vertical_displacement = float(b[0, 1])
        m.car_body_roll = float(b[0, 2])
        m.car_body_yaw = float(b[0, 4])
        m.bogie_lateral_displacement = np.ascontiguousarray(b[1:3, 0])
        m.bogie_roll = np.ascontiguousarray(b[1:3, 2])
        m.bogie_yaw = np.ascontiguousarray(b[1:3, 4])
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
    return m


def alert_message(record: AlertRecord, frame_id="track"):
    m = Alert()
    stamp(m, record.time_s)
    m.header.frame_id = frame_id
    for name in ("sample", "criterion", "severity", "value", "threshold", "wheelset", "wheel_side", "rail_side",
                 "track_position", "speed", "message"):
        setattr(m, name, getattr(record, name))
    return m


def alert_dict(message):
    """An Alert message (rclpy or decoded from MCAP) as the plain dict of AlertRecord."""
    return dict(time_s=seconds(message.header.stamp), sample=int(message.sample), criterion=message.criterion,
                severity=int(message.severity), value=float(message.value), threshold=float(message.threshold),
                wheelset=int(message.wheelset), wheel_side=message.wheel_side, rail_side=message.rail_side,
                track_position=float(message.track_position), speed=float(message.speed), message=message.message)


def derailment_dict(message):
    """A DerailmentEvent message as a dict (time_s, track_position_m of the car-body centre, ...)."""
    return dict(time_s=seconds(message.header.stamp), track_position_m=float(message.track_position),
                wheelset=int(message.wheelset), wheel_side=message.wheel_side, rail_side=message.rail_side,
                mechanism=message.mechanism, speed_kmh=float(message.speed) * 3.6,
                wheel_lift_m=float(message.wheel_lift), lateral_displacement_m=float(message.lateral_displacement))


__all__ = ["msgs", "TOPICS", "RowConverter", "derailment_message", "alert_message", "alert_dict", "derailment_dict"]
