"""The criteria the warning evaluation scores (`over_catalogue`) and the thresholds each is swept over: the
ground-truth criteria on the simulator's wheel forces and motions, and the measured ones on the on-board
sensors' signals (`onboard.measured`), their shipped levels added to their sweeps; the sensor variants of the
sensor sensitivity."""
from __future__ import annotations

import functools
import math

from railderail_sim.parameters import VehicleParameters

from ..onboard import measured
from ..warning.limits import critical_name, default_limits
from . import supervision_score as supervision

# thresholds of each criterion's sweep (its unit); the shipped levels are added to them
THRESHOLDS = {
    "attack_angle": (0.002, 0.003, 0.004, 0.005, 0.0075, 0.01, 0.02, 0.04, 0.06),       # rad
    "wheel_lift": (0.002, 0.004, 0.006, 0.008, 0.012, 0.015, 0.02),                     # m
    "derailment_coefficient": (0.5, 0.6, 0.7, 0.8, 1.0, 1.2),
    "derailment_coefficient_duration": (0.6, 0.8, 1.0, 1.2),
    "derailment_coefficient_mean": (0.4, 0.5, 0.6, 0.7, 0.8, 1.0),
    "wheel_unloading": (0.5, 0.6, 0.65, 0.7, 0.8, 0.9),
    "running_gear_unloading": (0.5, 0.6, 0.7, 0.8, 0.9),
    "flange_climb_distance": (0.1, 0.25, 0.5, 0.75, 1.0),
}
# the measured criteria's sweeps: multiples of the shipped level (their levels follow the car), the peak
# counts in peaks
MEASURED_FACTORS = (0.5, 0.7, 0.85, 1.0, 1.2, 1.5)
MEASURED_PEAKS = (3.0, 4.0, 5.0, 6.0, 8.0, 10.0)
COUNTS = ("bids_peak_count", "bids_peak_count_china")
CRITERIA = tuple(THRESHOLDS) + measured.CRITERIA + (supervision.CRITERION,)
# what each criterion's signals are: the simulator's wheel forces and motions, the on-board sensors', or the
# position and speed against the line data (the speed supervision)
SIGNALS = ({criterion: "ground_truth" for criterion in THRESHOLDS} | {c: measured.SIGNALS for c in measured.CRITERIA}
           | {supervision.CRITERION: supervision.SIGNALS})
# the sensor sensitivity: the shipped set (noise 1, bias 1, 200 Hz) and each change of one of them; the sample
# rate cannot exceed the simulator's output rate (sensors.sensor_set.Sampling), so 500 Hz is out of reach at 200 Hz
SENSOR_VARIANTS = (dict(noise=1.0, bias=1.0, rate_hz=200.0), dict(noise=0.0, bias=1.0, rate_hz=200.0),
                   dict(noise=3.0, bias=1.0, rate_hz=200.0), dict(noise=1.0, bias=0.0, rate_hz=200.0),
                   dict(noise=1.0, bias=3.0, rate_hz=200.0), dict(noise=1.0, bias=1.0, rate_hz=100.0),
                   dict(noise=1.0, bias=1.0, rate_hz=50.0))


@functools.lru_cache(maxsize=1)
def shipped_measured_limits():
    """The measured criteria's shipped levels and settings, of the shipped car (the catalogue's)."""
    return measured.measured_limits(VehicleParameters())


def shipped_level(criterion, limits=None):
    """A criterion's shipped WARNING level (the ground-truth monitor's parameter file, or the measured one's;
    the speed supervision's WARNING level's code)."""
    if criterion == supervision.CRITERION:
        return min(supervision.LEVELS)
    if SIGNALS[criterion] == measured.SIGNALS:
        return float(getattr(shipped_measured_limits(), criterion))
    return float(getattr(limits or default_limits(), criterion))


def thresholds(criterion, limits=None):
    """The sweep of a criterion with its shipped levels, ascending (the speed supervision's: its levels' codes)."""
    if criterion == supervision.CRITERION:
        return sorted(supervision.LEVELS)
    if SIGNALS[criterion] == measured.SIGNALS:
        level = shipped_level(criterion)
        sweep = MEASURED_PEAKS if criterion in COUNTS else [f * level for f in MEASURED_FACTORS]
        return sorted({float(x) for x in sweep} | ({level} if math.isfinite(level) else set()))
    limits = limits or default_limits()
    shipped = [getattr(limits, criterion), getattr(limits, critical_name(criterion))]
    return sorted({float(x) for x in THRESHOLDS[criterion]} | {float(x) for x in shipped if math.isfinite(x)})


def sensor_variant(sensors, variant):
    """The sensor set with a variant's noise and bias scales and sample rate (SENSOR_VARIANTS)."""
    return sensors.scaled(variant["noise"], variant["bias"]).resampled(variant["rate_hz"])


def variant_name(variant):
    return f"noise {variant['noise']:g}x, bias {variant['bias']:g}x, {variant['rate_hz']:g} Hz"
