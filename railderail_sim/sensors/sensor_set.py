"""The sensor set: which mounts carry which instruments (instruments.py) at what sample rate, latency and
loss of samples; the air springs' height and pressure sensors; the odometer; the seed of the noise. Its YAML
file is read and written by `config` (the shipped one: railderail_sim/config/sensors.yaml).

Mounts (`MOUNTS`), each a point of a body, x forward, y left, z up from the body's reference point:
car_body_front, car_body_centre, car_body_rear on the car-body floor above each bogie centre and at the
middle; bogie_front_frame, bogie_rear_frame at each frame's centre; bogie_frame_<wheelset> on the frame
above that wheelset's left axle box (where EN 14363 and the on-board instability detectors read the frame:
over each wheelset, the frame's yaw adding to its centre's lateral acceleration); axle_box_<wheelset>_<left|right> on
each axle box (at the primary spring, on the axle's height; it turns with the wheelset's roll and yaw,
not with its spin). Each mount holds a three-axis accelerometer and, optionally, a three-axis gyro in the
body's axes, or in axes turned from them by the mount's misalignment (`Mount.misalignment_rad`).
"""
from dataclasses import dataclass, field, replace
import math

import numpy as np

from ..parameters import VehicleParameters
from ..ranges import check_range
from ..vehicle.layout import N_WHEELSET, RUNNING_GEARS, Body
from .instruments import INSTRUMENTS, Instrument

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
# rad: 1-sigma of a mount's rotation about each of the body's axes, realistic_set's: a sensor bracket bolted
# to the car-body floor or the bogie frame with no alignment measured after fitting, half a degree. A (no
# source read; 1 degree of roll reads 0.17 m/s^2 of gravity as lateral acceleration, issue 42)
MOUNTING_MISALIGNMENT = 0.5 * math.pi / 180.0


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


def misaligned_axes(roll, pitch, yaw):
    """(3, 3): the rows are a unit's sensing axes in its body's axes, the unit turned by yaw about z, then
    pitch about y, then roll about x (rad): its readings are this times the body-axes vector."""
    cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    turn = ((cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
            (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
            (-sp, cp * sr, cp * cr))
    return tuple(tuple(turn[j][i] for j in range(3)) for i in range(3))      # the transpose: body -> unit


def reading_covariance(variance, scale_factor_error, misalignment_rad, readings):
    """(n, 9): the covariance (3 x 3, row by row) about the truth of each of n three-axis readings (n, 3):
    `variance` on each axis (the noise model's) plus the scale-factor error's (1-sigma times the reading, per
    axis) and the misalignment's (a small turn theta, 1-sigma about each axis, moves a reading a by theta x a:
    sigma^2 (|a|^2 I - a a^T)); the reading taken for the truth."""
    a = np.asarray(readings, dtype=float)
    eye = np.eye(3)
    outer = a[:, :, None] * a[:, None, :]
    cov = (variance * eye + scale_factor_error ** 2 * outer * eye
           + misalignment_rad ** 2 * (np.sum(a * a, axis=1)[:, None, None] * eye - outer))
    return cov.reshape(len(a), 9)


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
    # rad, 1-sigma of the unit's rotation about each body axis (roll, pitch, yaw), drawn once from the seed:
    # its accelerometer and gyro read in the turned axes; 0: aligned with the body
    misalignment_rad: float = 0.0


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
            check_range(f"mount {mount.name} misalignment_rad", mount.misalignment_rad, 0.0, 0.2, "rad")
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
        """The same set with every instrument free of noise, bias and scale-factor error, every mount aligned
        (an ideal sensor but for its filters, range and resolution) and no samples lost."""
        calm = {name: replace(inst, noise_density=0.0, bias=0.0, bias_random_walk=0.0, scale_factor_error=0.0)
                for name, inst in self.instruments.items()}
        sampling = lambda s: replace(s, dropout=0.0)
        mounts = tuple(replace(m, accelerometer=calm[m.accelerometer.name], sampling=sampling(m.sampling),
                               gyro=None if m.gyro is None else calm[m.gyro.name], misalignment_rad=0.0)
                       for m in self.mounts)
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
