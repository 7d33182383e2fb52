"""The nodes' parameter files (railderail_sim/config/simulator.yaml, railderail_monitor/config/monitor.yaml and,
beside it, the speed supervision's railderail_monitor/config/supervision.yaml): every declared parameter at its
default with a comment, the same as the nodes' tables; each node started with its files, changed, uses the
files' values."""
import sys

import pytest
import yaml
from rclpy.parameter import parameter_value_to_python

from railderail_monitor.warning.limits import default_limits
from railderail_monitor.warning.limits import SHIPPED as MONITOR_FILE
from railderail_monitor.node import (SUPERVISION_FILE, SUPERVISION_REGENERATE, SUPERVISION_SETUP, parameter_table,
                                     supervision_parameter_file)
from railderail_sim.cli import main
from railderail_sim.cli.nodes import REGENERATE, SHIPPED as SIMULATOR_FILE
from railderail_sim.ros.node import PARAMETERS
from test_parameters import Client

TABLES = {"railderail_simulator": (SIMULATOR_FILE, PARAMETERS),
          "railderail_monitor": (MONITOR_FILE, parameter_table(default_limits()))}
# a file of a node's parameters: (node, file, the part of its table the file holds)
FILES = {"simulator": ("railderail_simulator", *TABLES["railderail_simulator"]),
         "monitor": ("railderail_monitor", *TABLES["railderail_monitor"]),
         "monitor supervision": ("railderail_monitor", SUPERVISION_FILE, SUPERVISION_SETUP)}


def test_shipped_simulator_file_is_the_node_s_table(capsys):
    assert main(["simulator-params"]) == 0
    assert capsys.readouterr().out == SIMULATOR_FILE.read_text(), \
        f"railderail_sim/config/simulator.yaml is not the node's parameter table: regenerate it with `{REGENERATE}`"


def test_shipped_supervision_file_is_the_node_s_table():
    assert SUPERVISION_FILE.read_text() == supervision_parameter_file(), \
        f"railderail_monitor/config/supervision.yaml is not the node's table: regenerate it with `{SUPERVISION_REGENERATE}`"


def same_value(a, b):
    return type(a) is type(b) and (a == b or a != a and b != b)       # NaN equals NaN here


@pytest.mark.parametrize("which", FILES)
def test_file_holds_every_declared_parameter_with_its_default_and_a_comment(which):
    node, path, specs = FILES[which]
    text = path.read_text()
    values = yaml.safe_load(text)[node]["ros__parameters"]
    assert list(values) == [spec.name for spec in specs]
    for spec in specs:
        assert same_value(values[spec.name], spec.default), spec.name
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.startswith("    ") and not line.lstrip().startswith("#"):
            comment = lines[i - 1].strip()
            assert comment.startswith("# ") and ": " in comment, f"{node}: {line.strip()} has no comment above it"


RCLPY_OWN = {"use_sim_time", "start_type_description_service"}      # every rclpy node declares these
# node, module, the parameter changed, its value, the log line that shows it used, the line once it is up
SIMULATOR = ("railderail_simulator", "railderail_sim.ros.node", "radius", 1234.0, "R = 1234 m", "ready:")
MONITOR = ("railderail_monitor", "railderail_monitor.node", "wheel_lift", 0.012, "wheel_lift 0.012/", "monitoring")


@pytest.mark.timeout(240)
@pytest.mark.parametrize("how", ["edited file", "file and -p"])
@pytest.mark.parametrize("node, module, name, changed, log, up", [SIMULATOR, MONITOR], ids=["simulator", "monitor"])
def test_node_started_with_its_file_uses_it(node, module, name, changed, log, up, how, tmp_path, spawn, read_until):
    path, specs = TABLES[node]
    data = yaml.safe_load(path.read_text())
    expected = dict(data[node]["ros__parameters"], **{name: changed})
    # the monitor's speed supervision has a file of its own beside the thresholds'
    more = [SUPERVISION_FILE] if node == "railderail_monitor" else []
    for beside in more:
        expected.update(yaml.safe_load(beside.read_text())[node]["ros__parameters"])
    if how == "edited file":
        text = path.read_text()
        line = f"    {name}: {data[node]['ros__parameters'][name]!r}\n"
        assert line in text
        edited = tmp_path / "edited.yaml"
        edited.write_text(text.replace(line, f"    {name}: {changed!r}\n"))
        args = ["--params-file", str(edited)]
    else:
        args = ["--params-file", str(path), "-p", f"{name}:={changed!r}"]
    args += [a for beside in more for a in ("--params-file", str(beside))]
    child = spawn([sys.executable, "-m", module, "--ros-args", *args])
    if not any(up in line for line in read_until(child, log, timeout=30)):
        read_until(child, up, timeout=180)          # the simulator: a cold numba compile included
    client = Client(node)
    try:
        listed = client.call(client.client.list_parameters()).result.names
        assert set(listed) - RCLPY_OWN == set(expected)
        values = client.call(client.client.get_parameters(list(expected))).values
        got = dict(zip(expected, map(parameter_value_to_python, values)))
    finally:
        client.close()
    for key in expected:
        assert same_value(got[key], expected[key]), (key, got[key], expected[key])
