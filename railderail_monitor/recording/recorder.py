"""Recorder `railderail_recorder`: every railderail topic to an MCAP file.

`railderail record OUT.mcap` (or `python -m railderail_monitor.recording.recorder OUT.mcap`) subscribes to
the topics of railderail_sim/ros/interface.py and /clock from the start, and to any other topic
under /railderail/ that appears later, all *raw*: the CDR bytes are written as published, with no
decoding. The file is a standard MCAP with ROS 2 conventions, so the mcap CLI, Foxglove and
`ros2 bag` (rosbag2_storage_mcap) read it:

- schema per type: name `pkg/msg/Type`, encoding `ros2msg`, text = the installed `.msg` file and,
  for every type it uses (recursively), a line of 80 `=`, `MSG: pkg/Type` and that `.msg`;
- channel per topic: message encoding `cdr`, metadata as rosbag2's MCAP storage writes it: the
  QoS its publishers offer (`offered_qos_profiles`, a YAML list) and the type's hash (`topic_type_hash`);
- log_time = publish_time = the message's header stamp (simulation time, ns), for the clock its
  time; a message with no stamp gets the latest stamp seen. So the file's timeline is simulation
  time (it starts near 0 ns, i.e. 1970 for tools that show dates);
- a metadata record `railderail` (recorder version, wall-clock start, `--metadata KEY=VALUE`).

Durability: the file is written in place as OUT.mcap (no `.partial` name). Chunks are closed and
the file flushed every `--flush-period` s (0.5): Ctrl-C or SIGTERM finish the file (summary and
footer), once the recorder has written what its queues held at the stop, so that a recorder behind the
simulator at the run's end keeps the run's last part; after a SIGKILL or a power cut the messages up to
the last flushed chunk are readable with a streaming reader (`railderail replay --allow-truncated`), and
`railderail recover` makes a complete file of them. The recorder does not overwrite such a cut-off file:
it names the recover command.
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import struct
import sys
import time
import weakref
from pathlib import Path

import mcap.writer
import yaml
from mcap.writer import CompressionType
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.utilities import remove_ros_args
from rosidl_adapter.parser import parse_message_string

from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.sensors.config import load as load_sensors

from .bag import bag_file, write_bag_metadata

SEPARATOR = "=" * 80
STAMP_TYPES = ("std_msgs/Header", "builtin_interfaces/Time")     # a leading stamp: the message's time


# --- schemas ------------------------------------------------------------------------------------

def msg_file(package, name):
    """Path of the installed `.msg` of package/name (AMENT_PREFIX_PATH, then this Python's prefix)."""
    prefixes = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p] + [sys.prefix]
    for prefix in prefixes:
        path = Path(prefix, "share", package, "msg", f"{name}.msg")
        if path.is_file():
            return path
    raise FileNotFoundError(f"no {package}/msg/{name}.msg under {', '.join(prefixes)} (is {package} installed?)")


def split_type(type_name):
    """(package, name) of 'package/msg/Name' or 'package/Name'."""
    parts = type_name.split("/")
    if len(parts) == 3:
        return parts[0], parts[2]
    if len(parts) == 2:
        return parts[0], parts[1]
    raise ValueError(f"type name {type_name!r} is not package/msg/Name")


def _installed(package, name):
    """(text, rosidl_adapter MessageSpecification) of an installed .msg."""
    text = msg_file(package, name).read_text()
    return text, parse_message_string(package, name, text)


def _used_types(spec):
    return [(f.type.pkg_name, f.type.type) for f in spec.fields if not f.type.is_primitive_type()]


def schema_text(type_name):
    """The ros2msg schema text of a type such as 'railderail_msgs/msg/Alert'."""
    package, name = split_type(type_name)
    main, spec = _installed(package, name)
    parts, seen, queue = [main], {(package, name)}, _used_types(spec)
    while queue:
        dep = queue.pop(0)
        if dep in seen:
            continue
        seen.add(dep)
        text, dep_spec = _installed(*dep)
        parts.append(f"{SEPARATOR}\nMSG: {dep[0]}/{dep[1]}\n{text}")
        queue.extend(_used_types(dep_spec))
    return "\n".join(parts)


def schema_definitions(type_name, text):
    """{(package, name): MessageSpecification} of a ros2msg schema text: the type and every type it
    uses, parsed by rosidl_adapter (whose errors pass through)."""
    blocks = re.split(rf"^{SEPARATOR}$\n?", text, flags=re.MULTILINE)
    package, name = split_type(type_name)
    found = {(package, name): parse_message_string(package, name, blocks[0])}
    for block in blocks[1:]:
        header, _, body = block.partition("\n")
        if not header.startswith("MSG: "):
            raise ValueError(f"schema block of {type_name} without a 'MSG:' line: {header!r}")
        dep = split_type(header[5:].strip())
        found[dep] = parse_message_string(*dep, body)
    return found


