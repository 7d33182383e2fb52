"""The sensor set's YAML file (`sensor_set` holds the set itself): read (`load`, `from_dict`, with one-line errors
naming a bad key or value), the shipped set (`default_set`; railderail_sim/config/sensors.yaml is it written
out by `file_text`), the same with the realistic sensing errors on (`realistic_set`: scale-factor errors and
mounting misalignment; config/sensors-realistic.yaml) and the recording's metadata of a set (`metadata`)."""
from dataclasses import replace
import math
from pathlib import Path

import yaml

from .instruments import INSTRUMENT_FIELDS, INSTRUMENTS, REALISTIC, value_source, with_changes
from .sensor_set import (AIR_SPRINGS, MOUNTING_MISALIGNMENT, MOUNTS, AirSpringSensors, Mount, Odometer, Sampling,
                         SensorSet)

SHIPPED = Path(__file__).resolve().parents[1] / "config" / "sensors.yaml"
REALISTIC_FILE = SHIPPED.with_name("sensors-realistic.yaml")
TOP_KEYS = ("seed", "instruments", "mounts", "air_springs", "odometer")
SAMPLING_KEYS = ("sample_rate_hz", "latency_s", "dropout")


def _keys(where, given, accepted):
    if not isinstance(given, dict):
        raise ValueError(f"{where} must be a mapping of {', '.join(accepted)}, not {given!r}")
    unknown = sorted(set(given) - set(accepted))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {', '.join(map(str, unknown))}; the keys are {', '.join(accepted)}")


def _sampling(where, d):
    try:
        return Sampling(**{k: float(d[k]) for k in SAMPLING_KEYS if k in d})
    except TypeError:
        raise ValueError(f"{where} needs sample_rate_hz (Hz)") from None


def _instrument(instruments, where, name, quantity):
    if name not in instruments:
        raise ValueError(f"{where}: instrument {name!r} is unknown; the instruments are {', '.join(instruments)}")
    inst = instruments[name]
    if inst.quantity != quantity:
        raise ValueError(f"{where}: instrument {name!r} measures {inst.quantity}, not {quantity}")
    return inst


def from_dict(d):
    """A SensorSet from the file's mapping (ValueError naming a bad key or value)."""
    _keys("sensor file", d, TOP_KEYS)
    instruments = dict(INSTRUMENTS)
    for name, changes in (d.get("instruments") or {}).items():
        changes = dict(changes or {})
        base = changes.pop("like", name)
        if base not in instruments:
            raise ValueError(f"instrument {name!r}: no instrument {base!r} to start from; the instruments are "
                             f"{', '.join(instruments)} (a new one says `like: NAME`)")
        instruments[name] = with_changes(replace(instruments[base], name=name), changes)
    mounts = []
    for name, m in (d.get("mounts") or {}).items():
        if name not in MOUNTS:
            raise ValueError(f"mount {name!r} is unknown; the mounts are {', '.join(MOUNTS)}")
        m = m or {}
        _keys(f"mount {name}", m, ("accelerometer", "gyro", "offset_m", "misalignment_rad") + SAMPLING_KEYS)
        offset = tuple(float(v) for v in m.get("offset_m", (0.0, 0.0, 0.0)))
        if len(offset) != 3 or not all(abs(v) <= 5.0 for v in offset):
            raise ValueError(f"mount {name} offset_m {list(offset)} must be three numbers within [-5, 5] m")
        gyro = m.get("gyro")
        mounts.append(Mount(name=name, accelerometer=_instrument(instruments, f"mount {name}",
                                                                 m.get("accelerometer"), "acceleration"),
                            gyro=None if gyro in (None, "none") else _instrument(instruments, f"mount {name}", gyro,
                                                                                 "angular_rate"),
                            sampling=_sampling(f"mount {name}", m), offset=offset,
                            misalignment_rad=float(m.get("misalignment_rad", 0.0))))
    springs = d.get("air_springs")
    if springs is not None:
        _keys("air_springs", springs, ("deflection", "pressure", "effective_area_m2", "height_m") + SAMPLING_KEYS)
        springs = AirSpringSensors(
            deflection=_instrument(instruments, "air_springs", springs.get("deflection"), "deflection"),
            pressure=_instrument(instruments, "air_springs", springs.get("pressure"), "pressure"),
            sampling=_sampling("air_springs", springs),
            **{k: float(springs[k]) for k in ("effective_area_m2", "height_m") if k in springs})
    odometer = d.get("odometer")
    if odometer is not None:
        _keys("odometer", odometer, ("pulses_per_revolution", "radius_error") + SAMPLING_KEYS)
        odometer = Odometer(sampling=_sampling("odometer", odometer),
                            **{k: (int if k == "pulses_per_revolution" else float)(odometer[k])
                               for k in ("pulses_per_revolution", "radius_error") if k in odometer})
    return SensorSet(seed=int(d.get("seed", 0)), mounts=tuple(mounts), air_springs=springs, odometer=odometer,
                     instruments=instruments)


