"""The monitor stands on its own: its thresholds come from the shipped parameter file (what the model
gives, `railderail monitor-params`), and the monitor node starts without the model and without numba."""
import math
import subprocess
import sys
from dataclasses import fields

import pytest

from railderail_monitor.warning.limits import SHIPPED, Limits, default_limits, read_limits
from railderail_monitor.warning.monitor_params import REGENERATE, limits_of_car
from railderail_sim.cli import main
from test_replay import error_line


def test_shipped_file_is_what_the_model_gives(capsys):
    assert main(["monitor-params"]) == 0
    made = capsys.readouterr().out
    assert made == SHIPPED.read_text(), \
        f"railderail_monitor/config/monitor.yaml is not what the model gives today: regenerate it with `{REGENERATE}`"


def test_default_limits_are_the_model_s():
    limits, basis = limits_of_car()
    assert repr(default_limits()) == repr(limits)         # exactly (repr: NaN equals NaN); the file holds repr()
    assert basis["flange_height"] == pytest.approx(0.027793, abs=1e-6)    # LM (TB/T 449): 27.8 mm
    assert math.degrees(basis["max_contact_angle"]) == pytest.approx(69.5, abs=0.1)
    assert limits.wheel_lift == pytest.approx(basis["flange_height"] / 3.0, rel=1e-15)


def test_another_wheel_and_friction_give_other_limits(tmp_path):
    out = tmp_path / "s1002.yaml"
    assert main(["monitor-params", "--wheel", "s1002", "--friction", "0.4", "--out", str(out)]) == 0
    s1002 = read_limits(out)
    lm = default_limits()
    assert s1002.wheel_lift != lm.wheel_lift
    assert s1002.derailment_coefficient_critical < lm.derailment_coefficient_critical   # more friction, lower
    assert s1002.static_wheel_load == lm.static_wheel_load
    assert "--wheel s1002 --rail uic60 --friction 0.4 --vehicle-set hs19" in out.read_text()


def test_bad_input_is_one_line(capsys, tmp_path):
    assert "friction coefficient 2 is outside the accepted range (0, 1]" in error_line(
        capsys, ["monitor-params", "--friction", "2"])
    assert "'nothere' is neither a built-in" in error_line(capsys, ["monitor-params", "--wheel", "nothere"])
    assert "must end in .yaml" in error_line(capsys, ["monitor-params", "--out", str(tmp_path / "x.txt")])
    partial = tmp_path / "partial.yaml"
    partial.write_text("railderail_monitor:\n  ros__parameters:\n    wheel_lift: 0.01\n    wheel_size: 1.0\n")
    with pytest.raises(ValueError, match=r"partial.yaml: unknown parameter\(s\) wheel_size; missing parameter\(s\) "
                                         r"wheel_lift_critical, derailment_coefficient_critical"):
        read_limits(partial)


def test_every_parameter_has_its_comment():
    text = SHIPPED.read_text().splitlines()
    for f in fields(Limits):
        line = next(i for i, t in enumerate(text) if t.strip().startswith(f"{f.name}:"))
        comment = text[line - 1].strip()
        assert comment.startswith(f"# {f.metadata['unit'] or '-'}: ") and "Source: " in comment, f.name


MONITOR_UP = """
import sys
import rclpy
from railderail_monitor.node import MonitorNode

rclpy.init()
node = MonitorNode()
rclpy.spin_once(node, timeout_sec=0.1)
print(sorted({"numba", "llvmlite"} & set(sys.modules)))
print(node.get_parameter("wheel_lift").value, node.get_parameter("attack_angle_critical").value)
node.destroy_node()
rclpy.shutdown()
"""


def test_monitor_node_starts_without_numba(tmp_path):
    done = subprocess.run([sys.executable, "-c", MONITOR_UP], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    imported, values = done.stdout.splitlines()
    assert imported == "[]", f"the monitor node imported {imported}"
    assert values == f"{default_limits().wheel_lift!r} nan"


def test_monitor_node_takes_a_parameter_file(tmp_path, spawn, read_until):
    """The file of another wheel, given to the node the ROS way (--params-file)."""
    out = tmp_path / "s1002.yaml"
    assert main(["monitor-params", "--wheel", "s1002", "--out", str(out)]) == 0
    wheel_lift = read_limits(out).wheel_lift
    monitor = spawn([sys.executable, "-m", "railderail_monitor.node", "--ros-args", "--params-file", str(out)])
    line = read_until(monitor, "monitoring", timeout=30)[-1]
    assert f"wheel_lift {wheel_lift:.4g}/" in line and "attack_angle 0.06," in line    # .nan: no critical level
