"""`railderail replay FILE.mcap`: a recording back on the ROS topics, in Rerun, or as alerts.

- Publishes every recorded topic again (raw CDR, the QoS of ros.interface.TOPICS) at the recorded
  timing — the messages' log times, which are simulation time — divided by `--rate` (2 = twice as
  fast; 0 = as fast as possible), so that a monitor (or any node) can run offline against it. The
  recorded alerts are left out unless `--include-alerts`, so that a live monitor's alerts are not
  mixed with them. `--no-publish` skips ROS altogether.
- Runs the monitor's criteria (warning.monitor.Monitor, thresholds from the recording's metadata if the
  demo wrote them, else the defaults) over the recorded samples and prints the alerts found, with
  their lead before the recorded derailment; `--json` prints one JSON object instead. With
  `--signals measured` (the default for a recording of sensor topics only, `railderail recover
  --sensors-only`, or a user's own logger's) it runs the on-board criteria instead
  (`review_measured`: the sensor messages decoded as the measured-mode monitor node decodes them, into
  onboard.monitor.MeasuredMonitor), beside the measured-mode alerts the recording holds, if any.
- `--rerun` shows the run in a Rerun viewer; `--rrd OUT.rrd` writes it to a file (headless).

A recording made before the wheelset states and contact forces carried their sample's track curvature
(railderail_msgs before 2026-12-06) is still reviewed: each sample's curvature, which names an alert's rail,
is then the recorded vehicle status's at or before it (`status_curvature`). A topic recorded with another
definition of its type than the installed one (such as those) is not published: today's nodes would misread
its bytes.

A missing, truncated (no footer), damaged or foreign (no railderail_msgs topics) file is refused
with one line naming the file and the problem (exit status 2); `--allow-truncated` replays what a
killed recorder left (the messages up to its last flushed chunk).
"""
from __future__ import annotations

import argparse
import bisect
import struct
import sys
import time
from dataclasses import dataclass, field, fields
from pathlib import Path

from mcap.exceptions import McapError
from mcap.reader import NonSeekingReader, make_reader
from mcap_ros2.decoder import DecoderFactory
from rclpy.serialization import deserialize_message
from rosidl_adapter.parser import InvalidSpecification, InvalidValue

from railderail_sim import jsonout
from railderail_sim.parameters import VEHICLE_SETS
from railderail_sim.ranges import check_range
from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.ros.interface import ALERTS, DERAILMENT, FINAL_STATUS, FORCES, STATES, STATUS
from railderail_sim.ros.node_parameters import REAL_TIME_FACTOR_RANGE

from ..warning.limits import Limits, default_limits
from ..warning.monitor import Monitor
from ..warning.alerts import lead_times
from ..warning.alarms import nanoseconds
from ..node import measured_alert_text
from .recorder import MAGIC, recover_hint, schema_definitions, schema_text, split_type

# what the mcap readers raise on a cut or damaged file (besides McapError)
READ_ERRORS = (McapError, struct.error, EOFError, ValueError, KeyError)


class RecordingError(ValueError):
    """A recording that cannot be used; the message names the file and what is wrong."""


@dataclass
class Recording:
    path: Path
    messages: list                      # (topic, type name, log_time ns, CDR bytes, decoded or None)
    metadata: dict = field(default_factory=dict)
    truncated: bool = False
    problem: str = ""
    # topics recorded with a definition of their type other than the installed one (an older railderail's, or a
    # type not installed here)
    other_definition: set = field(default_factory=set)

    @property
    def duration_s(self):
        return (self.messages[-1][2] - self.messages[0][2]) * 1e-9 if self.messages else 0.0

    def topics(self):
        out = {}
        for topic, type_name, *_ in self.messages:
            out.setdefault(topic, [type_name, 0])[1] += 1
        return out


def _check_head(path):
    path = Path(path)
    if not path.exists():
        raise RecordingError(f"{path}: no such file")
    if path.is_dir():
        raise RecordingError(f"{path} is a folder, not an MCAP file")
    size = path.stat().st_size
    with open(path, "rb") as f:
        head = f.read(8)
        if head != MAGIC:
            what = "it is empty" if size == 0 else f"it starts with {head[:8]!r}, not the MCAP magic"
            raise RecordingError(f"{path} is not an MCAP file ({what})")
        f.seek(max(size - 8, 0))
        return f.read(8) == MAGIC


