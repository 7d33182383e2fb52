"""Simulator node `railderail_simulator`: steps the numba core and publishes its samples.

A timer fires at the publish rate (times the real-time factor); each tick integrates exactly one
publication period (`Simulation.advance`) and publishes the new sample on the state topics
(sensor-data QoS): wheelset states and contact forces at every sample, the vehicle status at
`status_rate` (every 4th sample by default), plus /clock when not running at real time. When the run stops it publishes the
final VehicleStatus on /railderail/final_status and, after a derailment, the ground-truth
DerailmentEvent on /railderail/derailment (both reliable, transient local), then exits (0; 1 if the
model diverged, with the reason in the log and in the final status). Topics and QoS:
railderail_sim/ros_interface.py; parameters (ros-args `-p name:=value`): PARAMETERS below.
"""
import sys
import time
from dataclasses import replace

import rclpy
from rclpy.node import Node
from rclpy.task import Future

from railderail_sim import ros_interface as m

MAX_CATCH_UP = 20   # samples one late tick may publish in a row

PARAMETERS = {  # name: (default, description)
    "radius": (1000.0, "curve radius, m (300-20000)"),
    "speed_mode": ("progressive", "progressive (the paper's staircase trial, until derailment) | constant"),
    "speed_kmh": (200.0, "constant speed, or the staircase's start speed, km/h"),
    "step_kmh": (5.0, "progressive: speed step of the staircase, km/h"),
    "hold_m": (200.0, "progressive: distance each speed is held, m"),
    "contact_model": ("hertz", "normal contact model: hertz | discrete (Kik-Piotrowski)"),
    "friction": (0.3, "wheel-rail friction coefficient"),
    "publish_rate": (200.0, "wheelset states and contact forces per second of simulated time, Hz"),
    "status_rate": (50.0, "vehicle status messages per second of simulated time, Hz (at most publish_rate)"),
    "real_time_factor": (1.0, "simulated seconds per wall-clock second; 0 = as fast as possible"),
    "wait_for_subscribers": (0, "start the run once wheelset_states and contact_forces have this many subscribers"),
    "exit_when_done": (True, "exit when the run stops (else keep the latched topics up until Ctrl-C)"),
    "linger_s": (1.0, "seconds the node stays up after the run stops, so that late subscribers get the "
                 "final status and derailment event (transient local)"),
    "frame_id": ("track", "header.frame_id of the published messages"),
}


def build_scenario(p):
    """The Scenario of the node's parameters (ValueError with a sentence on bad values)."""
    from railderail_sim.methods.progressive_trial import Staircase, staircase_scenario
    from railderail_sim.vehicle.simulate import scenario

    if p["speed_mode"] not in ("progressive", "constant"):
        raise ValueError(f"speed_mode {p['speed_mode']!r} is not progressive or constant")
    if p["contact_model"] not in ("hertz", "discrete"):
        raise ValueError(f"contact_model {p['contact_model']!r} is not hertz or discrete")
    if not 1.0 <= p["publish_rate"] <= 2000.0:
        raise ValueError(f"publish_rate {p['publish_rate']:g} Hz is outside 1-2000 Hz")
    if not 0.0 < p["status_rate"] <= p["publish_rate"]:
        raise ValueError(f"status_rate {p['status_rate']:g} Hz is outside 0-publish_rate ({p['publish_rate']:g} Hz)")
    if not 0.0 <= p["real_time_factor"] <= 1000.0:
        raise ValueError(f"real_time_factor {p['real_time_factor']:g} is outside 0-1000 (0 = as fast as possible)")
    base = scenario(radius=p["radius"], speed_kmh=p["speed_kmh"], contact_model=p["contact_model"],
                    friction=p["friction"])
    if p["speed_mode"] == "progressive":
        base = staircase_scenario(base, p["radius"], Staircase(start_kmh=p["speed_kmh"], step_kmh=p["step_kmh"],
                                                               hold_m=p["hold_m"]))
    return replace(base, output_rate=p["publish_rate"]).validated()


