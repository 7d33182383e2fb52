"""The sensor set: which mounts carry which instruments (instruments.py) at what sample rate, latency and
loss of samples; the air springs' height and pressure sensors; the odometer; the seed of the noise. Read
from and written to a YAML file (the shipped one: railderail_sim/config/sensors.yaml, `default_set()`).

Mounts (`MOUNTS`), each a point of a body, x forward, y left, z up from the body's reference point:
car_body_front, car_body_centre, car_body_rear on the car-body floor above each bogie centre and at the
middle; bogie_front_frame, bogie_rear_frame at each frame's centre; bogie_frame_<wheelset> on the frame
above that wheelset's left axle box (where EN 14363 and the on-board instability detectors read the frame:
over each wheelset, the frame's yaw adding to its centre's lateral acceleration); axle_box_<wheelset>_<left|right> on
each axle box (at the primary spring, on the axle's height; it turns with the wheelset's roll and yaw,
not with its spin). Each mount holds a three-axis accelerometer and, optionally, a three-axis gyro in the
body's axes.
"""
from dataclasses import dataclass, field, fields, replace
import math
from pathlib import Path

import yaml

from ..parameters import VehicleParameters
from ..ranges import check_range
from ..vehicle.layout import N_WHEELSET, RUNNING_GEARS, Body
from .instruments import INSTRUMENT_FIELDS, INSTRUMENT_SOURCES, INSTRUMENTS, Instrument, with_changes

SHIPPED = Path(__file__).resolve().parents[1] / "config" / "sensors.yaml"
SIDES = ("left", "right")
MOUNTS = (("car_body_front", "car_body_centre", "car_body_rear", "bogie_front_frame", "bogie_rear_frame")
          + tuple(f"bogie_frame_{w}" for w in range(N_WHEELSET))
          + tuple(f"axle_box_{w}_{side}" for w in range(N_WHEELSET) for side in SIDES))
AIR_SPRINGS = tuple(f"air_spring_{bogie}_{side}" for bogie in ("front", "rear") for side in SIDES)
ODOMETER = "odometer"
SEED_RANGE = (0, 2 ** 32 - 1)

# m: the car-body floor above the rail top, where the car-body sensors sit. A (no source read: a Velaro-class
# car's floor is about 1.26 m above the rail)
CAR_BODY_FLOOR_HEIGHT = 1.26
# m^2: effective area of an air spring, force over gauge pressure. A (a bellows of 0.46 m effective diameter,
# typical of high-speed bogies; gives 0.47 MPa under a quarter of the car body, inside the transducer's 1 MPa)
AIR_SPRING_EFFECTIVE_AREA = math.pi * 0.23 ** 2
# m: height of the air spring between its plates at its nominal deflection (A380 parameter file's bottom
# 0.80 m and top 1.00 m above the rail, S): the height sensor reads this less the deflection
AIR_SPRING_HEIGHT = 0.20


def mount_point(name, vp: VehicleParameters):
    """(layout.Body, point in its axes from its reference point, m) of a mount."""
    car_floor = CAR_BODY_FLOOR_HEIGHT - vp.car_body_cog_height
    if name.startswith("car_body_"):
        x = {"front": vp.bogie_semi_distance, "centre": 0.0, "rear": -vp.bogie_semi_distance}[name[len("car_body_"):]]
        return Body.car_body, (x, 0.0, car_floor)
    if name in ("bogie_front_frame", "bogie_rear_frame"):
        return Body[name.replace("_frame", "").replace("bogie_", "") + "_bogie"], (0.0, 0.0, 0.0)
    if name.startswith("bogie_frame_"):
        wheelset = int(name[len("bogie_frame_"):])
        gear = next(g for g, ws in enumerate(RUNNING_GEARS) if wheelset in ws)
        leading = wheelset == RUNNING_GEARS[gear][0]
        return (Body.front_bogie if gear == 0 else Body.rear_bogie,
                (vp.wheelbase_semi if leading else -vp.wheelbase_semi, vp.primary_semi_spacing, 0.0))
    _, _, wheelset, side = name.split("_")
    return Body[f"wheelset_{wheelset}"], (0.0, vp.primary_semi_spacing * (1.0 if side == "left" else -1.0), 0.0)


@dataclass(frozen=True)
class Sampling:
    """How a sensor's samples reach the logger: its rate, its latency (the time stamp is the physical
    instant plus this), the chance of losing each sample."""
    sample_rate_hz: float
    latency_s: float = 0.002        # A: a sensor bus and a logger's time stamp, a few milliseconds
    dropout: float = 0.0            # A: none by default; a bus under load loses 1e-4 to 1e-2

    def validated(self, where, output_rate):
        try:
            check_range(f"{where} sample_rate_hz", self.sample_rate_hz, 0.0, output_rate, "Hz", lo_open=True)
        except ValueError as error:
            raise ValueError(f"{error} (the top is the simulator's output rate)") from None
        ratio = output_rate / self.sample_rate_hz
        if abs(ratio - round(ratio)) > 1e-9 * ratio:
            raise ValueError(f"{where} sample_rate_hz {self.sample_rate_hz:g} Hz does not divide the simulator's "
                             f"output rate {output_rate:g} Hz: the accepted rates are {output_rate:g} Hz divided by "
                             "a whole number")
        check_range(f"{where} latency_s", self.latency_s, 0.0, 1.0, "s")
        check_range(f"{where} dropout", self.dropout, 0.0, 1.0, hi_open=True)
        return self

    def decimation(self, output_rate):
        """The output rows per sample."""
        return int(round(output_rate / self.sample_rate_hz))


