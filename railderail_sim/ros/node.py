"""Simulator node `railderail_simulator`: steps the numba core and publishes its samples.

A timer fires at the publish rate (times the real-time factor); each tick integrates exactly one
publication period (`Simulation.advance`) and publishes the new sample on the state topics
(the samples' QoS, reliable): wheelset states and contact forces at every sample, the vehicle status at
`status_rate` (every 4th sample by default), plus /clock when not running at real time. When the
run stops it publishes the final VehicleStatus on /railderail/final_status and, after a derailment,
the ground-truth DerailmentEvent on /railderail/derailment (both reliable, transient local), then
exits (0; 1 if the model diverged, with the reason in the log and in the final status). Topics and
QoS: railderail_sim/ros/interface.py.

Parameters (`-p name:=value`, `--params-file`): PARAMETERS below, each with its descriptor (range,
read-only). A bad value at start is one line `railderail-simulator: error: ...` and exit status 2.
The scenario's parameters are read-only (the model is built from them); real_time_factor,
status_rate, linger_s and frame_id may change while running (`ros2 param set`), checked as at start.
"""
import math
import sys
import time
from dataclasses import replace

import rclpy
from rclpy.node import Node
from rclpy.task import Future

from railderail_sim.loads.wind import DIRECTION_RANGE_DEG, GUSTS, WIND_SPEED_RANGE, Wind
from railderail_sim.parameters import CANT_RANGE_MM, FRICTION_RANGE, TRACK_MODELS
from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.ros.node_parameters import REAL_TIME_FACTOR_RANGE, ParameterSpec as P, declare_parameters
from railderail_sim.sensors.config import load as load_sensors
from railderail_sim.sensors.sensor_set import SEED_RANGE
from railderail_sim.supervision.braking import ADHESIONS, BrakingModel
from railderail_sim.supervision.closed_loop import BrakeCommand, apply_brake
from railderail_sim.track.irregularity import SEEDS, resolve
from railderail_sim.track.spectra import SPECTRA
from railderail_sim.vehicle.assemble import FAULT_NAMES, NORMAL_MODELS
from railderail_sim.vehicle.simulate import (RADIUS_RANGE, SPEED_RANGE_KMH, Simulation, SimulationDiverged,
                                             output_arrays)

MAX_CATCH_UP = 20   # samples one late tick may publish in a row
MATCH_WAIT_S = 5.0   # s the run waits, once its subscribers are there, for every subscription to match
# s the node waits at the end, at most, for its readers to acknowledge every message. What the transport dropped
# while a reader was held up is sent again on the writer's heartbeats (Fast DDS: every 3 s), a round or more per
# topic: 5 s lost a recorder's tail of one topic after a 3 s stall in 4 of 6 tries (docs/ros.md)
ACK_WAIT_S = 30.0
PUBLISH_RATE_RANGE = (1.0, 2000.0)        # Hz of simulated time