def installed_class(schema):
    """The rclpy class of a recorded ros2msg schema if this type is installed here with the
    recorded definition (compared as rosidl_adapter parses them, so comments and layout do not
    matter), else None."""
    try:
        recorded = schema_definitions(schema.name, schema.data.decode())
        if recorded != schema_definitions(schema.name, schema_text(schema.name)):
            return None
        package, name = split_type(schema.name)
        return m.message_class(f"{package}/msg/{name}")
    except (InvalidSpecification, InvalidValue, ValueError, TypeError, NameError, FileNotFoundError, ImportError,
            AttributeError):
        return None


def message_decoders():
    """schema -> decode(CDR bytes) -> message: rclpy's deserialize_message into the installed
    class where the recording's definition is the installed one (every railderail recording);
    mcap_ros2's generic decoder for any other (foreign or older) definition."""
    cache = {}
    fallback = DecoderFactory()

    def decoder(schema):
        d = cache.get(schema.id)
        if d is None:
            cls = installed_class(schema)
            if cls is not None:
                d = lambda data, cls=cls: deserialize_message(data, cls)  # noqa: E731
            else:
                d = fallback.decoder_for("cdr", schema) or (lambda data: None)
            cache[schema.id] = d
        return d
    return decoder


def read_recording(path, allow_truncated=False, decode=True):
    """All messages of a railderail MCAP in log-time order (RecordingError if it cannot be used); `decode`:
    True (every message), False (none: the decoded field None) or topic -> bool (those it names: decoding
    is most of the reading's time)."""
    path = Path(path)
    complete = _check_head(path)
    decoder = message_decoders()
    wanted = decode if callable(decode) else (lambda topic: decode)
    messages, problem = [], ""
    metadata, other, checked = {}, set(), set()

    def collect(iterator):
        for schema, channel, message in iterator:
            if channel.topic not in checked:
                checked.add(channel.topic)
                if schema is not None and schema.encoding == "ros2msg" and installed_class(schema) is None:
                    other.add(channel.topic)
            name = schema.name if schema else ""
            decoded = decoder(schema)(message.data) if schema is not None and schema.encoding == "ros2msg" \
                and channel.message_encoding == "cdr" and wanted(channel.topic) else None
            messages.append((channel.topic, name, message.log_time, message.data, decoded))

    # in file order, then a stable sort by log time: the order the reader's log-time merge gives (equal times in
    # file order), at a fraction of its cost
    with open(path, "rb") as f:
        if complete:
            try:
                reader = make_reader(f)
                collect(reader.iter_messages(log_time_order=False))
                for record in reader.iter_metadata():
                    metadata[record.name] = dict(record.metadata)
            except READ_ERRORS as error:
                raise RecordingError(f"{path} is damaged ({type(error).__name__}: {error})") from None
        else:
            try:
                collect(NonSeekingReader(f).iter_messages(log_time_order=False))
            except READ_ERRORS:
                pass                      # the cut: everything before it has been read
    messages.sort(key=lambda item: item[2])
    if not complete:
        last = f" up to t = {messages[-1][2] * 1e-9:.2f} s" if messages else ""
        problem = (f"{path} is truncated (no MCAP footer: the recording was cut off, e.g. the recorder was "
                   f"killed); {len(messages)} messages{last} are readable")
        if not messages:
            raise RecordingError(problem + ": nothing to replay")
        if not allow_truncated:
            raise RecordingError(problem + f": add --allow-truncated to use them, or make a complete copy: "
                                 f"{recover_hint(path)}")
    ours = {topic for topic, type_name, *_ in messages
            if type_name.startswith("railderail_msgs/") or topic.startswith(m.SENSORS_NS + "/")}
    if not ours:
        found = ", ".join(f"{t} ({n})" for t, (n, _) in Recording(path, messages).topics().items()) or "none"
        raise RecordingError(f"{path} is not a railderail recording: it has no railderail_msgs topics and no "
                             f"sensor topics under {m.SENSORS_NS}/ (topics: {found})")
    return Recording(path, messages, metadata, truncated=not complete, problem=problem, other_definition=other)


def limits_of(recording):
    """The monitor thresholds stored by the demo in the `railderail` metadata (key `monitor.NAME`),
    else the defaults."""
    meta = recording.metadata.get("railderail", {})
    names = {f.name for f in fields(Limits)}
    values = {key[len("monitor."):]: float(value) for key, value in meta.items()
              if key.startswith("monitor.") and key[len("monitor."):] in names}
    return Limits(**{**default_limits().as_dict(), **values}).validated()


