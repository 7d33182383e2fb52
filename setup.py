"""railderail: a ROS 2 package (ament_python, built by colcon) that is pip-installable too.

Commands: `railderail`, `railderail-simulator` and `railderail-monitor` are console scripts
(installed to bin/). `ros2 run railderail simulator|monitor|recorder` finds the small launchers of
ros2_run/, installed as data files to lib/railderail/ (where `ros2 run` and launch files look), so
that a pip install puts no generic `simulator`/`monitor` names on PATH. `ros2 launch railderail
demo.launch.py` finds launch/demo.launch.py in share/railderail/launch/.
"""
import re
from pathlib import Path

from setuptools import find_packages, setup

PACKAGE = "railderail"
VERSION = re.search(r'^__version__ = "([^"]+)"$',
                    (Path(__file__).parent / "railderail_sim" / "__init__.py").read_text(),
                    re.MULTILINE).group(1)

setup(
    name=PACKAGE,
    version=VERSION,
    description="CRH3 car over-speeding on a curve: derailment simulation, prediction and warning",
    license="Apache-2.0",
    maintainer="railderail maintainers",
    maintainer_email="railderail@example.org",
    python_requires=">=3.11",
    packages=find_packages(include=["railderail_sim", "railderail_sim.*",
                                    "railderail_monitor", "railderail_monitor.*"]),
    package_data={"railderail_sim": ["profiles/data/*", "config/*.yaml", "config/lines/*.yaml", "config/lines/*.json"], "railderail_monitor": ["config/*.yaml", "config/*.csv"]},
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
        (f"share/{PACKAGE}", ["package.xml"]),
        # the nodes' parameter files where ROS users and the launch file look for them (the package
        # data are the same files: the monitor reads its defaults from its copy)
        (f"share/{PACKAGE}/config", ["railderail_sim/config/simulator.yaml", "railderail_sim/config/sensors.yaml",
                                     "railderail_sim/config/sensors-realistic.yaml",
                                     "railderail_monitor/config/monitor.yaml",
                                     "railderail_monitor/config/supervision.yaml"]),
        (f"share/{PACKAGE}/launch", ["launch/demo.launch.py"]),
        (f"lib/{PACKAGE}", ["ros2_run/simulator", "ros2_run/monitor", "ros2_run/recorder"]),
    ],
    # Python libraries only: the ROS 2 packages (rclpy, messages) come from the ROS installation,
    # or in the pip-only set-up from the ros-jazzy-* wheels of requirements.txt.
    install_requires=[
        "numpy>=2,<2.6",  # numba needs <2.6, rerun-sdk >=2
        "scipy",
        "numba>=0.60,<0.69",  # railderail_sim/jit.py uses numba's private `_nrt` option: checked on 0.68
        "matplotlib",
        "tqdm",
        "dask[distributed]",
        "mcap",
        "mcap-ros2-support",
        "rerun-sdk",
    ],
    zip_safe=False,
    entry_points={
        "console_scripts": [
            "railderail = railderail_sim.cli:main",
            "railderail-simulator = railderail_sim.ros.node:main",
            "railderail-monitor = railderail_monitor.node:main",
        ],
        # subcommands and benchmark groups of railderail_monitor, found by railderail_sim.cli and .bench
        "railderail.commands": ["monitor = railderail_monitor.commands:COMMANDS"],
        "railderail.bench": ["ros = railderail_monitor.bench.ros:run",
                             "warnings = railderail_monitor.evaluation.over_catalogue:bench"],
    },
)
