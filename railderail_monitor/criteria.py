"""Derailment criteria as plain functions: the early-warning criteria of Yu et al. (2022) and the
classic ones, with the debounce and hysteresis that turn a crossing into one alert.

No ROS here: the monitor node (`railderail_monitor.node`), the replay, `alerts_of_run` (recordings
written without ROS, the warning-quality command) all run the same `Monitor` over their samples, so
their alerts agree by construction.

Criteria (values, units, default levels; `Limits` holds them and its field metadata is the table of
the monitor's parameters; the defaults are the shipped parameter file's, `default_limits`):

| criterion                | value (unit)                                   | WARNING level         | CRITICAL level         |
| ------------------------ | ---------------------------------------------- | --------------------- | ---------------------- |
| `attack_angle`           | abs. attack angle of the front wheelset (rad)  | 0.06 (Yu 2022)        | none                   |
| `wheel_lift`             | wheel lift hp of each wheel (m)                | 1/3 flange height     | 2/3 flange height      |
| `derailment_coefficient` | Q/P of each wheel (-)                          | 0.8 (EN 14363)        | Nadal's limit          |
| `wheel_unloading`        | unloading ratio dP/P0 of each wheel (-)        | 0.60 (GB 5599-85)     | 0.65 (GB 5599-85)      |
| `running_gear_unloading` | mean dP/P0 of a bogie's two wheels on one side | 0.90 (EN 14067-6)     | none                   |
| `derailment_coefficient_duration` | Q/P of each wheel held 50 ms  | 1.0 (AAR Chapter XI)  | Nadal's limit          |
| `derailment_coefficient_mean` | 2 m sliding mean of Q/P of each wheel | 0.8 (EN 14363) | Nadal's limit     |

Each criterion has its own two levels (a Limits field each): the three Q/P rules start with the same
CRITICAL level, Nadal's limit, but choosing one of them never moves another's.
| `flange_climb_distance`  | climb run at Nadal / TCRP's distance (-)       | 0.5 (half the limit)  | 1 (TCRP Report 71)     |

Sources and confidence:
- attack angle 0.06 rad on the front wheelset: Yu et al., Appl. Sci. 2022, 12, 11199 (the paper
  under reproduction). Evaluated on the magnitude (either sign), the wheelset leading in the
  direction of travel (wheelset 0).
- wheel lift: no standard value; 1/3 of the flange height (9.3 mm for the LM wheel) warns, 2/3
  (18.5 mm) is critical (the core declares a derailment near the full flange height). A modelling
  choice, stated as such; both are parameters.
- derailment coefficient: EN 14363:2016 / UIC 518 acceptance limit (Y/Q)lim = 0.8 (high confidence
  for the value; the standard applies it to the 2 m sliding mean, here a 2 m persistence); Nadal's
  limit (tan d - mu)/(1 + mu tan d) at the profile pair's maximum contact angle and the scenario's
  friction (1.319 for LM on UIC60, mu = 0.3) is the physical flange-climbing limit.
- wheel unloading ratio dP/P0 = (P0 - P)/P0: GB 5599-85 gives 0.60 (allowable) and 0.65 (danger
  limit) (medium confidence: later Chinese codes, GB/T 5599-2019 and TB 10761, keep 0.6-0.65 for
  the dynamic ratio but with different evaluation windows and speed classes).

- running-gear unloading: EN 14067-6's crosswind criterion, the mean unloading ratio of a running gear's
  (bogie's) wheels on one side, limit 0.90 (as quoted in ../shared/reference/track-and-loads.md;
  medium confidence on the evaluation, the standard's filter is not applied here).
- derailment coefficient with a duration rule: Q/P at or above its level for at least
  `duration_s` = 50 ms of time, not of track (AAR Manual of Standards, Chapter XI, single-wheel L/V
  1.0 over 50 ms, and the Japanese practice of a duration; medium confidence, as quoted in the
  issue tracker and TCRP Report 71; its CRITICAL level is Nadal's limit like the 2 m rule's). The time is
  counted in integer nanoseconds, the resolution of a ROS stamp, so that the node (which sees the stamps)
  and a batch evaluation (which sees the simulator's clock) decide every sample alike.
- flange-climb distance: TCRP Report 71 Vol. 5 (2005, Wu and Wilson) eq. 2.4, the distance over which a
  wheel's L/V may stay at Nadal's limit, falling with the attack angle (`climb_distance`: the formula, its
  constants and why their grouping is uncertain). Its limit is the CRITICAL level 1; the WARNING level
  at half of it is a modelling choice. The distance runs while Q/P is at or above Nadal's limit with
  mu = 0.5 (climb_nadal_limit, 0.931 for LM on UIC60), whatever the scenario's friction: the rule of
  49 CFR 238 App. C, and the friction of TCRP's simulations.

One event, one alert: a value must stay at or above its level over `debounce_m` of track (default
2 m, the window length of EN 14363's Q/P sliding mean) before the alert is raised, and the channel
re-arms only when the value has stayed below `rearm_fraction` x level (default 0.9) over `rearm_m`
of track (default 50 m, two car lengths: the dynamic unloading in a transition oscillates around
its level at a few metres' spacing). Each (criterion, level, wheel or wheelset) is its own channel.
"""
from __future__ import annotations

