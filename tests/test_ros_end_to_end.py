"""End to end with real rclpy nodes in separate processes: simulator -> monitor -> alerts before
the ground-truth derailment, all recorded to MCAP; the recording replays to the same alerts (offline
and through a fresh monitor node); `railderail demo` runs on a short staircase.

Which criterion fires first, and how early, is for the physics to decide: nothing here forces it.
The simulator runs as fast as possible (real_time_factor 0) wherever only its output matters. The
waits allow for a cold numba compile in the simulator node (about a minute; it happens when the
physics code changed since the cache was written).
"""
import json
import re
import signal
import sys
import time
from pathlib import Path

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.signals import SignalHandlerOptions

from conftest import STARTUP_S
from railderail_sim.ros import interface as m
from railderail_monitor.warning.limits import CRITERIA, default_limits
from railderail_monitor.warning.monitor import alerts_of_run
from railderail_monitor.warning.alarms import nanoseconds
from railderail_monitor.recording.replay import read_recording, review

PY = sys.executable
# a constant over-speed on R = 1000 m: the car derails about 5 s after the start (in the transition);
# published as fast as possible (about 1000 samples)
SIMULATOR = [PY, "-m", "railderail_sim.ros.node", "--ros-args", "-p", "speed_mode:=constant", "-p", "speed_kmh:=310.0",
             "-p", "radius:=1000.0", "-p", "real_time_factor:=0.0", "-p", "wait_for_subscribers:=3"]


class Listener:
    """The test's own node (own context): alerts, derailment event, final status."""

    def __init__(self):
        self.context = rclpy.Context()
        rclpy.init(context=self.context, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node("railderail_test_listener", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.alerts, self.derailment, self.final = [], None, None
        self.node.create_subscription(m.Alert, m.ALERTS, lambda msg: self.alerts.append(m.alert_dict(msg)),
                                      m.ALERT_QOS)
        self.node.create_subscription(m.DerailmentEvent, m.DERAILMENT,
                                      lambda msg: setattr(self, "derailment", m.derailment_dict(msg)), m.LATCHED)
        self.node.create_subscription(m.VehicleStatus, m.FINAL_STATUS, lambda msg: setattr(self, "final", msg),
                                      m.LATCHED)
        m.count_as_subscriber(self.node)             # with the monitor and the recorder: 3 subscribers

    def spin_until(self, condition, timeout):
        deadline = time.monotonic() + timeout
        while not condition() and time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.1)
        return condition()

    def spin_for(self, seconds):
        self.spin_until(lambda: False, seconds)

    def close(self):
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)


def keys(alerts):
    """Which sample, criterion, level, wheel and rail alerted (the rail from the sample's own curvature, so the
    same whatever order the live node got the topics in)."""
    return sorted((a["sample"], a["criterion"], a["severity"], a["wheelset"], a["wheel_side"], a["rail_side"])
                  for a in alerts)


def events(alerts):
    """The alerts without their samples: which criterion, level, wheel and rail alerted."""
    return sorted(key[1:] for key in keys(alerts))


def stop(process, timeout=20):
    process.send_signal(signal.SIGINT)
    return process.wait(timeout=timeout)


