"""`railderail recover`: a cut-off MCAP made whole, read by rosbags (a reader that shares no code with
ours), every message up to the last complete chunk; the recorder keeps a cut-off file and names the command."""
import signal
import sys
import time

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap.records import Chunk, Message
from mcap.stream_reader import StreamReader, breakup_chunk
from rclpy.serialization import serialize_message
from rosbags.highlevel import AnyReader

from railderail_monitor.recording.recorder import McapRecording, cut_off
from railderail_monitor.recording.recover import recover
from railderail_sim.ros import interface as m
from railderail_sim.cli import main
from test_recording import PUBLISHER, flushed
from test_replay import error_line


def write_synthetic(path, samples=3000):
    """A recording of wheelset states (and an alert every 500 samples) in many small chunks."""
    with McapRecording(path, metadata={"case": "synthetic"}, chunk_size=16_000, flush_period_s=1e9) as rec:
        for topic, (type_name, *_) in m.TOPICS.items():
            rec.add_topic(topic, type_name)
        for i in range(samples):
            states = m.WheelsetStates(sample=i, track_position=0.4 * i)
            m.stamp(states, 0.005 * i)
            states.wheel_lift = np.full(8, 1e-5 * i)
            rec.write(m.STATES, serialize_message(states))
            if i % 500 == 0:
                alert = m.Alert(criterion="wheel_lift", sample=i, message=f"alert {i}")
                m.stamp(alert, 0.005 * i)
                rec.write(m.ALERTS, serialize_message(alert))


def chunks(path):
    """[(end offset, [(topic, log_time), ...])] of every chunk of a complete MCAP, from its chunk index."""
    out = []
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
        topics = {c.id: c.topic for c in summary.channels.values()}
        for index in summary.chunk_indexes:
            f.seek(index.chunk_start_offset)
            chunk = next(StreamReader(f, skip_magic=True, emit_chunks=True).records)
            assert isinstance(chunk, Chunk)
            out.append((index.chunk_start_offset + index.chunk_length,
                        [(topics[r.channel_id], r.log_time) for r in breakup_chunk(chunk) if isinstance(r, Message)]))
    return out


def read_with_rosbags(path):
    """[(topic, log_time)] of a file as rosbags reads it; every message deserialised."""
    with AnyReader([path]) as reader:
        out = []
        for connection, log_time, raw in reader.messages():
            message = reader.deserialize(raw, connection.msgtype)
            assert message.header.stamp.sec * 10**9 + message.header.stamp.nanosec == log_time
            out.append((connection.topic, log_time))
    return out


def test_a_file_cut_at_any_byte_recovers_every_complete_chunk(tmp_path):
    full = tmp_path / "full.mcap"
    write_synthetic(full)
    data = full.read_bytes()
    table = chunks(full)
    assert len(table) > 10
    first_end = table[0][0]
    rng = np.random.default_rng(18)
    cuts = sorted({*rng.integers(first_end, len(data), 25).tolist(),      # anywhere
                   table[3][0], table[3][0] - 1, table[3][0] + 1,          # at a chunk's end, one byte either side
                   len(data) - 1, len(data) - 8})                          # in the footer
    for cut in cuts:
        broken, fixed = tmp_path / f"cut{cut}.mcap", tmp_path / f"fixed{cut}.mcap"
        broken.write_bytes(data[:cut])
        done = recover(broken, fixed)
        expected = [item for end, items in table if end <= cut for item in items]
        assert done.messages == len(expected) and not done.complete, cut
        got = read_with_rosbags(fixed)
        assert sorted(got) == sorted(expected), f"cut at byte {cut}"
        with open(fixed, "rb") as f:
            reader = make_reader(f)
            assert reader.get_header().profile == "ros2"
            assert {r.name: dict(r.metadata) for r in reader.iter_metadata()}["railderail"]["case"] == "synthetic"
    # a complete file comes out with the same messages
    done = recover(full, tmp_path / "copy.mcap")
    assert done.complete and sorted(read_with_rosbags(tmp_path / "copy.mcap")) == sorted(
        item for _, items in table for item in items)