def stamped(type_name):
    """True if the installed type's first field is a std_msgs/Header or a builtin_interfaces/Time."""
    fields = _installed(*split_type(type_name))[1].fields
    return bool(fields) and str(fields[0].type) in STAMP_TYPES


def cdr_stamp_ns(data):
    """The leading builtin_interfaces/Time of a CDR message (after the 4-byte encapsulation), in ns."""
    endian = "<" if data[1] & 1 else ">"
    sec, nanosec = struct.unpack_from(endian + "iI", data, 4)
    return sec * 1_000_000_000 + nanosec


def _duration(ns):
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


def qos_dict(qos):
    """An rclpy QoSProfile as rosbag2 writes it (metadata version 9: policies by name, durations as
    {sec, nsec})."""
    return {"history": qos.history.short_key, "depth": qos.depth, "reliability": qos.reliability.short_key,
            "durability": qos.durability.short_key, "deadline": _duration(qos.deadline.nanoseconds),
            "lifespan": _duration(qos.lifespan.nanoseconds), "liveliness": qos.liveliness.short_key,
            "liveliness_lease_duration": _duration(qos.liveliness_lease_duration.nanoseconds),
            "avoid_ros_namespace_conventions": qos.avoid_ros_namespace_conventions}


def type_hash(type_name):
    """The RIHS01 hash of an installed message type, from its share/PKG/msg/TYPE.json ('' when
    unknown, as rosbag2 writes it)."""
    package, name = split_type(type_name)
    try:
        description = json.loads(msg_file(package, name).with_suffix(".json").read_text())
    except (FileNotFoundError, ValueError):
        return ""
    full = f"{package}/msg/{name}"
    return next((h["hash_string"] for h in description.get("type_hashes", []) if h.get("type_name") == full), "")


def channel_metadata(type_name, offered_qos):
    """The metadata rosbag2's MCAP storage (rosbag2_storage_mcap) gives a channel: the offered QoS as a
    YAML list, which `ros2 bag play` offers again (the latched topics stay transient local), and the
    type hash."""
    return {"offered_qos_profiles": yaml.safe_dump([qos_dict(offered_qos)] if offered_qos is not None else []),
            "topic_type_hash": type_hash(type_name)}


# --- writer -------------------------------------------------------------------------------------

MAGIC = b"\x89MCAP0\r\n"


def cut_off(path):
    """True if `path` is an MCAP file that lacks its footer: a recording cut off by a killed recorder."""
    path = Path(path)
    if not path.is_file() or path.stat().st_size < len(MAGIC):
        return False
    with open(path, "rb") as f:
        head = f.read(len(MAGIC))
        f.seek(-len(MAGIC), 2)
        return head == MAGIC and f.read(len(MAGIC)) != MAGIC


def recover_hint(path):
    """The command that makes a complete copy of a cut-off recording (said by the recorder and the replay)."""
    path = Path(path)
    return f"railderail recover {path} {path.with_name(path.stem + '-recovered.mcap')}"


def _finish_file(writer, stream):
    writer.finish()
    stream.close()


