"""Monitor node `railderail_monitor`: the derailment criteria over the simulator's topics, or, with
`signals:=measured`, the on-board criteria over the sensors' topics only.

Ground truth (`signals` ground_truth, the default): subscribes to /railderail/wheelset_states and
/railderail/contact_forces (reliable, deep queue; each message carries its sample's track curvature, which names
an alert's inner or outer rail), runs `warning.monitor.Monitor` on every sample and
publishes each alert on /railderail/alerts (reliable, transient local). The criteria, their
thresholds and the debounce/hysteresis are in railderail_monitor/criteria.py. Every threshold is a
ROS parameter (the fields of `warning.limits.Limits`, `-p name:=value` or `--params-file FILE.yaml`; NaN
disables a level) whose default is the shipped parameter file's (railderail_monitor/config/
monitor.yaml, `railderail monitor-params`); all may change while running (`ros2 param set`): the
node checks them (`Limits.validated`) and starts a new Monitor with them. On exit it logs how many
samples it processed and how many the sample counters say it missed.

Measured (`signals:=measured`): subscribes to the topics of its sensor set (parameter `sensors`: the shipped
railderail_sim/config/sensors.yaml or a sensor file: which units, at which rates; /railderail/sensors/*,
sensor_messages.sensor_topics) and to nothing else, decodes them (sensor_messages.SensorDecoder) into
`onboard.monitor.MeasuredMonitor` and publishes its alerts on /railderail/onboard_alerts (a topic of their
own: what reads /railderail/alerts takes them for the ground truth's), each with header.frame_id the place
of the channel that raised it (the mount, air_springs, or the running-gear side), wheelset its bogie's
leading wheelset (-1 for the car body), wheel_side the running gear's side, and a message starting
"measured". Its thresholds are the fields of `onboard.measured.MeasuredLimits` with the car's defaults
(parameter `vehicle_set`); changed while running, they start a new MeasuredMonitor. Run it beside a
ground-truth monitor under another name: `--ros-args -r __node:=railderail_onboard_monitor -p signals:=measured`.
"""
from dataclasses import fields
from importlib.resources import files
import json
import math
import sys

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from railderail_sim.parameters import VEHICLE_SETS
from railderail_sim.ros import interface as m
from railderail_sim.ros.node_parameters import ParameterSpec as P, declare_parameters, parameter_file
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.supervision.braking import ADHESIONS
from railderail_sim.vehicle.layout import RUNNING_GEARS

from .supervision.on_line import SIGNALS as SUPERVISION_SIGNALS
from .warning.alerts import AlertRecord, amount_text, label
from .warning.limits import NODE, SEVERITY_NAMES, SIGNALS as MODES, SIGNALS_MEANING, Limits, default_limits
from .warning.monitor import Monitor


# the measured mode's subscriber queue: 2.5 minutes of a 200 Hz sensor. A message costs this Python node about
# 0.25 ms (rclpy's take and conversion, then the criteria), and the shipped set sends about 3000 a second of
# simulated time: behind a simulator faster than real time (the demo's 3 x) it falls behind and catches up
# after the run, and its queue must hold the backlog (the ground truth's 5000, 8 s at 3 x, would overflow).
# Reliable: best effort lost what the transport dropped while the node waited for a core (test_onboard_ros on a
# loaded machine: 864 of 17 627 sensor messages)
SENSOR_BACKLOG = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=30000, reliability=ReliabilityPolicy.RELIABLE,
                            durability=DurabilityPolicy.VOLATILE)
SIGNALS = P("signals", MODES[0], SIGNALS_MEANING, choices=MODES, read_only=True)
MEASURED_SETUP = [
    P("sensors", "shipped", "the sensor set whose topics it reads (its units and rates): shipped "
      "(railderail_sim/config/sensors.yaml) or the path of a sensor file", read_only=True),
    P("vehicle_set", "hs19", "the car: a built-in parameter set (" + ", ".join(VEHICLE_SETS) + ") or "
      "the path of a car file (onboard/car.py, config/car-example.yaml): masses and spacings of the "
      "estimator, the defaults of the levels", read_only=True),
    P("wind_speed", 0.0, "a steady wind known on board (an anemometer, the line's wind stations, a "
      "forecast) whose load on the car body the estimator takes out (onboard.estimator.GivenWind); "
      "0: none known", "m/s", (0.0, 60.0), read_only=True),
    P("wind_direction", 90.0, "where that wind comes from, relative to the track: + from the left, "
      "0 a head wind", "deg", (-180.0, 180.0), read_only=True)]


