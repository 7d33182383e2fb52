"""A recording as a rosbag2 bag: the folder of `railderail record --bag-dir DIR`.

rosbag2 (`ros2 bag info DIR`, `ros2 bag play DIR`) reads a folder holding the storage files and a
`metadata.yaml`. The recorder writes `DIR/NAME_0.mcap` (NAME = the folder's name, as `ros2 bag record
-o DIR -s mcap` does) and, once the MCAP is complete, the metadata from the MCAP's own summary and
channels (as rosbag2's MCAP storage reads them): storage `mcap`, serialization `cdr`, per topic its
type, message count, the QoS its publishers offer (what `ros2 bag play` republishes with: the
latched topics stay transient local) and the type's RIHS01 hash. The format is rosbag2's metadata
version 9, Jazzy's, field by field as rosbag2_storage's YAML converter (yaml.hpp, Jazzy) writes and
reads it: QoS policies as names (`keep_last`, `best_effort`, ...), durations as {sec, nsec}; the
recording's `railderail` metadata record goes into `custom_data`. A killed recorder leaves no
metadata.yaml: `railderail recover` the MCAP, then `ros2 bag reindex DIR` (or record again).
"""
from __future__ import annotations

from pathlib import Path

import yaml
from mcap.reader import make_reader

from railderail_sim.atomic import atomic_write


VERSION = 9                      # rosbag2's metadata version of ROS 2 Jazzy
METADATA = "metadata.yaml"


def bag_file(folder):
    """The MCAP file of a bag folder, named as rosbag2 names its first file."""
    folder = Path(folder)
    return folder / f"{folder.resolve().name}_0.mcap"


def bag_metadata(mcap_path):
    """The rosbag2 metadata of a complete MCAP file, from its summary and its channels' metadata
    (QoS, type hash), as rosbag2's MCAP storage reads them."""
    mcap_path = Path(mcap_path)
    with open(mcap_path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        custom = {k: v for r in reader.iter_metadata() if r.name == "railderail" for k, v in r.metadata.items()}
    stats = summary.statistics
    counts = stats.channel_message_counts
    start = stats.message_start_time if stats.message_count else 0
    duration = stats.message_end_time - start if stats.message_count else 0
    topics = []
    for channel in summary.channels.values():
        topics.append({"topic_metadata": {
            "name": channel.topic, "type": summary.schemas[channel.schema_id].name,
            "serialization_format": channel.message_encoding,
            "offered_qos_profiles": yaml.safe_load(channel.metadata.get("offered_qos_profiles", "")) or [],
            "type_description_hash": channel.metadata.get("topic_type_hash", "")},
            "message_count": counts.get(channel.id, 0)})

    def span():             # a new dict each time: PyYAML would write a shared one as an anchor and alias
        return {"starting_time": {"nanoseconds_since_epoch": start}, "duration": {"nanoseconds": duration}}
    return {"rosbag2_bagfile_information": {
        "version": VERSION, "storage_identifier": "mcap", **span(),
        "message_count": stats.message_count, "topics_with_message_count": topics,
        # rosbag2's own compression (of whole files or messages): none; the MCAP compresses its chunks
        "compression_format": "", "compression_mode": "",
        "relative_file_paths": [mcap_path.name],
        "files": [{"path": mcap_path.name, **span(), "message_count": stats.message_count}],
        "custom_data": custom, "ros_distro": "jazzy"}}


def write_bag_metadata(mcap_path):
    """Write metadata.yaml beside a complete MCAP file (atomically); returns its path."""
    path = Path(mcap_path).parent / METADATA
    with atomic_write(path) as handle:
        yaml.safe_dump(bag_metadata(mcap_path), handle, sort_keys=False)
    return path
