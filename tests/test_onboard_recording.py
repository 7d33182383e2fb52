"""Without the simulator: a recording's sensor topics alone (`railderail recover --sensors-only`) replay into
the on-board criteria (`railderail replay --signals measured`, replay.review_measured) to the alerts the
measured-mode monitor raised live, recorded on /railderail/onboard_alerts."""
import json

import pytest
from rclpy.serialization import serialize_message

from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.cli import main
from railderail_sim.parameters import vehicle_parameters
from railderail_sim.sensors.config import load as load_sensors
from railderail_monitor.node import measured_alert_message
from railderail_monitor.onboard.monitor import MeasuredMonitor
from railderail_monitor.recording.recorder import McapRecording
from railderail_monitor.recording.recover import recover, sensors_only
from railderail_monitor.recording.replay import measured_key, read_recording, review_measured
from test_onboard_node import _messages
from test_onboard_measured import _record


@pytest.fixture(scope="module")
def live_recording(tmp_path_factory):
    """(path, alerts): a recording as the demo makes it: the sensor topics, a ground-truth topic, and the alerts of a
    measured monitor fed the messages as they come (the default levels: the synthetic hunting at 9 m/s^2
    passes the peak-count rule's 8 m/s^2 and the frames' r.m.s. limit)."""
    path = tmp_path_factory.mktemp("live") / "demo.mcap"
    vp = vehicle_parameters("hs19")
    live = MeasuredMonitor(vp)
    decoder = sm.SensorDecoder(load_sensors())
    alerts = []
    with McapRecording(path) as rec:
        for topic, (type_name, *_) in {**sm.sensor_topics(load_sensors()), m.STATUS: m.TOPICS[m.STATUS],
                                       m.ONBOARD_ALERTS: m.ONBOARD_ALERTS_TOPIC}.items():
            rec.add_topic(topic, type_name)
        status = m.VehicleStatus()
        rec.write(m.STATUS, serialize_message(m.stamp(status, 0.0)))
        for _, topic, msg in _messages(_record(4.0, lost=0.0)):
            rec.write(topic, serialize_message(msg))
            for unit, t, signals in decoder.decode(topic, msg):
                for alert in live.feed(unit, t, **signals):
                    alerts.append(alert)
                    rec.write(m.ONBOARD_ALERTS, serialize_message(measured_alert_message(alert, 0.0)))
    return path, alerts


def test_the_sensor_topics_alone_replay_to_the_live_alerts(live_recording, tmp_path):
    (full, live), sensors = live_recording, tmp_path / "sensors.mcap"
    assert {a.criterion for a in live} >= {"bids_peak_count_china", "bogie_rms"}
    done = recover(full, sensors, keep=sensors_only)
    assert done.complete and done.channels == len(sm.sensor_topics(load_sensors()))
    copy = read_recording(sensors)
    # every sensor topic the original holds messages on, and nothing else
    assert set(copy.topics()) == {t for t in read_recording(full).topics() if t.startswith(m.SENSORS_NS + "/")}
    found, recorded = review_measured(copy)
    assert recorded == []                                        # the alerts are gone with the other topics
    assert sorted(map(measured_key, found)) == sorted(map(measured_key, live))
    # the original's recorded alerts are the live ones
    assert sorted(map(measured_key, review_measured(read_recording(full))[1])) == sorted(map(measured_key, live))


def test_the_commands(live_recording, tmp_path, capsys):
    (full, live), sensors = live_recording, tmp_path / "sensors.mcap"
    assert main(["recover", str(full), str(sensors), "--sensors-only"]) == 0
    assert "sensor topics" in capsys.readouterr().err
    assert main(["replay", str(sensors), "--no-publish", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["signals"] == "measured" and len(out["alerts"]) == len(live) and out["recorded_alerts"] == []
    assert main(["replay", str(full), "--no-publish", "--signals", "measured"]) == 0
    assert f"{len(live)} measured alerts found; the recording holds {len(live)} (the same criteria, places and stamps)" \
        in capsys.readouterr().out