import collections
import functools
from importlib.resources import files
import math
from dataclasses import MISSING, asdict, dataclass, field, fields
from pathlib import Path

import numpy as np

from railderail_sim.parameters import RUNNING_GEAR_UNLOADING_LIMIT
from railderail_sim.ranges import check_range
from railderail_sim.vehicle.layout import RUNNING_GEARS, running_gear_sides

from .climb_distance import CLIMB_FRICTION, ClimbDistance, tcrp_coefficients

SIDES = ("left", "right")
CRITERIA = ("attack_angle", "wheel_lift", "derailment_coefficient", "wheel_unloading", "running_gear_unloading",
            "derailment_coefficient_duration", "derailment_coefficient_mean", "flange_climb_distance")
# a running gear's side by its leading wheelset, in the order of vehicle.layout.running_gear_sides
BOGIE_PLACES = tuple((gear[0], side) for gear in RUNNING_GEARS for side in SIDES)
SEVERITY_WARNING, SEVERITY_CRITICAL = 1, 2          # the Alert message's constants
SEVERITY_NAMES = {SEVERITY_WARNING: "warning", SEVERITY_CRITICAL: "critical"}


def critical_name(criterion):
    """The Limits field of a criterion's CRITICAL level."""
    return criterion + "_critical"


TIMED = ("derailment_coefficient_duration",)      # their debounce is time, not track
NANOSECOND = 1e-9                                 # s: the clock of the timed rules (a ROS stamp's resolution)


def nanoseconds(seconds):
    """Integer nanoseconds of a time (s) or an array of times, as a ROS stamp holds it
    (`ros_interface.set_time`): exact for times below 10^6 s, whether they come from the simulator's clock
    or from a stamp's sec + 1e-9 nanosec."""
    ns = np.round(np.asarray(seconds, dtype=float) / NANOSECOND)
    return ns.astype(np.int64) if ns.ndim else int(ns)


def debounce(criterion, limits):
    """What a criterion's value must be held over before it alerts: duration_s of time for the duration
    rule (in integer nanoseconds, `nanoseconds`), nothing for the sliding mean and the climb distance (their
    window or distance is the evaluation), debounce_m of track otherwise."""
    return {"derailment_coefficient_duration": nanoseconds(limits.duration_s), "derailment_coefficient_mean": 0.0,
            "flange_climb_distance": 0.0}.get(criterion, limits.debounce_m)


def _value(unit, meaning, source, default=MISSING, accepted=(0.0, math.inf), lo_open=True, nan_disables=False):
    """A field of Limits with what the monitor's parameters and its parameter file say about it:
    unit ('' = dimensionless), meaning, source, the accepted range (lo open where flagged) and
    whether NaN is accepted (it disables a level)."""
    return field(default=default, metadata=dict(unit=unit, meaning=meaning, source=source, accepted=accepted,
                                                lo_open=lo_open, nan_disables=nan_disables))


def _level(unit, meaning, source, default=MISSING):
    return _value(unit, meaning, source, default, nan_disables=True)