class McapRecording:
    """An MCAP file of raw CDR messages; no ROS needed. Call `close()` (or use `with`). A recording
    still open when the interpreter exits is finished then (`weakref.finalize`), so a Ctrl-C that
    lands while its owner is being built, before anyone holds it to close, still leaves a whole file."""

    def __init__(self, path, metadata=None, chunk_size=512 * 1024, flush_period_s=0.5,
                 compression=CompressionType.ZSTD, stream=None):
        # `stream`: a binary file open on `path` to write into instead (atomic.atomic_write's, for a
        # recording written whole)
        self.path = Path(path)
        if stream is None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        self.stream = open(self.path, "wb") if stream is None else stream
        self.writer = mcap.writer.Writer(self.stream, chunk_size=chunk_size, compression=compression)
        self.writer.start(profile="ros2", library=f"railderail recorder (mcap {mcap.__version__})")
        self._finish = weakref.finalize(self, _finish_file, self.writer, self.stream)
        self.flush_period_s = flush_period_s
        self.last_flush = time.monotonic()
        self.schemas = {}
        self.channels = {}            # topic -> (channel id, stamped?)
        self.sequence = {}
        self.last_stamp = 0
        self.messages = 0
        self.bytes = 0
        meta = {"recorder": "railderail", "started_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(),
                "log_time": "simulation time (header stamps)"}
        meta.update(metadata or {})
        self.writer.add_metadata("railderail", {k: str(v) for k, v in meta.items()})
        self.flush()

    def add_topic(self, topic, type_name, offered_qos=None):
        """Add a topic of a type; `offered_qos`, the QoSProfile its publishers offer, goes into the
        channel's metadata."""
        if topic in self.channels:
            return self.channels[topic][0]
        if type_name not in self.schemas:
            self.schemas[type_name] = (self.writer.register_schema(type_name, "ros2msg",
                                                                   schema_text(type_name).encode()),
                                       stamped(type_name))
        schema_id, has_stamp = self.schemas[type_name]
        channel = self.writer.register_channel(topic, "cdr", schema_id, channel_metadata(type_name, offered_qos))
        self.channels[topic] = (channel, has_stamp)
        self.sequence[topic] = 0
        return channel

    def write(self, topic, data):
        """Write one CDR message (bytes as published) on a topic added before."""
        channel, has_stamp = self.channels[topic]
        if has_stamp and len(data) >= 12:
            self.last_stamp = max(cdr_stamp_ns(data), 0)
            stamp = self.last_stamp
        else:
            stamp = self.last_stamp
        self.writer.add_message(channel, log_time=stamp, data=data, publish_time=stamp,
                                sequence=self.sequence[topic])
        self.sequence[topic] += 1
        self.messages += 1
        self.bytes += len(data)
        if time.monotonic() - self.last_flush >= self.flush_period_s:
            self.flush()

    def flush(self):
        """Close the current chunk and push everything to the file (survives a SIGKILL from here)."""
        self.writer.flush()
        self.last_flush = time.monotonic()

    def close(self):
        self._finish()              # once: later calls do nothing

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def record_run(path, result, limits=None, metadata=None, sensor_log=None):
    """Write a finished core run (`vehicle.simulate.Result`) to MCAP exactly as the nodes would have
    published it — one WheelsetStates, ContactForces and VehicleStatus per sample, the monitor's
    alerts, the derailment event and the final status; with `sensor_log` (the run's
    `sensors.measure.SensorLog`) the sensor topics too, each message before the first sample at or after
    its stamp, as the simulator node sends them — without a ROS graph (tests, examples).
    Returns the alerts (warning.alerts.AlertRecord)."""
    from rclpy.serialization import serialize_message

    from ..node import alert_message
    from ..warning.limits import default_limits
    from ..warning.monitor import alerts_of_run

    limits = limits or default_limits()
    a = result.arrays()
    alerts = alerts_of_run(a, limits)
    by_sample = {}
    for alert in alerts:
        by_sample.setdefault(alert.sample, []).append(alert)
    convert = m.RowConverter()
    meta = {f"monitor.{k}": v for k, v in limits.as_dict().items()}
    meta.update(metadata or {})
    with McapRecording(path, metadata=meta) as rec:
        for topic, (type_name, _, offered, _) in m.TOPICS.items():
            rec.add_topic(topic, type_name, offered)
        sensor_messages = []
        if sensor_log is not None:
            sc = result.scenario
            sensor_messages = sm.SensorConverter(sensor_log.sensors, sc.output_rate, sc.vehicle.rolling_radius
                                                 ).arrays_messages(sensor_log.arrays())
            for topic, (type_name, _, offered, _) in sm.sensor_topics(sensor_log.sensors).items():
                rec.add_topic(topic, type_name, offered)
        sent = 0
        n = len(result.time)
        for i in range(n):
            while sent < len(sensor_messages) and sensor_messages[sent][0] <= a["time"][i] + 1e-9:
                rec.write(sensor_messages[sent][1], serialize_message(sensor_messages[sent][2]))
                sent += 1
            rec.write(m.STATES, serialize_message(convert.states(a, i, i)))
            rec.write(m.FORCES, serialize_message(convert.forces(a, i, i)))
            rec.write(m.STATUS, serialize_message(convert.status(a, i, i)))
            for alert in by_sample.get(i, ()):
                rec.write(m.ALERTS, serialize_message(alert_message(alert)))
        for _, topic, message in sensor_messages[sent:]:        # stamped after the last sample: its latency
            rec.write(topic, serialize_message(message))
        S = m.msgs.VehicleStatus
        if result.derailment is not None:
            d = result.derailment
            rec.write(m.DERAILMENT, serialize_message(m.derailment_message(d, float(result.position[-1]))))
            state, text = S.STATE_DERAILED, f"derailed: wheelset {d['wheelset']} {d['wheel_side']}"
        else:
            state, text = S.STATE_FINISHED, f"finished ({result.status})"
        rec.write(m.FINAL_STATUS, serialize_message(convert.status(a, n - 1, n - 1, state=state, message=text)))
    return alerts


