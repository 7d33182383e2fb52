"""Monitor node `railderail_monitor`: the derailment criteria over the simulator's topics.

Subscribes to /railderail/wheelset_states, /railderail/contact_forces (best effort, deep queue)
and /railderail/vehicle_status (for the curve's side), runs `criteria.Monitor` on every sample and
publishes each alert on /railderail/alerts (reliable, transient local). The criteria, their
thresholds and the debounce/hysteresis are in railderail_monitor/criteria.py. Every threshold is a
ROS parameter (the fields of `criteria.Limits`, `-p name:=value` or `--params-file FILE.yaml`; NaN
disables a level) whose default is the shipped parameter file's (railderail_monitor/config/
monitor.yaml, `railderail monitor-params`); all may change while running (`ros2 param set`): the
node checks them (`Limits.validated`) and starts a new Monitor with them. On exit it logs how many
samples it processed and how many the sample counters say it missed.
"""
import sys
from dataclasses import fields

from rclpy.node import Node

from railderail_sim import ros_interface as m

from .criteria import AlertRecord, Limits, Monitor, default_limits


def parameter_table(defaults: Limits):
    """The node's parameters: the fields of criteria.Limits with their metadata, defaults from `defaults`.
    All may change while running."""
    return [m.ParameterSpec(f.name, getattr(defaults, f.name), f.metadata["meaning"] + "; " + f.metadata["source"],
                            f.metadata["unit"], f.metadata["accepted"], f.metadata["lo_open"],
                            f.metadata["nan_disables"])
            for f in fields(Limits)]


def alert_message(record: AlertRecord, frame_id="track"):
    """The Alert message of an alert the monitor raised (stamped with the sample's time)."""
    message = m.Alert()
    m.stamp(message, record.time_s)
    message.header.frame_id = frame_id
    for f in fields(AlertRecord):
        if f.name != "time_s":
            setattr(message, f.name, getattr(record, f.name))
    return message


class MonitorNode(Node):
    def __init__(self):
        super().__init__("railderail_monitor")
        self.limit_values = m.declare_parameters(self, parameter_table(default_limits()),
                                                 check=lambda values: Limits(**values).validated(),
                                                 apply=self.on_limits)
        self.monitor = Monitor(Limits(**self.limit_values))
        self.publisher = self.create_publisher(m.Alert, m.ALERTS, m.ALERT_QOS)
        self.create_subscription(m.WheelsetStates, m.STATES, self.on_states, m.SENSOR_SUBSCRIBER)
        self.create_subscription(m.ContactForces, m.FORCES, self.on_forces, m.SENSOR_SUBSCRIBER)
        self.create_subscription(m.VehicleStatus, m.STATUS, self.on_status, m.SENSOR_SUBSCRIBER)
        self.counts = {"states": [0, 0, None], "forces": [0, 0, None]}   # received, missed, last sample
        self.alerts = 0
        self.get_logger().info(f"railderail monitor: {self.monitoring()}")

    def monitoring(self):
        levels = ", ".join(f"{c} {'/'.join(f'{t:.4g}' for _, t in self.monitor.limits.levels(c))}"
                           for c in self.monitor.channels)
        return f"monitoring {levels}; debounce {self.monitor.limits.debounce_m:g} m"

    def on_limits(self, changed):
        """New thresholds while running: a new Monitor (every channel armed again), the curvature
        history kept."""
        curvatures = self.monitor.curvatures
        self.monitor = Monitor(Limits(**self.limit_values))
        self.monitor.curvatures = curvatures
        self.get_logger().info("thresholds changed (" + ", ".join(f"{k} {v:g}" for k, v in changed.items())
                               + f"): {self.monitoring()}")

    def _count(self, kind, sample):
        c = self.counts[kind]
        if c[2] is not None and sample > c[2] + 1:
            c[1] += sample - c[2] - 1
        c[0] += 1
        c[2] = sample

    def _publish(self, alerts):
        for alert in alerts:                       # publish first, log after: logging takes time
            self.publisher.publish(alert_message(alert))
        for alert in alerts:
            self.alerts += 1
            self.get_logger().warning(f"t = {alert.time_s:.3f} s, s = {alert.track_position:.1f} m: {alert.message}")

    def on_states(self, msg):
        self._count("states", msg.sample)
        self._publish(self.monitor.on_states(m.seconds(msg.header.stamp), msg.sample, msg.track_position, msg.speed,
                                             msg.attack_angle, msg.wheel_lift))

    def on_forces(self, msg):
        self._count("forces", msg.sample)
        self._publish(self.monitor.on_forces(m.seconds(msg.header.stamp), msg.sample, msg.track_position, msg.speed,
                                             msg.derailment_coefficient, msg.vertical_force))

    def on_status(self, msg):
        self.monitor.set_curvature(msg.sample, msg.curvature)

    def summary(self):
        (ns, ms, _), (nf, mf, _) = self.counts["states"], self.counts["forces"]
        return (f"processed {ns} wheelset states ({ms} missed) and {nf} contact forces ({mf} missed); "
                f"{self.alerts} alerts")


    def destroy_node(self):
        print(f"[railderail_monitor] {self.summary()}", file=sys.stderr, flush=True)
        super().destroy_node()


def main(argv=None) -> int:
    return m.run_node("railderail-monitor", MonitorNode, argv)


if __name__ == "__main__":
    sys.exit(main())