@dataclass(frozen=True)
class Limits:
    """Thresholds of every criterion (NaN disables a level) and the alerting behaviour; the field
    metadata is the one table of the monitor's parameters (names, units, meanings, sources, ranges).

    The first four depend on the car and the profiles: take them from the model with
    `limits_for_model` (`railderail monitor-params` writes them to a parameter file; the monitor's
    defaults are the shipped file's, `default_limits`), never by hand."""
    wheel_lift: float = _level("m", "wheel lift hp of each wheel, WARNING level",
                               "1/3 of the wheel's flange height (no standard value: a modelling choice)")
    wheel_lift_critical: float = _level("m", "wheel lift, CRITICAL level",
                                        "2/3 of the flange height (the core declares a derailment near the "
                                        "full height)")
    derailment_coefficient_critical: float = _level(
        "", "derailment coefficient Q/P of each wheel, CRITICAL level",
        "Nadal's limit (tan d - mu)/(1 + mu tan d) at the profile pair's largest contact angle d, friction mu")
    derailment_coefficient_duration_critical: float = _level(
        "", "Q/P held for duration_s, CRITICAL level",
        "Nadal's limit (tan d - mu)/(1 + mu tan d) at the profile pair's largest contact angle d, friction mu")
    derailment_coefficient_mean_critical: float = _level(
        "", "2 m sliding mean of Q/P, CRITICAL level",
        "Nadal's limit (tan d - mu)/(1 + mu tan d) at the profile pair's largest contact angle d, friction mu")
    static_wheel_load: float = _value("N", "static wheel load P0 of the unloading ratio (P0 - P)/P0",
                                      "the car's load per wheel at rest on level track "
                                      "(VehicleParameters.static_wheel_load)")
    climb_nadal_limit: float = _value("", "Nadal's limit that starts the climb distance: Q/P at or above it counts",
                                      "Nadal at the profile pair's largest contact angle with mu = 0.5, the "
                                      "friction of the US single-wheel L/V rule (49 CFR 238 App. C) and of TCRP "
                                      "Report 71's climb simulations; the monitor does not know the friction")
    climb_distance_scale: float = _value("m", "TCRP's limiting climb distance at zero attack angle, A of eq. 2.4",
                                         "TCRP Report 71 Vol. 5 eq. 2.4 at the wheel's largest flange angle and "
                                         "flange length (grouping of its constants uncertain, climb_distance.py)")
    climb_attack_angle_scale: float = _value("rad", "attack angle at which TCRP's limiting climb distance is "
                                             "halved, B Len of eq. 2.4", "TCRP Report 71 Vol. 5 eq. 2.4, as "
                                             "climb_distance_scale")
    attack_angle: float = _level("rad", "magnitude of the front wheelset's attack angle, WARNING level",
                                 "Yu et al., Appl. Sci. 2022, 12, 11199", 0.06)
    attack_angle_critical: float = _level("rad", "attack angle, CRITICAL level",
                                          "none in the sources, so disabled", math.nan)
    derailment_coefficient: float = _level("", "derailment coefficient Q/P of each wheel, WARNING level",
                                           "EN 14363:2016 / UIC 518 limit (Y/Q)lim", 0.8)
    wheel_unloading: float = _level("", "wheel unloading ratio dP/P0 of each wheel, WARNING level",
                                    "GB 5599-85 allowable value", 0.60)
    wheel_unloading_critical: float = _level("", "wheel unloading ratio, CRITICAL level",
                                             "GB 5599-85 danger limit", 0.65)
    running_gear_unloading: float = _level("", "mean unloading ratio of a bogie's two wheels on one side, "
                                           "WARNING level", "EN 14067-6 limit of the running-gear unloading",
                                           RUNNING_GEAR_UNLOADING_LIMIT)
    running_gear_unloading_critical: float = _level("", "running-gear unloading, CRITICAL level",
                                                    "none in the sources, so disabled", math.nan)
    derailment_coefficient_duration: float = _level("", "Q/P of each wheel held for duration_s, WARNING level",
                                                    "AAR Chapter XI single-wheel L/V limit", 1.0)
    derailment_coefficient_mean: float = _level("", "sliding mean of Q/P over sliding_mean_m of track, each "
                                                "wheel, WARNING level", "EN 14363:2016 / UIC 518 limit (Y/Q)lim "
                                                "of the 2 m sliding mean", 0.8)
    flange_climb_distance: float = _level("", "track run with Q/P at Nadal's limit over TCRP's limiting climb "
                                          "distance at the wheelset's attack angle, each wheel, WARNING level",
                                          "half TCRP's limit (a modelling choice)", 0.5)
    flange_climb_distance_critical: float = _level("", "flange-climb distance ratio, CRITICAL level",
                                                   "TCRP Report 71 Vol. 5 eq. 2.4: the limiting distance", 1.0)
    sliding_mean_m: float = _value("m", "track over which Q/P is averaged for its sliding-mean criterion",
                                   "EN 14363:2016: 2 m", 2.0, (0.0, 100.0))
    duration_s: float = _value("s", "time Q/P must stay at or above a level for the duration criterion",
                               "AAR Chapter XI: 50 ms", 0.05, (0.0, 10.0), False)
    debounce_m: float = _value("m", "track a value must stay at or above a level before its alert",
                               "the 2 m window of EN 14363's Q/P sliding mean", 2.0, (0.0, 100.0), False)
    rearm_fraction: float = _value("", "re-arm level of a channel after its alert, as a fraction of the threshold",
                                   "a modelling choice (10 % hysteresis)", 0.9, (0.0, 1.0))
    rearm_m: float = _value("m", "track the value must stay below the re-arm level before the channel re-arms",
                            "two car lengths: the dynamic unloading in a transition oscillates around its "
                            "level a few metres apart", 50.0, (0.0, 10000.0), False)

    def levels(self, criterion):
        """[(severity, threshold)] of a criterion, enabled levels only."""
        out = [(SEVERITY_WARNING, getattr(self, criterion)),
               (SEVERITY_CRITICAL, getattr(self, critical_name(criterion)))]
        return [(sev, float(thr)) for sev, thr in out if math.isfinite(thr)]

    def validated(self):
        """self if every value is within its accepted range and each warning level is below its
        critical level, else ValueError naming the value and the range."""
        for f in fields(self):
            value, meta = getattr(self, f.name), f.metadata
            if not (meta["nan_disables"] and math.isnan(value)):
                lo, hi = meta["accepted"]
                check_range(f.name, value, lo, hi, meta["unit"], lo_open=meta["lo_open"], hi_open=math.isinf(hi))
        for criterion in CRITERIA:
            warn, crit = getattr(self, criterion), getattr(self, critical_name(criterion))
            if math.isfinite(warn) and math.isfinite(crit) and not warn < crit:
                raise ValueError(f"{criterion} {warn:g} must be below {critical_name(criterion)} {crit:g}")
        return self

    def as_dict(self):
        return asdict(self)