@dataclass
class Review:
    """What a replay found."""
    alerts: list = field(default_factory=list)           # warning.alerts.AlertRecord
    recorded_alerts: list = field(default_factory=list)  # dicts
    derailment: dict = None
    final_status: str = ""
    samples: int = 0
    curvature_from: str = "samples"      # where each sample's curvature came from: its own messages, or
                                         # vehicle_status (a recording made before they carried it)

    def as_json(self, recording):
        found = [a.as_dict() for a in self.alerts]
        key = lambda a: (a["sample"], a["criterion"], a["severity"], a["wheelset"], a["wheel_side"])  # noqa: E731
        return dict(file=str(recording.path), truncated=recording.truncated, messages=len(recording.messages),
                    duration_s=recording.duration_s, samples=self.samples, curvature_from=self.curvature_from,
                    derailment=self.derailment,
                    final_status=self.final_status, alerts=found,
                    lead_times=lead_times(self.alerts, self.derailment),
                    recorded_alerts=self.recorded_alerts,
                    same_as_recorded=sorted(map(key, found)) == sorted(map(key, self.recorded_alerts)))


def status_curvature(recording):
    """sample -> track curvature (1/m, + left) of a recording whose wheelset states and contact forces do not
    carry it (made before 2026-12-06): the curvature of its vehicle status at the latest sample at or before the
    sample (the simulator publishes the status every few samples: status_rate), 0 before the first."""
    kept = sorted((int(msg.sample), float(msg.curvature)) for topic, _, _, _, msg in recording.messages
                  if topic == STATUS and msg is not None)
    samples = [sample for sample, _ in kept]

    def curvature(sample):
        k = bisect.bisect_right(samples, sample)
        return kept[k - 1][1] if k else 0.0
    return curvature


def review(recording, limits=None, on_message=None, on_alert=None):
    """Run the criteria over a recording in log-time order; `on_message(topic, type, log_time, data,
    decoded)` sees every message first (publishing, viewer), `on_alert(record)` every alert found."""
    monitor = Monitor(limits or limits_of(recording))
    out = Review()
    from_status = None

    def curvature(msg):
        nonlocal from_status
        if hasattr(msg, "curvature"):
            return msg.curvature
        if from_status is None:
            from_status, out.curvature_from = status_curvature(recording), "vehicle_status"
        return from_status(msg.sample)

    for item in recording.messages:
        topic, _, _, _, msg = item
        if on_message is not None:
            on_message(*item)
        if msg is None:
            continue
        found = []
        if topic == STATES:
            out.samples += 1
            found = monitor.on_states(m.seconds(msg.header.stamp), msg.sample, msg.track_position, msg.speed,
                                      curvature(msg), msg.attack_angle, msg.wheel_lift)
        elif topic == FORCES:
            found = monitor.on_forces(m.seconds(msg.header.stamp), msg.sample, msg.track_position, msg.speed,
                                      curvature(msg), msg.derailment_coefficient, msg.vertical_force)
        elif topic == ALERTS:
            out.recorded_alerts.append(m.alert_dict(msg))
        elif topic == DERAILMENT:
            out.derailment = m.derailment_dict(msg)
        elif topic == FINAL_STATUS:
            out.final_status = msg.message
        for alert in found:
            out.alerts.append(alert)
            if on_alert is not None:
                on_alert(alert)
    return out


def review_measured(recording, vehicle_set="hs19", sensors=None, limits=None, on_alert=None):
    """(alerts found, alerts recorded) of the on-board criteria over a recording's sensor messages in
    log-time order: decoded (sensor_messages.SensorDecoder) into a MeasuredMonitor as the measured-mode
    monitor node does, without its last undecided stamps (the node, fed live, never ends its streams);
    the recorded ones are those of /railderail/onboard_alerts, as dicts. `sensors`: the sensor set
    (sensors.sensor_set.SensorSet, default the shipped one); `limits`: MeasuredLimits (default the car's);
    `vehicle_set`: a built-in set or a car file (onboard.car.load_car)."""
    from railderail_sim.sensors.config import default_set

    from ..onboard import measured as me
    from ..onboard.car import load_car
    from ..onboard.monitor import MeasuredMonitor

    sensors = sensors or default_set()
    vehicle = load_car(vehicle_set)
    monitor = MeasuredMonitor(vehicle, limits or me.measured_limits(vehicle), me.sample_rates(sensors))
    decoder = sm.SensorDecoder(sensors)
    topics = set(decoder.topics())
    found, recorded = [], []
    for topic, _, _, _, msg in recording.messages:
        if msg is None:
            continue
        if topic in topics:
            for unit, t, signals in decoder.decode(topic, msg):
                for alert in monitor.feed(unit, t, **signals):
                    found.append(alert)
                    if on_alert is not None:
                        on_alert(alert)
        elif topic == m.ONBOARD_ALERTS:
            recorded.append(dict(m.alert_dict(msg), place=msg.header.frame_id))
    return found, recorded