# The scenario's parameters are read-only: the model is built from them before the run starts.
PARAMETERS = (
    P("radius", 1000.0, "curve radius", "m", RADIUS_RANGE, read_only=True),
    P("cant_mm", 175.0, "cant height of the curve (Table 2: 175 mm)", "mm", CANT_RANGE_MM, read_only=True),
    P("approach_m", 0.0, "0: the Table 2 line's straight before the curve's transition; else this many metres of "
      "straight (a train approaching the curve, for the speed supervision)", "m", (0.0, 1.0e5), read_only=True),
    P("line_length_m", 0.0, "0: the Table 2 line (or the staircase's); else the circular curve made longer so that "
      "the line is this long", "m", (0.0, 1.0e6), read_only=True),
    P("speed_mode", "progressive", "progressive: the paper's staircase trial, until derailment; constant: "
      "speed_kmh throughout", choices=("progressive", "constant"), read_only=True),
    P("speed_kmh", 200.0, "constant speed, or the staircase's start speed", "km/h", SPEED_RANGE_KMH, read_only=True),
    P("step_kmh", 5.0, "progressive: speed step of the staircase", "km/h", (0.0, 100.0), lo_open=True,
      read_only=True),
    P("hold_m", 200.0, "progressive: distance each speed is held", "m", (0.0, 10000.0), lo_open=True, read_only=True),
    P("contact_model", "hertz", "normal contact model (discrete: Kik-Piotrowski)", choices=tuple(NORMAL_MODELS),
      read_only=True),
    P("friction", 0.3, "wheel-rail friction coefficient", "", FRICTION_RANGE, lo_open=True, read_only=True),
    P("irregularity", "none", "track irregularity: none, a spectrum (" + ", ".join(SPECTRA) + "; a random sample "
      "along the line) or the path of a CSV file (docs/track-irregularity.md)", read_only=True),
    P("irregularity_seed", 0, "seed of a generated irregularity", "", SEEDS, read_only=True),
    P("track", "rigid", "rigid rails, or elastic: a co-running rail mass under each wheel (docs/elastic-track.md)",
      choices=TRACK_MODELS, read_only=True),
    P("wind_speed_m_s", 0.0, "wind speed (with a gust its peak); 0: still air (docs/loads.md)", "m/s",
      WIND_SPEED_RANGE, read_only=True),
    P("wind_direction_deg", 90.0, "where the wind comes from, relative to the direction of travel: 90 from the "
      "left, -90 from the right", "deg", DIRECTION_RANGE_DEG, read_only=True),
    P("gust", "none", "steady wind (none) or the CEN extreme gust of EN 14067-6 at the middle of the curve",
      choices=GUSTS, read_only=True),
    P("faults", [], "suspension faults, NAME@LOCATION (docs/vehicle-model.md, Suspension limits and faults)",
      choices=FAULT_NAMES, read_only=True),
    P("publish_rate", 200.0, "wheelset states and contact forces per second of simulated time", "Hz",
      PUBLISH_RATE_RANGE, read_only=True),
    P("status_rate", 50.0, "vehicle status messages per second of simulated time, at most publish_rate", "Hz",
      (0.0, PUBLISH_RATE_RANGE[1]), lo_open=True),
    P("real_time_factor", 1.0, "simulated seconds per wall-clock second; 0 = as fast as possible; not 1: "
      "publishes /clock", "", REAL_TIME_FACTOR_RANGE),
    P("wait_for_subscribers", 0, "start the run once wheelset_states and contact_forces have this many "
      "subscribers", "", (0, 100), read_only=True),
    P("wait_for_sensor_subscribers", 0, "with sensors, start the run only once every sensor topic has this many "
      "subscribers too (a measured-mode monitor reads no states or forces)", "", (0, 100), read_only=True),
    P("exit_when_done", True, "exit when the run stops (else keep the latched topics up until Ctrl-C)",
      read_only=True),
    P("linger_s", 1.0, "time the node stays up after the run stops, so that late subscribers get the final "
      "status and derailment event (transient local)", "s", (0.0, 60.0)),
    P("frame_id", "track", "header.frame_id of the published messages"),
    P("sensors", "none", "on-board sensors published under /railderail/sensors/ (docs/onboard.md): none, shipped "
      "(railderail_sim/config/sensors.yaml) or the path of a sensor file", read_only=True),
    P("brake_on_command", True, "brake on the speed supervision's commands (/railderail/brake_command) by the "
      "braking model, the forward speed following its braking curve (docs/supervision.md)", read_only=True),
    P("adhesion", "dry", "the braking model's emergency decelerations: dry rail, or wet (degraded adhesion)",
      choices=ADHESIONS, read_only=True),
    P("sensor_seed", -1, "seed of the sensors' noise, biases and lost samples; -1: the sensor file's", "",
      (-1, SEED_RANGE[1]), read_only=True),
)


