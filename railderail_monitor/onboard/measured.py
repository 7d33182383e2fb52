"""Every criterion on measured signals over whole records (`evaluate`), their levels and settings
(`MeasuredLimits`, the monitor's parameters in measured mode) and their alerts (`alerts`): the on-board
monitor's batch form, scored beside the ground-truth criteria (signals `measured`).

Input: the `sensor_<unit>_<signal>` arrays of a run (`sensors.measure.SensorLog.arrays()`, `railderail
simulate --sensors`, docs/output-format.md) or the same decoded from the sensor topics. Each criterion is
evaluated on its own time base, documented here as its `time`, and each of its channels (`places`) on its own
mount's samples, at the mount's sample rate (`sample_rates`: the monitor is configured with its sensors'
rates, as an acquisition unit is; a rate guessed from the stamps would differ between a whole record and a
stream). A channel's value on the criterion's time base is its last sample at or before each stamp (NaN
before its first): what a monitor knows at that instant.

| criterion                          | places (channels)             | time (the criterion's stamps)               |
| ---------------------------------- | ----------------------------- | ------------------------------------------- |
| `bogie_rms`, `bogie_peak`          | bogie_front_frame, _rear_frame| the two frame mounts' stamps, merged        |
| `bids_peak_count`, `_china`        | the same                      | the same                                    |
| `car_body_lateral`, `_qst`         | car_body_front, car_body_rear | the two floor mounts' stamps, merged        |
| `car_body_roll`                    | air_springs                   | the air springs' stamps                     |
| `car_body_roll_rate`               | car_body_centre (its gyro x)  | car_body_centre's stamps                    |
| `car_body_twist`                   | front_minus_rear (air_springs | car_body_centre's stamps from the first air |
|                                    | held, car_body_centre gyro x) | springs' sample                             |
| `estimated_running_gear_unloading` | bogie_<front/rear>_<left/right> | car_body_centre's stamps (estimator.estimate)|
| `estimated_side_ratio`             | the same                      | the same                                    |

The estimator's two criteria warn on its estimates at the ground-truth monitor's shipped WARNING levels of
the same quantities: `running_gear_unloading`, EN 14067-6's 0.90; the side ratio (the running gear's lateral
force over one side's load) at `derailment_coefficient`'s 0.8 times the side ratio per unit of the outer
leading wheel's Y/Q in steady curving (SIDE_RATIO_PER_WHEEL_Y_Q, 0.765): 0.61. The twist warns at three
standard deviations of what the height sensors' offsets make of it. Every level here is a WARNING: an
on-board unit's alarm, not a derailment limit.

Track position (the EN 14363 windows, the debounce and the re-arm are in metres): the odometer's distance,
each sample's speed integrated over the step to the next at the speed it reads (`criteria.Odometer`), so the
position is known at every instant from the samples before it alone (no interpolation to a later sample),
does not decrease, and lags the true distance by at most a sample period's change of speed times the period.

The hunting frequency f0 of EN 14363's band f0 +- 2 Hz: a monitor cannot take it from the spectrum of a
record it has not seen, so it is a design value, the parameter `hunting_frequency`, by default the rigid
bogie's kinematic frequency (`kinematic_bogie_frequency`) at the car's design speed with the shipped profile
pair's equivalent conicity. At 300 km/h that is 3.96 Hz (band 1.96-5.96 Hz); the simulated hunting with
failed yaw dampers at 250 km/h was at 4.25 Hz, without the fault 3.75 Hz (docs/onboard-criteria.md): inside.
"""
from __future__ import annotations

from dataclasses import MISSING, asdict, dataclass, field, fields
import math
import warnings

import numpy as np

from railderail_sim.assessment import en14363
from railderail_sim.parameters import VehicleParameters
from railderail_sim.ranges import check_range
from railderail_sim.sensors.config import default_set
from railderail_sim.sensors.instruments import INSTRUMENTS
from railderail_sim.sensors.sensor_set import AIR_SPRING_EFFECTIVE_AREA, ODOMETER

from ..warning.limits import Limits, SEVERITY_WARNING, SIDES, default_limits
from . import criteria as oc
from . import estimator as est