SUPERVISION_SETUP = [
    P("supervision", "", "supervise the speed against a survey's safe speeds (the path of `railderail "
      "survey LINE.yaml --json`'s output, docs/supervision.md); empty: no speed supervision",
      read_only=True),
    P("supervision_signals", SUPERVISION_SIGNALS[0], "what the speed supervision takes the position "
      "and speed from: ground_truth, the wheelset states; odometer, the sensor set's odometer "
      "(/railderail/sensors/odometer, with its modelled error) from a balise at its first sample, its "
      "confidence interval's max safe front supervised", choices=SUPERVISION_SIGNALS, read_only=True),
    P("supervision_brake", True, "at the supervision's intervention, command the emergency brake on "
      "/railderail/brake_command (the simulator obeys it): the loop closed", read_only=True),
    P("supervision_adhesion", "dry", "the braking model's emergency decelerations the supervision "
      "plans with: dry rail, or wet (degraded adhesion)", choices=ADHESIONS, read_only=True),
    P("supervision_vehicle_set", "hs19", "the car whose leading wheelset is the train's front",
      choices=VEHICLE_SETS, read_only=True),
    P("supervision_wind_speed", math.nan, "live input: the measured wind (an anemometer's reading) "
      "against the characteristic wind curve of the survey's wind sites; NaN: none measured",
      "m/s", (0.0, 60.0), nan_disables=True),
    P("supervision_friction", math.nan, "live input: the wheel-rail friction estimate that picks a "
      "curve's safe speed among the survey's per-friction ones; NaN: none (the lowest)", "-",
      (0.0, 1.0), lo_open=True, nan_disables=True),
    P("supervision_nonlinear_critical_speed_kmh", 234.375, "live input hunting: once the measured "
      "monitor's bogie-instability rules alert (on /railderail/onboard_alerts), a target under this "
      "speed from there to the end of the line; the car's nonlinear critical speed, of the shipped "
      "limit-cycle scan (docs/report/report.json, hs19, 10 mm kink: A, own simulation)", "km/h",
      (1.0, 1000.0), read_only=True)]
# the live inputs' parameters (may change while running) -> LiveInputs' fields
LIVE_PARAMETERS = {"supervision_wind_speed": "wind_speed_m_s", "supervision_friction": "friction"}
# the speed supervision's parameter file, beside the thresholds' (config/monitor.yaml, made from a model)
SUPERVISION_FILE = files("railderail_monitor") / "config" / "supervision.yaml"
SUPERVISION_REGENERATE = "python -m railderail_monitor.node --supervision-params > railderail_monitor/config/supervision.yaml"


def supervision_parameter_file():
    """The text of the speed supervision's parameter file: SUPERVISION_SETUP at its defaults."""
    return parameter_file(NODE, SUPERVISION_SETUP, [
        f"Parameters of the railderail monitor node ({NODE}): its speed supervision (docs/supervision.md).",
        "Give it beside the thresholds' file: railderail-monitor --ros-args --params-file monitor.yaml "
        "--params-file THIS_FILE.yaml",
        f"Made by `{SUPERVISION_REGENERATE.split(' >')[0]}`. NaN (.nan): no live input of that kind. Units SI; "
        "'-' = dimensionless."])


def parameter_table(defaults):
    """The node's parameters in the mode of `defaults`: `signals`, for measured mode (onboard MeasuredLimits)
    its sensor set and car, then the fields of the limits (warning.limits.Limits, or MeasuredLimits) with their
    metadata, defaults from `defaults`; the limits may change while running."""
    setup = [] if isinstance(defaults, Limits) else MEASURED_SETUP
    return [SIGNALS] + setup + [
        P(f.name, getattr(defaults, f.name), f.metadata["meaning"] + "; " + f.metadata["source"],
          f.metadata["unit"], f.metadata["accepted"], f.metadata["lo_open"], f.metadata["nan_disables"])
        for f in fields(defaults)]