def measured_key(alert):
    """What identifies a measured alert, live or replayed: criterion, place and stamp in ns. Not its sample
    number, which counts the messages a monitor received (a replay of a recording that lost one counts
    differently from the live node)."""
    a = alert if isinstance(alert, dict) else alert.as_dict()
    return a["criterion"], a["place"], nanoseconds(a["time_s"])


def compare_measured(found, recorded):
    """(same, why): whether the alerts found are those the recording holds, by measured_key, and if not one
    sentence naming the alerts on either side only."""
    def name(keys):
        return "; ".join(f"{c} at {p}, t = {t * 1e-9:.3f} s" for c, p, t in sorted(keys, key=lambda k: k[2]))

    mine, theirs = set(map(measured_key, found)), set(map(measured_key, recorded))
    if mine == theirs:
        return True, ""
    parts = ([f"found here only: {name(mine - theirs)}"] if mine - theirs else []) + \
        ([f"in the recording only: {name(theirs - mine)}"] if theirs - mine else [])
    return False, "; ".join(parts)


# --- publishing -----------------------------------------------------------------------------------

class Publisher:
    """Republishes recorded messages on their topics at the recorded timing / rate."""

    def __init__(self, recording, rate, include_alerts, wait_for_subscribers, log):
        import rclpy
        from rclpy.qos import QoSProfile

        self.rclpy = rclpy
        rclpy.init()
        self.node = rclpy.create_node("railderail_replay")
        qos = {**{t: q for t, (_, _, q, _) in m.TOPICS.items()}, m.CLOCK: m.CLOCK_QOS}
        self.publishers = {}
        for topic, (type_name, _) in recording.topics().items():
            if topic in (ALERTS, m.ONBOARD_ALERTS) and not include_alerts:
                continue
            try:
                cls = m.message_class(type_name)
            except (ImportError, AttributeError, ValueError):
                log(f"replay: cannot publish {topic}: type {type_name} is not installed")
                continue
            if topic in recording.other_definition:
                log(f"replay: cannot publish {topic}: recorded with another definition of {type_name} than the "
                    "installed one (an older railderail's), which today's nodes would misread")
                continue
            sensor = topic.startswith(m.SENSORS_NS + "/")
            self.publishers[topic] = self.node.create_publisher(cls, topic, qos.get(topic, m.SENSOR if sensor else
                                                                                    QoSProfile(depth=100)))
        self.rate = rate
        self.t0_log = recording.messages[0][2] if recording.messages else 0
        self.t0_wall = None
        if wait_for_subscribers > 0:
            deadline = time.monotonic() + 30.0
            # the state topics, or in a recording of sensors only the odometer's
            watched = [p for t, p in self.publishers.items() if t in (STATES, FORCES)] or \
                [p for t, p in self.publishers.items() if t == f"{m.SENSORS_NS}/odometer"]
            while min((p.get_subscription_count() for p in watched), default=0) < wait_for_subscribers:
                if time.monotonic() > deadline:
                    raise RecordingError(f"replay: no {wait_for_subscribers} subscribers on "
                                         f"{watched[0].topic_name if watched else STATES} after 30 s")
                rclpy.spin_once(self.node, timeout_sec=0.1)
            time.sleep(0.5)

    def __call__(self, topic, type_name, log_time, data, decoded):
        publisher = self.publishers.get(topic)
        if publisher is None:
            return
        if self.rate > 0:
            if self.t0_wall is None:
                self.t0_wall = time.monotonic()
            delay = self.t0_wall + (log_time - self.t0_log) * 1e-9 / self.rate - time.monotonic()
            if delay > 0:
                time.sleep(delay)
        publisher.publish(data)

    def close(self):
        for publisher in self.publishers.values():
            if publisher.qos_profile.reliability == 1:          # RELIABLE: let late subscribers catch up
                publisher.wait_for_all_acked(self.rclpy.duration.Duration(seconds=2.0))
        self.node.destroy_node()
        self.rclpy.try_shutdown()