SIGNALS = "measured"
FRAMES = ("bogie_front_frame", "bogie_rear_frame")
FLOORS = ("car_body_front", "car_body_rear")
ROLL_GYRO = "car_body_centre"
AIR_SPRINGS = "air_springs"
GEAR_SIDES = tuple(f"bogie_{bogie}_{side}" for bogie in est.BOGIES for side in SIDES)
TWIST = "car_body_twist"
PLACES = {"bogie_rms": FRAMES, "bogie_peak": FRAMES, "bids_peak_count": FRAMES, "bids_peak_count_china": FRAMES,
          "car_body_lateral": FLOORS, "car_body_lateral_qst": FLOORS, "car_body_roll": (AIR_SPRINGS,),
          "car_body_roll_rate": (ROLL_GYRO,), "estimated_running_gear_unloading": GEAR_SIDES,
          "estimated_side_ratio": GEAR_SIDES, TWIST: ("front_minus_rear",)}
CRITERIA = tuple(PLACES)
# held over debounce_m of track before the alert; the others are windows or counts already
INSTANTANEOUS = ("bogie_peak", "car_body_lateral", "car_body_roll", "car_body_roll_rate",
                 "estimated_running_gear_unloading", "estimated_side_ratio")

# EN 15302 Annex B equivalent conicity of LM on UIC60 at 1:40 at 3 mm amplitude, computed by this project's
# contact geometry (docs/contact-report.md; the amplitude of UIC 518 / EN 14363's conicity, B)
EQUIVALENT_CONICITY = 0.1164
# m/s: the design speed of the f0 default: 300 km/h, the reference scenario's speed (vehicle.simulate.scenario,
# the high-speed car of Yu et al. 2022; A)
DESIGN_SPEED = 300.0 / 3.6
# the side ratio (a running gear's lateral force over one side's load) per unit of the outer leading wheel's
# Y/Q, the ratio at which the estimated side ratio is warned at the single wheel's level: the mean over the
# outer side of both bogies in steady curving of this model, smooth track, 5 s from 100 m into the curve
# (R 800 m 200 km/h, R 1000 m 220 km/h, R 1400 m 250 km/h with 175 mm cant, R 2000 m 300 km/h with 150 mm):
# 0.71-0.85, mean 0.765. At the catalogue's over-speed derailments (R 800-1400 m, erri-low, 10 runs) the 2 m
# means relate as 0.60-0.74 when the wheel's Y/Q peaks: the side ratio rises less than the flange's Q/P, so
# the level from steady curving is not the early one (C: one model's simulation, docs/onboard-criteria.md)
SIDE_RATIO_PER_WHEEL_Y_Q = 0.765


def kinematic_bogie_frequency(vehicle: VehicleParameters, conicity=EQUIVALENT_CONICITY, speed=DESIGN_SPEED):
    """The rigid bogie's kinematic (Klingel) hunting frequency (Hz): V / 2 pi sqrt(lambda b0 / (r0 (b0^2 + a^2))),
    two wheelsets held parallel at a semi-wheelbase a (Wickens, Fundamentals of Rail Vehicle Dynamics, 2003,
    C: recalled). The frequency of the simulated hunting lies between it and the free wheelset's."""
    check_range("equivalent conicity", conicity, 0.0, 1.0, lo_open=True)
    check_range("design speed", speed, 0.0, 200.0, "m/s", lo_open=True)
    b0, a, r0 = est.CONTACT_SEMI_DISTANCE, vehicle.wheelbase_semi, vehicle.rolling_radius
    return speed / (2.0 * math.pi) * math.sqrt(conicity * b0 / (r0 * (b0 * b0 + a * a)))


def bogie_mass(vehicle: VehicleParameters):
    """kg: a bogie with its wheelsets (frame and two wheelsets), the M_b of the instability limits."""
    return vehicle.bogie_frame_mass + 2.0 * vehicle.wheelset_mass


def _value(unit, meaning, source, sure, default=MISSING, accepted=(0.0, math.inf), lo_open=True, nan_disables=False):
    """A field of MeasuredLimits with what the node's parameters say about it (as warning.limits.Limits' fields)."""
    return field(default=default, metadata=dict(unit=unit, meaning=meaning, source=source, sure=sure,
                                                accepted=accepted, lo_open=lo_open, nan_disables=nan_disables))