def model_basis(model):
    """What the limits take from a built `vehicle.assemble.Model`: flange height (m), the profile
    pair's largest contact angle in rigid contact (rad), the static wheel load (N), and the wheel's
    largest flange angle (rad) and flange length (m, its face within 1 deg of that angle: TCRP's Len).
    The one function that reads the model's internals for the monitor."""
    from railderail_sim import profiles
    from railderail_sim.contact.conicity import max_contact_angle

    delta, _ = max_contact_angle(model.cg)
    wheel = profiles.resolve(model.contact.wheel_profile, "wheel")
    return dict(flange_height=model.flange_height, max_contact_angle=float(delta),
                static_wheel_load=float(model.vehicle.static_wheel_load), flange_angle=wheel.max_flange_angle(),
                flange_length=wheel.flange_length())


def limits_for_model(model, friction, **changes):
    """Limits whose model-dependent values come from a built model (`model_basis`): wheel lift 1/3
    and 2/3 of the flange height, Nadal's limit at the largest contact angle and `friction`, the
    static wheel load, TCRP's climb-distance scales from the flange; the others their defaults unless
    `changes` says otherwise."""
    from railderail_sim.contact.nadal import nadal_limit

    basis = model_basis(model)
    hf = basis["flange_height"]
    distance, angle = tcrp_coefficients(basis["flange_angle"], basis["flange_length"])
    nadal = float(nadal_limit(basis["max_contact_angle"], friction))
    values = dict(wheel_lift=hf / 3.0, wheel_lift_critical=2.0 * hf / 3.0, derailment_coefficient_critical=nadal,
                  derailment_coefficient_duration_critical=nadal, derailment_coefficient_mean_critical=nadal,
                  static_wheel_load=basis["static_wheel_load"], climb_distance_scale=distance,
                  climb_nadal_limit=float(nadal_limit(basis["max_contact_angle"], CLIMB_FRICTION)),
                  climb_attack_angle_scale=angle)
    values.update(changes)
    return Limits(**values).validated()


