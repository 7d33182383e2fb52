"""The live viewer node `railderail_viewer` (`railderail view`, `python -m railderail_monitor.views.viewer_node`):
every /railderail topic, the sensors' included, into a `viewer.RunViewer` that spawns a Rerun viewer, streams
to one (`--connect URL`) or writes a file (`--rrd FILE.rrd`)."""
from __future__ import annotations

import argparse
import sys

from rclpy.node import Node

from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.sensors.config import default_set

from .rerun_views import RunViewer


class ViewerNode(Node):
    """The viewer node `railderail_viewer`: every /railderail topic (the sensors' included) into a
    RunViewer, which it closes (flushing the file or the stream) in `destroy_node`."""

    def __init__(self, viewer, saving=None):
        super().__init__("railderail_viewer")
        self.viewer = viewer
        handlers = {m.STATES: viewer.on_states, m.FORCES: viewer.on_forces, m.STATUS: viewer.on_status,
                    m.ALERTS: viewer.on_alert, m.DERAILMENT: viewer.on_derailment,
                    m.FINAL_STATUS: viewer.on_final_status, m.BRAKE: viewer.on_brake,
                    m.SUPERVISION: viewer.on_supervision, m.SUPERVISION_STATUS: viewer.on_supervision_status}
        for topic, handler in handlers.items():     # the braking curves it draws itself (planning.py)
            _, cls, _, qos = m.TOPICS[topic]
            self.create_subscription(cls, topic, handler, qos)
        self.create_subscription(m.Alert, m.ONBOARD_ALERTS, viewer.on_onboard_alert, m.ALERT_QOS)
        # every mount's, the air springs' and the odometer's topics: those of a smaller set never publish
        for topic, (_, cls, _, qos) in sm.sensor_topics(default_set()).items():
            self.create_subscription(cls, topic, lambda msg, topic=topic: viewer.on_sensor(topic, msg), qos)
        self.get_logger().info("showing /railderail in Rerun" + (f" (saving {saving})" if saving else ""))

    def destroy_node(self):
        self.viewer.close()
        super().destroy_node()


def viewer_node_main(args):
    viewer = RunViewer(exaggeration=args.exaggeration, scene_rate=args.scene_rate, flush_every=20)
    if args.rrd:
        viewer.save(args.rrd)
    elif args.connect:
        viewer.connect(args.connect)
    else:
        viewer.spawn()
    return m.run_node("railderail view", lambda: ViewerNode(viewer, args.rrd))


def add_arguments(parser):
    sink = parser.add_mutually_exclusive_group()
    sink.add_argument("--spawn", action="store_true", help="start a Rerun viewer and stream to it (default)")
    sink.add_argument("--connect", metavar="URL", help="stream to a running viewer (rerun+http://HOST:9876/proxy)")
    sink.add_argument("--rrd", metavar="FILE.rrd", help="write a .rrd file instead (headless)")
    parser.add_argument("--exaggeration", type=float, default=10.0, help="scale of displacements in the 3-D view")
    parser.add_argument("--scene-rate", type=float, default=25.0, help="3-D frames per simulated second")


def command(parser: argparse.ArgumentParser):
    """`railderail view`: the live topics in Rerun."""
    add_arguments(parser)

    def run(args):
        if args.rrd and not args.rrd.endswith(".rrd"):
            raise ValueError(f"--rrd {args.rrd}: the file name must end in .rrd")
        if not 0.0 < args.exaggeration <= 1000.0:
            raise ValueError(f"--exaggeration {args.exaggeration:g} is outside 0-1000")
        return viewer_node_main(args)
    return run


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m railderail_monitor.views.viewer_node",
                                     description="Show the live /railderail topics in Rerun.")
    run = command(parser)
    try:
        return run(parser.parse_args(argv))
    except ValueError as error:
        print(f"{parser.prog}: error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