def measured_alert_text(criterion, severity, value, threshold, place):
    """One line of a measured alert, its values with the unit of the criterion's level (MeasuredLimits)."""
    from .onboard.measured import MeasuredLimits
    unit = next((f.metadata["unit"] for f in fields(MeasuredLimits) if f.name == criterion), "")
    return f"measured {SEVERITY_NAMES[severity]}: {label(criterion)} {amount_text(value, threshold, unit)} at {place}"


def measured_alert_message(alert, speed):
    """The Alert message of an on-board monitor's alert (`onboard.measured.MeasuredAlert`) at the odometer's
    speed (m/s)."""
    message = m.Alert()
    m.stamp(message, alert.time_s)
    message.header.frame_id = alert.place
    bogie = next((j for j, g in enumerate(("bogie_front", "bogie_rear")) if alert.place.startswith(g)), None)
    message.wheelset = -1 if bogie is None else RUNNING_GEARS[bogie][0]
    message.wheel_side = next((side for side in ("left", "right") if alert.place.endswith(side)), "")
    message.sample, message.criterion, message.severity = alert.sample, alert.criterion, alert.severity
    message.value, message.threshold = alert.value, alert.threshold
    message.track_position, message.speed = alert.track_position, speed
    message.message = measured_alert_text(alert.criterion, alert.severity, alert.value, alert.threshold, alert.place)
    return message