@dataclass(frozen=True)
class Mount:
    """An inertial measuring unit at a mount."""
    name: str
    accelerometer: Instrument
    gyro: Instrument | None
    sampling: Sampling
    offset: tuple = (0.0, 0.0, 0.0)     # m, from the mount's nominal point, in the body's axes


@dataclass(frozen=True)
class AirSpringSensors:
    """A height (deflection) and a pressure sensor at each air spring. The pressure is a proxy: the
    spring's elastic force over its effective area, the gauge pressure of a bellows of constant area."""
    deflection: Instrument
    pressure: Instrument
    sampling: Sampling
    effective_area_m2: float = AIR_SPRING_EFFECTIVE_AREA
    height_m: float = AIR_SPRING_HEIGHT


@dataclass(frozen=True)
class Odometer:
    """An axle-end pulse generator on wheelset 0: the speed from the pulses counted in each sample period,
    each pulse taken as 2 pi r0 / pulses_per_revolution of the nominal rolling radius r0, while the wheel
    really rolls on r0 (1 + e), e drawn once from the seed (1-sigma radius_error: wear not calibrated out)."""
    sampling: Sampling
    pulses_per_revolution: int = 200    # C: tens to about 200 pulses per revolution (reference sheet 1.1)
    radius_error: float = 0.005         # A: 0.5 % of the rolling radius after calibration


@dataclass(frozen=True)
class SensorSet:
    seed: int = 0
    mounts: tuple = ()
    air_springs: AirSpringSensors | None = None
    odometer: Odometer | None = None
    instruments: dict = field(default_factory=lambda: dict(INSTRUMENTS))   # by name, as the file gives them

    def validated(self, output_rate):
        """self if every rate fits the simulator's output rate (Hz) and every value its range."""
        check_range("sensor seed", self.seed, *SEED_RANGE)
        for inst in self.instruments.values():
            inst.validated()
        for mount in self.mounts:
            mount.sampling.validated(f"mount {mount.name}", output_rate)
        if self.air_springs is not None:
            self.air_springs.sampling.validated("air_springs", output_rate)
            check_range("air_springs effective_area_m2", self.air_springs.effective_area_m2, 0.0, 10.0, "m^2",
                        lo_open=True)
        if self.odometer is not None:
            self.odometer.sampling.validated("odometer", output_rate)
            check_range("odometer pulses_per_revolution", self.odometer.pulses_per_revolution, 1, 100000)
            check_range("odometer radius_error", self.odometer.radius_error, 0.0, 0.1)
        return self

    def quiet(self):
        """The same set with every instrument free of noise and bias (an ideal sensor but for its filters,
        range and resolution) and no samples lost."""
        calm = {name: replace(inst, noise_density=0.0, bias=0.0, bias_random_walk=0.0)
                for name, inst in self.instruments.items()}
        sampling = lambda s: replace(s, dropout=0.0)
        mounts = tuple(replace(m, accelerometer=calm[m.accelerometer.name], sampling=sampling(m.sampling),
                               gyro=None if m.gyro is None else calm[m.gyro.name]) for m in self.mounts)
        springs = None if self.air_springs is None else replace(
            self.air_springs, deflection=calm[self.air_springs.deflection.name],
            pressure=calm[self.air_springs.pressure.name], sampling=sampling(self.air_springs.sampling))
        odometer = None if self.odometer is None else replace(self.odometer, radius_error=0.0,
                                                              sampling=sampling(self.odometer.sampling))
        return replace(self, mounts=mounts, air_springs=springs, odometer=odometer, instruments=calm)

    def scaled(self, noise=1.0, bias=1.0):
        """The same set with every instrument's white noise density times `noise`, its constant bias and the
        bias's random walk times `bias`, the odometer's radius error times `bias` (a sensitivity study over
        the same run: `measure.run_signals`)."""
        check_range("noise scale", noise, 0.0, 1.0e4)
        check_range("bias scale", bias, 0.0, 1.0e4)
        changed = {name: replace(inst, noise_density=noise * inst.noise_density, bias=bias * inst.bias,
                                 bias_random_walk=bias * inst.bias_random_walk)
                   for name, inst in self.instruments.items()}
        mounts = tuple(replace(m, accelerometer=changed[m.accelerometer.name],
                               gyro=None if m.gyro is None else changed[m.gyro.name]) for m in self.mounts)
        springs = None if self.air_springs is None else replace(
            self.air_springs, deflection=changed[self.air_springs.deflection.name],
            pressure=changed[self.air_springs.pressure.name])
        odometer = None if self.odometer is None else replace(self.odometer,
                                                              radius_error=bias * self.odometer.radius_error)
        return replace(self, mounts=mounts, air_springs=springs, odometer=odometer, instruments=changed)

    def resampled(self, rate_hz):
        """The same set with every mount sampled at rate_hz, the air springs and the odometer at the lower of
        their own rate and it (each instrument's anti-alias filter follows its rate)."""
        check_range("sample rate", rate_hz, 0.0, 1.0e5, "Hz", lo_open=True)
        at = lambda s: replace(s, sample_rate_hz=rate_hz)
        low = lambda s: replace(s, sample_rate_hz=min(s.sample_rate_hz, rate_hz))
        return replace(self, mounts=tuple(replace(m, sampling=at(m.sampling)) for m in self.mounts),
                       air_springs=None if self.air_springs is None else replace(
                           self.air_springs, sampling=low(self.air_springs.sampling)),
                       odometer=None if self.odometer is None else replace(self.odometer,
                                                                           sampling=low(self.odometer.sampling)))