def test_nothing_to_recover_and_bad_names_are_one_line(tmp_path, capsys):
    full = tmp_path / "full.mcap"
    write_synthetic(full, samples=10)
    early = tmp_path / "early.mcap"
    early.write_bytes(full.read_bytes()[:40])                 # inside the header
    assert "early.mcap has nothing to recover: no complete chunk after its header" in error_line(
        capsys, ["recover", str(early), str(tmp_path / "x.mcap")])
    assert not (tmp_path / "x.mcap").exists()
    assert "nothere.mcap: no such file" in error_line(capsys, ["recover", str(tmp_path / "nothere.mcap"), "x.mcap"])
    (tmp_path / "text.mcap").write_text("hello, world")
    assert "text.mcap is not an MCAP file" in error_line(capsys, ["recover", str(tmp_path / "text.mcap"), "x.mcap"])
    assert "the recovered file's name must end in .mcap" in error_line(
        capsys, ["recover", str(full), str(tmp_path / "fixed.bag")])
    assert "does not exist" in error_line(capsys, ["recover", str(full), str(tmp_path / "no" / "fixed.mcap")])


def test_an_existing_file_is_not_replaced_without_force(tmp_path, capsys):
    full = tmp_path / "full.mcap"
    write_synthetic(full, samples=3000)
    broken = tmp_path / "broken.mcap"
    broken.write_bytes(full.read_bytes()[:len(full.read_bytes()) // 2])
    before = broken.read_bytes()
    err = error_line(capsys, ["recover", str(broken), str(broken)])
    assert "broken.mcap is the recording being recovered" in err and "--force" in err
    assert broken.read_bytes() == before
    other = tmp_path / "other.mcap"
    other.write_text("keep me")
    assert "other.mcap exists: give another name, or add --force" in error_line(
        capsys, ["recover", str(broken), str(other)])
    assert other.read_text() == "keep me"
    assert main(["recover", str(broken), str(other), "--force"]) == 0
    assert "recovered" in capsys.readouterr().err and len(read_with_rosbags(other)) > 100


def test_a_cut_inside_a_record_is_said_in_words(tmp_path, capsys):
    full = tmp_path / "full.mcap"
    write_synthetic(full, samples=3000)
    data = full.read_bytes()
    for cut in (len(data) - 1, len(data) // 2):       # in the footer, in a chunk
        broken, fixed = tmp_path / f"cut{cut}.mcap", tmp_path / f"fixed{cut}.mcap"
        broken.write_bytes(data[:cut])
        assert main(["recover", str(broken), str(fixed)]) == 0
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.rstrip().endswith("was cut off (the file ends inside a record)"), err
        assert "error" not in err and "buffer" not in err and "EndOfFile" not in err


@pytest.mark.timeout(180)
def test_a_killed_recorder_s_file_recovers_and_is_not_overwritten(spawn, read_until, tmp_path, capsys):
    publisher = spawn([sys.executable, "-c", PUBLISHER])
    read_until(publisher, "publishing", timeout=30)
    killed = tmp_path / "killed.mcap"
    recorder = spawn([sys.executable, "-m", "railderail_monitor.recording.recorder", str(killed), "--flush-period", "0.2"])
    read_until(recorder, "recording", timeout=30)
    deadline = time.monotonic() + 60
    while flushed(killed) < 300:
        assert time.monotonic() < deadline, "the recorder did not get 300 messages within 60 s"
        time.sleep(0.25)
    recorder.send_signal(signal.SIGKILL)
    recorder.wait(timeout=20)
    publisher.send_signal(signal.SIGINT)
    assert cut_off(killed)
    readable = flushed(killed)                                 # what a streaming reader gets: the complete chunks

    # the recorder refuses to overwrite it and names the command
    again = spawn([sys.executable, "-m", "railderail_monitor.recording.recorder", str(killed)])
    assert again.wait(timeout=60) == 2
    err = again.stderr.read()
    assert "is a cut-off recording" in err
    assert f"railderail recover {killed} {tmp_path / 'killed-recovered.mcap'}" in err
    assert cut_off(killed)

    fixed = tmp_path / "killed-recovered.mcap"
    assert main(["recover", str(killed), str(fixed)]) == 0
    assert f"recovered {readable} messages" in capsys.readouterr().err
    got = read_with_rosbags(fixed)
    assert len(got) == readable >= 300