NODE = "railderail_monitor"
SHIPPED = files("railderail_monitor") / "config" / "monitor.yaml"
# the node's mode parameter, the first of its parameter file (node.SIGNALS)
SIGNALS = ("ground_truth", "measured")
SIGNALS_MEANING = ("what the monitor reads: ground_truth, the simulator's wheelset states and contact forces; "
                   "measured, the on-board sensors' topics only")


def read_limits(path):
    """Limits from a parameter file of the monitor node (ValueError naming the file and what is wrong)."""
    import yaml
    try:
        data = yaml.safe_load(Path(path).read_text())
        values = data[NODE]["ros__parameters"]
    except OSError as error:
        raise ValueError(f"{path}: cannot read it ({error.strerror or error})") from None
    except (yaml.YAMLError, TypeError, KeyError):
        raise ValueError(f"{path} is not a parameter file with a '{NODE}: ros__parameters:' mapping") from None
    names = [f.name for f in fields(Limits)]
    unknown, missing = sorted(set(values) - set(names) - {"signals"}), [n for n in names if n not in values]
    if unknown or missing:
        raise ValueError(f"{path}: " + "; ".join(
            text for text in (unknown and f"unknown parameter(s) {', '.join(unknown)}",
                              missing and f"missing parameter(s) {', '.join(missing)}") if text))
    return Limits(**{name: float(values[name]) for name in names}).validated()


@functools.lru_cache(maxsize=None)
def default_limits():
    """The monitor's default limits: those of the parameter file shipped with the package
    (railderail_monitor/config/monitor.yaml, made by `railderail monitor-params` for the built-in
    car: vehicle set hs19, LM on UIC60 at 1:40, friction 0.3). Reads no model, imports no numba."""
    return read_limits(SHIPPED)


# --- values of the criteria -------------------------------------------------------------------

def front_attack_angle(attack_angle):
    """Magnitude of the front wheelset's attack angle (rad) from (..., 4) attack angles."""
    return np.abs(np.asarray(attack_angle, dtype=float)[..., 0])


def unloading_ratio(vertical_force, static_wheel_load):
    """Wheel unloading ratio dP/P0 = (P0 - P) / P0 (dimensionless; 1 = wheel fully unloaded)."""
    if not static_wheel_load > 0.0:
        raise ValueError(f"static wheel load {static_wheel_load:g} N must be positive")
    return (static_wheel_load - np.asarray(vertical_force, dtype=float)) / static_wheel_load


def running_gear_unloading(unloading):
    """Mean unloading ratio of each bogie's two wheels on one side (EN 14067-6), (..., 4) in the order of
    BOGIE_PLACES, from the (..., 8) ratios of the wheels [wheelset 0 left, wheelset 0 right, ...]."""
    return running_gear_sides(unloading)


def sliding_mean(values, position, window):
    """The mean of each column of `values` (n, ...) over the samples of the last `window` m of track up to
    each sample (those with position > position_i - window), as EN 14363 evaluates Q/P. From prefix sums,
    so that the monitor's running version (`SlidingMean`) gives the same numbers."""
    v = np.asarray(values, dtype=float)
    pos = np.asarray(position, dtype=float)
    sums = np.concatenate((np.zeros((1,) + v.shape[1:]), np.cumsum(v, axis=0)))
    first = np.searchsorted(pos, pos - window, side="right")
    count = (np.arange(len(pos)) + 1 - first).reshape((-1,) + (1,) * (v.ndim - 1))
    return (sums[1:] - sums[first]) / count


