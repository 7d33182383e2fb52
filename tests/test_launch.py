"""launch/demo.launch.py without the launch packages (not on PyPI): it compiles, and run against stand-ins
for the classes it imports, every node it starts exists in ros2_run/, every parameter file is the shipped
file of that node, every parameter it sets is declared by that node with the type it gives, and every
launch argument it reads is declared with a default the node accepts."""
import ast
import signal
import sys
import types
from pathlib import Path

import pytest
import yaml

from railderail_monitor.warning.limits import default_limits
from railderail_monitor.node import parameter_table
from railderail_monitor.onboard.measured import measured_limits
from railderail_sim.ros.node import PARAMETERS
from railderail_sim.parameters import vehicle_parameters

ROOT = Path(__file__).resolve().parents[1]
LAUNCH = ROOT / "launch" / "demo.launch.py"
TABLES = {"railderail_simulator": PARAMETERS, "railderail_monitor": parameter_table(default_limits()),
          "railderail_onboard_monitor": parameter_table(measured_limits(vehicle_parameters("hs19"))),
          "railderail_recorder": ()}
FILES = {"simulator.yaml": ROOT / "railderail_sim" / "config" / "simulator.yaml",
         "monitor.yaml": ROOT / "railderail_monitor" / "config" / "monitor.yaml"}


class StandIn:
    """Any class the launch file imports: keeps what it was called with."""

    def __init__(self, *args, **kwargs):
        self.args, self.kwargs = args, kwargs


@pytest.fixture
def launched(monkeypatch, tmp_path):
    """The LaunchDescription stand-in of the launch file, with share/railderail holding the shipped files."""
    source = LAUNCH.read_text()
    tree = ast.parse(source, str(LAUNCH))
    compile(tree, str(LAUNCH), "exec")
    share = tmp_path / "share" / "railderail"
    (share / "config").mkdir(parents=True)
    for name, path in FILES.items():
        (share / "config" / name).write_bytes(path.read_bytes())
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module.split(".")[0] in ("launch", "launch_ros",
                                                                              "ament_index_python"):
            module = types.ModuleType(node.module)
            for alias in node.names:
                setattr(module, alias.name, type(alias.name, (StandIn,), {}))
            monkeypatch.setitem(sys.modules, node.module, module)
    sys.modules["ament_index_python.packages"].get_package_share_directory = \
        lambda package: str(share) if package == "railderail" else pytest.fail(f"looked up package {package}")
    namespace = {"__name__": "demo_launch", "__file__": str(LAUNCH)}
    exec(compile(tree, str(LAUNCH), "exec"), namespace)
    return namespace["generate_launch_description"]()


def named(items, kind):
    return [item for item in items if type(item).__name__ == kind]


def test_the_launch_file_starts_the_four_nodes_with_declared_parameters(launched):
    items = launched.args[0]
    arguments = {a.args[0] if a.args else a.kwargs["name"]: a.kwargs["default_value"]
                 for a in named(items, "DeclareLaunchArgument")}
    assert {"radius", "speed_mode", "speed_kmh", "output"} <= set(arguments)
    nodes = {n.kwargs["name"]: n.kwargs for n in named(items, "Node")}
    assert set(nodes) == set(TABLES)
    used_arguments = set()
    for name, node in nodes.items():
        assert node["package"] == "railderail"
        assert (ROOT / "ros2_run" / node["executable"]).is_file(), f"no ros2_run/{node['executable']}"
        specs = {spec.name: spec for spec in TABLES[name]}
        for entry in node.get("parameters", []):
            if isinstance(entry, str):                     # a parameter file: the node's own
                path = Path(entry)
                assert path.name in FILES and path.is_file()
                assert set(yaml.safe_load(path.read_text())) == {name}, f"{name} given {path.name}"
                continue
            for key, value in entry.items():
                assert key in specs, f"{name} declares no parameter {key}"
                spec = specs[key]
                if type(value).__name__ == "ParameterValue":
                    (configuration,) = value.args
                    argument = configuration.args[0]
                    used_arguments.add(argument)
                    kind = value.kwargs["value_type"]
                    assert kind is type(spec.default), f"{key}: launch gives {kind.__name__}"
                    spec.checked(kind(arguments[argument]))          # the default is accepted
                else:
                    assert type(value) is type(spec.default), key
                    spec.checked(value)
        for argument in node.get("arguments", []):
            used_arguments.add(argument.args[0])
    assert used_arguments <= set(arguments)
    assert "output" in used_arguments and arguments["output"].endswith(".mcap")
    # the simulator waits for the monitor and the recorder; its end stops the launch
    simulator = nodes["railderail_simulator"]
    assert {"wait_for_subscribers": 2}.items() <= simulator["parameters"][1].items()
    (handler,) = named(items, "RegisterEventHandler")
    assert handler.args[0].kwargs["target_action"].kwargs is simulator


def test_the_recorder_launcher_takes_the_ros_arguments_launch_adds(spawn, read_until, tmp_path):
    """`ros2 launch` runs lib/railderail/recorder OUT.mcap --ros-args -r __node:=NAME."""
    out = tmp_path / "launched.mcap"
    recorder = spawn([sys.executable, ROOT / "ros2_run" / "recorder", str(out), "--ros-args",
                      "-r", "__node:=railderail_recorder_launched"])
    read_until(recorder, "[railderail_recorder_launched]: recording", timeout=30)
    recorder.send_signal(signal.SIGINT)
    assert recorder.wait(timeout=20) == 0, recorder.stderr.read()
    assert out.read_bytes().endswith(b"\x89MCAP0\r\n")