def check_rates(p):
    if p["status_rate"] > p["publish_rate"]:
        raise ValueError(f"status_rate {p['status_rate']:g} Hz is above publish_rate {p['publish_rate']:g} Hz")


def sensor_set(p):
    """The sensor set of the node's parameters (None: no sensors), checked against the publish rate."""
    if p["sensors"] == "none":
        return None
    sensors = load_sensors(None if p["sensors"] == "shipped" else p["sensors"])
    if p["sensor_seed"] >= 0:
        sensors = replace(sensors, seed=p["sensor_seed"])
    return sensors.validated(p["publish_rate"])


def build_scenario(p):
    """The Scenario of the node's (checked) parameters (ValueError with a sentence on bad values)."""
    from railderail_sim.methods.progressive_trial import Staircase, staircase_scenario
    from railderail_sim.vehicle.simulate import scenario

    base = scenario(radius=p["radius"], speed_kmh=p["speed_kmh"], contact_model=p["contact_model"],
                    friction=p["friction"])
    base = replace(base, track=replace(base.track, cant_height=p["cant_mm"] / 1000.0))
    if p["approach_m"] > 0.0:
        base = replace(base, track=replace(base.track, straight_in=p["approach_m"]))
    if p["line_length_m"] > 0.0:
        base = replace(base, track=base.track.with_line_length(p["line_length_m"]))
    if p["speed_mode"] == "progressive":
        base = staircase_scenario(base, p["radius"], Staircase(start_kmh=p["speed_kmh"], step_kmh=p["step_kmh"],
                                                               hold_m=p["hold_m"]))
    irregularity = resolve(p["irregularity"], p["irregularity_seed"], base.track.line_length)
    wind = Wind(speed=p["wind_speed_m_s"], direction_deg=p["wind_direction_deg"], gust=p["gust"])
    return replace(base, output_rate=p["publish_rate"], irregularity=irregularity, track_model=p["track"],
                   wind=wind if wind.blows else None, faults=tuple(p["faults"])).validated()