def _level(unit, meaning, source, sure, default=MISSING, accepted=(0.0, math.inf)):
    return _value(unit, meaning, source, sure, default, accepted, nan_disables=True)


_GROUND = {f.name: f for f in fields(Limits)}


def _ground(name):
    """A setting of the ground-truth monitor taken over as it is (its default and metadata)."""
    f = _GROUND[name]
    return _value(f.metadata["unit"], f.metadata["meaning"], f.metadata["source"] + " (the ground-truth monitor's)",
                  "A", f.default, f.metadata["accepted"], f.metadata["lo_open"])


@dataclass(frozen=True)
class MeasuredLimits:
    """The level (WARNING; NaN disables it) and the settings of every criterion on measured signals; the
    field metadata (unit, meaning, source, sure: A read / B several secondary / C recalled, accepted range) is
    the table of the measured-mode monitor's parameters. The fields without a default depend on the car or on
    the ground-truth monitor's levels: take them from `measured_limits(vehicle)`."""
    bogie_rms: float = _level("m/s^2", "sliding r.m.s. of the bogie frame's lateral acceleration in f0 +- 2 Hz",
                              "EN 14363:2005 / UIC 518 simplified method: (12 - M_b/5)/2, M_b the bogie's mass in t",
                              "C")
    bogie_peak: float = _level("m/s^2", "bogie frame's lateral acceleration in f0 +- 2 Hz, magnitude",
                               "UIC 515 / UIC 518 / EN 14363:2005: 12 - M_b/5", "C")
    car_body_roll: float = _level("rad", "car body's roll to its bogie from the air-spring heights",
                                  "an air spring at its emergency spring: clearance / semi-spacing (parameters.py)",
                                  "A")
    car_body_roll_rate: float = _level("rad/s", "car body's roll rate (gyro x) in 0.4-10 Hz, magnitude",
                                       "car_body_roll x 2 pi x the car body's roll frequency (derived)", "A")
    hunting_frequency: float = _value("Hz", "design hunting frequency f0 of the band f0 +- 2 Hz",
                                      "the rigid bogie's kinematic frequency at 300 km/h, conicity 0.1164 "
                                      "(kinematic_bogie_frequency)", "C", accepted=(2.5, 20.0), lo_open=False)
    estimated_running_gear_unloading: float = _level(
        "", "estimated mean unloading ratio of a bogie's two wheels on one side (roll balance)",
        "the ground-truth monitor's running_gear_unloading WARNING level (EN 14067-6)", "B")
    estimated_side_ratio: float = _level(
        "", "estimated lateral force of a bogie toward one side's rail over that side's load",
        "the ground-truth monitor's derailment_coefficient WARNING level (EN 14363 (Y/Q)lim) times the side "
        "ratio per wheel Y/Q in steady curving, 0.765 (SIDE_RATIO_PER_WHEEL_Y_Q)", "C")
    car_body_twist: float = _level("rad", "trailing mean of the car body's roll to its front bogie minus that to its "
                                   "rear bogie (air-spring heights), gated off on cant ramps",
                                   "3 sigma of the four height sensors' offsets (criteria.twist_level, derived)", "A")
    bids_peak_count: float = _level("peaks", "consecutive half-wave peaks of the frame's band-passed lateral "
                                    "acceleration at or over bids_peak_limit within bids_window (7: more than 6)",
                                    "UIC 515-5 as stated in EP 2166333 A1 [0004]: more than (e.g.) 6", "A",
                                    float(oc.BIDS_PEAKS), (1.0, 1000.0))
    bids_window: float = _value("s", "time within which the BIDS rule's peaks count",
                                "EP 2166333 A1 [0004] (e.g. 500 ms)", "A", oc.BIDS_WINDOW_S, (0.0, 60.0))
    bids_peak_limit: float = _value("m/s^2", "peak level of the BIDS rule", "EP 2166333 A1 [0004]", "A",
                                    oc.BIDS_LIMIT, (0.0, 1000.0))
    bids_band_low: float = _value("Hz", "lower edge of the BIDS band-pass", "EP 2166333 A1 [0004]: about 4-8 Hz", "A",
                                  oc.BIDS_BAND_HZ[0], (0.0, 50.0))
    bids_band_high: float = _value("Hz", "upper edge of the BIDS band-pass", "EP 2166333 A1 [0004]", "A",
                                   oc.BIDS_BAND_HZ[1], (0.0, 50.0))
    bids_peak_count_china: float = _level("peaks", "consecutive peaks of the Chinese on-board rule",
                                          oc.CHINA_SOURCE, "C", float(oc.CHINA_PEAKS), (1.0, 1000.0))
    china_peak_limit: float = _value("m/s^2", "peak level of the Chinese rule (10 for power bogies)", oc.CHINA_SOURCE,
                                     "C", oc.CHINA_LIMIT, (0.0, 1000.0))
    china_band_low: float = _value("Hz", "lower edge of the Chinese rule's band-pass", oc.CHINA_SOURCE, "A",
                                   oc.CHINA_BAND_HZ[0], (0.0, 50.0))
    china_band_high: float = _value("Hz", "upper edge of the Chinese rule's band-pass", oc.CHINA_SOURCE, "A",
                                    oc.CHINA_BAND_HZ[1], (0.0, 50.0))
    car_body_lateral: float = _level("m/s^2", "car-body floor's lateral acceleration in 0.4-10 Hz (EN 14363 ydd*)",
                                     en14363.LIMITS["ydd_car_body"].source, en14363.LIMITS["ydd_car_body"].sure,
                                     en14363.LIMITS["ydd_car_body"].value)
    car_body_lateral_qst: float = _level("m/s^2", "mean of the floor's 20 Hz low-passed lateral acceleration over "
                                         "qst_window_m (EN 14363 ydd*_qst)", en14363.LIMITS["ydd_qst"].source,
                                         en14363.LIMITS["ydd_qst"].sure, en14363.LIMITS["ydd_qst"].value)
    rms_window_m: float = _value("m", "window of the frame's sliding r.m.s.", "EN 14363:2005 / UIC 518", "C",
                                 en14363.RMS_WINDOW_M, (1.0, 10000.0), False)
    window_step_m: float = _value("m", "step of the sliding windows (r.m.s. and ydd*_qst)", "EN 14363:2005", "C",
                                  en14363.RMS_STEP_M, (0.1, 1000.0), False)
    qst_window_m: float = _value("m", "window of the floor's quasi-static mean", "EN 14363: the shortest curve "
                                 "section, 100 m", "C", en14363.MIN_SECTION_M, (1.0, 10000.0), False)
    air_spring_effective_area: float = _value("m^2", "air spring's effective area: force over gauge pressure",
                                              "a 0.46 m bellows (sensors.sensor_set.AIR_SPRING_EFFECTIVE_AREA)", "A",
                                              AIR_SPRING_EFFECTIVE_AREA, (0.0, 10.0))
    axle_box_corner: float = _value("Hz", "corner of the axle-box accelerometers' AC coupling: the estimator's "
                                    "crossover from the frame's reading to theirs", "the IEPE sensor's lower -3 dB "
                                    "frequency (sensors.instruments)", "B", INSTRUMENTS["iepe_axle_box"].high_pass_hz,
                                    (0.0, 50.0))
    twist_window_m: float = _value("m", "window of the twist's trailing mean", "EN 14363: the shortest curve "
                                   "section, 100 m", "C", en14363.MIN_SECTION_M, (1.0, 10000.0), False)
    debounce_m: float = _ground("debounce_m")
    rearm_fraction: float = _ground("rearm_fraction")
    rearm_m: float = _ground("rearm_m")

    def levels(self, criterion):
        """[(severity, level)] of a criterion, enabled levels only (all WARNING)."""
        level = float(getattr(self, criterion))
        return [(SEVERITY_WARNING, level)] if math.isfinite(level) else []

    def debounce(self, criterion):
        """m of track a criterion's value must stay at or above its level before the alert."""
        return self.debounce_m if criterion in INSTANTANEOUS else 0.0

    def validated(self):
        """self if every value is within its accepted range and each band's edges are in order, else
        ValueError naming the value and the range."""
        for f in fields(self):
            value, meta = getattr(self, f.name), f.metadata
            if not (meta["nan_disables"] and math.isnan(value)):
                lo, hi = meta["accepted"]
                check_range(f.name, value, lo, hi, meta["unit"], lo_open=meta["lo_open"], hi_open=math.isinf(hi))
        for low, high in (("bids_band_low", "bids_band_high"), ("china_band_low", "china_band_high")):
            if not getattr(self, low) < getattr(self, high):
                raise ValueError(f"{low} {getattr(self, low):g} Hz must be below {high} {getattr(self, high):g} Hz")
        return self

    def as_dict(self):
        return asdict(self)