# --- what was lost -------------------------------------------------------------------------------

def recorded_counts(path):
    """{topic: messages} a complete MCAP holds, from its summary's statistics (what the recorder wrote)."""
    from mcap.reader import make_reader
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    counts = summary.statistics.channel_message_counts
    return {channel.topic: counts.get(cid, 0) for cid, channel in summary.channels.items()}


def delivery(published, recorded):
    """{topic: {published, recorded, lost}} of every topic published (the simulator's run report), in
    topic order; lost is published - recorded (negative: the recording holds more, another publisher's)."""
    return {topic: dict(published=n, recorded=recorded.get(topic, 0), lost=n - recorded.get(topic, 0))
            for topic, n in sorted(published.items())}


def lost_count(table):
    """The messages the recording lost, /clock's left out (delivery_text)."""
    return sum(max(row["lost"], 0) for topic, row in table.items() if topic != m.CLOCK)


def delivery_text(table):
    """One line: every published message recorded, or how many of what were lost on which topics; /clock's
    apart, whose subscribers keep only the latest message (its QoS, depth 1), so it loses some by design."""
    lost = {topic: row for topic, row in table.items() if row["lost"] > 0 and topic != m.CLOCK}
    kept = {topic: row for topic, row in table.items() if topic != m.CLOCK}
    total = sum(row["published"] for row in kept.values())
    clock = table.get(m.CLOCK)
    note = "" if clock is None or clock["lost"] <= 0 else \
        f"; {m.CLOCK} {clock['recorded']} of {clock['published']} (its depth-1 QoS keeps only the latest)"
    if not lost:
        return (f"the recording holds every one of the {total} messages published on {len(kept)} "
                f"topic{'s' if len(kept) != 1 else ''}" + note)
    return ("the recording LOST " + ", ".join(f"{row['lost']} of {row['published']} {topic}"
                                              for topic, row in lost.items())
            + " (a reader's queue holds 5000 messages a topic: a recorder that far behind the simulator loses the"
              " oldest)" + note)


# --- the recorder node --------------------------------------------------------------------------

class RecorderNode(Node):
    """The recorder node `railderail_recorder`: subscribes raw to every railderail topic and
    /clock, and to any new topic under /railderail/; its file is complete once `destroy_node`
    returns (`log` gets the line that says what it wrote). With `bag` true it then writes the
    rosbag2 metadata.yaml beside the file (railderail_monitor/recording/bag.py)."""

    def __init__(self, path, metadata=None, flush_period_s=0.5, log=print, bag=False):
        super().__init__("railderail_recorder")
        self.log = log
        self.bag = bag
        if cut_off(path):       # the only copy of a run that ended in a crash: not overwritten
            raise ValueError(f"{path} is a cut-off recording (no MCAP footer: its recorder was killed); it is left "
                             f"as it is: recover it with `{recover_hint(path)}`, or remove it, then record again")
        self.recording = McapRecording(path, metadata=metadata, flush_period_s=flush_period_s)
        self.subscriptions_by_topic = {}
        # the shipped sensor set's topics from the start too (another set's are discovered within a second)
        shipped_sensors = sm.sensor_topics(load_sensors())
        for topic, (type_name, _, pub_qos, sub_qos) in {**m.TOPICS, **shipped_sensors,
                                                        m.CLOCK: m.CLOCK_TOPIC}.items():
            self.subscribe(topic, type_name, sub_qos, pub_qos)
        self.create_timer(1.0, self.discover)
        self.create_timer(flush_period_s, self.recording.flush)
        self.get_logger().info(f"recording {len(self.subscriptions_by_topic)} topics to {self.recording.path}")

    def subscribe(self, topic, type_name, qos, offered):
        if topic in self.subscriptions_by_topic:
            return
        self.recording.add_topic(topic, type_name, offered)
        self.subscriptions_by_topic[topic] = self.create_subscription(
            m.message_class(type_name), topic, lambda data: self.recording.write(topic, data), qos, raw=True)

    def discover(self):
        """Subscribe to a new /railderail/ topic with the reliability and durability its publishers offer."""
        for topic, types in self.get_topic_names_and_types():
            if topic in self.subscriptions_by_topic or not topic.startswith(m.NS + "/") or len(types) != 1:
                continue
            infos = self.get_publishers_info_by_topic(topic)
            if not infos:
                continue
            reliable = all(i.qos_profile.reliability == ReliabilityPolicy.RELIABLE for i in infos)
            latched = all(i.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL for i in infos)
            qos = QoSProfile(depth=5000,
                             reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)
            try:
                self.subscribe(topic, types[0], qos, qos)
                self.get_logger().info(f"recording {topic} ({types[0]}) too")
            except (FileNotFoundError, ImportError, AttributeError, ValueError) as error:
                self.get_logger().warning(f"cannot record {topic}: {error}")

    def take_queued(self):
        """Write what the subscriptions' queues held when the node stopped: messages the transport delivered and
        acknowledged that no callback had taken yet. A recorder behind the simulator at the run's end (its
        process waiting for a core) lost them when Ctrl-C came (up to a quarter of a sensor topic's run). Taken
        here without the executor, each queue until it is empty or holds a message received after the stop, so
        that a publisher still going cannot hold the recorder up. Returns the number written."""
        stop, taken = time.time_ns(), 0
        for topic, subscription in self.subscriptions_by_topic.items():
            while True:
                with subscription.handle:
                    message = subscription.handle.take_message(subscription.msg_type, subscription.raw)
                if message is None:
                    break
                data, info = message
                self.recording.write(topic, data)
                taken += 1
                if info["received_timestamp"] > stop:
                    break
        return taken

    def destroy_node(self):
        r = self.recording
        queued = self.take_queued()
        r.close()
        self.log(f"[railderail_recorder] wrote {r.messages} messages ({r.bytes / 1e6:.2f} MB of CDR) "
                 f"on {len(r.channels)} topics to {r.path}"
                 + (f" ({queued} of them still queued at the stop)" if queued else ""))
        if self.bag:
            self.log(f"[railderail_recorder] wrote {write_bag_metadata(r.path)} (rosbag2)")
        super().destroy_node()


