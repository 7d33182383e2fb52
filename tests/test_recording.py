"""MCAP recording: ros2msg schemas, decoding (rclpy, mcap_ros2 for foreign schemas), the recorder node
under Ctrl-C and SIGKILL."""
import signal
import sys
import time
from dataclasses import replace

import numpy as np
import pytest
from mcap.reader import NonSeekingReader, make_reader
from mcap_ros2.decoder import DecoderFactory
from rclpy.serialization import serialize_message

import railderail_msgs.msg as msgs
from railderail_sim.ros import interface as m
from railderail_monitor.recording.recorder import cdr_stamp_ns, record_run, schema_definitions, schema_text, stamped
from railderail_monitor.recording.replay import RecordingError, message_decoders, read_recording

SEPARATOR = "=" * 80


def test_schema_text_has_the_ros2_dependencies():
    text = schema_text("railderail_msgs/msg/Alert")
    main, header, time_ = text.split(SEPARATOR)
    assert "string criterion" in main and "uint8 SEVERITY_CRITICAL=2" in main
    assert header.startswith("\nMSG: std_msgs/Header\n") and "builtin_interfaces/Time stamp" in header
    assert time_.startswith("\nMSG: builtin_interfaces/Time\n") and "uint32 nanosec" in time_
    assert stamped("railderail_msgs/msg/Alert") and stamped("rosgraph_msgs/msg/Clock")
    assert not stamped("std_msgs/msg/String")
    definitions = schema_definitions("railderail_msgs/msg/Alert", text)
    assert list(definitions) == [("railderail_msgs", "Alert"), ("std_msgs", "Header"), ("builtin_interfaces", "Time")]
    assert [f.name for f in definitions["builtin_interfaces", "Time"].fields] == ["sec", "nanosec"]
    with pytest.raises(FileNotFoundError, match="no_such_msgs/msg/Nothing.msg"):
        schema_text("no_such_msgs/msg/Nothing")


def sample_messages():
    """One message of every recorded type, from a real core row."""
    from railderail_sim.vehicle.simulate import Simulation, output_arrays, scenario

    sim = Simulation(replace(scenario(radius=1000.0, speed_kmh=300.0), output_rate=200.0))
    rows = sim.advance(0.01)
    a = output_arrays(rows)
    c = m.RowConverter()
    alert = msgs.Alert(criterion="wheel_lift", severity=2, value=0.02, threshold=0.0185, wheelset=1,
                       wheel_side="left", rail_side="inner", track_position=12.5, speed=80.0, sample=3,
                       message="critical: wheel lift")
    m.stamp(alert, 1.25)
    event = dict(time_s=2.5, wheelset=0, wheel_side="left", rail_side="inner", mechanism="wheel_unloading",
                 speed_kmh=300.0, wheel_lift_m=0.028, lateral_displacement_m=-0.018,
                 attack_angle_rad=0.004, contact_position_m=-0.03)
    from rosgraph_msgs.msg import Clock
    clock = Clock()
    clock.clock.sec, clock.clock.nanosec = 3, 5
    return {"railderail_msgs/msg/WheelsetStates": c.states(a, 1, 1),
            "railderail_msgs/msg/ContactForces": c.forces(a, 1, 1),
            "railderail_msgs/msg/VehicleStatus": c.status(a, 1, 1, state=1, message="derailed: ünïcode"),
            "railderail_msgs/msg/Alert": alert,
            "railderail_msgs/msg/DerailmentEvent": m.derailment_message(event, 200.0),
            "rosgraph_msgs/msg/Clock": clock}


def same(a, b, path=""):
    """Field-by-field equality of an rclpy message and a decoded one."""
    for name in a.get_fields_and_field_types():
        x, y = getattr(a, name), getattr(b, name)
        if hasattr(x, "get_fields_and_field_types"):
            same(x, y, f"{path}{name}.")
        elif isinstance(x, str):
            assert x == y, path + name
        else:
            y = list(y) if isinstance(y, bytes) else y         # mcap_ros2 gives uint8 arrays as bytes
            assert np.array_equal(np.asarray(x), np.asarray(y)), path + name