def measured_limits(vehicle: VehicleParameters, ground_truth: Limits = None, **changes):
    """MeasuredLimits of a car: the frame limits from its bogie mass, the roll levels from its air springs,
    f0 from its bogie (`kinematic_bogie_frequency`), the estimator's levels from the ground-truth monitor's
    (default: its shipped parameter file, warning.limits.default_limits); `changes` override any field."""
    ground_truth = ground_truth or default_limits()
    peak, rms = oc.bogie_limits(bogie_mass(vehicle))
    roll = oc.roll_level(vehicle)
    values = dict(bogie_rms=rms, bogie_peak=peak, car_body_roll=roll,
                  car_body_roll_rate=2.0 * math.pi * oc.car_body_roll_frequency(vehicle) * roll,
                  hunting_frequency=kinematic_bogie_frequency(vehicle),
                  estimated_running_gear_unloading=ground_truth.running_gear_unloading,
                  estimated_side_ratio=ground_truth.derailment_coefficient * SIDE_RATIO_PER_WHEEL_Y_Q,
                  car_body_twist=oc.twist_level(vehicle, INSTRUMENTS["air_spring_height"].bias))
    values.update(changes)
    return MeasuredLimits(**values).validated()


def sample_rates(sensors=None):
    """{sensor unit: sample rate (Hz)} of a sensor set (sensors.sensor_set.SensorSet; default the shipped one)."""
    sensors = sensors or default_set()
    rates = {m.name: m.sampling.sample_rate_hz for m in sensors.mounts}
    if sensors.air_springs is not None:
        rates[AIR_SPRINGS] = sensors.air_springs.sampling.sample_rate_hz
    if sensors.odometer is not None:
        rates[ODOMETER] = sensors.odometer.sampling.sample_rate_hz
    return rates


