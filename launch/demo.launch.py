"""`ros2 launch railderail demo.launch.py`: the demo's three nodes on a ROS 2 installation.

Starts the recorder (every /railderail topic to `output`), the monitor (with the shipped thresholds,
share/railderail/config/monitor.yaml), a second monitor in measured mode (`railderail_onboard_monitor`:
the on-board sensors' topics only, its alerts on /railderail/onboard_alerts) and the simulator
(share/railderail/config/simulator.yaml with the launch arguments on top, its shipped sensor set on). The simulator starts its run once the monitor and the recorder
subscribe, and when it exits (derailment or end of the line) the launch shuts the others down, so
the MCAP is complete. The launch packages are not on PyPI: the pip set-up runs the same job with
`railderail demo`, which also prints the alerts' lead times.

    ros2 launch railderail demo.launch.py radius:=1200.0 speed_mode:=constant speed_kmh:=330.0 output:=r1200.mcap
"""
import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, EmitEvent, RegisterEventHandler
from launch.event_handlers import OnProcessExit
from launch.events import Shutdown
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue

# launch argument: (default, description, type of the simulator parameter it sets, or None)
ARGUMENTS = {
    "radius": ("1000.0", "curve radius, m (150-20000)", float),
    "speed_mode": ("progressive", "progressive (the paper's staircase until derailment) or constant", str),
    "speed_kmh": ("200.0", "constant speed, or the staircase's start speed, km/h", float),
    "real_time_factor": ("1.0", "simulated seconds per wall second; 0 = as fast as possible", float),
    "output": ("demo.mcap", "the recording (MCAP) to write", None),
}


def generate_launch_description():
    config = os.path.join(get_package_share_directory("railderail"), "config")
    arguments = [DeclareLaunchArgument(name, default_value=default, description=text)
                 for name, (default, text, _) in ARGUMENTS.items()]
    overrides = {name: ParameterValue(LaunchConfiguration(name), value_type=kind)
                 for name, (_, _, kind) in ARGUMENTS.items() if kind is not None}
    recorder = Node(package="railderail", executable="recorder", name="railderail_recorder", output="screen",
                    arguments=[LaunchConfiguration("output")])
    monitor = Node(package="railderail", executable="monitor", name="railderail_monitor", output="screen",
                   parameters=[os.path.join(config, "monitor.yaml")])
    onboard = Node(package="railderail", executable="monitor", name="railderail_onboard_monitor", output="screen",
                   parameters=[{"signals": "measured"}])
    # waits for the monitor and the recorder, so that neither misses the start of the run
    simulator = Node(package="railderail", executable="simulator", name="railderail_simulator", output="screen",
                     parameters=[os.path.join(config, "simulator.yaml"),
                                 {**overrides, "sensors": "shipped", "wait_for_subscribers": 2}])
    stop_all = RegisterEventHandler(OnProcessExit(target_action=simulator,
                                                  on_exit=[EmitEvent(event=Shutdown(reason="the run stopped"))]))
    return LaunchDescription([*arguments, recorder, monitor, onboard, simulator, stop_all])