def test_recorded_messages_decode_with_rclpy_and_foreign_schemas_with_mcap_ros2():
    from mcap.records import Schema

    decoder = message_decoders()
    for schema_id, (type_name, message) in enumerate(sample_messages().items(), start=1):
        data = serialize_message(message)
        text = schema_text(type_name)
        decoded = decoder(Schema(id=schema_id, name=type_name, encoding="ros2msg", data=text.encode()))(data)
        assert type(decoded) is type(message)                  # rclpy's deserialize_message
        same(message, decoded)
        # the same definition written otherwise (a comment added): still the installed type
        commented = decoder(Schema(id=100 + schema_id, name=type_name, encoding="ros2msg",
                                   data=("# recorded elsewhere\n" + text).encode()))(data)
        assert type(commented) is type(message)
    # a definition that is not the installed one (a field renamed): mcap_ros2's decoder
    message = sample_messages()["railderail_msgs/msg/WheelsetStates"]
    foreign = schema_text("railderail_msgs/msg/WheelsetStates").replace(" track_position", " position", 1)
    decoded = decoder(Schema(id=200, name="railderail_msgs/msg/WheelsetStates", encoding="ros2msg",
                             data=foreign.encode()))(serialize_message(message))
    assert type(decoded) is not type(message) and decoded.position == message.track_position
    assert np.array_equal(decoded.wheel_lift, message.wheel_lift)
    assert cdr_stamp_ns(serialize_message(sample_messages()["railderail_msgs/msg/Alert"])) == 1_250_000_000


@pytest.fixture(scope="module")
def short_run():
    from railderail_sim.vehicle.simulate import scenario, simulate
    return simulate(replace(scenario(radius=1000.0, speed_kmh=310.0), output_rate=200.0))


def test_record_run_is_a_ros2_mcap(short_run, tmp_path):
    path = tmp_path / "run.mcap"
    alerts = record_run(path, short_run)
    assert short_run.derailment is not None and alerts
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
        assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
        topics = {c.topic for c in summary.channels.values()}
        assert {m.STATES, m.FORCES, m.STATUS, m.ALERTS, m.DERAILMENT, m.FINAL_STATUS} <= topics
        n = len(short_run.time)
        counts = {summary.channels[k].topic: v for k, v in summary.statistics.channel_message_counts.items()}
        assert counts[m.STATES] == counts[m.FORCES] == counts[m.STATUS] == n
        assert counts[m.ALERTS] == len(alerts)
        for schema, channel, message, decoded in reader.iter_decoded_messages(topics=[m.STATES]):
            # log time = header stamp = simulation time
            assert message.log_time == decoded.header.stamp.sec * 10**9 + decoded.header.stamp.nanosec
        assert decoded.sample == n - 1
        assert np.allclose(decoded.wheel_lift, short_run.wheel("wheel_lift")[-1])
        meta = {r.name: r.metadata for r in reader.iter_metadata()}
        assert meta["railderail"]["monitor.debounce_m"] == "2.0"


UNCLOSED = """
import sys
from rclpy.serialization import serialize_message
from railderail_sim.ros import interface as m
from railderail_monitor.recording.recorder import McapRecording
rec = McapRecording(sys.argv[1])
rec.add_topic(m.STATES, m.TOPICS[m.STATES][0])
rec.write(m.STATES, serialize_message(m.WheelsetStates(sample=7)))
raise KeyboardInterrupt   # as a Ctrl-C while the recorder node is still being built
"""


def test_a_recording_nobody_closed_is_finished_when_the_process_ends(tmp_path):
    import subprocess
    path = tmp_path / "unclosed.mcap"
    ended = subprocess.run([sys.executable, "-c", UNCLOSED, str(path)], capture_output=True, text=True, timeout=120)
    assert "KeyboardInterrupt" in ended.stderr
    assert path.read_bytes().endswith(b"\x89MCAP0\r\n")
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    assert sum(summary.statistics.channel_message_counts.values()) == 1


PUBLISHER = """
import rclpy, numpy as np
from rclpy.executors import ExternalShutdownException
from railderail_sim.ros import interface as m
rclpy.init()
try:
    node = rclpy.create_node("railderail_test_states")
    pub = node.create_publisher(m.WheelsetStates, m.STATES, m.SENSOR)
    n = [0]
    def tick():
        msg = m.WheelsetStates(sample=n[0], track_position=0.4 * n[0])
        m.stamp(msg, 0.005 * n[0])
        msg.wheel_lift = np.full(8, 1e-3)
        pub.publish(msg)
        n[0] += 1
    node.create_timer(0.005, tick)
    node.get_logger().info("publishing")
    rclpy.spin(node)
except (KeyboardInterrupt, ExternalShutdownException):
    pass
finally:
    rclpy.try_shutdown()
"""


def flushed(path):
    """Messages readable so far in a file being written."""
    count = 0
    try:
        with open(path, "rb") as f:
            for _ in NonSeekingReader(f).iter_messages(log_time_order=False):
                count += 1
    except Exception:
        pass
    return count