def held(source_time, values, time):
    """The last of `values` (rows) at or before each of `time`, NaN before the first (a zero-order hold)."""
    values = np.asarray(values, dtype=float)
    k = np.searchsorted(source_time, time, "right") - 1
    out = values[np.maximum(k, 0)]
    out[k < 0] = np.nan
    return out


def _lateral(signals):
    return np.asarray(signals["acceleration"])[:, 1]


def _roll_rate(signals):
    return np.asarray(signals["angular_rate"])[:, 0]


def _deflection(signals):
    return np.asarray(signals["deflection"])


# criterion: (what a channel reads of its unit's signals, its value's processor from (limits, vehicle, rate))
CHANNELS = {
    "bogie_rms": (_lateral, lambda lim, vp, rate: oc.BogieRms(rate, lim.hunting_frequency, lim.rms_window_m,
                                                               lim.window_step_m)),
    "bogie_peak": (_lateral, lambda lim, vp, rate: oc.BogiePeak(rate, lim.hunting_frequency)),
    "bids_peak_count": (_lateral, lambda lim, vp, rate: oc.PeakCount(rate, (lim.bids_band_low, lim.bids_band_high),
                                                                     lim.bids_peak_limit, lim.bids_window)),
    "bids_peak_count_china": (_lateral, lambda lim, vp, rate: oc.PeakCount(
        rate, (lim.china_band_low, lim.china_band_high), lim.china_peak_limit)),
    "car_body_lateral": (_lateral, lambda lim, vp, rate: oc.CarBodyLateral(rate)),
    "car_body_lateral_qst": (_lateral, lambda lim, vp, rate: oc.CarBodyLateralQst(rate, lim.qst_window_m,
                                                                                  lim.window_step_m)),
    "car_body_roll": (_deflection, lambda lim, vp, rate: oc.CarBodyRoll(rate, vp)),
    "car_body_roll_rate": (_roll_rate, lambda lim, vp, rate: oc.CarBodyRollRate(rate)),
}