# --- Rerun --------------------------------------------------------------------------------------

VIEWED = (STATES, FORCES, STATUS, ALERTS, m.ONBOARD_ALERTS, DERAILMENT, FINAL_STATUS, m.BRAKE, m.SUPERVISION,
          m.SUPERVISION_STATUS)


def viewed(topic):
    """The topics a viewer.RunViewer shows (the others need no decoding for a .rrd)."""
    return topic in VIEWED or topic.startswith(m.SENSORS_NS + "/")


def feed_viewer(viewer):
    """An on_message callback that shows the recorded topics (the sensors' included) in a viewer.RunViewer."""
    handlers = dict(zip(VIEWED, (viewer.on_states, viewer.on_forces, viewer.on_status, viewer.on_alert,
                                 viewer.on_onboard_alert, viewer.on_derailment, viewer.on_final_status,
                                 viewer.on_brake, viewer.on_supervision, viewer.on_supervision_status)))

    def on_message(topic, type_name, log_time, data, decoded):
        if decoded is None:
            return
        handler = handlers.get(topic)
        if handler is not None:
            handler(decoded)
        elif topic.startswith(m.SENSORS_NS + "/"):
            viewer.on_sensor(topic, decoded)
    return on_message


def write_rrd(recording, rrd_path, limits=None):
    """The Rerun file of a recording (headless)."""
    from ..views.rerun_views import RunViewer

    viewer = RunViewer(limits or limits_of(recording), flush_every=5000)
    viewer.save(rrd_path)
    try:
        for item in recording.messages:
            feed_viewer(viewer)(*item)
    finally:
        viewer.close()
    return Path(rrd_path)


# --- command ------------------------------------------------------------------------------------

def format_alert(a, derailment=None):
    lead = ""
    if derailment is not None:
        lead = (f"  [{derailment['time_s'] - a.time_s:.2f} s, {derailment['track_position_m'] - a.track_position:.0f} m "
                "before the derailment]")
    return f"t = {a.time_s:8.3f} s  s = {a.track_position:7.1f} m  {a.speed * 3.6:5.1f} km/h  {a.message}{lead}"


