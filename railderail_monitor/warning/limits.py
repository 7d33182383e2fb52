"""The ground-truth criteria's levels: `Limits` (every level and the alerting behaviour, the one table of the
monitor's parameters), the model values they take (`limits_for_model`) and their parameter file
(`read_limits`, `default_limits`). The criteria themselves: their values `quantities`, the alarm mechanics
`alarms`, the alert and its wording `alerts`, the streaming monitor `monitor`.

No ROS here: the monitor node (`railderail_monitor.node`), the replay, `alerts_of_run` (recordings
written without ROS, the warning evaluation) all run the same `Monitor` over their samples, so
their alerts agree by construction.

Criteria (values, units, default levels; `Limits` holds them and its field metadata is the table of
the monitor's parameters; the defaults are the shipped parameter file's, `default_limits`):

| criterion                | value (unit)                                   | WARNING level         | CRITICAL level         |
| ------------------------ | ---------------------------------------------- | --------------------- | ---------------------- |
| `attack_angle`           | abs. attack angle of the front wheelset (rad)  | 0.06 (Yu 2022)        | none                   |
| `wheel_lift`             | wheel lift hp of each wheel (m)                | 1/3 flange height     | 2/3 flange height      |
| `derailment_coefficient` | Y/Q of each wheel (-)                          | 0.8 (EN 14363)        | Nadal's limit          |
| `wheel_unloading`        | unloading ratio ΔQ/Q0 of each wheel (-)        | 0.60 (GB 5599-85)     | 0.65 (GB 5599-85)      |
| `running_gear_unloading` | mean ΔQ/Q0 of a bogie's two wheels on one side | 0.90 (EN 14067-6)     | none                   |
| `derailment_coefficient_duration` | Y/Q of each wheel held 50 ms  | 1.0 (AAR Chapter XI)  | Nadal's limit          |
| `derailment_coefficient_mean` | 2 m sliding mean of Y/Q of each wheel | 0.8 (EN 14363) | Nadal's limit     |

Each criterion has its own two levels (a Limits field each): the three Y/Q rules start with the same
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
- wheel unloading ratio ΔQ/Q0 = (Q0 - Q)/Q0: GB 5599-85 gives 0.60 (allowable) and 0.65 (danger
  limit) (medium confidence: later Chinese codes, GB/T 5599-2019 and TB 10761, keep 0.6-0.65 for
  the dynamic ratio but with different evaluation windows and speed classes).

- running-gear unloading: EN 14067-6's crosswind criterion, the mean unloading ratio of a running gear's
  (bogie's) wheels on one side, limit 0.90 (as quoted in ../shared/reference/track-and-loads.md;
  medium confidence on the evaluation, the standard's filter is not applied here).
- derailment coefficient with a duration rule: Y/Q at or above its level for at least
  `duration_s` = 50 ms of time, not of track (AAR Manual of Standards, Chapter XI, single-wheel L/V
  1.0 over 50 ms, and the Japanese practice of a duration; medium confidence, as quoted in the
  issue tracker and TCRP Report 71; its CRITICAL level is Nadal's limit like the 2 m rule's). The time is
  counted in integer nanoseconds, the resolution of a ROS stamp, so that the node (which sees the stamps)
  and a batch evaluation (which sees the simulator's clock) decide every sample alike.
- flange-climb distance: TCRP Report 71 Vol. 5 (2005, Wu and Wilson) eq. 2.4, the distance over which a
  wheel's L/V may stay at Nadal's limit, falling with the attack angle (`climb_distance`: the formula, its
  constants and why their grouping is uncertain). Its limit is the CRITICAL level 1; the WARNING level
  at half of it is a modelling choice. The distance runs while Y/Q is at or above Nadal's limit with
  mu = 0.5 (climb_nadal_limit, 0.931 for LM on UIC60), whatever the scenario's friction: the rule of
  49 CFR 238 App. C, and the friction of TCRP's simulations.

One event, one alert: a value must stay at or above its level over `debounce_m` of track (default
2 m, the window length of EN 14363's Y/Q sliding mean) before the alert is raised, and the channel
re-arms only when the value has stayed below `rearm_fraction` x level (default 0.9) over `rearm_m`
of track (default 50 m, two car lengths: the dynamic unloading in a transition oscillates around
its level at a few metres' spacing). Each (criterion, level, wheel or wheelset) is its own channel.
"""
from __future__ import annotations

import functools
from importlib.resources import files
import math
from dataclasses import MISSING, asdict, dataclass, field, fields
from pathlib import Path

from railderail_sim.parameters import RUNNING_GEAR_UNLOADING_LIMIT
from railderail_sim.ranges import check_range
from railderail_sim.vehicle.layout import RUNNING_GEARS