def _metadata(pairs):
    out = {}
    for pair in pairs or []:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise ValueError(f"metadata {pair!r} is not KEY=VALUE")
        out[key] = value
    return out


def add_arguments(parser):
    parser.add_argument("out", metavar="OUT.mcap", nargs="?", help="file to write (its folder is created)")
    parser.add_argument("--bag-dir", metavar="DIR", help="instead of OUT.mcap: a rosbag2 bag, DIR/DIR_0.mcap and "
                        "DIR/metadata.yaml (for ros2 bag info/play); DIR must be new or empty")
    parser.add_argument("--metadata", action="append", metavar="KEY=VALUE",
                        help="add KEY=VALUE to the file's `railderail` metadata record (repeatable)")
    parser.add_argument("--flush-period", type=float, default=0.5,
                        help="seconds between chunk flushes (what a SIGKILL can lose); default 0.5")


def command(parser: argparse.ArgumentParser):
    """`railderail record OUT.mcap` or `railderail record --bag-dir DIR`."""
    add_arguments(parser)

    def run(args):
        if not 0.01 <= args.flush_period <= 60.0:
            raise ValueError(f"--flush-period {args.flush_period:g} s is outside 0.01-60 s")
        if (args.out is None) == (args.bag_dir is None):
            raise ValueError("give either OUT.mcap or --bag-dir DIR")
        if args.bag_dir is not None:
            folder = Path(args.bag_dir)
            if folder.exists() and (not folder.is_dir() or any(folder.iterdir())):
                raise ValueError(f"--bag-dir {folder}: it exists and is not an empty folder (a bag is a new folder)")
            out = bag_file(folder)
        elif not args.out.endswith(".mcap"):
            raise ValueError(f"{args.out}: the recording's name must end in .mcap")
        else:
            out = args.out
        metadata = _metadata(args.metadata)
        log = lambda text: print(text, file=sys.stderr, flush=True)  # noqa: E731
        return m.run_node("railderail record", lambda: RecorderNode(out, metadata, args.flush_period, log,
                                                                    bag=args.bag_dir is not None))
    return run


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m railderail_monitor.recording.recorder",
                                     description=__doc__.split("\n")[0])
    run = command(parser)
    # ROS arguments (`--ros-args -r __node:=NAME`, which `ros2 launch` adds) are for rclpy.init, which
    # reads them from sys.argv
    args = parser.parse_args(remove_ros_args(sys.argv[1:] if argv is None else argv))
    try:
        return run(args)
    except ValueError as error:
        print(f"{parser.prog}: error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
