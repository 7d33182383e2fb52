"""railderail_msgs: built into the venv, and carried between two processes by rclpy."""
import json
import signal
import sys
import time
from pathlib import Path

import numpy as np
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions

import railderail_msgs.msg as msgs

HEADER = {"stamp": {"sec": 12, "nanosec": 345_000_000}, "frame_id": "track"}

# One message of each type, with every field set to a value that is not the default.
SAMPLES = {
    "WheelsetStates": {
        "header": HEADER,
        "track_position": 1234.5,
        "curvature": 1 / 2800,
        "lateral_displacement": [0.001, -0.002, 0.0035, -0.0045],
        "vertical_displacement": [1e-4, 2e-4, -3e-4, 4e-4],
        "roll": [0.0011, -0.0012, 0.0013, -0.0014],
        "yaw": [0.002, 0.001, -0.001, -0.002],
        "attack_angle": [0.0051, 0.0042, -0.0033, -0.0024],
        "wheel_lift": [0.0, 0.0123, 1e-5, 0.0, 0.0, 2.5e-3, 0.0, 7e-4],
    },
    "ContactForces": {
        "header": HEADER,
        "track_position": 1234.5,
        "curvature": -1 / 1000,
        "lateral_force": [-12e3, 45e3, -8e3, 30e3, -7e3, 20e3, -6e3, 10e3],
        "vertical_force": [60e3, 95e3, 62e3, 90e3, 61e3, 88e3, 63e3, 86e3],
        "longitudinal_force": [100.0, -200.0, 300.0, -400.0, 500.0, -600.0, 700.0, -800.0],
        "derailment_coefficient": [-0.2, 0.47368, -0.129, 0.333, -0.115, 0.227, -0.095, 0.116],
        "contact_position": [0.001, -0.031, 0.002, -0.029, 0.003, -0.028, 0.004, -0.027],
        "contact_angle": [0.05, 1.1, 0.04, 1.0, 0.03, 0.9, 0.02, 0.8],
        "patch_length": [0.012, 0.009, 0.011, 0.008, 0.013, 0.0095, 0.0105, 0.0085],
        "patch_width": [0.008, 0.004, 0.007, 0.0045, 0.0085, 0.005, 0.0075, 0.0055],
        "contact_count": [1, 2, 1, 2, 1, 1, 0, 1],
    },
    "VehicleStatus": {
        "header": HEADER,
        "track_position": 1234.5,
        "speed": 97.2,
        "section": msgs.VehicleStatus.SECTION_TRANSITION,
        "curvature": 1 / 2800,
        "cant": 0.0667,
        "uncompensated_lateral_acceleration": 0.71,
        "car_body_lateral_displacement": -0.012,
        "car_body_roll": 0.004,
        "state": msgs.VehicleStatus.STATE_DERAILED,
        "message": "wheelset 0 left: flange climbing",
    },
    "Alert": {
        "header": HEADER,
        "criterion": "wheel_lift",
        "severity": msgs.Alert.SEVERITY_CRITICAL,
        "value": 0.0123,
        "threshold": 0.005,
        "wheelset": 0,
        "wheel_side": "right",
        "rail_side": "outer",
        "track_position": 1234.5,
        "speed": 97.2,
    },
    "DerailmentEvent": {
        "header": HEADER,
        "wheelset": 3,
        "wheel_side": "left",
        "rail_side": "inner",
        "mechanism": "wheel_unloading",
        "track_position": 1300.25,
        "speed": 98.0,
        "wheel_lift": 0.031,
        "lateral_displacement": -0.0089,
    },
    "OnboardEstimate": {
        "header": {**HEADER, "frame_id": "car_body"},
        "wheel_load": [48e3, 74e3, 50e3, 72e3],
        "unloading": [0.31, -0.06, 0.28, -0.03],
        "lateral_force": [41e3, 12e3],
        "derailment_coefficient": [-0.43, 0.28, -0.12, 0.08],
    },
    "BrakeCommand": {
        "header": HEADER,
        "sample": 2052,
        "speed": 88.89,
        "release_speed": 70.83,
        "track_position": 1016.4,
        "reason": "curve R 1000 m: critical derailment speed 270.0 km/h (given)",
    },
}

# Runs in the child process: publishes the messages of SAMPLES (argv[1], JSON) every 0.1 s on
# test/<Type> until SIGINT or SIGTERM.
PUBLISHER = """
import json, sys
import rclpy
from rclpy.executors import ExternalShutdownException
import railderail_msgs.msg as msgs

def fill(message, values):
    for name, value in values.items():
        if isinstance(value, dict):
            fill(getattr(message, name), value)
        else:
            setattr(message, name, value)
    return message

rclpy.init()
try:
    node = rclpy.create_node("railderail_test_publisher")
    outgoing = [(node.create_publisher(getattr(msgs, name), "test/" + name, 10),
                 fill(getattr(msgs, name)(), values))
                for name, values in json.loads(sys.argv[1]).items()]
    node.create_timer(0.1, lambda: [publisher.publish(message) for publisher, message in outgoing])
    node.get_logger().info("publishing")
    rclpy.spin(node)
except (KeyboardInterrupt, ExternalShutdownException):
    pass
finally:
    rclpy.try_shutdown()
"""


def assert_fields(message, expected, path=""):
    for name, value in expected.items():
        actual = getattr(message, name)
        if isinstance(value, dict):
            assert_fields(actual, value, f"{path}{name}.")
        elif isinstance(value, list):
            assert np.asarray(actual).tolist() == value, f"{path}{name}"
        else:
            assert actual == value, f"{path}{name}"


def receive_one_of_each(names, timeout):
    """Subscribe in this process (own rclpy context) and return the first message of each type."""
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node("railderail_test_subscriber", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    received = {}
    try:
        for name in names:
            node.create_subscription(getattr(msgs, name), "test/" + name,
                                     lambda message, name=name: received.setdefault(name, message), 10)
        deadline = time.monotonic() + timeout
        while len(received) < len(names) and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.1)
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)
    return received


def test_messages_are_installed_in_the_venv():
    share = Path(sys.prefix, "share", "railderail_msgs", "msg")
    assert sorted(path.name for path in share.glob("*.msg")) == sorted(f"{name}.msg" for name in SAMPLES)
    assert msgs.VehicleStatus.STATE_FINISHED == 3
    assert msgs.Alert.SEVERITY_WARNING == 1


def test_messages_cross_processes(spawn, read_until):
    publisher = spawn([sys.executable, "-c", PUBLISHER, json.dumps(SAMPLES)])
    read_until(publisher, "publishing", timeout=30)

    received = receive_one_of_each(list(SAMPLES), timeout=30)

    assert sorted(received) == sorted(SAMPLES), "not every message type arrived"
    for name, values in SAMPLES.items():
        assert_fields(received[name], values, f"{name}.")
    publisher.send_signal(signal.SIGINT)
    assert publisher.wait(timeout=10) == 0, publisher.stderr.read()