# --- the file -------------------------------------------------------------------------------------

NOTES = {f.name: f.metadata for f in fields(Instrument) if f.metadata}
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
        _keys(f"mount {name}", m, ("accelerometer", "gyro", "offset_m") + SAMPLING_KEYS)
        offset = tuple(float(v) for v in m.get("offset_m", (0.0, 0.0, 0.0)))
        if len(offset) != 3 or not all(abs(v) <= 5.0 for v in offset):
            raise ValueError(f"mount {name} offset_m {list(offset)} must be three numbers within [-5, 5] m")
        gyro = m.get("gyro")
        mounts.append(Mount(name=name, accelerometer=_instrument(instruments, f"mount {name}",
                                                                 m.get("accelerometer"), "acceleration"),
                            gyro=None if gyro in (None, "none") else _instrument(instruments, f"mount {name}", gyro,
                                                                                 "angular_rate"),
                            sampling=_sampling(f"mount {name}", m), offset=offset))
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


def default_set():
    """The shipped sensor set, built here (config/sensors.yaml is this written out by `file_text`): every
    mount at 200 Hz, MEMS accelerometers (ADXL355 on the car body, ADXL357 on the bogie frames) and IEPE ones
    on the axle boxes, a MEMS gyro at every mount but those over the wheelsets on the frames (a frame is one
    rigid body: its centre's gyro reads its rates); the air springs at 50 Hz; the odometer at 10 Hz."""
    accelerometer = {"car": "adxl355", "bog": "adxl357", "axl": "iepe_axle_box"}
    mounts = tuple(Mount(name=name, accelerometer=INSTRUMENTS[accelerometer[name[:3]]],
                         gyro=None if name.startswith("bogie_frame_") else INSTRUMENTS["adis16470"],
                         sampling=Sampling(200.0)) for name in MOUNTS)
    return SensorSet(seed=0, mounts=mounts,
                     air_springs=AirSpringSensors(deflection=INSTRUMENTS["air_spring_height"],
                                                  pressure=INSTRUMENTS["air_spring_pressure"], sampling=Sampling(50.0)),
                     odometer=Odometer(sampling=Sampling(10.0)))


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
             "# The shipped file is railderail_sim/config/sensors.yaml, written by sensors.config.file_text from",
             "# sensors.config.default_set(); copy it and change what you need (docs/onboard.md).",
             "# seed: the noise, biases and lost samples; the same seed gives the same signals, bit for bit.",
             f"seed: {sensors.seed}",
             "# instruments: the sensor models (sensors/instruments.py). A changed value is a field here; a new",
             "# instrument starts from another one with `like: NAME`.",
             "instruments:"]
    for inst in sensors.instruments.values():
        lines.append(f"  {inst.name}:   # {inst.quantity}, {inst.unit}")
        sources = INSTRUMENT_SOURCES.get(inst.name, {})
        for name in INSTRUMENT_FIELDS:
            source, sure, note = sources.get(name, (NOTES[name]["source"], NOTES[name]["sure"], NOTES[name]["note"]))
            lines.append(f"    {name}: {_value(getattr(inst, name))}   # {source} ({sure})" + (f": {note}" if note else ""))
    lines += ["# mounts (sensors/config.py MOUNTS): an accelerometer and a gyro (or none), each reading in the body's",
              "# axes, x forward, y left, z up; the sample rate must divide the simulator's output rate.",
              "mounts:"]
    for m in sensors.mounts:
        gyro = "none" if m.gyro is None else m.gyro.name
        offset = "" if m.offset == (0.0, 0.0, 0.0) else f", offset_m: [{', '.join(map(_value, m.offset))}]"
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
