"""`railderail recover BROKEN.mcap FIXED.mcap`: a complete MCAP of everything readable in a cut-off one;
with `--sensors-only`, of its on-board sensors' topics only.

A recorder killed by SIGKILL or a power cut leaves an MCAP without its summary and footer (the
recorder closes a chunk and flushes every `--flush-period`). The mcap library's streaming reader
reads such a file record by record up to the cut: every complete chunk (its schemas, channels and
messages), and the metadata and attachments between chunks; a chunk cut in two is lost whole (its
compressed data cannot be read in part). The mcap writer then writes those records again, with new
chunk indexes, statistics, summary and footer, so that every MCAP reader (rosbags, Foxglove,
`ros2 bag`, `mcap info`) opens the result. FIXED is written atomically (`atomic.atomic_write`): a
failure leaves no half file. An existing FIXED, BROKEN itself above all (the only copy of a crashed run), is
not replaced without `--force`.

Message times, sequence numbers, channel metadata and the header's profile are kept; schema and
channel ids are renumbered in the order they appear. The library string of the header says the
file was recovered.

`--sensors-only` (`keep=sensors_only`) keeps the channels of /railderail/sensors/* and /clock, with their
schemas, and the metadata: the recording a train's own logger would have made, which `railderail replay
--signals measured` runs the on-board monitor over (the same alerts as the live measured monitor's).
"""
from __future__ import annotations

import argparse
import struct
import sys
from dataclasses import dataclass
from pathlib import Path

import mcap
import mcap.writer
from mcap.exceptions import EndOfFile
from mcap.records import Attachment, Channel, Header, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType

from railderail_sim.atomic import atomic_write
from railderail_sim.ros import interface as m

from .replay import READ_ERRORS, RecordingError, _check_head


@dataclass
class Recovered:
    """What `recover` wrote."""
    messages: int
    channels: int
    complete: bool                  # the input had its footer (nothing was missing)
    end_time_ns: int                # log time of the last message kept (0 if none)
    stopped_by: str                 # why reading stopped early ("" when complete)


def sensors_only(topic):
    """The topics a sensor-only copy keeps: the on-board sensors' and the clock."""
    return topic.startswith(m.SENSORS_NS + "/") or topic == m.CLOCK


def cut_reason(error):
    """Why reading stopped, in words: the reader's own error text names bytes and buffers, not the file."""
    if isinstance(error, (EndOfFile, struct.error, EOFError)):
        return "the file ends inside a record"
    return f"the bytes after them are damaged ({type(error).__name__})"


def recover(broken, fixed, chunk_size=512 * 1024, keep=None, force=False) -> Recovered:
    """Write `fixed`, a complete MCAP of every record of `broken` up to its cut (RecordingError naming
    the file when it is missing, not an MCAP file or holds no complete chunk, or when `fixed` exists and
    `force` is false); `keep(topic)`, if given, chooses the channels written (their schemas with them)."""
    broken, fixed = Path(broken), Path(fixed)
    complete = _check_head(broken)
    if fixed.suffix != ".mcap":
        raise RecordingError(f"{fixed}: the recovered file's name must end in .mcap")
    if not fixed.resolve().parent.is_dir():
        raise RecordingError(f"{fixed}: its folder {fixed.parent} does not exist")
    if fixed.exists() and not force:
        what = ("is the recording being recovered, perhaps the only copy of the run"
                if fixed.resolve() == broken.resolve() else "exists")
        raise RecordingError(f"{fixed} {what}: give another name, or add --force to replace it")
    schemas, channels = {}, {}           # old id -> new id
    schema_records = {}                  # old id -> the record, registered with its first kept channel
    messages, end_time, stopped_by = 0, 0, ""
    with open(broken, "rb") as source, atomic_write(fixed, "wb") as target:
        writer = mcap.writer.Writer(target, chunk_size=chunk_size, compression=CompressionType.ZSTD)
        # no record is longer than the file: a length read from damaged bytes cannot ask for more
        records = StreamReader(source, record_size_limit=max(broken.stat().st_size, 1))
        started = False
        try:
            for record in records.records:
                if isinstance(record, Header):
                    writer.start(profile=record.profile,
                                 library=f"{record.library} (recovered by railderail, mcap {mcap.__version__})")
                    started = True
                elif isinstance(record, Schema):
                    schema_records.setdefault(record.id, record)
                elif isinstance(record, Channel) and record.id not in channels and (keep is None or keep(record.topic)):
                    schema = schema_records.get(record.schema_id)
                    if schema is not None and schema.id not in schemas:
                        schemas[schema.id] = writer.register_schema(schema.name, schema.encoding, schema.data)
                    channels[record.id] = writer.register_channel(record.topic, record.message_encoding,
                                                                  schemas.get(record.schema_id, 0),
                                                                  dict(record.metadata))
                elif isinstance(record, Message) and record.channel_id in channels:
                    writer.add_message(channels[record.channel_id], log_time=record.log_time, data=record.data,
                                       publish_time=record.publish_time, sequence=record.sequence)
                    messages += 1
                    end_time = max(end_time, record.log_time)
                elif isinstance(record, Metadata):
                    writer.add_metadata(record.name, dict(record.metadata))
                elif isinstance(record, Attachment):
                    writer.add_attachment(record.create_time, record.log_time, record.name, record.media_type,
                                          record.data)
                # the summary section's records (indexes, statistics) are made anew by the writer
        except READ_ERRORS as error:
            # the cut (EndOfFile), or damage after it: everything before it has been read
            stopped_by = cut_reason(error)
        if not started or not channels:
            raise RecordingError(f"{broken} has nothing to recover: no complete chunk after its header"
                                 + (" with a sensor topic" if keep is not None else "")
                                 + (f" ({stopped_by})" if stopped_by else ""))
        writer.finish()
    return Recovered(messages, len(channels), complete and not stopped_by, end_time, stopped_by)


def command(parser: argparse.ArgumentParser):
    """`railderail recover BROKEN.mcap FIXED.mcap`."""
    parser.add_argument("broken", metavar="BROKEN.mcap", help="the cut-off recording (no summary, no footer)")
    parser.add_argument("fixed", metavar="FIXED.mcap", help="the complete MCAP to write (atomically)")
    parser.add_argument("--sensors-only", action="store_true",
                        help="keep only the on-board sensors' topics (/railderail/sensors/*) and /clock")
    parser.add_argument("--force", action="store_true", help="replace FIXED.mcap if it exists (even BROKEN.mcap)")

    def run(args):
        done = recover(args.broken, args.fixed, keep=sensors_only if args.sensors_only else None, force=args.force)
        if args.sensors_only:
            print(f"wrote the {done.messages} messages of {done.channels} sensor topics of {args.broken} to "
                  f"{args.fixed}" + ("" if done.complete else f" (it was cut off: {done.stopped_by})"),
                  file=sys.stderr)
        elif done.complete:
            print(f"{args.broken} was complete: wrote its {done.messages} messages to {args.fixed}", file=sys.stderr)
        else:
            print(f"recovered {done.messages} messages on {done.channels} topics up to t = "
                  f"{done.end_time_ns * 1e-9:.3f} s (log time) into {args.fixed}; the rest of {args.broken} "
                  f"was cut off ({done.stopped_by})", file=sys.stderr)
    return run
