"""Node parameters: descriptors (description, range, read-only), bad values refused at start with one
line and exit status 2, and while running through the parameter services."""
import math
import signal
import subprocess
import sys

import numpy as np
import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient
from rclpy.signals import SignalHandlerOptions

from railderail_monitor.warning.limits import default_limits
from railderail_sim.ros import interface as m

PY = sys.executable


SIMULATOR, MONITOR = "railderail-simulator", "railderail-monitor"


@pytest.mark.parametrize("command, parameter, message", [
    (SIMULATOR, "radius:=50.0", "radius 50 m is outside the accepted range [150, 20000] m"),
    (SIMULATOR, "radius:=50", "radius 50 m is outside the accepted range [150, 20000] m"),    # an integer
    (SIMULATOR, "real_time_factor:=5000", "real_time_factor 5000 is outside the accepted range [0, 1000]"),
    (SIMULATOR, "contact_model:=rigid", "contact_model 'rigid' is not one of hertz, discrete"),
    (SIMULATOR, "status_rate:=300.0", "status_rate 300 Hz is above publish_rate 200 Hz"),
    (SIMULATOR, "irregularity:=bumpy", "irregularity 'bumpy' is not 'none', a spectrum (erri-low, erri-high, fra-1, "
                                       "fra-2, fra-3, fra-4, fra-5, fra-6, china-hsr) or a .csv file"),
    (SIMULATOR, "irregularity_seed:=-3", "irregularity_seed -3 is outside the accepted range [0, 999999]"),
    (MONITOR, "debounce_m:=-1.0", "debounce_m -1 m is outside the accepted range [0, 100] m"),
    (MONITOR, "wheel_lift_critical:=0.005", "wheel_lift 0.00926425 must be below wheel_lift_critical 0.005"),
])
def test_bad_value_at_start_is_one_line_and_status_2(command, parameter, message, venv_bin):
    done = subprocess.run([venv_bin / command, "--ros-args", "-p", parameter], capture_output=True, text=True,
                          timeout=60)
    assert (done.returncode, done.stderr) == (2, f"{command}: error: {message}\n")


class Client:
    """The parameter services of one node, from this process (own context)."""

    def __init__(self, node_name):
        self.context = rclpy.Context()
        rclpy.init(context=self.context, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node("railderail_test_parameters", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.client = AsyncParameterClient(self.node, node_name)
        assert self.client.wait_for_services(timeout_sec=30.0)

    def call(self, future):
        self.executor.spin_until_future_complete(future, timeout_sec=10.0)
        assert future.done(), "the node's parameter service gave no answer within 10 s"
        return future.result()

    def set(self, name, value):
        (result,) = self.call(self.client.set_parameters([Parameter(name, value=value)])).results
        return result

    def get(self, name):
        (value,) = self.call(self.client.get_parameters([name])).values
        return parameter_value_to_python(value)

    def describe(self, name):
        (descriptor,) = self.call(self.client.describe_parameters([name])).descriptors
        return descriptor

    def close(self):
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)


@pytest.mark.timeout(300)
def test_running_simulator_refuses_bad_changes_and_applies_good_ones(spawn, read_until):
    simulator = spawn([PY, "-m", "railderail_sim.ros.node", "--ros-args", "-p", "speed_mode:=constant",
                       "-p", "exit_when_done:=false"])
    read_until(simulator, "ready:", timeout=240)           # a cold numba compile included
    client = Client("railderail_simulator")
    try:
        radius = client.describe("radius")
        assert radius.read_only and "curve radius [m]" in radius.description
        assert (radius.floating_point_range[0].from_value, radius.floating_point_range[0].to_value) == (150.0, 20000.0)
        assert client.describe("wait_for_subscribers").integer_range[0].to_value == 100

        refused = client.set("radius", 50.0)                 # read-only: the model is built
        assert not refused.successful and "read-only" in refused.reason
        assert not client.set("radius", 1200.0).successful
        assert client.get("radius") == 1000.0
        refused = client.set("real_time_factor", 5000)       # an integer: the node's own range check
        assert not refused.successful and "real_time_factor 5000 is outside the accepted range [0, 1000]" \
            in refused.reason
        assert not client.set("real_time_factor", 5000.0).successful      # a double: rclpy's FloatingPointRange
        assert not client.set("real_time_factor", "fast").successful
        refused = client.set("status_rate", 400.0)
        assert not refused.successful and "status_rate 400 Hz is above publish_rate 200 Hz" in refused.reason
        assert client.get("real_time_factor") == 1.0

        assert client.set("real_time_factor", 2).successful
        assert client.get("real_time_factor") == 2
        read_until(simulator, "parameters changed: real_time_factor 2.0 (2 x real time)", timeout=10)
    finally:
        client.close()
    simulator.send_signal(signal.SIGINT)
    assert simulator.wait(timeout=20) == 0


def states(sample, wheel_lift):
    msg = m.WheelsetStates(sample=sample, track_position=0.5 * sample, speed=80.0)
    m.stamp(msg, 0.005 * sample)
    msg.wheel_lift = np.array(wheel_lift, dtype=float)
    return msg


def test_monitor_thresholds_change_while_running():
    """New thresholds are checked (Limits.validated) and applied by a new Monitor."""
    from railderail_monitor.node import MonitorNode

    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    try:
        node = MonitorNode()
        defaults = default_limits()
        lift = [0.005, 0, 0, 0, 0, 0, 0, 0]                 # below the default warning level (9.3 mm)
        node.on_states(states(0, lift))
        assert node.alerts == 0

        (result,) = node.set_parameters([Parameter("wheel_lift", value=0.03)])   # above the critical level
        assert not result.successful
        assert f"wheel_lift 0.03 must be below wheel_lift_critical {defaults.wheel_lift_critical:g}" in result.reason
        (result,) = node.set_parameters([Parameter("debounce_m", value=500)])
        assert not result.successful and "debounce_m 500 m is outside the accepted range [0, 100] m" in result.reason
        (result,) = node.set_parameters([Parameter("wheel_lift_critical", value=math.nan)])   # NaN disables it
        assert result.successful and node.monitor.limits.levels("wheel_lift") == [(1, defaults.wheel_lift)]

        result = node.set_parameters_atomically([Parameter("wheel_lift", value=0.004),
                                                 Parameter("debounce_m", value=0)])     # an integer for a float
        assert result.successful
        assert node.monitor.limits.wheel_lift == 0.004 and node.monitor.limits.debounce_m == 0.0
        node.on_states(states(1, lift))                     # 5 mm now passes the warning level
        assert node.alerts == 1
        node.destroy_node()
    finally:
        rclpy.shutdown()