@pytest.mark.timeout(180)
def test_recorder_survives_ctrl_c_and_sigkill(spawn, read_until, tmp_path):
    """Ctrl-C leaves a complete file; SIGKILL a file whose flushed chunks are readable."""
    publisher = spawn([sys.executable, "-c", PUBLISHER])
    read_until(publisher, "publishing", timeout=30)
    complete, killed = tmp_path / "complete.mcap", tmp_path / "killed.mcap"
    rec_int = spawn([sys.executable, "-m", "railderail_monitor.recording.recorder", str(complete)])
    rec_kill = spawn([sys.executable, "-m", "railderail_monitor.recording.recorder", str(killed), "--flush-period", "0.5"])
    read_until(rec_int, "recording", timeout=30)
    read_until(rec_kill, "recording", timeout=30)
    deadline = time.monotonic() + 60          # discovery, then 1 s of stamps (200 messages) flushed in both files
    while min(flushed(complete), flushed(killed)) < 200:
        assert time.monotonic() < deadline, "the recorders did not get 200 messages within 60 s"
        time.sleep(0.25)
    rec_kill.send_signal(signal.SIGKILL)
    rec_int.send_signal(signal.SIGINT)
    assert rec_int.wait(timeout=20) == 0
    rec_kill.wait(timeout=20)
    publisher.send_signal(signal.SIGINT)

    with open(complete, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        last_complete = summary.statistics.message_end_time
    counts = {summary.channels[k].topic: v for k, v in summary.statistics.channel_message_counts.items()}
    assert counts[m.STATES] >= 200                          # everything flushed before the stop, and more

    with open(killed, "rb") as f:
        f.seek(-8, 2)
        assert f.read(8) != b"\x89MCAP0\r\n"                 # no footer: it was killed
        f.seek(0)
        recovered = []
        try:
            for _, channel, message in NonSeekingReader(f).iter_messages(log_time_order=False):
                recovered.append(message.log_time)
        except Exception:
            pass
    # both recorders were stopped at the same moment: the killed one lost at most the last flush
    # period (0.5 s) and kept everything before it (stamps every 5 ms)
    assert len(recovered) >= 200                             # what was flushed before the kill
    assert max(recovered) >= last_complete - 1_000_000_000
    span = (max(recovered) - min(recovered)) / 5e6 + 1
    assert len(recovered) >= 0.9 * span
    with pytest.raises(RecordingError, match="killed.mcap is truncated .* add --allow-truncated"):
        read_recording(killed)
    assert len(read_recording(killed, allow_truncated=True).messages) == len(recovered)


def test_what_the_recording_lost_is_counted_per_topic(tmp_path):
    from railderail_monitor.recording.recorder import (McapRecording, delivery, delivery_text, lost_count,
                                                       recorded_counts)

    path = tmp_path / "lossy.mcap"
    with McapRecording(path) as rec:
        for topic in (m.STATES, m.FORCES):
            rec.add_topic(topic, m.TOPICS[topic][0])
        for i in range(100):
            states = m.stamp(m.WheelsetStates(sample=i), 0.005 * i)
            rec.write(m.STATES, serialize_message(states))
            if i % 10 != 3:                  # the recorder missed every tenth contact-forces message
                rec.write(m.FORCES, serialize_message(m.stamp(m.ContactForces(sample=i), 0.005 * i)))
    recorded = recorded_counts(path)
    assert recorded == {m.STATES: 100, m.FORCES: 90}
    # the simulator's run report, as its log carries it
    report = m.run_report("[INFO] [1.0] [railderail_simulator]: finished; published 100 samples\n"
                          "[INFO] [1.1] [railderail_simulator]: "
                          + m.run_report_line({m.STATES: 100, m.FORCES: 100, m.FINAL_STATUS: 1}, 134.46, 600.0))
    assert report["achieved_samples_per_s"] == 134.46 and report["requested_samples_per_s"] == 600.0
    table = delivery(report["published"], recorded)
    assert table[m.FORCES] == dict(published=100, recorded=90, lost=10)
    assert table[m.STATES]["lost"] == 0 and table[m.FINAL_STATUS] == dict(published=1, recorded=0, lost=1)
    text = delivery_text(table)
    assert text.startswith(f"the recording LOST 10 of 100 {m.FORCES}, 1 of 1 {m.FINAL_STATUS}")
    assert lost_count(table) == 11
    assert delivery_text(delivery({m.STATES: 100}, recorded)) == \
        "the recording holds every one of the 100 messages published on 1 topic"
    assert m.run_report("[INFO] no report here") is None
    # the clock's subscribers keep only its latest message: its shortfall is said apart, not as a loss
    recorded[m.CLOCK] = 70
    text = delivery_text(delivery({m.STATES: 100, m.CLOCK: 100}, recorded))
    assert text == (f"the recording holds every one of the 100 messages published on 1 topic; {m.CLOCK} 70 of 100 "
                    "(its depth-1 QoS keeps only the latest)")
