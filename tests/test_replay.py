"""`railderail replay`: clear refusals of bad files, and the same alerts as the recording."""
import json
from dataclasses import replace

import pytest

from railderail_monitor.warning.limits import default_limits
from railderail_monitor.recording.recorder import McapRecording, record_run, schema_text
from railderail_monitor.recording.replay import Publisher, RecordingError, read_recording, review
from railderail_sim.cli import main
from railderail_sim.ros import interface as m


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A short derailing run (R = 1000 m at 310 km/h) written as the nodes would have published it."""
    from railderail_sim.vehicle.simulate import scenario, simulate

    result = simulate(replace(scenario(radius=1000.0, speed_kmh=310.0), output_rate=200.0))
    path = tmp_path_factory.mktemp("replay") / "run.mcap"
    alerts = record_run(path, result)
    return path, result, alerts


def key(alert):
    """An alert without its float noise: the stamp went through integer nanoseconds."""
    d = alert if isinstance(alert, dict) else alert.as_dict()
    return {**d, "time_s": round(d["time_s"], 6)}


def error_line(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("railderail: error: ")
    return err


def test_missing_foreign_and_not_mcap_files_are_refused(capsys, tmp_path):
    assert "nothere.mcap: no such file" in error_line(capsys, ["replay", str(tmp_path / "nothere.mcap")])
    text = tmp_path / "notes.mcap"
    text.write_text("hello")
    assert "notes.mcap is not an MCAP file" in error_line(capsys, ["replay", str(text), "--no-publish"])
    foreign = tmp_path / "chatter.mcap"
    with McapRecording(foreign) as rec:
        rec.add_topic("/chatter", "std_msgs/msg/String")
        rec.write("/chatter", b"\x00\x01\x00\x00\x06\x00\x00\x00hello\x00")
    err = error_line(capsys, ["replay", str(foreign), "--no-publish"])
    assert "chatter.mcap is not a railderail recording" in err and "/chatter (std_msgs/msg/String)" in err


def test_truncated_file_is_refused_unless_allowed(capsys, recorded, tmp_path):
    path, _, _ = recorded
    data = path.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    err = error_line(capsys, ["replay", str(cut), "--no-publish"])
    assert "cut.mcap is truncated" in err and "--allow-truncated" in err
    partial = read_recording(cut, allow_truncated=True)
    assert partial.truncated and 0 < len(partial.messages) < len(read_recording(path).messages)
    tiny = tmp_path / "tiny.mcap"
    tiny.write_bytes(data[:40])
    with pytest.raises(RecordingError, match="tiny.mcap is truncated .* nothing to replay"):
        read_recording(tiny, allow_truncated=True)


def test_review_finds_the_recorded_alerts(recorded):
    path, result, alerts = recorded
    recording = read_recording(path)
    found = review(recording)
    assert [key(a) for a in found.alerts] == [key(a) for a in alerts]
    assert [key(a) for a in found.recorded_alerts] == [key(a) for a in alerts]
    # each alert holds the value its criterion had at its sample in the simulator's own arrays
    a, p0 = result.arrays(), default_limits().static_wheel_load
    wheel = {"left": 0, "right": 1}
    values = {"wheel_lift": a["wheel_lift"], "derailment_coefficient": a["derailment_coefficient"],
              "wheel_unloading": (p0 - a["vertical_force"]) / p0}
    checked = 0
    for alert in alerts:
        if alert.criterion in values:
            k = 2 * alert.wheelset + wheel[alert.wheel_side]
            assert alert.value == values[alert.criterion][alert.sample, k] >= alert.threshold
            checked += 1
    assert checked > 0
    assert found.derailment["time_s"] == pytest.approx(result.derailment["time_s"])
    assert found.as_json(recording)["same_as_recorded"]


def test_json_output(capsys, recorded):
    path, result, alerts = recorded
    assert main(["replay", str(path), "--no-publish", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["same_as_recorded"] and len(out["alerts"]) == len(alerts) == len(out["recorded_alerts"])
    assert out["derailment"]["mechanism"] == result.derailment["mechanism"]
    assert out["samples"] == len(result.time)
    first = min(out["lead_times"].values(), key=lambda v: v["time_s"])
    assert first["lead_s"] > 0 and first["lead_m"] > 0


def test_measured_alerts_are_compared_by_what_identifies_them():
    from railderail_monitor.recording.replay import compare_measured

    live = [dict(sample=1200, criterion="car_body_roll", place="air_springs", time_s=6.0, severity=1),
            dict(sample=5000, criterion="bogie_rms", place="bogie_front_frame", time_s=25.005, severity=1)]
    # the replay counted the messages of a recording that lost some: other sample numbers, the same alerts
    replayed = [dict(a, sample=a["sample"] - 46, message="") for a in live]
    assert compare_measured(replayed, live) == (True, "")
    same, why = compare_measured(replayed[:1], live)
    assert not same and why == "in the recording only: bogie_rms at bogie_front_frame, t = 25.005 s"
    moved = [replayed[0], dict(replayed[1], time_s=25.010)]
    same, why = compare_measured(moved, live)
    assert why == ("found here only: bogie_rms at bogie_front_frame, t = 25.010 s; "
                   "in the recording only: bogie_rms at bogie_front_frame, t = 25.005 s")


def plain(message):
    """An rclpy message as the nested dict of lists that mcap_ros2's encoder takes."""
    return {name: plain(v) if hasattr(v, "get_fields_and_field_types") else (v.tolist() if hasattr(v, "tolist") else v)
            for name in message.get_fields_and_field_types() for v in [getattr(message, name)]}


