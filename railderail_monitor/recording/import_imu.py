"""`railderail import-imu LOG.csv OUT.mcap`: a logger's CSV of on-board sensor readings as the recording
the measured-mode monitor replays (`railderail replay OUT.mcap --signals measured --sensors OUT.sensors.yaml`),
and the sensor file that says which mounts it holds at which rates.

The CSV (comma separated, one header row, lines starting with `#` skipped; docs/onboard.md, "Your own IMU
log") has a column `time_s`, the instant each row's readings were measured (s, >= 0), and, per sensor unit,
columns named `<unit>_<signal>_<unit of measure>`:

- a mount (sensors.sensor_set.MOUNTS: car_body_front, ..., axle_box_3_right): `<mount>_acc_x|y|z_m_s2` or
  `_g` (specific force, gravity included: +1 g up at rest), optionally `<mount>_gyro_x|y|z_rad_s` or `_deg_s`,
  in the car's axes, x toward its front end, y to its left, z up;
- the air springs (all four or none): `air_spring_<front|rear>_<left|right>_height_m` or `_mm` (the spring's
  height) and `_pressure_pa`, `_kpa` or `_bar` (gauge);
- the odometer: `odometer_speed_m_s` or `_kmh` (the forward speed, >= 0).

A unit's cells are all filled on the rows where it has a sample and all empty on the others, so units at
different rates share one table; each unit's rate is the inverse of the median spacing of its stamps.
`--running reversed`: the car ran with its rear end leading, so the monitor's front is the log's rear, its
left the log's right: the mounts are renamed (car_body_front <-> car_body_rear, bogie_front_frame <->
bogie_rear_frame, axle_box_<w>_<side> -> axle_box_<3-w>_<other side>, air_spring_<front>_<left> ->
air_spring_<rear>_<right>) and the readings' x and y change sign (a half turn about z). The frame mounts over
a wheelset (bogie_frame_<w>, over its left axle box) have no mount to go to running reversed and are refused.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path
import re
import sys

import numpy as np

from railderail_sim.parameters import GRAVITY
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.sensors.sensor_set import AIR_SPRING_HEIGHT, AIR_SPRINGS, MOUNTS, ODOMETER

ACCELERATION = {"m_s2": 1.0, "g": GRAVITY}
ANGULAR_RATE = {"rad_s": 1.0, "deg_s": math.pi / 180.0}
HEIGHT = {"m": 1.0, "mm": 1e-3}
PRESSURE = {"pa": 1.0, "kpa": 1e3, "bar": 1e5}
SPEED = {"m_s": 1.0, "kmh": 1.0 / 3.6}
# signal: (its units of measure, axes); the columns of a unit are <unit>_<signal>[_<axis>]_<unit of measure>
SIGNALS = {"acc": (ACCELERATION, "xyz"), "gyro": (ANGULAR_RATE, "xyz"), "height": (HEIGHT, ""),
           "pressure": (PRESSURE, ""), "speed": (SPEED, "")}
RUNNING = ("forward", "reversed")
TIME = "time_s"
# a small log of the CSV's form (docs/onboard.md says how it was made): `railderail import-imu` it to try
EXAMPLE = Path(__file__).resolve().parents[1] / "config" / "imu-example.csv"


def _pattern():
    units = "|".join(re.escape(u) for table, _ in SIGNALS.values() for u in table)
    return re.compile(rf"^(?P<unit>.+?)_(?P<signal>{'|'.join(SIGNALS)})(?:_(?P<axis>[xyz]))?_(?P<measure>{units})$")


COLUMN = _pattern()


def column_forms():
    """The accepted column names, for messages."""
    return (f"{TIME}; <mount>_acc_<x|y|z>_<{'|'.join(ACCELERATION)}>, <mount>_gyro_<x|y|z>_<{'|'.join(ANGULAR_RATE)}> "
            f"(mounts {', '.join(MOUNTS)}); <air spring>_height_<{'|'.join(HEIGHT)}>, <air spring>_pressure_"
            f"<{'|'.join(PRESSURE)}> ({', '.join(AIR_SPRINGS)}); odometer_speed_<{'|'.join(SPEED)}>")


def running_name(name, running):
    """The monitor's name of a log's unit when the car ran `running` (forward: the same)."""
    if running == "forward" or name in (ODOMETER, "car_body_centre"):
        return name
    swap = {"front": "rear", "rear": "front", "left": "right", "right": "left"}
    if name.startswith("bogie_frame_"):
        raise ValueError(f"mount {name} is over wheelset {name[-1]}'s left axle box, which running reversed is "
                         "over a right one, where the monitor has no mount: give the frame's centre "
                         "(bogie_front_frame, bogie_rear_frame), or --running forward")
    if name.startswith("axle_box_"):
        _, _, wheelset, side = name.split("_")
        return f"axle_box_{3 - int(wheelset)}_{swap[side]}"
    return "_".join(swap.get(part, part) for part in name.split("_"))


def _signal_columns(header):
    """{unit: {signal: [(column index, scale to SI)] in axis order}} of a CSV header; ValueError naming an
    unknown column, unit or missing axis."""
    units = {}
    for k, name in enumerate(header):
        if name == TIME:
            continue
        found = COLUMN.match(name)
        kind = found and ("mount" if found["unit"] in MOUNTS else "air spring" if found["unit"] in AIR_SPRINGS
                          else "odometer" if found["unit"] == ODOMETER else None)
        allowed = {"mount": ("acc", "gyro"), "air spring": ("height", "pressure"), "odometer": ("speed",)}
        table, axes = SIGNALS[found["signal"]] if found else (None, None)
        if (not found or kind is None or found["signal"] not in allowed[kind] or found["measure"] not in table
                or bool(found["axis"]) != bool(axes)):
            raise ValueError(f"column {name!r} is not one the import reads; the columns are {column_forms()}")
        signal = units.setdefault(found["unit"], {}).setdefault(found["signal"], {})
        if (found["axis"] or "") in signal:
            raise ValueError(f"column {name!r}: {found['unit']} {found['signal']} {found['axis'] or ''} is given twice")
        signal[found["axis"] or ""] = (k, table[found["measure"]])
    out = {}
    for unit, signals in units.items():
        for signal, by_axis in signals.items():
            axes = SIGNALS[signal][1] or ""
            missing = [a for a in axes if a not in by_axis]
            if missing:
                raise ValueError(f"{unit} {signal}: no column for axis {', '.join(missing)} (a three-axis reading "
                                 "needs x, y and z)")
        if unit in MOUNTS and "acc" not in signals:
            raise ValueError(f"mount {unit} has a gyro but no accelerometer: the monitor reads its acc columns")
        out[unit] = {signal: [by_axis[a] for a in (SIGNALS[signal][1] or [""])] for signal, by_axis in signals.items()}
    springs = [u for u in out if u in AIR_SPRINGS]
    if springs and (len(springs) != len(AIR_SPRINGS) or any(set(out[u]) != {"height", "pressure"} for u in springs)):
        raise ValueError(f"the air springs need a height and a pressure column each, all four ({', '.join(AIR_SPRINGS)}) "
                         "or none")
    return out


def read_log(path):
    """({unit: {"time": (n,), signal: (n,) or (n, 3)}} in SI, the log's own unit names, of a logger's CSV;
    ValueError naming a bad file, column, cell or stamp."""
    try:
        with open(path, newline="") as f:
            rows = [row for row in csv.reader(f) if row and not row[0].lstrip().startswith("#")]
    except OSError as error:
        raise ValueError(f"IMU log {str(path)!r} cannot be read: {error.strerror}") from None
    if not rows:
        raise ValueError(f"IMU log {str(path)!r} holds no header row")
    header = [name.strip() for name in rows[0]]
    if TIME not in header:
        raise ValueError(f"IMU log {str(path)!r} has no column {TIME} (the instant of each row's readings, s)")
    units = _signal_columns(header)
    if not units:
        raise ValueError(f"IMU log {str(path)!r} has no sensor column; the columns are {column_forms()}")
    table = rows[1:]

    def line(i):
        return f"IMU log {path}, data row {i + 1}"

    def number(i, k):
        try:
            return float(table[i][k])
        except (ValueError, IndexError):
            raise ValueError(f"{line(i)}, column {header[k]}: {table[i][k] if k < len(table[i]) else ''!r} is not "
                             "a number") from None

    time_column = header.index(TIME)
    out = {}
    for unit, signals in units.items():
        columns = [k for cols in signals.values() for k, _ in cols]
        filled = [[k < len(row) and row[k].strip() != "" for k in columns] for row in table]
        rows_of = [i for i, f in enumerate(filled) if any(f)]
        for i in rows_of:
            if not all(filled[i]):
                empty = [header[k] for k, f in zip(columns, filled[i]) if not f]
                raise ValueError(f"{line(i)}: {unit} has some cells filled and {', '.join(empty)} empty (a unit's "
                                 "cells are all filled where it has a sample)")
        if len(rows_of) < 2:
            raise ValueError(f"IMU log {path}: {unit} has {len(rows_of)} sample(s); its rate needs two or more")
        time = np.array([number(i, time_column) for i in rows_of])
        bad = np.flatnonzero(np.diff(time) <= 0.0)
        if len(bad) or time[0] < 0.0 or not np.all(np.isfinite(time)):
            i = rows_of[bad[0] + 1] if len(bad) else rows_of[0]
            raise ValueError(f"{line(i)}: {unit}'s {TIME} {table[i][time_column]} is not after its previous sample's "
                             "and at or after 0 s (each unit's stamps increase)")
        data = {"time": time}
        for signal, cols in signals.items():
            values = np.array([[number(i, k) * scale for k, scale in cols] for i in rows_of])
            data[signal] = values if SIGNALS[signal][1] else values[:, 0]
        out[unit] = data
    return out


def samples_of(log, running="forward", height_m=AIR_SPRING_HEIGHT):
    """The log's readings as `sensors.measure.SensorStream.process` gives them ({unit: {"time", "acceleration",
    "angular_rate" | "deflection", "pressure" | "speed"}}), the units named and the axes turned for the
    direction of running; the air springs' deflection is `height_m` (their nominal height, m) less the height."""
    if running not in RUNNING:
        raise ValueError(f"running {running!r} is not one of {', '.join(RUNNING)}")
    turn = np.array([1.0, 1.0, 1.0]) if running == "forward" else np.array([-1.0, -1.0, 1.0])
    out = {}
    for unit, data in log.items():
        if unit in MOUNTS:
            out[running_name(unit, running)] = dict(
                time=data["time"], acceleration=data["acc"] * turn,
                **({"angular_rate": data["gyro"] * turn} if "gyro" in data else {}))
        elif unit == ODOMETER:
            if np.any(data["speed"] < 0.0):
                raise ValueError("odometer speed: a reading below 0; the column is the forward speed in the "
                                 "direction of running (--running says which end led)")
            out[ODOMETER] = dict(time=data["time"], speed=data["speed"])
    springs = [u for u in AIR_SPRINGS if u in log]
    if springs:
        stamps = [log[u]["time"] for u in springs]
        if any(not np.array_equal(stamps[0], s) for s in stamps[1:]):
            raise ValueError("the four air springs' rows differ: their heights and pressures are one sample of an "
                             "instant, on the same rows")
        order = [springs.index(running_name(u, running)) for u in AIR_SPRINGS]
        out["air_springs"] = dict(time=stamps[0],
                                  deflection=np.stack([height_m - log[springs[j]]["height"] for j in order], axis=1),
                                  pressure=np.stack([log[springs[j]]["pressure"] for j in order], axis=1))
    return out