from .alarms import nanoseconds
from .climb_distance import CLIMB_FRICTION, tcrp_coefficients

SIDES = ("left", "right")
CRITERIA = ("attack_angle", "wheel_lift", "derailment_coefficient", "wheel_unloading", "running_gear_unloading",
            "derailment_coefficient_duration", "derailment_coefficient_mean", "flange_climb_distance")
# a running gear's side by its leading wheelset, in the order of vehicle.layout.running_gear_sides
BOGIE_PLACES = tuple((gear[0], side) for gear in RUNNING_GEARS for side in SIDES)
SEVERITY_INFO, SEVERITY_WARNING, SEVERITY_CRITICAL = 0, 1, 2   # the Alert message's constants
# the criteria's two levels; the speed supervision's indication is an INFO (railderail_monitor/supervision)
SEVERITY_NAMES = {SEVERITY_INFO: "indication", SEVERITY_WARNING: "warning", SEVERITY_CRITICAL: "critical"}


def critical_name(criterion):
    """The Limits field of a criterion's CRITICAL level."""
    return criterion + "_critical"


TIMED = ("derailment_coefficient_duration",)      # their debounce is time, not track


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
        "", "derailment quotient Y/Q of each wheel, CRITICAL level",
        "Nadal's limit (tan d - mu)/(1 + mu tan d) at the profile pair's largest contact angle d, friction mu")
    derailment_coefficient_duration_critical: float = _level(
        "", "Y/Q held for duration_s, CRITICAL level",
        "Nadal's limit (tan d - mu)/(1 + mu tan d) at the profile pair's largest contact angle d, friction mu")
    derailment_coefficient_mean_critical: float = _level(
        "", "2 m sliding mean of Y/Q, CRITICAL level",
        "Nadal's limit (tan d - mu)/(1 + mu tan d) at the profile pair's largest contact angle d, friction mu")
    static_wheel_load: float = _value("N", "static wheel load Q0 of the unloading ratio (Q0 - Q)/Q0",
                                      "the car's load per wheel at rest on level track "
                                      "(VehicleParameters.static_wheel_load)")
    climb_nadal_limit: float = _value("", "Nadal's limit that starts the climb distance: Y/Q at or above it counts",
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
    derailment_coefficient: float = _level("", "derailment quotient Y/Q of each wheel, WARNING level",
                                           "EN 14363:2016 / UIC 518 limit (Y/Q)lim", 0.8)
    wheel_unloading: float = _level("", "wheel unloading ratio ΔQ/Q0 of each wheel, WARNING level",
                                    "GB 5599-85 allowable value", 0.60)
    wheel_unloading_critical: float = _level("", "wheel unloading ratio, CRITICAL level",
                                             "GB 5599-85 danger limit", 0.65)
    running_gear_unloading: float = _level("", "mean unloading ratio of a bogie's two wheels on one side, "
                                           "WARNING level", "EN 14067-6 limit of the running-gear unloading",
                                           RUNNING_GEAR_UNLOADING_LIMIT)
    running_gear_unloading_critical: float = _level("", "running-gear unloading, CRITICAL level",
                                                    "none in the sources, so disabled", math.nan)
    derailment_coefficient_duration: float = _level("", "Y/Q of each wheel held for duration_s, WARNING level",
                                                    "AAR Chapter XI single-wheel L/V limit", 1.0)
    derailment_coefficient_mean: float = _level("", "sliding mean of Y/Q over sliding_mean_m of track, each "
                                                "wheel, WARNING level", "EN 14363:2016 / UIC 518 limit (Y/Q)lim "
                                                "of the 2 m sliding mean", 0.8)
    flange_climb_distance: float = _level("", "track run with Y/Q at Nadal's limit over TCRP's limiting climb "
                                          "distance at the wheelset's attack angle, each wheel, WARNING level",
                                          "half TCRP's limit (a modelling choice)", 0.5)
    flange_climb_distance_critical: float = _level("", "flange-climb distance ratio, CRITICAL level",
                                                   "TCRP Report 71 Vol. 5 eq. 2.4: the limiting distance", 1.0)
    sliding_mean_m: float = _value("m", "track over which Y/Q is averaged for its sliding-mean criterion",
                                   "EN 14363:2016: 2 m", 2.0, (0.0, 100.0))
    duration_s: float = _value("s", "time Y/Q must stay at or above a level for the duration criterion",
                               "AAR Chapter XI: 50 ms", 0.05, (0.0, 10.0), False)
    debounce_m: float = _value("m", "track a value must stay at or above a level before its alert",
                               "the 2 m window of EN 14363's Y/Q sliding mean", 2.0, (0.0, 100.0), False)
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