@pytest.mark.timeout(500)
def test_nodes_warn_before_the_derailment_and_the_recording_replays_to_the_same_alerts(spawn, read_until, tmp_path):
    mcap = tmp_path / "e2e.mcap"
    listener = Listener()
    try:
        recorder = spawn([PY, "-m", "railderail_monitor.recording.recorder", str(mcap)])
        monitor = spawn([PY, "-m", "railderail_monitor.node"])
        read_until(recorder, "recording", timeout=STARTUP_S)
        read_until(monitor, "monitoring", timeout=STARTUP_S)
        simulator = spawn(SIMULATOR)
        assert listener.spin_until(lambda: listener.final is not None, timeout=300), \
            f"no final status; simulator stderr: {simulator.stderr.read() if simulator.poll() is not None else ''}"
        assert simulator.wait(timeout=30) == 0
        listener.spin_for(1.0)                                       # the last alerts
        assert listener.final.state == m.msgs.VehicleStatus.STATE_DERAILED
        d = listener.derailment
        assert d is not None and d["mechanism"] in ("flange_climbing", "wheel_unloading")

        # alerts came, every one of them before the ground-truth derailment
        live = listener.alerts
        assert live, "no alert before the derailment"
        assert all(a["time_s"] <= d["time_s"] for a in live)
        assert min(a["time_s"] for a in live) < d["time_s"]
        assert all(a["criterion"] in CRITERIA
                   for a in live)
        # one alert per event: no (criterion, level, wheel) repeats within this short run
        assert len(set((a["criterion"], a["severity"], a["wheelset"], a["wheel_side"]) for a in live)) == len(live)

        assert stop(monitor) == 0
        monitor_log = monitor.stderr.read()
        assert "processed" in monitor_log and f"{len(live)} alerts" in monitor_log
        # the subscriber queue kept every sample of the run (else the comparisons below cannot hold)
        assert "wheelset states (0 missed) and" in monitor_log and "contact forces (0 missed)" in monitor_log
        assert stop(recorder) == 0

        # the recording, and the criteria over it give the alerts the monitor raised: sample for sample when the
        # recording holds every sample the monitor processed; when the recorder lost some (under load, or a
        # subscription matched after the first messages), the same alerts at the same wheels, their samples moved
        # by what was lost
        recording = read_recording(mcap)
        found = review(recording)
        assert keys(found.recorded_alerts) == keys(live) and found.curvature_from == "samples"
        processed = re.search(r"processed (\d+) wheelset states \(0 missed\) and (\d+) contact forces", monitor_log)
        held = recording.topics()
        complete = (held[m.STATES][1], held[m.FORCES][1]) == tuple(int(n) for n in processed.groups())
        same = keys if complete else events
        assert same(a.as_dict() for a in found.alerts) == same(live)
        assert found.derailment["time_s"] == pytest.approx(d["time_s"])

        # replayed on the topics to a fresh monitor node: the same alerts again
        listener.alerts.clear()
        monitor2 = spawn([PY, "-m", "railderail_monitor.node"])
        read_until(monitor2, "monitoring", timeout=STARTUP_S)
        replay = spawn([PY, "-m", "railderail_sim.cli", "replay", str(mcap), "--rate", "1",
                        "--wait-for-subscribers", "1"])
        assert replay.wait(timeout=120) == 0, replay.stderr.read()
        listener.spin_until(lambda: len(listener.alerts) >= len(live), timeout=10)
        listener.spin_for(1.0)
        assert stop(monitor2) == 0
        assert same(listener.alerts) == same(live)
    finally:
        listener.close()


# Node = batch: a flange climb at a 20 mm twist on R = 150 m (30 km/h, mu 0.6, the catalogue's twist-20mm
# without its random track) with every level lowered so that every criterion fires, the 50 ms Q/P duration,
# the 2 m mean and the climb distance included; the running-gear rule with a short debounce to see it fire.
TWIST = dict(radius=150.0, cant_mm=150.0, speed_mode="constant", speed_kmh=30.0, friction=0.6,
             irregularity=str(Path(__file__).parents[1] / "railderail_monitor" / "config" / "twist-20mm-5m.csv"))
LOWERED = dict(attack_angle=0.01, attack_angle_critical=0.015, wheel_lift=0.004, wheel_lift_critical=0.008,
               wheel_unloading=0.3, wheel_unloading_critical=0.4, derailment_coefficient=0.6,
               derailment_coefficient_critical=0.8, derailment_coefficient_duration=0.6,
               derailment_coefficient_duration_critical=0.8, derailment_coefficient_mean=0.6,
               derailment_coefficient_mean_critical=0.8, running_gear_unloading=0.2,
               flange_climb_distance=0.1, flange_climb_distance_critical=0.3, climb_nadal_limit=0.6, debounce_m=0.5)


def alert_keys(alerts):
    """What must agree, alert for alert: sample, criterion, level, wheel, and the stamp in integer ns."""
    return sorted((a["sample"], a["criterion"], a["severity"], a["wheelset"], a["wheel_side"], a["rail_side"],
                   nanoseconds(a["time_s"])) for a in alerts)