def load(path=None, output_rate=None):
    """The sensor set of a YAML file (None: the shipped one), checked against the simulator's output rate
    (Hz) when given."""
    path = Path(path) if path is not None else SHIPPED
    try:
        data = yaml.safe_load(path.read_text())
    except OSError as error:
        raise ValueError(f"sensor file {str(path)!r} cannot be read: {error.strerror}") from None
    except yaml.YAMLError as error:
        raise ValueError(f"sensor file {str(path)!r} is not YAML: {str(error).splitlines()[0]}") from None
    sensors = from_dict(data or {})
    return sensors if output_rate is None else sensors.validated(output_rate)


def shipped_accelerometer(mount):
    """The shipped set's accelerometer at a mount: ADXL355 on the car body, ADXL357 on the bogie frames, IEPE
    on the axle boxes."""
    return INSTRUMENTS[{"car": "adxl355", "bog": "adxl357", "axl": "iepe_axle_box"}[mount[:3]]]


def default_set():
    """The shipped sensor set, built here (config/sensors.yaml is this written out by `file_text`): every
    mount at 200 Hz, MEMS accelerometers (ADXL355 on the car body, ADXL357 on the bogie frames) and IEPE ones
    on the axle boxes, a MEMS gyro at every mount but those over the wheelsets on the frames (a frame is one
    rigid body: its centre's gyro reads its rates); the air springs at 50 Hz; the odometer at 10 Hz."""
    mounts = tuple(Mount(name=name, accelerometer=shipped_accelerometer(name),
                         gyro=None if name.startswith("bogie_frame_") else INSTRUMENTS["adis16470"],
                         sampling=Sampling(200.0)) for name in MOUNTS)
    return SensorSet(seed=0, mounts=mounts,
                     air_springs=AirSpringSensors(deflection=INSTRUMENTS["air_spring_height"],
                                                  pressure=INSTRUMENTS["air_spring_pressure"], sampling=Sampling(50.0)),
                     odometer=Odometer(sampling=Sampling(10.0)))


def realistic_set():
    """The shipped set with the realistic sensing errors on (config/sensors-realistic.yaml is it written out):
    every instrument's scale-factor error of instruments.REALISTIC and every mount misaligned by
    sensor_set.MOUNTING_MISALIGNMENT (1-sigma about each axis), drawn from the same seed."""
    shipped = default_set()
    instruments = {name: replace(inst, **{k: v[0] for k, v in REALISTIC.get(name, {}).items()})
                   for name, inst in shipped.instruments.items()}
    mounts = tuple(replace(m, accelerometer=instruments[m.accelerometer.name], misalignment_rad=MOUNTING_MISALIGNMENT,
                           gyro=None if m.gyro is None else instruments[m.gyro.name]) for m in shipped.mounts)
    return replace(shipped, mounts=mounts, instruments=instruments)