def command(parser: argparse.ArgumentParser):
    parser.add_argument("file", metavar="FILE.mcap", help="a recording of `railderail demo` or `railderail record`")
    parser.add_argument("--rate", type=float, default=1.0,
                        help="replay speed: 1 = recorded (simulation) timing, 2 = twice as fast, 0 = as fast as "
                        "possible (default 1)")
    parser.add_argument("--no-publish", action="store_true", help="do not publish on ROS topics (review only)")
    parser.add_argument("--include-alerts", action="store_true", help="republish the recorded alerts too")
    parser.add_argument("--wait-for-subscribers", type=int, default=0, metavar="N",
                        help="start publishing once N nodes subscribe to the state topics (default 0)")
    parser.add_argument("--rerun", action="store_true", help="show the run in a Rerun viewer (spawned)")
    parser.add_argument("--rrd", metavar="OUT.rrd", help="write the Rerun views to a file")
    parser.add_argument("--json", action="store_true", help="print the alerts found as one JSON object")
    parser.add_argument("--allow-truncated", action="store_true",
                        help="replay the readable part of a truncated recording instead of refusing it")
    parser.add_argument("--signals", choices=("ground_truth", "measured"),
                        help="the criteria run over it: ground_truth (the wheelset states and contact forces) or "
                        "measured (the on-board sensors' topics); default ground_truth if it holds the states")
    parser.add_argument("--vehicle-set", default="hs19", metavar="SET|FILE.yaml",
                        help="measured: the car, a built-in set (" + ", ".join(VEHICLE_SETS) + ") or a car file "
                        "(onboard/car.py; default hs19)")
    parser.add_argument("--sensors", metavar="FILE.yaml",
                        help="measured: the sensor set recorded (default the shipped railderail_sim/config/sensors.yaml)")

    def run(args):
        check_range("--rate", args.rate, *REAL_TIME_FACTOR_RANGE)
        if args.rrd and not args.rrd.endswith(".rrd"):
            raise ValueError(f"--rrd {args.rrd}: the file name must end in .rrd")
        recording = read_recording(args.file, allow_truncated=args.allow_truncated)
        err = lambda text: print(text, file=sys.stderr, flush=True)  # noqa: E731
        if recording.truncated:
            err(f"railderail: warning: {recording.problem}; replaying them")
        signals = args.signals or ("ground_truth" if STATES in recording.topics() else "measured")
        if signals == "measured" and (args.rerun or args.rrd):
            raise ValueError("--rerun and --rrd show the ground-truth topics: not with --signals measured")
        limits = limits_of(recording) if signals == "ground_truth" else None
        callbacks = []
        publisher = None
        viewer = None
        if not args.no_publish:
            publisher = Publisher(recording, args.rate, args.include_alerts, args.wait_for_subscribers, err)
            callbacks.append(publisher)
            err(f"replaying {len(recording.messages)} messages ({recording.duration_s:.1f} s of simulation) from "
                f"{recording.path} on {len(publisher.publishers)} topics"
                + (f" at {args.rate:g} x" if args.rate else " as fast as possible"))
        if args.rerun or args.rrd:
            from ..views.rerun_views import RunViewer
            viewer = RunViewer(limits, flush_every=20 if args.rerun else 5000)
            viewer.spawn() if args.rerun else viewer.save(args.rrd)
            callbacks.append(feed_viewer(viewer))
        derailment = next((m.derailment_dict(msg) for topic, _, _, _, msg in recording.messages
                           if topic == DERAILMENT and msg is not None), None)
        on_alert = None if args.json else (lambda a: print(format_alert(a, derailment), flush=True))
        if signals == "measured":
            return _run_measured(args, recording, callbacks, publisher, err)
        try:
            result = review(recording, limits, on_message=(lambda *item: [c(*item) for c in callbacks]),
                            on_alert=on_alert)
        finally:
            if viewer is not None:
                viewer.close()
            if publisher is not None:
                publisher.close()
        if args.json:
            print(jsonout.dumps(result.as_json(recording), indent=1))
        else:
            if derailment is not None:
                print(f"derailment: t = {derailment['time_s']:.3f} s, s = {derailment['track_position_m']:.1f} m, "
                      f"wheelset {derailment['wheelset']} {derailment['wheel_side']} ({derailment['rail_side']}), "
                      f"{derailment['mechanism'].replace('_', ' ')}, {derailment['speed_kmh']:.1f} km/h")
            elif result.final_status:
                print(f"no derailment: {result.final_status}")
            same = result.as_json(recording)["same_as_recorded"]
            print(f"{len(result.alerts)} alerts found; the recording holds {len(result.recorded_alerts)} "
                  f"({'the same' if same else 'they differ'})")
            if result.curvature_from == "vehicle_status":
                print("(recorded before the wheelset states and contact forces carried their sample's curvature: "
                      "each alert's rail from the vehicle status at or before its sample)")
        if args.rrd:
            err(f"wrote {args.rrd}")
        return 0
    return run


def _run_measured(args, recording, callbacks, publisher, err):
    """`railderail replay --signals measured`: publish (as the ground-truth replay does) and run the on-board
    criteria over the sensor messages."""
    from railderail_sim.sensors.config import load as load_sensors

    sensors = load_sensors(args.sensors)
    try:
        for item in recording.messages:
            for c in callbacks:
                c(*item)
        found, recorded = review_measured(
            recording, args.vehicle_set, sensors,
            on_alert=None if args.json else lambda a: print(
                f"t = {a.time_s:8.3f} s  s = {a.track_position:7.1f} m  "
                + measured_alert_text(a.criterion, a.severity, a.value, a.threshold, a.place), flush=True))
    finally:
        if publisher is not None:
            publisher.close()
    same, why = compare_measured(found, recorded)
    if args.json:
        print(jsonout.dumps(dict(file=str(recording.path), signals="measured", truncated=recording.truncated,
                                 messages=len(recording.messages), duration_s=recording.duration_s,
                                 alerts=[a.as_dict() for a in found], recorded_alerts=recorded,
                                 same_as_recorded=same, differences=why), indent=1))
    elif m.ONBOARD_ALERTS not in recording.topics():
        print(f"{len(found)} measured alerts found (the recording holds no measured-mode monitor's alerts to compare: "
              "a logger's, `railderail import-imu`, or sensor topics only)")
    else:
        print(f"{len(found)} measured alerts found; the recording holds {len(recorded)} "
              + ("(the same criteria, places and stamps)" if same else
                 f"(they differ: {why}; the recording holds what the sensors sent: a live monitor that missed some "
                 "of it, which its log counts as incomplete stamps, decides later or not at all)"))
    return 0