def estimate_messages(stamps, estimates):
    """The OnboardEstimate messages of the estimator's values at stamps (estimator.RollBalance's dict)."""
    out = []
    for k, t in enumerate(stamps):
        message = m.stamp(m.OnboardEstimate(), float(t))
        message.header.frame_id = "car_body"
        message.wheel_load = 0.5 * estimates["side_load"][k]
        message.unloading = estimates["unloading"][k]
        message.lateral_force = estimates["lateral_force"][k]
        message.derailment_coefficient = estimates["derailment_coefficient"][k]
        out.append(message)
    return out


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
        self.mode = declare_parameters(self, [SIGNALS])["signals"]
        if self.mode == "measured":
            self._measured()
            return
        self.limit_values = declare_parameters(self, parameter_table(default_limits())[1:],
                                               check=lambda values: Limits(**values).validated(),
                                               apply=self.on_limits)
        self.monitor = Monitor(Limits(**self.limit_values))
        self.publisher = self.create_publisher(m.Alert, m.ALERTS, m.ALERT_QOS)
        self.supervision = self._supervision()
        self.create_subscription(m.WheelsetStates, m.STATES, self.on_states, m.SENSOR_SUBSCRIBER)
        self.create_subscription(m.ContactForces, m.FORCES, self.on_forces, m.SENSOR_SUBSCRIBER)
        self.counts = {"states": [0, 0, None], "forces": [0, 0, None]}   # received, missed, last sample
        self.alerts = 0
        self.get_logger().info(f"railderail monitor: {self.monitoring()}")

    def _supervision(self):
        """The speed supervision of the `supervision` parameters, or None: its brake command's and its views'
        publishers, the odometer's and the measured monitor's subscriptions."""
        setup = declare_parameters(self, SUPERVISION_SETUP, apply=self.on_live_inputs)
        if not setup["supervision"]:
            return None
        from railderail_sim.sensors.config import load as load_sensors

        from .supervision.on_line import OnLineSupervision
        path = setup["supervision"]
        try:
            with open(path) as f:
                survey = json.load(f)
        except (OSError, ValueError) as error:
            raise ValueError(f"supervision {path}: not a survey's JSON ({error})") from None
        odometer = load_sensors(None).odometer if setup["supervision_signals"] == "odometer" else None
        supervision = OnLineSupervision(survey, path, setup["supervision_vehicle_set"], setup["supervision_adhesion"],
                                        setup["supervision_signals"], odometer,
                                        setup["supervision_nonlinear_critical_speed_kmh"])
        self.brake_publisher = (self.create_publisher(m.BrakeCommand, m.BRAKE, m.BRAKE_QOS)
                                if setup["supervision_brake"] else None)
        self.setup_publisher = self.create_publisher(m.TOPICS[m.SUPERVISION][1], m.SUPERVISION, m.LATCHED)
        self.status_publisher = self.create_publisher(m.TOPICS[m.SUPERVISION_STATUS][1], m.SUPERVISION_STATUS,
                                                      m.SENSOR)
        self.curves_publisher = self.create_publisher(m.TOPICS[m.BRAKING_CURVES][1], m.BRAKING_CURVES, m.SENSOR)
        self.supervision = supervision
        self.on_live_inputs({k: setup[k] for k in LIVE_PARAMETERS})
        if odometer is not None:
            topic = f"{m.SENSORS_NS}/{sm.ODOMETER}"
            self.create_subscription(sm.sensor_topics(load_sensors(None))[topic][1], topic, self.on_odometer,
                                     SENSOR_BACKLOG)
        self.create_subscription(m.Alert, m.ONBOARD_ALERTS, self.on_onboard_alert, m.ALERT_QOS)
        targets = supervision.supervisor.base
        self.get_logger().info(f"speed supervision ({setup['supervision_signals']}): {len(targets)} targets of "
                               f"{path}" + ("" if self.brake_publisher else " (alerts only: no brake commands)"))
        return supervision

    def on_live_inputs(self, changed):
        """The live inputs' parameters set (at start, or `ros2 param set` while running): the targets they move
        rebuilt, and published again."""
        given = {LIVE_PARAMETERS[k]: (None if math.isnan(v) else v) for k, v in changed.items() if k in LIVE_PARAMETERS}
        if not given or getattr(self, "supervision", None) is None:
            return
        self.supervision.inputs(**given)
        self._publish_setup(", ".join(f"{k} {v:g}" for k, v in changed.items() if k in LIVE_PARAMETERS))

    def _publish_setup(self, why):
        self.setup_publisher.publish(m.supervision_setup_message(self.supervision.setup()))
        self.get_logger().info(f"speed supervision: live inputs {why}: {len(self.supervision.supervisor.curves)} "
                               "targets")

    def on_onboard_alert(self, msg):
        if self.supervision.on_onboard_alert(msg.criterion):
            self._publish_setup(f"hunting ({msg.criterion} at {msg.header.frame_id})")

    def on_odometer(self, msg):
        self._supervised(self.supervision.on_odometer(m.seconds(msg.header.stamp), msg.twist.twist.linear.x))

    def _measured(self):
        """The measured mode: the sensor topics only, MeasuredMonitor, /railderail/onboard_alerts."""
        from railderail_sim.sensors.config import load as load_sensors

        from .onboard import measured as me
        from .onboard.car import load_car
        from .onboard.estimator import GivenWind
        from .onboard.monitor import MeasuredMonitor

        setup = declare_parameters(self, MEASURED_SETUP)
        self.sensors = load_sensors(None if setup["sensors"] == "shipped" else setup["sensors"])
        self.vehicle = load_car(setup["vehicle_set"])
        self.rates = me.sample_rates(self.sensors)
        self.limit_values = declare_parameters(
            self, parameter_table(me.measured_limits(self.vehicle))[len(MEASURED_SETUP) + 1:],
            check=lambda values: me.MeasuredLimits(**values).validated(), apply=self.on_measured_limits)
        self.estimates = []            # the estimator's (stamps, values) decided by a sensor message
        wind = (GivenWind(0.0, setup["wind_speed"], math.radians(setup["wind_direction"]))
                if setup["wind_speed"] > 0.0 else None)
        self.make_monitor = lambda: MeasuredMonitor(self.vehicle, me.MeasuredLimits(**self.limit_values), self.rates,
                                                    on_estimate=lambda *decided: self.estimates.append(decided),
                                                    wind=wind)
        self.monitor = self.make_monitor()
        self.decoder = sm.SensorDecoder(self.sensors)
        self.publisher = self.create_publisher(m.Alert, m.ONBOARD_ALERTS, m.ALERT_QOS)
        self.estimate_publisher = self.create_publisher(m.OnboardEstimate, m.ONBOARD_ESTIMATES, m.SENSOR)
        topics = sm.sensor_topics(self.sensors)
        for topic in self.decoder.topics():
            self.create_subscription(topics[topic][1], topic, lambda msg, topic=topic: self.on_sensor(topic, msg),
                                     SENSOR_BACKLOG)
        self.received, self.alerts = 0, 0
        levels = ", ".join(f"{c} {getattr(self.monitor.limits, c):.4g}" for c in me.CRITERIA
                           if c in me.criteria_of(self.rates))
        self.get_logger().info(f"railderail monitor (measured, {len(topics)} sensor topics): monitoring {levels}")
        if self.monitor.left_out[0]:
            self.get_logger().warning(f"on-board criteria without their sensors: {self.monitor.left_out[1]}")

    def on_measured_limits(self, changed):
        self.monitor = self.make_monitor()
        self.get_logger().info("thresholds changed (" + ", ".join(f"{k} {v:g}" for k, v in changed.items())
                               + "): a new measured monitor")

    def on_sensor(self, topic, msg):
        self.received += 1
        for unit, t, signals in self.decoder.decode(topic, msg):
            alerts = self.monitor.feed(unit, t, **signals)
            for alert in alerts:                   # publish first, log after: logging takes time
                speed = float(self.monitor.odometer.speed(alert.time_s))
                self.publisher.publish(measured_alert_message(alert, speed))
            for decided in self.estimates:         # after the alerts, which are the hurry
                for message in estimate_messages(*decided):
                    self.estimate_publisher.publish(message)
            self.estimates.clear()
            for alert in alerts:
                self.alerts += 1
                self.get_logger().warning(f"t = {alert.time_s:.3f} s, s = {alert.track_position:.1f} m: measured "
                                          f"{alert.criterion} {alert.value:.4g} >= {alert.threshold:.4g} at "
                                          f"{alert.place}")

    def monitoring(self):
        levels = ", ".join(f"{c} {'/'.join(f'{t:.4g}' for _, t in self.monitor.limits.levels(c))}"
                           for c in self.monitor.channels)
        return f"monitoring {levels}; debounce {self.monitor.limits.debounce_m:g} m"

    def on_limits(self, changed):
        """New thresholds while running: a new Monitor (every channel armed again)."""
        self.monitor = Monitor(Limits(**self.limit_values))
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
        t = m.seconds(msg.header.stamp)
        if self.supervision is not None:
            self._supervised(self.supervision.on_states(t, msg.sample, msg.track_position, msg.speed))
        self._publish(self.monitor.on_states(t, msg.sample, msg.track_position, msg.speed, msg.curvature,
                                             msg.attack_angle, msg.wheel_lift))

    def _supervised(self, steps):
        """Publish what the supervision's steps gave: the brake before anything else, then the alerts, the
        status and the braking curves when they are sent."""
        for step in steps:
            if step.brake is not None and self.brake_publisher is not None:
                sv = self.supervision
                t, position, speed = step.time_s, step.position_m, step.speed_m_s
                command = m.stamp(m.BrakeCommand(), t)
                command.header.frame_id = "track"
                command.sample, command.speed, command.release_speed = sv.sample, speed, step.brake
                command.track_position, command.reason = position, sv.reason()
                self.brake_publisher.publish(command)
                self.get_logger().warning(f"t = {t:.3f} s, s = {position:.1f} m: emergency brake commanded "
                                          f"at {speed * 3.6:.1f} km/h, down to {step.brake * 3.6:.1f} km/h")
            self._publish(step.alerts)
            self.status_publisher.publish(m.supervision_status_message(step.status))
            if step.curves is not None:
                self.curves_publisher.publish(m.braking_curves_message(step.curves))

    def on_forces(self, msg):
        self._count("forces", msg.sample)
        self._publish(self.monitor.on_forces(m.seconds(msg.header.stamp), msg.sample, msg.track_position, msg.speed,
                                             msg.curvature, msg.derailment_coefficient, msg.vertical_force))

    def summary(self):
        if self.mode == "measured":
            return (f"measured: processed {self.received} sensor messages ({self.decoder.missed} air-spring stamps "
                    f"incomplete); {self.alerts} alerts")
        (ns, ms, _), (nf, mf, _) = self.counts["states"], self.counts["forces"]
        return (f"processed {ns} wheelset states ({ms} missed) and {nf} contact forces ({mf} missed); "
                f"{self.alerts} alerts")


    def destroy_node(self):
        print(f"[railderail_monitor] {self.summary()}", file=sys.stderr, flush=True)
        super().destroy_node()


def main(argv=None) -> int:
    if (sys.argv[1:] if argv is None else argv) == ["--supervision-params"]:
        sys.stdout.write(supervision_parameter_file())
        return 0
    return m.run_node("railderail-monitor", MonitorNode, argv, executor_class=m.events_executor)


if __name__ == "__main__":
    sys.exit(main())