def write_before_curvature(recording, path, status_every=4):
    """`recording` as a railderail before 2026-12-06 recorded it: its wheelset states and contact forces without
    the curvature field (their definitions and bytes), a vehicle status every `status_every` samples only (the
    simulator's default status_rate)."""
    from mcap_ros2.writer import Writer

    with open(path, "wb") as f:
        writer, schemas = Writer(f), {}
        for topic, type_name, log_time, _, msg in recording.messages:
            if topic == m.STATUS and msg.sample % status_every:
                continue
            if type_name not in schemas:
                text = schema_text(type_name)
                if topic in (m.STATES, m.FORCES):
                    text = "\n".join(line for line in text.split("\n") if not line.startswith("float64 curvature"))
                    assert text != schema_text(type_name)
                schemas[type_name] = writer.register_msgdef(type_name, text)
            writer.write_message(topic, schemas[type_name], plain(msg), log_time, log_time)
        writer.finish()


def test_a_recording_made_before_the_samples_carried_their_curvature_is_reviewed_and_not_published(
        capsys, recorded, tmp_path):
    """Recordings of before 2026-12-06 (issue 43): the review names each alert's rail from the recorded vehicle
    status at or before its sample (said so); their states and forces are not published, since today's nodes
    would misread their bytes."""
    path, _, alerts = recorded
    old = tmp_path / "old.mcap"
    write_before_curvature(read_recording(path), old)
    recording = read_recording(old)
    assert {m.STATES, m.FORCES} <= recording.other_definition and m.STATUS not in recording.other_definition
    found = review(recording)
    assert found.curvature_from == "vehicle_status" and review(read_recording(path)).curvature_from == "samples"
    # the alerts fall on the curve, where the status of up to 3 samples before names the same rail
    assert [key(a) for a in found.alerts] == [key(a) for a in alerts]
    assert {a.rail_side for a in found.alerts if a.wheel_side} == {"inner"}       # unloading on the inner rail
    assert main(["replay", str(old), "--no-publish"]) == 0
    assert "each alert's rail from the vehicle status at or before its sample" in capsys.readouterr().out
    said = []
    publisher = Publisher(recording, 0.0, False, 0, said.append)
    try:
        assert m.STATUS in publisher.publishers and not {m.STATES, m.FORCES} & set(publisher.publishers)
    finally:
        publisher.close()
    assert sorted(said) == [f"replay: cannot publish {topic}: recorded with another definition of {type_name} than "
                            "the installed one (an older railderail's), which today's nodes would misread"
                            for topic, type_name in sorted([(m.FORCES, m.TOPICS[m.FORCES][0]),
                                                            (m.STATES, m.TOPICS[m.STATES][0])])]