def sensor_set(samples, height_m=AIR_SPRING_HEIGHT):
    """The sensors.sensor_set.SensorSet of a log's samples (`samples_of`): its mounts (a gyro where it has
    one; the shipped instruments' models, which the monitor does not read), the air springs and the odometer,
    each at the inverse of its stamps' median spacing, latency 0 (the stamps are the instants)."""
    from railderail_sim.sensors.config import shipped_accelerometer
    from railderail_sim.sensors.instruments import INSTRUMENTS
    from railderail_sim.sensors.sensor_set import AirSpringSensors, Mount, Odometer, Sampling, SensorSet

    def sampling(unit):
        return Sampling(sample_rate_hz=round(1.0 / float(np.median(np.diff(samples[unit]["time"]))), 6), latency_s=0.0)

    mounts = tuple(Mount(name=name, accelerometer=shipped_accelerometer(name), sampling=sampling(name),
                         gyro=INSTRUMENTS["adis16470"] if "angular_rate" in samples[name] else None)
                   for name in MOUNTS if name in samples)
    springs = None if "air_springs" not in samples else AirSpringSensors(
        deflection=INSTRUMENTS["air_spring_height"], pressure=INSTRUMENTS["air_spring_pressure"],
        sampling=sampling("air_springs"), height_m=height_m)
    odometer = None if ODOMETER not in samples else Odometer(sampling=sampling(ODOMETER))
    return SensorSet(mounts=mounts, air_springs=springs, odometer=odometer)