class SlidingMean:
    """`sliding_mean` sample by sample: the prefix sum so far and, for the samples in the window, where they
    are and the prefix sum before them."""

    def __init__(self, window, width):
        self.window = float(window)
        self.total = np.zeros(width)
        self.kept = collections.deque()

    def update(self, value, position):
        self.kept.append((float(position), self.total.copy()))
        self.total = self.total + np.asarray(value, dtype=float)
        while self.kept[0][0] <= position - self.window:
            self.kept.popleft()
        return (self.total - self.kept[0][1]) / len(self.kept)


def rail_side(wheel_side, curvature):
    """'inner' / 'outer' rail of a wheel on a curve of signed curvature (+ = curve to the left);
    '' on straight track."""
    if curvature == 0.0 or not math.isfinite(curvature):
        return ""
    inner = "left" if curvature > 0.0 else "right"
    return "inner" if wheel_side == inner else "outer"


# --- debounce and hysteresis ------------------------------------------------------------------

class Detector:
    """One alert per event on one channel: the value must stay >= threshold over `debounce` (m of
    track, or integer nanoseconds of time for a duration rule) to raise the alert; the channel re-arms once the value has
    stayed below rearm_fraction x threshold over `rearm_m` of track. `update` returns True on the
    sample that raises the alert."""

    __slots__ = ("threshold", "rearm_level", "debounce", "rearm_m", "armed", "start")

    def __init__(self, threshold, debounce=2.0, rearm_fraction=0.9, rearm_m=50.0):
        self.threshold = float(threshold)
        self.rearm_level = float(rearm_fraction) * self.threshold
        self.debounce = debounce                   # m, or integer ns of a timed rule
        self.rearm_m = float(rearm_m)
        self.armed = True
        self.start = None      # where (or when) the value crossed (the level, or the re-arm level)

    def update(self, value, position, clock=None):
        """`clock`: what the debounce is measured on, the track position by default (a duration rule
        passes the time in integer nanoseconds); the re-arm is always measured on the track."""
        if not self.armed:
            if value < self.rearm_level:
                if self.start is None:
                    self.start = position
                if position - self.start >= self.rearm_m:
                    self.armed = True
                    self.start = None
            else:
                self.start = None
            return False
        at = position if clock is None else clock
        if value >= self.threshold:
            if self.start is None:
                self.start = at
            if at - self.start >= self.debounce:
                self.armed = False
                self.start = None
                return True
        else:
            self.start = None
        return False


def alarm_intervals(values, position, threshold, debounce=2.0, rearm_fraction=0.9, rearm_m=50.0, clock=None):
    """[(alert, rearm)] of a Detector fed (values[i], position[i], clock[i]): the sample that raises each
    alert and the one at which the channel re-arms (len(values) if it never does), so the channel is in
    alarm over alert <= i < rearm. Found over the runs of samples above the level and below the re-arm level
    instead of sample by sample, with the same decisions (the same comparisons of the same differences), so
    that a threshold sweep over long runs (`warning_catalogue`) is what the monitor would have said at each
    threshold. Positions (and the clock) must not decrease."""
    v = np.asarray(values, dtype=float)
    pos = np.asarray(position, dtype=float)
    at = pos if clock is None else np.asarray(clock)
    above = np.flatnonzero(v >= float(threshold))
    not_above = np.flatnonzero(~(v >= float(threshold)))
    rearm_level = float(rearm_fraction) * float(threshold)
    below = np.flatnonzero(v < rearm_level)
    not_below = np.flatnonzero(~(v < rearm_level))
    n = len(v)

    def first_after(indices, i):
        k = np.searchsorted(indices, i)
        return int(indices[k]) if k < len(indices) else n

    def held(coordinate, start, end, length):
        """The first sample in [start, end) whose coordinate is `length` past the start's, else end."""
        k = int(np.searchsorted(coordinate[start:end], coordinate[start] + length)) + start
        k = max(k - 1, start)                  # the exact comparison decides, not the sum's rounding
        while k < end and not coordinate[k] - coordinate[start] >= length:
            k += 1
        return k

    intervals, i, armed = [], 0, True
    while i < n:
        if armed:
            start = first_after(above, i)
            if start >= n:
                break
            end = first_after(not_above, start)
            k = held(at, start, end, debounce)
            if k < end:
                intervals.append([k, n])
                armed = False
            i = k + 1 if k < end else end
        else:
            start = first_after(below, i)
            if start >= n:
                break
            end = first_after(not_below, start)
            k = held(pos, start, end, float(rearm_m))
            if k < end:
                intervals[-1][1] = k
                armed = True
            i = k + 1 if k < end else end
    return [tuple(x) for x in intervals]