class SimulatorNode(Node):
    def __init__(self):
        super().__init__("railderail_simulator")
        self.p = declare_parameters(self, PARAMETERS, check=check_rates, apply=self.on_parameters)
        self.scenario = build_scenario(self.p)
        self.sensors = sensor_set(self.p)
        self.get_logger().info(f"railderail simulator: building the model (R = {self.p['radius']:g} m, "
                               f"{self.p['speed_mode']} speed from {self.p['speed_kmh']:g} km/h, "
                               f"{self.p['contact_model']} contact"
                               + "".join(f", {fault}" for fault in self.p["faults"])
                               + "); the first run in a fresh checkout also "
                               "compiles the core (about a minute)")
        self.sim = Simulation(self.scenario)
        self.period = 1.0 / self.p["publish_rate"]
        self.status_every = max(1, round(self.p["publish_rate"] / self.p["status_rate"]))
        self.pending = self.sim.advance(self.period)      # compiles; the start sample and the first period
        self.convert = m.RowConverter(self.p["frame_id"])
        self.pubs = {topic: self.create_publisher(cls, topic, qos)
                     for topic, (_, cls, qos, _) in m.TOPICS.items() if topic not in m.MONITOR_TOPICS}
        self.sensor_stream = self.sensor_messages = None
        if self.sensors is not None:
            from railderail_sim.sensors.measure import SensorStream
            self.sensor_stream = SensorStream(self.sensors, self.scenario, self.sim.model, self.sim.speed_table)
            self.sensor_messages = sm.SensorConverter(self.sensors, self.p["publish_rate"],
                                                      self.scenario.vehicle.rolling_radius)
            self.sensor_topics = sm.sensor_topics(self.sensors)
            self.pubs.update({topic: self.create_publisher(cls, topic, qos)
                              for topic, (_, cls, qos, _) in self.sensor_topics.items()})
            self.sensor_queue = []      # (stamp, topic, message) not yet due: a sample's latency after its instant
        self.braking, self.brakes = BrakingModel(adhesion=self.p["adhesion"]).validated(), []
        if self.p["brake_on_command"]:
            self.create_subscription(m.BrakeCommand, m.BRAKE, self.on_brake, m.BRAKE_QOS)
        self.clock_pub = None
        self.published = {}                    # topic -> messages published
        self.sample = 0
        self.done = Future()
        self.exit_code = 0
        self.settle_until = None
        self.run_start = None                  # wall clock of the first tick (the achieved rate)
        self.pace_start = self.pace_sample = None   # wall clock and sample the pacing counts from
        self.last_arrays, self.last_index = None, 0
        self.timer = None
        on_sensors = self.p["wait_for_sensor_subscribers"] if self.sensors is not None else 0
        waiting = self.p["wait_for_subscribers"] > 0 or on_sensors > 0
        self.get_logger().info(f"ready: {self.p['publish_rate']:g} Hz of simulated time, {self.pace_text()}"
                               + (f"; waiting for {self.p['wait_for_subscribers']} subscribers" if waiting else "")
                               + (f" and {on_sensors} on every sensor topic" if on_sensors else ""))
        if waiting:
            self.wait_timer = self.create_timer(0.05, self.wait_for_subscribers)
        else:
            self.start()

    def pace_text(self):
        rtf = self.p["real_time_factor"]
        return "as fast as possible" if rtf == 0.0 else f"{rtf:g} x real time"

    def start(self):
        """(Re)start the timer at the real-time factor; the pacing counts from the current sample."""
        rtf = self.p["real_time_factor"]
        if rtf != 1.0 and self.clock_pub is None:
            _, clock_cls, qos, _ = m.CLOCK_TOPIC
            self.clock_pub, self.Clock = self.create_publisher(clock_cls, m.CLOCK, qos), clock_cls
        self.pace_start = None
        period = 0.0 if rtf == 0.0 else self.period / rtf
        if self.timer is None:
            self.timer = self.create_timer(period, self.tick)
        else:
            self.timer.timer_period_ns = int(period * 1e9)

    def on_parameters(self, changed):
        """Apply the parameters that may change while running (the others are read-only)."""
        if "status_rate" in changed:
            self.status_every = max(1, round(self.p["publish_rate"] / self.p["status_rate"]))
        if "frame_id" in changed:
            self.convert.frame_id = self.p["frame_id"]
        if "real_time_factor" in changed and self.timer is not None and not self.done.done():
            self.start()
        self.get_logger().info("parameters changed: " + ", ".join(f"{k} {v}" for k, v in changed.items())
                               + f" ({self.pace_text()})")

    def on_brake(self, msg):
        """The speed supervision's emergency brake: from the last published sample on, the speed follows the
        braking model's curve down to the command's release speed (the forward speed stays prescribed, as in
        the batch closed loop, railderail_sim/supervision/closed_loop.py); a command while a brake is on is
        ignored. The brake starts where the command arrives, not where it was decided: the delay is DDS's."""
        a, i = self.last_arrays, self.last_index
        if a is None or self.done.done():
            return
        position, speed = float(a["position"][i]), float(a["speed"][i])
        if self.brakes and position < self.sim.speed_table[-2, 0]:
            return
        if not msg.release_speed < speed:
            self.get_logger().warning(f"brake command ignored: release speed {msg.release_speed * 3.6:.1f} km/h "
                                      f"is not below the speed {speed * 3.6:.1f} km/h")
            return
        command = BrakeCommand(float(a["time"][i]), position, speed, float(msg.release_speed))
        apply_brake(self.sim, command, self.braking)
        if self.sensor_stream is not None:
            self.sensor_stream.speed_table = self.sim.speed_table
        self.brakes.append(command)
        self.get_logger().warning(
            f"EMERGENCY BRAKE at t = {command.time_s:.3f} s, s = {position:.1f} m, {speed * 3.6:.1f} km/h "
            f"(commanded at sample {msg.sample}, {self.sample - 1 - msg.sample} samples ago), down to "
            f"{msg.release_speed * 3.6:.1f} km/h: {msg.reason}")

    def wait_for_subscribers(self):
        if self._subscribers_ready():
            self.wait_timer.cancel()
            self.get_logger().info("subscribers present: starting the run")
            self.start()

    def _subscribers_ready(self):
        need = self.p["wait_for_subscribers"]
        if min(self.pubs[t].get_subscription_count() for t in (m.STATES, m.FORCES)) < need:
            return False
        if self.sensors is not None and min(self.pubs[t].get_subscription_count()
                                            for t in self.sensor_topics) < self.p["wait_for_sensor_subscribers"]:
            return False
        if self.settle_until is None:          # let the subscribers' side of the discovery settle too
            self.settle_until = time.monotonic() + 0.5
        now = time.monotonic()
        if now < self.settle_until:
            return False
        # and every subscription the graph shows matched to its publisher, the sensor topics' too: a best-effort
        # message sent before its reader matched is lost to it (a measured-mode monitor lost its first
        # messages so); at most MATCH_WAIT_S, for a subscription whose QoS never matches
        return now >= self.settle_until + MATCH_WAIT_S or all(
            pub.get_subscription_count() >= self.count_subscribers(topic) for topic, pub in self.pubs.items())

    def tick(self):
        """Publish the samples that are due: one per tick as fast as possible, else as many as the
        wall clock x real-time factor asks for (a late tick catches up instead of losing periods)."""
        if self.done.done():
            return
        now = time.monotonic()
        if self.run_start is None:
            self.run_start = now
        if self.pace_start is None:
            self.pace_start, self.pace_sample = now, self.sample
        rtf = self.p["real_time_factor"]
        due = 1 if rtf == 0.0 else (int((now - self.pace_start) * self.p["publish_rate"] * rtf) + 1
                                    - (self.sample - self.pace_sample))
        for _ in range(min(due, MAX_CATCH_UP)):
            if not self.step():
                return

    def step(self):
        """Integrate one publication period and publish it; False once the run has stopped."""
        try:
            rows, self.pending = (self.pending, None) if self.pending is not None else (self.sim.advance(self.period), None)
        except SimulationDiverged as error:
            self.get_logger().error(str(error))
            self.finish(m.msgs.VehicleStatus.STATE_DIVERGED, str(error), self.last_arrays, self.last_index, code=1)
            return False
        if len(rows):
            a = output_arrays(rows)
            if self.sensor_stream is not None:
                self.sensor_queue += self.sensor_messages.messages(self.sensor_stream.process(a))
                self.sensor_queue.sort(key=lambda item: item[0])   # the mounts' latencies differ
            for i in range(len(rows)):
                self.publish_sample(a, i)
            self.last_arrays, self.last_index = a, len(rows) - 1
        if self.sim.status != 0:
            self.stop_run()
            return False
        return True

    def publish_sample(self, a, i):
        if self.clock_pub is not None:
            clock = self.Clock()
            m.set_time(clock.clock, a["time"][i])
            self.send(m.CLOCK, clock)
        if self.sensor_stream is not None:
            self.publish_sensors(a["time"][i])
        self.send(m.STATES, self.convert.states(a, i, self.sample))
        self.send(m.FORCES, self.convert.forces(a, i, self.sample))
        if self.sample % self.status_every == 0:
            self.send(m.STATUS, self.convert.status(a, i, self.sample))
        self.sample += 1
        if self.sample % int(10 * self.p["publish_rate"]) == 0:
            self.get_logger().info(f"t = {a['time'][i]:.1f} s, s = {a['position'][i]:.0f} m, "
                                   f"v = {a['speed'][i] * 3.6:.1f} km/h ({self.achieved_rate():.0f} samples/s)")

    def publish_sensors(self, now):
        """Publish the sensors' messages stamped up to the simulated time `now` (s; the rest wait: latency)."""
        due = 0
        while due < len(self.sensor_queue) and self.sensor_queue[due][0] <= now + 1e-9:
            _, topic, message = self.sensor_queue[due]
            self.send(topic, message)
            due += 1
        del self.sensor_queue[:due]

    def send(self, topic, message):
        """Publish on a topic and count it: the recorder's and the monitors' counts are compared with these."""
        (self.clock_pub if topic == m.CLOCK else self.pubs[topic]).publish(message)
        self.published[topic] = self.published.get(topic, 0) + 1

    def achieved_rate(self):
        wall = time.monotonic() - self.run_start if self.run_start else 0.0
        return self.sample / wall if wall > 0 else 0.0

    def stop_run(self):
        S = m.msgs.VehicleStatus
        event = self.sim.derailment()
        a, i = self.last_arrays, self.last_index
        if event is not None:
            body_position = event["car_body_position_m"]
            self.send(m.DERAILMENT, m.derailment_message(event, body_position, self.p["frame_id"]))
            text = (f"derailed: wheelset {event['wheelset']} {event['wheel_side']} ({event['rail_side']} rail), "
                    f"{event['mechanism'].replace('_', ' ')}, at t = {event['time_s']:.3f} s, "
                    f"s = {body_position:.1f} m, {event['speed_kmh']:.1f} km/h")
            self.finish(S.STATE_DERAILED, text, a, i)
        else:
            self.finish(S.STATE_FINISHED, f"finished: end of the line at s = {a['position'][i]:.1f} m", a, i)

    def finish(self, state, text, a, i, code=0):
        if self.sensor_stream is not None:
            # the last rows' samples, stamped after them by their latency: the train's sensors still send them
            self.publish_sensors(math.inf)
        if a is None:
            status = m.msgs.VehicleStatus(state=state, message=text)
        else:
            status = self.convert.status(a, i, max(self.sample - 1, 0), state=state, message=text)
        self.send(m.FINAL_STATUS, status)
        log = self.get_logger().error if code else self.get_logger().info
        log(f"{text}; published {self.sample} samples at {self.achieved_rate():.1f} samples/s "
            f"(requested {self.p['publish_rate'] * self.p['real_time_factor']:g}"
            f"{'' if self.p['real_time_factor'] else ' = as fast as possible'})")
        self.get_logger().info(m.run_report_line(self.published, self.achieved_rate(),
                                                 self.p["publish_rate"] * self.p["real_time_factor"]))
        if self.timer is not None:
            self.timer.cancel()
        self.exit_code = code
        self.done.set_result(code)


    def destroy_node(self):
        if not self.done.done():
            self.get_logger().info(f"stopped (Ctrl-C/SIGTERM) after {self.sample} samples")
        super().destroy_node()


def run_until_done(node, executor):
    """Spin until the run stops, stay up `linger_s` for late subscribers and until the readers
    acknowledged every message (at most ACK_WAIT_S); or, with exit_when_done false, until Ctrl-C."""
    if not node.p["exit_when_done"]:
        m.spin_until(executor)
        return node.exit_code
    m.spin_until(executor, node.done.done)
    end = time.monotonic() + node.p["linger_s"]
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)
    # every topic is reliable: the readers' last samples too, which the transport may have to send again
    end = time.monotonic() + ACK_WAIT_S
    unacknowledged = [topic for topic, pub in node.pubs.items()
                      if not pub.wait_for_all_acked(rclpy.duration.Duration(seconds=max(end - time.monotonic(), 0.0)))]
    if unacknowledged:
        node.get_logger().warning(f"readers did not acknowledge every message within {ACK_WAIT_S:g} s (their "
                                  f"recordings may lack the last ones): {', '.join(unacknowledged)}")
    return node.exit_code


def main(argv=None) -> int:
    return m.run_node("railderail-simulator", SimulatorNode, argv, spin=run_until_done)


if __name__ == "__main__":
    sys.exit(main())
