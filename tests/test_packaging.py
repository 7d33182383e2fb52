"""The package as ROS 2 (package.xml, ament files, ros2 run launchers) and as pip sees it."""
import shutil
import signal
import stat
import subprocess
import sys
import zipfile
from importlib.metadata import distribution
from pathlib import Path

import pytest
from catkin_pkg.package import parse_package

import railderail_sim

ROOT = Path(__file__).resolve().parents[1]
CONSOLE_SCRIPTS = {
    "railderail": "railderail_sim.cli:main",
    "railderail-simulator": "railderail_sim.ros.node:main",
    "railderail-monitor": "railderail_monitor.node:main",
}


def test_console_scripts_are_installed(venv_bin):
    entry_points = {ep.name: ep for ep in distribution("railderail").entry_points
                    if ep.group == "console_scripts"}
    assert {name: ep.value for name, ep in entry_points.items()} == CONSOLE_SCRIPTS
    for name, ep in entry_points.items():
        assert callable(ep.load())
        assert (venv_bin / name).is_file()


def test_package_xml():
    package = parse_package(ROOT / "package.xml")
    package.validate()
    assert package.name == "railderail"
    assert package.version == railderail_sim.__version__
    assert package.get_build_type() == "ament_python"
    exec_depends = {dep.name for dep in package.exec_depends}
    assert {"rclpy", "std_msgs", "builtin_interfaces", "railderail_msgs", "python3-numpy"} <= exec_depends


def test_msgs_package_xml():
    package = parse_package(ROOT / "msg_defs" / "package.xml")
    package.validate()
    assert package.name == "railderail_msgs"
    assert package.version == railderail_sim.__version__
    assert package.get_build_type() == "ament_cmake"
    assert "rosidl_interface_packages" in {group.name for group in package.member_of_groups}
    assert {"ament_cmake", "rosidl_default_generators"} <= {dep.name for dep in package.buildtool_depends}
    assert {"std_msgs", "builtin_interfaces"} <= {dep.name for dep in package.build_depends}


def test_wheel_layout(tmp_path):
    """What pip (and so colcon's ament files) get from setup.py: the ament marker, package.xml, the
    `ros2 run` launchers in lib/railderail (executable), the nodes' parameter files (package data, and
    in share/railderail/config/), and no scripts besides the entry points."""
    source = tmp_path / "source"
    source.mkdir()
    for name in ("setup.py", "package.xml"):
        shutil.copy2(ROOT / name, source)
    for name in ("resource", "ros2_run", "launch", "railderail_sim", "railderail_monitor"):
        shutil.copytree(ROOT / name, source / name,
                        ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-index",
                    "--no-build-isolation", "--wheel-dir", tmp_path / "wheel", source],
                   check=True, capture_output=True)
    [wheel] = (tmp_path / "wheel").glob("railderail-*.whl")
    data = f"railderail-{railderail_sim.__version__}.data/"
    with zipfile.ZipFile(wheel) as archive:
        infos = {info.filename: info for info in archive.infolist()}
        entry_points = archive.read(f"railderail-{railderail_sim.__version__}.dist-info/entry_points.txt")

    assert data + "data/share/ament_index/resource_index/packages/railderail" in infos
    assert data + "data/share/railderail/package.xml" in infos
    for launcher in ("simulator", "monitor", "recorder"):
        mode = infos[f"{data}data/lib/railderail/{launcher}"].external_attr >> 16
        assert mode & stat.S_IXUSR, f"lib/railderail/{launcher} is not executable"
    assert not [name for name in infos if name.startswith(data + "scripts/")]
    assert "railderail_sim/cli/__init__.py" in infos and "railderail_monitor/node.py" in infos
    with zipfile.ZipFile(wheel) as archive:
        for package, name in (("railderail_monitor", "monitor.yaml"), ("railderail_sim", "simulator.yaml")):
            shipped = (ROOT / package / "config" / name).read_bytes()
            assert archive.read(f"{package}/config/{name}") == shipped
            assert archive.read(f"{data}data/share/railderail/config/{name}") == shipped
        for line in ("table2.yaml", "hsr-300-demo.yaml"):        # the shipped lines (railderail survey NAME)
            assert archive.read(f"railderail_sim/config/lines/{line}") == \
                (ROOT / "railderail_sim" / "config" / "lines" / line).read_bytes()
        assert archive.read(f"{data}data/share/railderail/launch/demo.launch.py") == \
            (ROOT / "launch" / "demo.launch.py").read_bytes()
    for name, target in CONSOLE_SCRIPTS.items():
        assert f"{name} = {target}".encode() in entry_points


NODES = [("railderail-simulator", "simulator", "railderail_simulator"),
         ("railderail-monitor", "monitor", "railderail_monitor")]


@pytest.mark.parametrize("command, launcher, node", NODES)
@pytest.mark.parametrize("how", ["console script", "ros2 run launcher"])
def test_node_starts_and_stops_on_sigint(how, command, launcher, node, spawn, read_until, venv_bin):
    if how == "console script":
        child = spawn([venv_bin / command])
    else:
        child = spawn([sys.executable, ROOT / "ros2_run" / launcher])
    read_until(child, f"[{node}]: railderail", timeout=30)
    child.send_signal(signal.SIGINT)
    assert child.wait(timeout=10) == 0, child.stderr.read()