def metadata(sensors: SensorSet, source):
    """What an output file's metadata says of its sensor set (docs/output-format.md)."""
    return dict(file=str(source), seed=sensors.seed, mounts=[m.name for m in sensors.mounts],
                gyros=[m.name for m in sensors.mounts if m.gyro is not None],
                air_springs=list(AIR_SPRINGS) if sensors.air_springs is not None else [],
                odometer=sensors.odometer is not None)


def _value(v):
    if isinstance(v, float) and math.isinf(v):
        return ".inf" if v > 0 else "-.inf"
    return repr(v) if isinstance(v, float) else str(v)


def _sampling_text(s: Sampling):
    return f"sample_rate_hz: {_value(s.sample_rate_hz)}, latency_s: {_value(s.latency_s)}, dropout: {_value(s.dropout)}"


def file_text(sensors: SensorSet):
    """The YAML text of a sensor set, every instrument value under a comment with its unit and source."""
    lines = ["# railderail sensor set: `railderail simulate --sensors FILE`, the simulator node's parameter `sensors`.",
             "# The shipped files are railderail_sim/config/sensors.yaml and sensors-realistic.yaml (the same with",
             "# scale-factor errors and mounting misalignment), written by sensors.config.file_text from",
             "# sensors.config.default_set() and realistic_set(); copy one and change what you need (docs/onboard.md).",
             "# seed: the noise, biases and lost samples; the same seed gives the same signals, bit for bit.",
             f"seed: {sensors.seed}",
             "# instruments: the sensor models (sensors/instruments.py). A changed value is a field here; a new",
             "# instrument starts from another one with `like: NAME`.",
             "instruments:"]
    for inst in sensors.instruments.values():
        lines.append(f"  {inst.name}:   # {inst.quantity}, {inst.unit}")
        for name in INSTRUMENT_FIELDS:
            source, sure, note = value_source(inst.name, name, getattr(inst, name))
            lines.append(f"    {name}: {_value(getattr(inst, name))}   # {source} ({sure})" + (f": {note}" if note else ""))
    lines += ["# mounts (sensors/config.py MOUNTS): an accelerometer and a gyro (or none), each reading in the body's",
              "# axes, x forward, y left, z up; the sample rate must divide the simulator's output rate.",
              "# misalignment_rad: 1-sigma of the unit's rotation about each body axis, drawn from the seed (0 if not given)"
              + ("; here sensor_set.MOUNTING_MISALIGNMENT (A): an unmeasured bracket, half a degree"
                 if any(m.misalignment_rad == MOUNTING_MISALIGNMENT for m in sensors.mounts) else ""),
              "mounts:"]
    for m in sensors.mounts:
        gyro = "none" if m.gyro is None else m.gyro.name
        offset = "" if m.offset == (0.0, 0.0, 0.0) else f", offset_m: [{', '.join(map(_value, m.offset))}]"
        offset += "" if m.misalignment_rad == 0.0 else f", misalignment_rad: {_value(m.misalignment_rad)}"
        lines.append(f"  {m.name}: {{accelerometer: {m.accelerometer.name}, gyro: {gyro}, {_sampling_text(m.sampling)}"
                     f"{offset}}}")
    if sensors.air_springs is not None:
        a = sensors.air_springs
        lines += ["# air springs: deflection (compression +, m) and the pressure proxy (the spring's elastic force over",
                  "# its effective area, Pa gauge) of each of the four",
                  f"air_springs: {{deflection: {a.deflection.name}, pressure: {a.pressure.name}, "
                  f"effective_area_m2: {_value(a.effective_area_m2)}, height_m: {_value(a.height_m)}, "
                  f"{_sampling_text(a.sampling)}}}"]
    if sensors.odometer is not None:
        o = sensors.odometer
        lines += ["# odometer: forward speed from an axle-end pulse generator on wheelset 0",
                  f"odometer: {{pulses_per_revolution: {o.pulses_per_revolution}, radius_error: "
                  f"{_value(o.radius_error)}, {_sampling_text(o.sampling)}}}"]
    return "\n".join(lines) + "\n"