def alert_indices(values, position, threshold, debounce=2.0, rearm_fraction=0.9, rearm_m=50.0, clock=None):
    """The samples at which a Detector fed (values[i], position[i], clock[i]) raises its alerts
    (`alarm_intervals`' first samples)."""
    return [a for a, _ in alarm_intervals(values, position, threshold, debounce, rearm_fraction, rearm_m, clock)]


# --- the monitor --------------------------------------------------------------------------------

@dataclass
class AlertRecord:
    """An alert, field for field the Alert message (time_s is the header stamp in seconds)."""
    time_s: float
    sample: int
    criterion: str
    severity: int
    value: float
    threshold: float
    wheelset: int
    wheel_side: str
    rail_side: str
    track_position: float
    speed: float
    message: str = ""

    def as_dict(self):
        return asdict(self)


def level_text(criterion, value):
    """A value of a criterion as the alerts and the views write it: the same rounding everywhere."""
    if criterion == "wheel_lift":
        return f"{value * 1e3:.1f} mm"
    if criterion == "attack_angle":
        return f"{value:.4f} rad"
    return f"{value:.3f}"


def describe(criterion, severity, value, threshold, wheelset, wheel_side, rail):
    where = f"wheelset {wheelset}" + (f" {wheel_side}" if wheel_side else "") + (f" ({rail})" if rail else "")
    amount = f"{level_text(criterion, value)} >= {level_text(criterion, threshold)}"
    return f"{SEVERITY_NAMES[severity]}: {criterion.replace('_', ' ')} {amount} on {where}"