class _Estimate:
    """The estimator as a criterion group's processor: the roll balance of the inputs held at the stamps."""

    def __init__(self, limits, vehicle, rates, wind=None):
        self.balance = est.RollBalance(vehicle, limits.air_spring_effective_area, limits.axle_box_corner,
                                       rates[est.TIME_BASE])
        self.wind = wind

    def __call__(self, arrays, stamps, odometer):
        aero = None if self.wind is None else self.wind.load(stamps, odometer.speed(stamps))
        return self.balance(est.held_inputs(arrays, stamps), aero)


class _Twist:
    """The twist as a criterion group's processor: the air springs held at the gyro's stamps."""

    def __init__(self, limits, vehicle, rates, wind=None):
        self.twist = oc.CarBodyTwist(rates[ROLL_GYRO], vehicle, limits.car_body_twist, limits.twist_window_m,
                                     limits.window_step_m)

    def __call__(self, arrays, stamps, odometer):
        deflection = held(arrays[f"sensor_{AIR_SPRINGS}_time"], arrays[f"sensor_{AIR_SPRINGS}_deflection"], stamps)
        rate = held(arrays[f"sensor_{ROLL_GYRO}_time"], arrays[f"sensor_{ROLL_GYRO}_angular_rate"][:, 0], stamps)
        value = self.twist(deflection, rate, odometer.position(stamps), odometer.speed(stamps))
        return {"twist": value[:, None]}


@dataclass(frozen=True)
class Group:
    """Criteria on several units' samples held at one unit's stamps, the group's time base, from the first
    stamp at which every input has a sample: `make(limits, vehicle, rates, wind)` the processor, fed
    (sensor_* arrays, stamps, odometer) in stamp order, giving {key: (n, places)}; `criteria` {criterion: key}."""
    base: str
    inputs: tuple
    criteria: dict
    make: object

    @property
    def units(self):
        return (self.base,) + self.inputs


GROUPS = (Group(est.TIME_BASE, est.INPUTS, {"estimated_running_gear_unloading": "unloading",
                                             "estimated_side_ratio": "derailment_coefficient"}, _Estimate),
          Group(ROLL_GYRO, (AIR_SPRINGS,), {TWIST: "twist"}, _Twist))
GROUP_OF = {c: g for g in GROUPS for c in g.criteria}
ESTIMATED = GROUPS[0].criteria
UNITS = tuple(dict.fromkeys(FRAMES + FLOORS + (ROLL_GYRO, AIR_SPRINGS, ODOMETER) + est.INPUTS))


def units_for(criterion):
    """The sensor units a criterion reads (besides the odometer)."""
    return GROUP_OF[criterion].units if criterion in GROUP_OF else PLACES[criterion]


def units_of(signals):
    """{unit: {signal: array}} of the `sensor_<unit>_<signal>` arrays of the units the criteria read."""
    units = {}
    for unit in UNITS:
        prefix = f"sensor_{unit}_"
        found = {name[len(prefix):]: values for name, values in signals.items() if name.startswith(prefix)}
        if "time" in found:
            units[unit] = found
    return units


def criteria_of(units):
    """The criteria whose sensors (and the odometer) are all among `units`."""
    if ODOMETER not in units:
        return ()
    return tuple(c for c in CRITERIA if all(u in units for u in units_for(c)))


def left_out(units):
    """{criterion: the sensor units it needs that `units` lacks} of the criteria that cannot run, and the
    sentence saying so (a monitor degrades with a word, not silently)."""
    missing = {c: [u for u in (ODOMETER,) + tuple(units_for(c)) if u not in units] for c in CRITERIA}
    missing = {c: m for c, m in missing.items() if m}
    return missing, "; ".join(f"{c} left out: no {', '.join(m)}" for c, m in missing.items())


