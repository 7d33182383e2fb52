"""The measured-mode monitor through real nodes: the simulator with its shipped sensors, paced at real time,
the monitor node with signals:=measured and the recorder, in separate processes; the monitor's alerts on
/railderail/onboard_alerts are MeasuredMonitor's on the simulator's own sensor samples (the same run offline,
its samples turned into the same messages), and it lost no sensor message; the recording made live through
DDS holds those alerts, and replayed (its sensor topics through the on-board criteria) gives them again."""
import re
import sys

import pytest
from rclpy.serialization import deserialize_message, serialize_message

from conftest import STARTUP_S
from railderail_sim.ros import node as sim_node
from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.parameters import vehicle_parameters
from railderail_sim.sensors.measure import SensorStream
from railderail_sim.vehicle.simulate import run_to_stop
from railderail_monitor.bench.ros import MEASURED_LEVELS
from railderail_monitor.warning.alarms import nanoseconds
from railderail_monitor.demo import wait_idle
from railderail_monitor.onboard import measured as me
from railderail_monitor.onboard.monitor import MeasuredMonitor
from railderail_monitor.recording.replay import measured_key, read_recording, review_measured
from test_ros_end_to_end import Listener, stop

PY = sys.executable
# a constant over-speed on R = 1000 m: the car derails about 5 s after the start
RUN = dict(speed_mode="constant", speed_kmh=310.0, radius=1000.0, sensors="shipped")


def _offline_alerts():
    """(alerts, messages) of MeasuredMonitor fed the run's sensor messages as the node publishes them."""
    p = {spec.name: spec.default for spec in sim_node.PARAMETERS} | RUN
    sc = sim_node.build_scenario(p)
    sim, arrays, error = run_to_stop(sc)
    assert not error
    sensors = sim_node.sensor_set(p)
    samples = SensorStream(sensors, sc, sim.model, sim.speed_table).process(arrays)
    convert = sm.SensorConverter(sensors, p["publish_rate"], sc.vehicle.rolling_radius)
    decoder = sm.SensorDecoder(sensors)
    vp = vehicle_parameters("hs19")
    monitor = MeasuredMonitor(vp, me.measured_limits(vp, **MEASURED_LEVELS), me.sample_rates(sensors))
    # the node publishes a message once the simulated time reaches its stamp, and at the end of the run the rest
    found, messages = [], convert.messages(samples)
    for _, topic, msg in messages:
        for unit, t, signals in decoder.decode(topic, deserialize_message(serialize_message(msg), type(msg))):
            found += monitor.feed(unit, t, **signals)
    return found, len(messages)


def _live_run(spawn, read_until, mcap):
    """(the monitor node's stderr, its alerts) over one live run of RUN, recorded to `mcap` by the recorder."""
    listener = Listener()
    alerts = []
    listener.node.create_subscription(m.Alert, m.ONBOARD_ALERTS, alerts.append, m.ALERT_QOS)
    try:
        recorder = spawn([PY, "-m", "railderail_monitor.recording.recorder", str(mcap)])
        monitor = spawn([PY, "-m", "railderail_monitor.node", "--ros-args", "-p", "signals:=measured"]
                        + [a for k, v in MEASURED_LEVELS.items() for a in ("-p", f"{k}:={v!r}")])
        read_until(monitor, "monitoring", timeout=STARTUP_S)
        # the recorder takes the monitor's alerts once it has discovered their publisher
        read_until(recorder, f"recording {m.ONBOARD_ALERTS}", timeout=120)     # 60 s was missed once in CI
        assert listener.spin_until(lambda: listener.node.count_subscribers(f"{m.SENSORS_NS}/odometer") >= 1, 30)
        simulator = spawn([PY, "-m", "railderail_sim.ros.node", "--ros-args", "-p", "real_time_factor:=1.0",
                           "-p", "wait_for_subscribers:=1", "-p", "wait_for_sensor_subscribers:=2"]
                          + [a for k, v in RUN.items() for a in ("-p", f"{k}:={v}")])
        assert listener.spin_until(lambda: listener.final is not None, timeout=300), simulator.stderr.read()
        assert simulator.wait(timeout=30) == 0
        wait_idle(monitor.pid)                  # it may be behind: its queue holds the rest of the run
        listener.spin_for(1.0)
        assert stop(monitor) == 0
        assert stop(recorder) == 0
        return monitor.stderr.read(), alerts
    finally:
        listener.close()


def _sensor_messages(recording):
    return sum(n for topic, (_, n) in recording.topics().items() if topic.startswith(m.SENSORS_NS + "/"))


@pytest.mark.timeout(900)
def test_the_measured_monitor_node_alerts_as_on_the_simulator_s_own_sensor_samples_and_its_recording_replays_to_them(
        spawn, read_until, tmp_path):
    expected, published = _offline_alerts()
    assert len({a.criterion for a in expected}) >= 3, "the run must exercise several criteria"
    # the comparison needs a run in which the monitor lost nothing (the simulator starts once the monitor and
    # the recorder subscribe to every sensor topic, and the transport is reliable); one more run is allowed,
    # and a loss in both is reported with the recorder's count beside the monitor's
    for attempt in range(2):
        mcap = tmp_path / f"live-{attempt}.mcap"
        log, alerts = _live_run(spawn, read_until, mcap)
        found = re.search(r"processed (\d+) sensor messages \((\d+) air-spring stamps incomplete\)", log)
        assert found, log
        if (int(found.group(1)), int(found.group(2))) == (published, 0):
            break
    assert (int(found.group(1)), int(found.group(2))) == (published, 0), (
        f"the monitor lost sensor messages in both runs ({found.group(0)} of {published}; the recorder held "
        f"{_sensor_messages(read_recording(mcap))}): no comparison can hold")
    got = sorted((a.sample, a.criterion, a.header.frame_id, a.header.stamp.sec * 10 ** 9 + a.header.stamp.nanosec)
                 for a in alerts)
    assert got == sorted((a.sample, a.criterion, a.place, nanoseconds(a.time_s)) for a in expected)

    # the live recording (DDS, the recorder beside the nodes): it holds the monitor's alerts as they came,
    # and its sensor topics replayed through the on-board criteria give them again, stamp for stamp when the
    # recorder got every sensor message the monitor processed; when the recorder (best effort, under load) lost
    # some, an alert may move or go, so then the replay must still alert where the live monitor did
    recording = read_recording(mcap)
    vp = vehicle_parameters("hs19")
    replayed, recorded = review_measured(recording, sensors=sim_node.sensor_set(
        {spec.name: spec.default for spec in sim_node.PARAMETERS} | RUN), limits=me.measured_limits(vp, **MEASURED_LEVELS))
    live = [dict(m.alert_dict(a), place=a.header.frame_id) for a in alerts]
    assert live and sorted(map(measured_key, recorded)) == sorted(map(measured_key, live))
    if _sensor_messages(recording) == published:
        assert sorted(map(measured_key, replayed)) == sorted(map(measured_key, live))
    else:
        assert bool(replayed) == bool(live)