class Monitor:
    """Every criterion over a stream of samples. Feed it `on_states` (wheelset states) and
    `on_forces` (contact forces), each returning the list of AlertRecords the sample raised, and
    `set_curvature` (vehicle status): an alert on sample i names the inner or outer rail from the
    curvature (1/m, + left) of the latest status before sample i (so that the order in which the
    three topics of one sample arrive does not matter)."""

    # (wheelset, side) of each channel of a criterion that is not per wheel; side '' for a wheelset
    PLACES = {"attack_angle": ((0, ""),), "running_gear_unloading": BOGIE_PLACES}

    def __init__(self, limits: Limits = None):
        limits = (limits or default_limits()).validated()
        self.limits = limits
        r, rm = limits.rearm_fraction, limits.rearm_m
        self.channels = {}
        for criterion in CRITERIA:
            count = len(self.PLACES.get(criterion, range(8)))
            held = debounce(criterion, limits)
            self.channels[criterion] = [(sev, thr, [Detector(thr, held, r, rm) for _ in range(count)])
                                        for sev, thr in limits.levels(criterion)]
        self.curvatures = collections.deque(maxlen=256)       # (sample, curvature), arrival order
        self.attack_angles = collections.deque(maxlen=256)    # (sample, 4 attack angles), arrival order
        self.qp_mean = SlidingMean(limits.sliding_mean_m, 8)
        self.climb = ClimbDistance(limits.climb_nadal_limit, limits.climb_distance_scale,
                                   limits.climb_attack_angle_scale)

    def set_curvature(self, sample, curvature):
        self.curvatures.append((int(sample), float(curvature)))

    def curvature_before(self, sample):
        return self._before(self.curvatures, sample, 0.0)

    @staticmethod
    def _before(kept, sample, none):
        for s, value in reversed(kept):
            if s < sample:
                return value
        return none

    def _check(self, criterion, values, t, sample, position, speed):
        t, sample, position, speed = float(t), int(sample), float(position), float(speed)
        clock = nanoseconds(t) if criterion in TIMED else None
        alerts = []
        for sev, thr, detectors in self.channels[criterion]:
            for k, detector in enumerate(detectors):
                value = float(values[k])
                if detector.update(value, position, clock):
                    ws, side = self.PLACES[criterion][k] if criterion in self.PLACES else (k // 2, SIDES[k % 2])
                    rail = rail_side(side, self.curvature_before(sample)) if side else ""
                    alerts.append(AlertRecord(t, sample, criterion, sev, value, thr, ws, side, rail, position,
                                              speed, describe(criterion, sev, value, thr, ws, side, rail)))
        return alerts

    def on_states(self, t, sample, position, speed, attack_angle, wheel_lift):
        """Attack angle (4 wheelsets, rad) and wheel lift (8 wheels, m) of one sample."""
        self.attack_angles.append((int(sample), np.asarray(attack_angle, dtype=float)))
        return (self._check("attack_angle", [front_attack_angle(attack_angle)], t, sample, position, speed)
                + self._check("wheel_lift", wheel_lift, t, sample, position, speed))

    def on_forces(self, t, sample, position, speed, derailment_coefficient, vertical_force):
        """Q/P (8 wheels) and vertical forces P (8 wheels, N) of one sample."""
        unloading = unloading_ratio(vertical_force, self.limits.static_wheel_load)
        return (self._check("derailment_coefficient", derailment_coefficient, t, sample, position, speed)
                + self._check("derailment_coefficient_duration", derailment_coefficient, t, sample, position, speed)
                + self._check("derailment_coefficient_mean", self.qp_mean.update(derailment_coefficient, position), t,
                              sample, position, speed)
                + self._check("wheel_unloading", unloading, t, sample, position, speed)
                + self._check("running_gear_unloading", running_gear_unloading(unloading), t, sample, position,
                              speed)
                + self._check("flange_climb_distance", self.climb.update(
                    derailment_coefficient, self._before(self.attack_angles, int(sample), np.zeros(4)), position),
                    t, sample, position, speed))


def alerts_of_run(arrays, limits: Limits = None):
    """Alerts of a whole run, from the named arrays of `vehicle.simulate.Result.arrays()` or
    `vehicle.simulate.output_arrays` (or the same names from a recording): a Monitor fed sample by
    sample as the monitor node is fed, the states, then the forces, then the status (curvature) of
    each sample, so that batch and stream give the same alerts by construction."""
    monitor = Monitor(limits)
    t, s, v = arrays["time"], arrays["position"], arrays["speed"]
    attack, lift = arrays["attack_angle"], arrays["wheel_lift"]
    qp, load = arrays["derailment_coefficient"], arrays["vertical_force"]
    curvature = arrays.get("curvature")
    found = []
    for i, sample in enumerate(arrays.get("sample", range(len(t)))):
        found += monitor.on_states(t[i], sample, s[i], v[i], attack[i], lift[i])
        found += monitor.on_forces(t[i], sample, s[i], v[i], qp[i], load[i])
        if curvature is not None:
            monitor.set_curvature(sample, curvature[i])
    return found


def lead_times(alerts, derailment):
    """First alert of each (criterion, severity) with its lead before the derailment.

    `alerts`: AlertRecords (or dicts with the same keys); `derailment`: dict with time_s and
    track_position_m (car-body centre), or None. Returns {"criterion/severity": {...}}, lead_s and
    lead_m being NaN when no derailment follows (a false alarm)."""
    first = {}
    for a in alerts:
        a = a.as_dict() if isinstance(a, AlertRecord) else a
        key = f"{a['criterion']}/{SEVERITY_NAMES[a['severity']]}"
        if key not in first:
            first[key] = a
    out = {}
    for key, a in first.items():
        lead_s = lead_m = math.nan
        if derailment is not None:
            lead_s = derailment["time_s"] - a["time_s"]
            lead_m = derailment["track_position_m"] - a["track_position"]
        out[key] = dict(time_s=a["time_s"], track_position_m=a["track_position"], speed_kmh=a["speed"] * 3.6,
                        value=a["value"], threshold=a["threshold"], wheelset=a["wheelset"],
                        wheel_side=a["wheel_side"], rail_side=a["rail_side"], lead_s=lead_s, lead_m=lead_m)
    return out