def measured(criterion, value, limits: MeasuredLimits, time, position):
    """The Measured of a criterion's values (n, places) on its time base."""
    meta = next(f.metadata for f in fields(MeasuredLimits) if f.name == criterion)
    return oc.Measured(criterion, np.asarray(value, dtype=float).reshape(len(time), -1),
                       float(getattr(limits, criterion)), meta["unit"], meta["source"], meta["sure"],
                       limits.debounce(criterion), time, position, PLACES[criterion])


def evaluate(signals, vehicle: VehicleParameters, limits: MeasuredLimits = None, rates=None, wind=None):
    """{criterion: Measured} of every criterion on measured signals whose sensors the record holds (those
    lacking a sensor, or all without the odometer, are left out with a warning naming them and the missing
    units, `left_out`): value (n, places), `time` and `position`
    (n,) on the criterion's time base (the module's table). `rates`: {unit: Hz} of the sensors
    (`sample_rates`, default the shipped set's); `limits` default `measured_limits(vehicle)`; `wind`: an
    estimator.GivenWind the estimator takes into account (default: none known)."""
    limits = (limits or measured_limits(vehicle)).validated()
    rates = sample_rates() if rates is None else rates
    units = units_of(signals)
    found = criteria_of(units)
    if left_out(units)[0]:
        warnings.warn(f"on-board criteria without their sensors: {left_out(units)[1]}", stacklevel=2)
    unknown = sorted(u for c in found for u in units_for(c) if u not in rates)
    if unknown:
        raise ValueError(f"no sample rate for sensor unit(s) {', '.join(dict.fromkeys(unknown))}: the rates given are "
                         f"those of {', '.join(rates) or 'no unit'} (measured.sample_rates of the record's sensor set)")
    odometer = oc.Odometer()
    if found:
        odometer.add(units[ODOMETER]["time"], units[ODOMETER]["speed"])
    out = {}
    for c in found:
        if c in CHANNELS:
            read, processor = CHANNELS[c]
            channels = []
            for unit in PLACES[c]:
                t = np.asarray(units[unit]["time"], dtype=float)
                channels.append((t, processor(limits, vehicle, rates[unit])(read(units[unit]), odometer.position(t))))
            time = np.unique(np.concatenate([t for t, _ in channels]))
            value = np.stack([held(t, v, time) for t, v in channels], axis=1)
            out[c] = measured(c, value, limits, time, odometer.position(time))
    for g in GROUPS:
        if any(c in g.criteria for c in found):
            t = np.asarray(units[g.base]["time"], dtype=float)
            t = t[t >= max(units[u]["time"][0] for u in g.inputs)]
            values = g.make(limits, vehicle, rates, wind)(signals, t, odometer)
            for c, key in g.criteria.items():
                out[c] = measured(c, values[key], limits, t, odometer.position(t))
    return out


@dataclass(frozen=True)
class MeasuredAlert:
    """An alert of a criterion on measured signals: the sample of the criterion's time base that raised it."""
    time_s: float
    sample: int
    criterion: str
    severity: int
    value: float
    threshold: float
    place: str                 # the mount (or running-gear side) of the channel
    track_position: float      # m, the odometer's
    signals: str = SIGNALS

    def as_dict(self):
        return asdict(self)


def alerts(results, limits: MeasuredLimits):
    """Every alert of `evaluate`'s results under the monitor's alarm logic (warning.alarms.alarm_intervals, a
    Detector per channel), ordered by time, then criterion (CRITERIA's order), then place."""
    found = []
    for c in CRITERIA:
        if c not in results:
            continue
        m = results[c]
        for k, intervals in enumerate(m.channel_intervals(None, limits.rearm_fraction, limits.rearm_m)):
            for a, _ in intervals:
                found.append(MeasuredAlert(float(m.time[a]), int(a), c, SEVERITY_WARNING,
                                           float(m.value[a, k]), m.level, m.places[k], float(m.position[a])))
    order = {c: i for i, c in enumerate(CRITERIA)}
    return sorted(found, key=lambda a: (a.time_s, order[a.criterion], PLACES[a.criterion].index(a.place)))


__all__ = ["MeasuredLimits", "measured_limits", "evaluate", "alerts", "MeasuredAlert", "sample_rates",
           "kinematic_bogie_frequency", "CRITERIA", "PLACES", "SIGNALS"]