def gaps(samples, sensors):
    """{unit: number of stamps more than 1.5 periods after the previous}: samples the logger lost."""
    from ..onboard.measured import sample_rates
    rates = sample_rates(sensors)
    return {unit: int(np.sum(np.diff(data["time"]) * rates[unit] > 1.5)) for unit, data in samples.items()}


def write_recording(samples, sensors, out, source):
    """Write `out`, an MCAP of the samples' sensor messages in stamp order (atomically), as the recorder
    writes the simulator's; the number of messages."""
    from rclpy.serialization import serialize_message

    from railderail_sim.atomic import atomic_write
    from railderail_sim.ros.interface import SENSOR

    from .recorder import McapRecording

    messages = sm.SensorConverter(sensors).messages(samples)
    with atomic_write(out, "wb") as stream:
        with McapRecording(out, metadata={"source": f"railderail import-imu {source}"}, stream=stream) as rec:
            for topic, (type_name, *_) in sm.sensor_topics(sensors).items():
                rec.add_topic(topic, type_name, SENSOR)
            for _, topic, message in messages:
                rec.write(topic, serialize_message(message))
    return len(messages)


def csv_text(signals, comment=""):
    """The CSV of `sensor_<unit>_<signal>` arrays (`railderail simulate --sensors --out`) as a logger writes
    it, in SI, running forward: stamps to the microsecond, readings to 7 significant digits (a 20-bit
    converter's resolution is 6); `comment` its first lines. The shipped example is one (EXAMPLE)."""
    units = [u for u in MOUNTS if f"sensor_{u}_time" in signals]
    columns = []            # (name, unit's time key, values (n,))
    for u in units:
        for signal, key, measure in (("acc", "acceleration", "m_s2"), ("gyro", "angular_rate", "rad_s")):
            if f"sensor_{u}_{key}" in signals:
                columns += [(f"{u}_{signal}_{a}_{measure}", u, signals[f"sensor_{u}_{key}"][:, j])
                            for j, a in enumerate("xyz")]
    if "sensor_air_springs_time" in signals:
        for j, spring in enumerate(AIR_SPRINGS):
            columns += [(f"{spring}_height_m", "air_springs", AIR_SPRING_HEIGHT - signals["sensor_air_springs_deflection"][:, j]),
                        (f"{spring}_pressure_pa", "air_springs", signals["sensor_air_springs_pressure"][:, j])]
    if "sensor_odometer_time" in signals:
        columns.append(("odometer_speed_m_s", ODOMETER, signals["sensor_odometer_speed"]))
    times = {u: np.asarray(signals[f"sensor_{u}_time"]) for u in {c[1] for c in columns}}
    stamps = np.unique(np.concatenate(list(times.values())))
    where = {u: dict(zip(t.tolist(), range(len(t)))) for u, t in times.items()}
    lines = [f"# {text}" for text in comment.splitlines()] + [",".join([TIME] + [c[0] for c in columns])]
    for t in stamps.tolist():
        cells = [f"{t:.6f}"]
        for _, unit, values in columns:
            k = where[unit].get(t)
            cells.append("" if k is None else f"{values[k]:.7g}")
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def command(parser):
    parser.add_argument("log", metavar="LOG.csv", nargs="?", help="the logger's readings (columns: docs/onboard.md, "
                        "'Your own IMU log', or `railderail import-imu --columns`)")
    parser.add_argument("out", metavar="OUT.mcap", nargs="?", help="the recording to write (atomically)")
    parser.add_argument("--running", choices=RUNNING, default="forward",
                        help="forward: the log's front end led (its names are the monitor's); reversed: its rear "
                        "end led (front and rear, left and right swapped, x and y turned)")
    parser.add_argument("--air-spring-height-m", type=float, default=AIR_SPRING_HEIGHT,
                        help="the air springs' nominal height (m) from which their compression counts "
                        f"(default %(default)s, the shipped car's)")
    parser.add_argument("--sensors-out", metavar="FILE.yaml", help="the sensor file of the log (default OUT with "
                        ".sensors.yaml for .mcap)")
    parser.add_argument("--columns", action="store_true", help="print the accepted columns and stop")

    def run(args):
        from railderail_sim.atomic import atomic_write
        from railderail_sim.ranges import check_range
        from railderail_sim.sensors.config import file_text

        from ..onboard.measured import left_out, sample_rates

        if args.columns:
            print(column_forms())
            return 0
        if not args.log:
            raise ValueError("LOG.csv: give the logger's CSV to import (its columns: railderail import-imu --columns)")
        if not args.out or not args.out.endswith(".mcap"):
            raise ValueError(f"OUT {args.out!r}: give the recording to write, a file name ending in .mcap")
        check_range("--air-spring-height-m", args.air_spring_height_m, 0.0, 2.0, "m", lo_open=True)
        samples = samples_of(read_log(args.log), args.running, args.air_spring_height_m)
        sensors = sensor_set(samples, args.air_spring_height_m)
        sensors_out = args.sensors_out or args.out[:-len(".mcap")] + ".sensors.yaml"
        count = write_recording(samples, sensors, args.out, args.log)
        with atomic_write(sensors_out) as f:
            f.write(f"# the sensor set of {args.log} (railderail import-imu, running {args.running}): its mounts, "
                    "rates and air-spring height;\n# the instruments are the shipped models, which the monitor "
                    "does not read\n" + file_text(sensors))
        rates = ", ".join(f"{u} {r:g} Hz" for u, r in sample_rates(sensors).items())
        lost = {u: n for u, n in gaps(samples, sensors).items() if n}
        print(f"wrote {args.out} ({count} messages; {rates})" + (
            "; gaps (lost samples?): " + ", ".join(f"{u} {n}" for u, n in lost.items()) if lost else ""), file=sys.stderr)
        missing = left_out(set(samples))[1]
        if missing:
            print(f"the monitor will run without some criteria: {missing}", file=sys.stderr)
        print(f"wrote {sensors_out}\nreplay: railderail replay {args.out} --signals measured --sensors {sensors_out} "
              "--no-publish", file=sys.stderr)
        return 0
    return run