@pytest.mark.timeout(600)
def test_every_criterion_alerts_through_the_nodes_as_on_the_simulator_s_own_arrays(spawn, read_until, tmp_path):
    from dataclasses import replace

    from railderail_monitor.warning.monitor_params import limits_of_car, parameter_file
    from railderail_sim.ros import node
    from railderail_sim.vehicle.simulate import run_to_stop

    limits = replace(default_limits(), **LOWERED).validated()
    params = tmp_path / "lowered.yaml"
    params.write_text(parameter_file(limits, limits_of_car()[1], "test_ros_end_to_end (levels lowered)"))
    p = {spec.name: spec.default for spec in node.PARAMETERS} | TWIST
    sim, arrays, error = run_to_stop(node.build_scenario(p))
    assert not error and sim.derailment() is not None
    batch = [a.as_dict() for a in alerts_of_run(arrays, limits)]
    assert {a["criterion"] for a in batch} == set(CRITERIA), "the scenario must exercise every criterion"

    listener = Listener()
    try:
        monitor = spawn([PY, "-m", "railderail_monitor.node", "--ros-args", "--params-file", str(params)])
        read_until(monitor, "monitoring", timeout=STARTUP_S)
        # paced at real time (the run takes 72 s): as fast as possible, a monitor on a busy machine falls
        # behind 14000 samples and its queue drops some, and then no comparison can hold
        simulator = spawn([PY, "-m", "railderail_sim.ros.node", "--ros-args", "-p", "real_time_factor:=1.0",
                           "-p", "wait_for_subscribers:=2"]
                          + [arg for k, v in TWIST.items() for arg in ("-p", f"{k}:={v}")])
        assert listener.spin_until(lambda: listener.final is not None, timeout=420), simulator.stderr.read()
        assert simulator.wait(timeout=30) == 0
        listener.spin_for(1.0)
        assert stop(monitor) == 0
        log = monitor.stderr.read()
        assert "wheelset states (0 missed) and" in log and "contact forces (0 missed)" in log
    finally:
        listener.close()
    assert listener.derailment["time_s"] == pytest.approx(sim.derailment()["time_s"])
    assert alert_keys(listener.alerts) == alert_keys(batch)


@pytest.mark.timeout(560)
def test_demo_command(tmp_path):
    """`railderail demo` on a short staircase (from 295 km/h instead of 200): nodes, alerts, files."""
    import subprocess

    out = tmp_path / "demo"
    done = subprocess.run([PY, "-m", "railderail_sim.cli", "demo", "--start-kmh", "295", "--out", str(out),
                           "--real-time-factor", "0"], capture_output=True, text=True, timeout=540)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "DERAILED" in done.stdout and "ALERT" in done.stdout and "before the derailment" in done.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["derailment"] is not None and summary["alerts"]
    assert (out / "demo.mcap").stat().st_size > 0 and (out / "demo.rrd").stat().st_size > 0
    assert {p.name for p in (out / "logs").iterdir()} == {"recorder.log", "monitor.log", "onboard.log",
                                                          "simulator.log"}
    assert keys(review(read_recording(out / "demo.mcap")).recorded_alerts) == keys(summary["alerts"])
    # the measured-mode monitor beside it: its alerts marked, recorded, and the same from the sensor topics alone
    assert all(a["signals"] == "measured" for a in summary["onboard_alerts"]) and "[measured]" in done.stdout
    assert all(a["signals"] == "ground_truth" for a in summary["alerts"])
    from railderail_monitor.recording.recover import recover, sensors_only
    from railderail_monitor.recording.replay import measured_key, review_measured
    # what the recorder lost is counted against what the simulator published, and said
    delivered = summary["recording_delivery"]
    assert delivered[m.STATES]["published"] == delivered[m.FORCES]["published"] > 0
    assert summary["recording_lost"] == sum(max(r["lost"], 0) for t, r in delivered.items() if t != m.CLOCK)
    assert "recorder: " + ("the recording LOST" if summary["recording_lost"] else "the recording holds every one") \
        in done.stdout
    assert summary["simulator_pace"]["requested_samples_per_s"] == 0 and not summary["simulator_pace"]["behind"]
    assert all("speed_kmh" in a and "track_position_m" in a and "speed" not in a for a in summary["alerts"])
    recover(out / "demo.mcap", out / "sensors.mcap", keep=sensors_only)
    found, recorded = review_measured(read_recording(out / "sensors.mcap"))
    assert recorded == []
    # the sensor topics alone give the live measured alerts, when the recording and the live monitor got the same
    # messages (best effort: under load either side may lose some, and an alert then moves by a few samples);
    # then the replay still finds the criteria alerting
    sensor = {t: r for t, r in delivered.items() if t.startswith(m.SENSORS_NS + "/")}
    processed = int(re.search(r"processed (\d+) sensor messages", summary["onboard_log"]).group(1))
    if not any(r["lost"] for r in sensor.values()) and processed == sum(r["recorded"] for r in sensor.values()):
        assert sorted(map(measured_key, found)) == sorted(map(measured_key, summary["onboard_alerts"]))
    else:
        assert bool(found) == bool(summary["onboard_alerts"])


