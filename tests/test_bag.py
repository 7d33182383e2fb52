"""`railderail record --bag-dir DIR`: a rosbag2 bag (DIR/DIR_0.mcap and metadata.yaml, version 9) that
rosbags reads as a rosbag2 folder, with the fields rosbag2 (Jazzy) reads, the topics' QoS and type hashes."""
import json
import signal
import sys
import time

import pytest
import yaml
from rosbags.highlevel import AnyReader
from rosbags.rosbag2 import Reader
from rosbags.rosbag2.metadata import QosDurability, QosReliability

from railderail_monitor.recording.bag import bag_file
from railderail_sim.sensors.config import load as load_sensors
from railderail_monitor.recording.recorder import msg_file
from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from test_recording import PUBLISHER, flushed
from test_replay import error_line

# the keys rosbag2_storage's YAML converter (yaml.hpp of Jazzy) reads for version 9
BAG_KEYS = {"version", "storage_identifier", "duration", "starting_time", "message_count",
            "topics_with_message_count", "compression_format", "compression_mode", "relative_file_paths",
            "files", "custom_data", "ros_distro"}
TOPIC_KEYS = {"name", "type", "serialization_format", "offered_qos_profiles", "type_description_hash"}
QOS_KEYS = {"history", "depth", "reliability", "durability", "deadline", "lifespan", "liveliness",
            "liveliness_lease_duration", "avoid_ros_namespace_conventions"}
FILE_KEYS = {"path", "starting_time", "duration", "message_count"}


@pytest.mark.timeout(180)
def test_recorder_writes_a_rosbag2_bag_that_rosbags_reads(spawn, read_until, tmp_path):
    publisher = spawn([sys.executable, "-c", PUBLISHER])
    read_until(publisher, "publishing", timeout=30)
    folder = tmp_path / "run1"
    recorder = spawn([sys.executable, "-m", "railderail_monitor.recording.recorder", "--bag-dir", str(folder),
                      "--metadata", "case=bag"])
    read_until(recorder, "recording", timeout=30)
    deadline = time.monotonic() + 60
    while flushed(bag_file(folder)) < 200:
        assert time.monotonic() < deadline, "the recorder did not get 200 messages within 60 s"
        time.sleep(0.25)
    recorder.send_signal(signal.SIGINT)
    assert recorder.wait(timeout=20) == 0
    publisher.send_signal(signal.SIGINT)
    assert sorted(p.name for p in folder.iterdir()) == ["metadata.yaml", "run1_0.mcap"]

    text = (folder / "metadata.yaml").read_text()
    assert "&id" not in text                              # plain YAML: no anchors or aliases
    info = yaml.safe_load(text)["rosbag2_bagfile_information"]
    assert set(info) == BAG_KEYS and info["version"] == 9 and info["storage_identifier"] == "mcap"
    assert info["relative_file_paths"] == ["run1_0.mcap"] and set(info["files"][0]) == FILE_KEYS
    assert info["custom_data"]["case"] == "bag" and info["ros_distro"] == "jazzy"
    topics = {t["topic_metadata"]["name"]: t for t in info["topics_with_message_count"]}
    assert set(topics) == {*m.TOPICS, *sm.sensor_topics(load_sensors()), m.CLOCK}   # the shipped sensors' too
    for topic in topics.values():
        assert set(topic["topic_metadata"]) == TOPIC_KEYS and topic["topic_metadata"]["serialization_format"] == "cdr"
        (qos,) = topic["topic_metadata"]["offered_qos_profiles"]
        assert set(qos) == QOS_KEYS
    alerts = topics[m.ALERTS]["topic_metadata"]
    assert alerts["offered_qos_profiles"][0]["durability"] == "transient_local"
    hashes = json.loads(msg_file("railderail_msgs", "Alert").with_suffix(".json").read_text())["type_hashes"]
    assert alerts["type_description_hash"] == hashes[0]["hash_string"]
    assert hashes[0]["hash_string"].startswith("RIHS01_")

    with Reader(folder) as reader:                       # rosbags' rosbag2 folder reader: metadata.yaml
        assert reader.message_count == info["message_count"] >= 200
        connections = {c.topic: c for c in reader.connections}
        states = connections[m.STATES]
        assert states.msgtype == "railderail_msgs/msg/WheelsetStates" and states.msgcount >= 200
        (offered,) = states.ext.offered_qos_profiles
        assert offered.reliability == QosReliability.RELIABLE and offered.durability == QosDurability.VOLATILE
        assert connections[m.FINAL_STATUS].ext.offered_qos_profiles[0].durability == QosDurability.TRANSIENT_LOCAL
    with AnyReader([folder]) as reader:
        samples = [reader.deserialize(raw, c.msgtype).sample for c, _, raw in reader.messages()
                   if c.topic == m.STATES]
    assert len(samples) == states.msgcount and samples == sorted(samples)


def test_bag_dir_must_be_new_and_alone(tmp_path, capsys):
    (tmp_path / "used").mkdir()
    (tmp_path / "used" / "x").write_text("")
    assert "--bag-dir" in error_line(capsys, ["record", "--bag-dir", str(tmp_path / "used")])
    assert "give either OUT.mcap or --bag-dir DIR" in error_line(
        capsys, ["record", str(tmp_path / "a.mcap"), "--bag-dir", str(tmp_path / "b")])
    assert "give either OUT.mcap or --bag-dir DIR" in error_line(capsys, ["record"])