class SimulatorNode(Node):
    def __init__(self):
        super().__init__("railderail_simulator")
        self.p = m.declare_parameters(self, PARAMETERS)
        sc = build_scenario(self.p)
        from railderail_sim.vehicle.simulate import Result, Simulation

        self.Result = Result
        self.scenario = sc
        self.get_logger().info(f"railderail simulator: building the model (R = {self.p['radius']:g} m, {self.p['speed_mode']} speed from "
                               f"{self.p['speed_kmh']:g} km/h, {self.p['contact_model']} contact); the first run "
                               "in a fresh checkout also compiles the core (about a minute)")
        self.sim = Simulation(sc)
        self.period = 1.0 / self.p["publish_rate"]
        self.status_every = max(1, round(self.p["publish_rate"] / self.p["status_rate"]))
        self.pending = self.sim.advance(self.period)      # compiles; the start sample and the first period
        self.convert = m.RowConverter(self.p["frame_id"])
        self.pubs = {topic: self.create_publisher(cls, topic, qos)
                     for topic, (_, cls, qos, _) in m.TOPICS.items() if topic != m.ALERTS}
        rtf = self.p["real_time_factor"]
        self.clock_pub = None
        if rtf != 1.0:
            _, clock_cls, qos, _ = m.CLOCK_TOPIC
            self.clock_pub, self.Clock = self.create_publisher(clock_cls, m.CLOCK, qos), clock_cls
        self.sample = 0
        self.done = Future()
        self.exit_code = 0
        self.settle_until = None
        self.wall_start = None
        self.last_arrays, self.last_index = None, 0
        self.timer = None
        waiting = self.p["wait_for_subscribers"] > 0
        pace = "as fast as possible" if rtf == 0.0 else f"{rtf:g} x real time"
        self.get_logger().info(f"ready: {self.p['publish_rate']:g} Hz of simulated time, {pace}"
                               + (f"; waiting for {self.p['wait_for_subscribers']} subscribers" if waiting else ""))
        if waiting:
            self.wait_timer = self.create_timer(0.05, self.wait_for_subscribers)
        else:
            self.start()

    def start(self):
        rtf = self.p["real_time_factor"]
        self.timer = self.create_timer(0.0 if rtf == 0.0 else self.period / rtf, self.tick)

    def wait_for_subscribers(self):
        if self._subscribers_ready():
            self.wait_timer.cancel()
            self.get_logger().info("subscribers present: starting the run")
            self.start()

    def _subscribers_ready(self):
        need = self.p["wait_for_subscribers"]
        if min(self.pubs[t].get_subscription_count() for t in (m.STATES, m.FORCES)) < need:
            return False
        if self.settle_until is None:          # let the subscribers' side of the discovery settle too
            self.settle_until = time.monotonic() + 0.5
        return time.monotonic() >= self.settle_until

    def tick(self):
        """Publish the samples that are due: one per tick as fast as possible, else as many as the
        wall clock x real-time factor asks for (a late tick catches up instead of losing periods)."""
        if self.done.done():
            return
        if self.wall_start is None:
            self.wall_start = time.monotonic()
        rtf = self.p["real_time_factor"]
        due = 1 if rtf == 0.0 else int((time.monotonic() - self.wall_start) * self.p["publish_rate"] * rtf) + 1 - self.sample
        for _ in range(min(due, MAX_CATCH_UP)):
            if not self.step():
                return

    def step(self):
        """Integrate one publication period and publish it; False once the run has stopped."""
        from railderail_sim.vehicle.simulate import SimulationDiverged

        try:
            rows, self.pending = (self.pending, None) if self.pending is not None else (self.sim.advance(self.period), None)
        except SimulationDiverged as error:
            self.get_logger().error(str(error))
            self.finish(m.msgs.VehicleStatus.STATE_DIVERGED, str(error), self.last_arrays, self.last_index, code=1)
            return False
        if len(rows):
            a = m.sample_arrays(self.Result(rows=rows, scenario=self.scenario, status=""))
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
            self.clock_pub.publish(clock)
        self.pubs[m.STATES].publish(self.convert.states(a, i, self.sample))
        self.pubs[m.FORCES].publish(self.convert.forces(a, i, self.sample))
        if self.sample % self.status_every == 0:
            self.pubs[m.STATUS].publish(self.convert.status(a, i, self.sample))
        self.sample += 1
        if self.sample % int(10 * self.p["publish_rate"]) == 0:
            self.get_logger().info(f"t = {a['time'][i]:.1f} s, s = {a['position'][i]:.0f} m, "
                                   f"v = {a['speed'][i] * 3.6:.1f} km/h ({self.achieved_rate():.0f} samples/s)")

    def achieved_rate(self):
        wall = time.monotonic() - self.wall_start if self.wall_start else 0.0
        return self.sample / wall if wall > 0 else 0.0

    def stop_run(self):
        S = m.msgs.VehicleStatus
        event = self.sim.derailment()
        a, i = self.last_arrays, self.last_index
        if event is not None:
            body_position = event["car_body_position_m"]
            self.pubs[m.DERAILMENT].publish(m.derailment_message(event, body_position, self.p["frame_id"]))
            text = (f"derailed: wheelset {event['wheelset']} {event['wheel_side']} ({event['rail_side']} rail), "
                    f"{event['mechanism'].replace('_', ' ')}, at t = {event['time_s']:.3f} s, "
                    f"s = {body_position:.1f} m, {event['speed_kmh']:.1f} km/h")
            self.finish(S.STATE_DERAILED, text, a, i)
        else:
            self.finish(S.STATE_FINISHED, f"finished: end of the line at s = {a['position'][i]:.1f} m", a, i)

    def finish(self, state, text, a, i, code=0):
        if a is None:
            status = m.msgs.VehicleStatus(state=state, message=text)
        else:
            status = self.convert.status(a, i, max(self.sample - 1, 0), state=state, message=text)
        self.pubs[m.FINAL_STATUS].publish(status)
        log = self.get_logger().error if code else self.get_logger().info
        log(f"{text}; published {self.sample} samples at {self.achieved_rate():.1f} samples/s "
            f"(requested {self.p['publish_rate'] * self.p['real_time_factor']:g}"
            f"{'' if self.p['real_time_factor'] else ' = as fast as possible'})")
        if self.timer is not None:
            self.timer.cancel()
        self.exit_code = code
        self.done.set_result(code)


    def destroy_node(self):
        if not self.done.done():
            self.get_logger().info(f"stopped (Ctrl-C/SIGTERM) after {self.sample} samples")
        super().destroy_node()


def run_until_done(node, executor):
    """Spin until the run stops, stay up `linger_s` for late subscribers and until the reliable
    readers of the latched topics acknowledged; or, with exit_when_done false, until Ctrl-C."""
    if not node.p["exit_when_done"]:
        executor.spin()
        return node.exit_code
    executor.spin_until_future_complete(node.done)
    end = time.monotonic() + node.p["linger_s"]
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)
    for topic in (m.FINAL_STATUS, m.DERAILMENT):
        node.pubs[topic].wait_for_all_acked(rclpy.duration.Duration(seconds=2.0))
    return node.exit_code


def main(argv=None) -> int:
    return m.run_node("railderail-simulator", SimulatorNode, argv, spin=run_until_done)


if __name__ == "__main__":
    sys.exit(main())