DIVERGING_SIMULATOR = """
import importlib, sys
simulate = importlib.import_module("railderail_sim.vehicle.simulate")   # the module, not the function

calls = [0]
advance = simulate.Simulation.advance

def failing_advance(self, duration):
    calls[0] += 1
    if calls[0] > 50:      # the model runs away after a quarter of a second
        raise simulate.SimulationDiverged("the simulation diverged at t = 0.2500 s, track position 21.53 m: "
                                          "wheelset_1 lateral displacement = 0.6 ran away (test)")
    return advance(self, duration)

simulate.Simulation.advance = failing_advance
from railderail_sim.ros.node import main
sys.exit(main())
"""


@pytest.mark.timeout(400)
def test_divergence_gives_a_clear_error_and_a_final_status(spawn):
    listener = Listener()
    try:
        simulator = spawn([PY, "-c", DIVERGING_SIMULATOR, "--ros-args", "-p", "speed_mode:=constant",
                           "-p", "speed_kmh:=300.0", "-p", "real_time_factor:=0.0", "-p", "linger_s:=3.0"])
        assert listener.spin_until(lambda: listener.final is not None, timeout=300)
        assert simulator.wait(timeout=30) == 1
        assert listener.final.state == m.msgs.VehicleStatus.STATE_DIVERGED
        assert "diverged at t = 0.2500 s" in listener.final.message
        assert "diverged at t = 0.2500 s" in simulator.stderr.read()
        assert listener.derailment is None
    finally:
        listener.close()


@pytest.mark.timeout(400)
def test_demo_stops_cleanly_on_ctrl_c(spawn, read_until, tmp_path):
    out = tmp_path / "stopped"
    demo = spawn([PY, "-u", "-m", "railderail_sim.cli", "demo", "--out", str(out)])
    deadline = time.monotonic() + 300
    lines = []
    while not any("samples/s" in line or "subscribers present" in line for line in lines):
        assert time.monotonic() < deadline and demo.poll() is None, lines
        lines.append(demo.stdout.readline())
    time.sleep(2.0)
    demo.send_signal(signal.SIGINT)
    assert demo.wait(timeout=60) == 130
    assert "Ctrl-C: stopping the nodes" in demo.stdout.read()
    with open(out / "demo.mcap", "rb") as f:                 # the recorder finished its file
        f.seek(-8, 2)
        assert f.read(8) == b"\x89MCAP0\r\n"
    time.sleep(1.0)
    assert not nodes_running(str(out)), "a node outlived the demo"


def nodes_running(text):
    """Processes whose command line contains `text` (the demo passes its run folder to the recorder)."""
    from pathlib import Path
    found = []
    for p in Path("/proc").iterdir():
        try:
            if p.name.isdigit() and text.encode() in (p / "cmdline").read_bytes():
                found.append(int(p.name))
        except OSError:
            pass
    return found
