"""Ground truth of the warning evaluation: every sample of a run labelled by hazard, from the simulator's own
physics at the run's own friction, and the time a warning must come ahead to be of use.

Labels (for a derailment window W, `HazardRules.windows_s`):
  derailment  the last W before the derailment the core declared (`Simulation.derailment`);
  near miss   a safety margin fallen below its stated level (`MARGINS`), from W before it falls until it
              recovers, in a run that derails or not;
  beyond permitted  outside every hazard window, running beyond the line's permitted conditions (above
              its permitted speed, or above the permitted cant deficiency) with every margin intact: neither
              a hazard nor the exposure; an alarm there is neither credited nor false (`beyond_permitted`);
  normal      everything else: running within permitted conditions, the exposure over which false alarms
              are counted.
A run is labelled by its margins, never by "it did not derail": a car running far beyond the line's
permitted cant deficiency whose margins hold is beyond permitted, and one whose margins fall is a near
miss. Each hazard has a place: a running gear (bogie) and the side of the wheel whose margin fell, or both
sides for the track-shift force of a wheelset; a warning is true only at its hazard's place
(`scoring`). The margins, with their sources and how sure each is (the standards are paywalled; the
figures are as quoted in ../shared/reference/ and docs/warning-evaluation.md):

| margin | quantity, evaluation | level | source |
|---|---|---|---|
| `wheel_unloading` | dQ/Q0 of a wheel (20 Hz), mean over 1.524 m (5 ft) | 0.90 | 49 CFR 213.333 (vertical wheel load >= 10 % of static over 5 ft); EN 14067-6's 0.90 of a running gear |
| `flange_climb` | Q/P of a wheel (20 Hz), mean over 1.524 m | Nadal's limit at the run's friction | 49 CFR 213.333 single-wheel L/V (Nadal, 5 ft) with the friction the simulator knows |
| `track_shift` | \\|sum Y\\| of a wheelset (20 Hz), mean over 2 m | Prud'homme alpha (10 + P0/3) kN, alpha 1 | EN 14363 / UIC 518 (sum Y)2m,lim, P0 the static axle load in kN |
| `instability` | sum Y of a wheelset (20 Hz), band-passed f0 +- 2 Hz, r.m.s. over 100 m | half Prud'homme's limit | EN 14363 / UIC 518 (sum Y)rms,lim: the running is unstable (hunting) |
| `wheel_lift` | lift of a wheel | half the flange height | no standard value: half way up the flange, a modelling choice (sensitivity in the report) |

The flange-climb margin is Nadal's limit at the run's own friction, not 49 CFR 213.333's L/V limit (Nadal
at friction 0.5): the simulator knows the friction and the wheel climbs by it; both limits and the peak Q/P
are kept per run (`flange_climb_limits`) so that the report shows the runs over each.

Useful lead: a warning is of use when it comes early enough for the train to react and brake to the speed
that cures its hazard (`hazard_cure`: by mechanism) before it: reaction_s + brake_buildup_s + the braking
time from the speed at the warning down to that speed at the emergency deceleration of each speed band
(`braking_time`), on dry rail, and shown beside on wet rail (the braking model's degraded-adhesion bands,
railderail_sim/supervision/braking.py). The braking is timed,
not placed: braking covers less track than running on in the same time, so a warning that brakes in time
also brakes before the hazard's place.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields
import math

import numpy as np

from railderail_sim.assessment.en14363 import RMS_WINDOW_M
from railderail_sim.parameters import ContactParameters
from railderail_sim.methods.survey import SurveyRules
from railderail_sim.supervision.braking import BrakingModel
from railderail_sim.vehicle.layout import RUNNING_GEARS

from ..onboard.criteria import sample_rate
from ..warning.quantities import sliding_mean, unloading_ratio

FOOT = 0.3048                        # m
NORMAL, NEAR_MISS, DERAILMENT, BEYOND_PERMITTED = 0, 1, 2, 3
LABELS = ("normal", "near_miss", "derailment", "beyond_permitted")
# the characteristic wind curves of the shipped car (railderail cwc, docs/report/cwc.json: the running gear's
# unloading 0.9 under the CEN gust): train speed km/h -> wind m/s on straight track and on a curve at 1 m/s^2
CWC_SPEEDS_KMH = (200.0, 220.0, 240.0, 260.0, 280.0, 300.0, 320.0, 340.0, 360.0)
CWC_STRAIGHT_M_S = (48.046875, 47.265625, 45.703125, 44.296875, 43.203125, 42.734375, 41.796875, 40.390625,
                    39.453125)
CWC_CURVE_M_S = (42.265625, 41.328125, 40.234375, 38.828125, 38.203125, 35.234375, 34.921875, 35.078125, 35.234375)
SIDES = ("left", "right")
BOGIE_OF_WHEELSET = {ws: g for g, gear in enumerate(RUNNING_GEARS) for ws in gear}
PLACES = tuple((bogie, side) for bogie in range(len(RUNNING_GEARS)) for side in range(2))   # (bogie, 0 left/1 right)


def _rule(value, unit, meaning, source, sure):
    return field(default=value, metadata=dict(unit=unit, meaning=meaning, source=source, sure=sure))


def _defined_in(record, name):
    """A rule whose value, unit, source and sureness are a field of `record`, a parameter table of railderail_sim
    (the braking model's, the survey's hazard margins), so that each is defined once."""
    f = next(f for f in fields(record) if f.name == name)
    return _rule(f.default, f.metadata["unit"], f.metadata["note"], f.metadata["source"], f.metadata["sure"])


@dataclass(frozen=True)
class HazardRules:
    """The labelling rule and the braking model of the evaluation, each value with unit, source and how sure
    (A read in a primary text, B several secondary sources agree, C one source or recalled)."""
    windows_s: tuple = _rule((5.0, 10.0, 20.0, 40.0), "s", "derailment windows W the evaluation is shown for",
                             "Numenta Anomaly Benchmark's labelled windows before each event; the lengths a "
                             "modelling choice (the useful lead at 300 km/h is about 13 s)", "-")
    window_s: float = _rule(20.0, "s", "the derailment window of the recommendation and of the runs' rows",
                            "a modelling choice: longer than the useful lead at the catalogue's top speeds", "-")
    unloading_level: float = _defined_in(SurveyRules, "unloading_level")
    margin_window_m: float = _defined_in(SurveyRules, "margin_window_m")
    track_shift_alpha: float = _rule(1.0, "-", "Prud'homme's alpha of the track-shift limit",
                                     "EN 14363 / UIC 518: alpha = 1 for passenger vehicles", "B")
    track_shift_window_m: float = _rule(2.0, "m", "track over which the track-shift force is averaged",
                                        "EN 14363: (sum Y)2m, the 2 m sliding mean", "B")
    instability_share: float = _rule(0.5, "-", "near miss (instability): a wheelset's sum Y band-passed f0 +- 2 Hz, "
                                     "its r.m.s. over instability_window_m, at or above this share of the "
                                     "track-shift limit", "EN 14363 / UIC 518 (sum Y)rms,lim = (sum Y)2m,lim / 2",
                                     "B (formula), C (window)")
    instability_window_m: float = _rule(RMS_WINDOW_M, "m", "track over which the instability r.m.s. is taken",
                                        "EN 14363: 100 m sliding r.m.s. (en14363.RMS_WINDOW_M)", "C")
    lift_share: float = _defined_in(SurveyRules, "lift_share")
    low_pass_forces: bool = _rule(True, "-", "the wheel forces low-passed 20 Hz before their margins are judged",
                                 "EN 14363 / UIC 518: Y and Q through a 20 Hz low-pass (49 CFR 213.333: a cut-off "
                                 "of at least 25 Hz); unfiltered, the rigid track's wheel-force spikes of a few ms "
                                 "read as margins falling in ordinary running", "B")
    merge_m: float = _rule(50.0, "m", "near misses of one margin at one place closer than this are one",
                           "the monitor's re-arm distance (warning.limits.Limits.rearm_m)", "-")
    reaction_s: float = _defined_in(BrakingModel, "reaction_s")
    brake_buildup_s: float = _defined_in(BrakingModel, "buildup_s")
    deceleration_bands: tuple = _defined_in(BrakingModel, "emergency_bands")
    safe_speed_reduction: float = _rule(0.10, "-", "share of the speed to brake off where no cure is known "
                                        "(`hazard_cure`: straight track, no gust, defect or hunting)",
                                        "a modelling choice: the quasi-static loads fall with v^2 (19 % for 10 "
                                        "%); the report's braking sensitivity shows 0.05, 0.2 and 1 (stopping) "
                                        "for every hazard", "-")
    critical_uncompensated_acceleration: float = _rule(
        5.18, "m/s^2", "the car's critical derailment speed on a curve: where the uncompensated acceleration "
        "reaches this", "the smallest of the shipped progressive trials on ideal track, R 800-1800 m at 175 mm "
        "(docs/report/report.json: 258.1-384.3 km/h, 5.18-5.28 m/s^2; a test holds it to them); irregular track "
        "derails about 2 % lower in speed", "A (own simulation)")
    critical_speed_margin: float = _rule(1.1, "-", "over-speed is cured below the critical derailment speed over "
                                         "this factor", "EN 14363's margin of 1.1 on a critical speed (as the "
                                         "catalogue's admissible speed takes it), applied to the derailment speed: "
                                         "covers the 2 % of irregular track", "C")
    nonlinear_critical_speed_kmh: float = _rule(234.375, "km/h", "hunting is cured below the car's nonlinear "
                                                "critical speed (a fault's own, given by its catalogue entry, wins)",
                                                "the shipped limit-cycle scan (docs/report/report.json: 10 mm kink)",
                                                "A (own simulation)")
    permitted_cant_deficiency: float = _rule(0.150, "m", "the largest cant deficiency of ordinary running",
                                             "EN 13803 / TSI INF for high-speed lines (as quoted)", "C")

    def validated(self):
        for name in ("window_s", "unloading_level", "margin_window_m", "track_shift_alpha", "track_shift_window_m",
                     "instability_share", "instability_window_m", "lift_share", "reaction_s", "brake_buildup_s",
                     "permitted_cant_deficiency", "critical_uncompensated_acceleration",
                     "critical_speed_margin", "nonlinear_critical_speed_kmh"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"{name} {getattr(self, name)!r} must be positive")
        if not 0.0 < self.safe_speed_reduction <= 1.0:
            raise ValueError(f"safe_speed_reduction {self.safe_speed_reduction!r} is outside (0, 1]")
        if self.window_s not in self.windows_s:
            raise ValueError(f"window_s {self.window_s:g} s is not one of windows_s {self.windows_s}")
        return self

    def table(self):
        """Rows (name, value, unit, meaning, source, sure) for the report."""
        return [(f.name, getattr(self, f.name), *(f.metadata[k] for k in ("unit", "meaning", "source", "sure")))
                for f in fields(self)]


def braking(rules, adhesion="dry"):
    """The braking model of the rules' deceleration bands and times, on dry rail or on wet (its degraded-adhesion
    bands, railderail_sim.supervision.braking)."""
    return BrakingModel(emergency_bands=rules.deceleration_bands, buildup_s=rules.brake_buildup_s,
                        reaction_s=rules.reaction_s, adhesion=adhesion)


def braking_time(rules, speed, reduction=None, adhesion="dry"):
    """Time (s) to brake from `speed` (m/s) by `reduction` (the rules' share by default) of it, band by band."""
    reduction = rules.safe_speed_reduction if reduction is None else reduction
    return braking(rules, adhesion).deceleration_time(speed, (1.0 - reduction) * speed)


def useful_lead(rules, speed, reduction=None, adhesion="dry"):
    """The lead (s) a warning at `speed` (m/s) needs to be of use: reaction, brake build-up and braking."""
    return rules.reaction_s + rules.brake_buildup_s + braking_time(rules, speed, reduction, adhesion)


def line_numbers(line):
    """A line (`catalogue.Entry.line`) with JSON's nulls read back: a cached run's infinite radius and class
    speed and its unknown critical speed are written as null (`jsonout`)."""
    unknown = dict(radius_m=math.inf, class_speed_kmh=math.inf, critical_speed_kmh=math.nan)
    return {**line, **{k: v for k, v in unknown.items() if line.get(k) is None}}


def permitted_speed(line, rules):
    """The line's permitted speed (m/s): its track class's, and on a curve the speed at the permitted cant
    deficiency (`line`: `catalogue.Entry.line`)."""
    line = line_numbers(line)
    from railderail_sim.parameters import GRAVITY
    top = line["class_speed_kmh"] / 3.6
    if math.isinf(line["radius_m"]):
        return top
    curve = math.sqrt(line["radius_m"] * GRAVITY * (line["cant_m"] + rules.permitted_cant_deficiency)
                      / line["rail_spacing_m"])
    return min(top, curve)


def critical_derailment_speed(line, rules):
    """The curve's critical derailment speed (m/s) where the run cannot tell it: where the uncompensated
    acceleration v^2/R - g h/e reaches the car's critical one (`critical_uncompensated_acceleration`), a
    closed form per curve; inf on straight track. A catalogue entry's own `critical_speed_kmh` wins."""
    line = line_numbers(line)
    from railderail_sim.parameters import GRAVITY
    if math.isfinite(line["critical_speed_kmh"]):
        return line["critical_speed_kmh"] / 3.6
    if math.isinf(line["radius_m"]):
        return math.inf
    return math.sqrt(line["radius_m"] * (rules.critical_uncompensated_acceleration
                                         + GRAVITY * line["cant_m"] / line["rail_spacing_m"]))


def characteristic_wind_speed_kmh(wind_m_s, curved):
    """The highest train speed (km/h) of the characteristic wind curve (straight track, or a curve at
    1 m/s^2) at which a gust of `wind_m_s` leaves the margins intact; 0 (a stop) above the curve's slowest
    point, 360 below its fastest (the tabled range)."""
    winds = np.asarray(CWC_CURVE_M_S if curved else CWC_STRAIGHT_M_S)
    speeds = np.asarray(CWC_SPEEDS_KMH)
    below = np.flatnonzero(winds >= wind_m_s)
    if not len(below):
        return 0.0
    k = below[-1]
    if k == len(speeds) - 1:
        return float(speeds[-1])
    # between the last tabled speed the gust is within and the next (whose wind is below the gust), linearly
    w0, w1 = winds[k], winds[k + 1]
    return float(speeds[k] + (speeds[k + 1] - speeds[k]) * (w0 - wind_m_s) / (w0 - w1))


def hazard_cure(rules, hazard, line):
    """What cures a hazard of a run on `line` (`catalogue.Entry.line`), by its mechanism: {mechanism,
    speed_kmh (0 a stop), permitted_speed_kmh, critical_speed_kmh (the speed the cure keeps under, or null),
    basis}. A gust: the characteristic wind curve's speed at the gust's peak; a defect or twist: a stop before
    it; hunting (a failed yaw damper, or the instability margin): below the nonlinear critical speed; another
    fault: below the entry's critical speed if it gives one, else a stop; over-speed on a curve: below its
    critical derailment speed over EN 14363's margin; else the rules' share off."""
    line = line_numbers(line)
    permitted = permitted_speed(line, rules) * 3.6
    speed = hazard["speed_m_s"] * 3.6
    critical = None
    if line["gust_m_s"] > 0.0:
        mechanism, cure = "gust overturning", characteristic_wind_speed_kmh(line["gust_m_s"],
                                                                             math.isfinite(line["radius_m"]))
        basis = f"the characteristic wind curve at the gust's {line['gust_m_s']:g} m/s"
    elif line["defect"]:
        mechanism, cure, basis = "flange climb at a defect", 0.0, "a stop before the defect"
    elif line["hunting"] or hazard["margin"] == "instability":
        critical = line["critical_speed_kmh"] if line["hunting"] and math.isfinite(line["critical_speed_kmh"]) \
            else rules.nonlinear_critical_speed_kmh
        mechanism, cure, basis = "hunting", critical, "below the car's nonlinear critical speed"
    elif line["faults"] and math.isnan(line["critical_speed_kmh"]):
        mechanism, cure, basis = "fault-driven", 0.0, "a stop: the fault's own critical speed is not known"
    elif math.isfinite(line["radius_m"]) or math.isfinite(line["critical_speed_kmh"]):
        critical = critical_derailment_speed(line, rules) * 3.6
        mechanism, cure = "over-speed", critical / rules.critical_speed_margin
        basis = (f"the curve's critical derailment speed {critical:.0f} km/h over {rules.critical_speed_margin:g}")
    else:
        mechanism, cure = "unnamed", (1.0 - rules.safe_speed_reduction) * speed
        basis = f"no cure known: {rules.safe_speed_reduction:.0%} off the speed"
    if line["faults"]:
        mechanism = f"{mechanism} with {', '.join(line['faults'])}"
    return dict(mechanism=mechanism, speed_kmh=float(cure), permitted_speed_kmh=float(permitted),
                critical_speed_kmh=critical, basis=basis)


def lead_needed(rules, speed, cure_kmh, adhesion="dry"):
    """The lead (s) a warning at `speed` (m/s) needs to brake to a cure speed (km/h) before its hazard: reaction
    and brake build-up, and the braking (none when the train is already below it)."""
    reduction = max(0.0, 1.0 - cure_kmh / 3.6 / speed) if speed > 0.0 else 0.0
    return useful_lead(rules, speed, reduction, adhesion)


def flange_climb_limits(car):
    """(Nadal's limit at the run's friction, 49 CFR 213.333's single-wheel L/V limit: Nadal at friction 0.5)
    at the profile pair's largest contact angle."""
    from railderail_sim.contact.nadal import nadal_limit
    return car.nadal, float(nadal_limit(car.max_contact_angle, CFR_FRICTION))


CFR_FRICTION = 0.5      # 49 CFR 213.333 / 238 App. C: the single-wheel L/V limit is Nadal's at this friction


def beyond_permitted(arrays, line, rules):
    """(n,) bool: running beyond the line's permitted conditions, above its permitted speed or above the
    permitted cant deficiency (`permitted_speed`, `cant_deficiency`)."""
    line = line_numbers(line)
    v = np.asarray(arrays["speed"], dtype=float)
    return ((v > permitted_speed(line, rules) * (1.0 + 1e-9))
            | (cant_deficiency(arrays, line["rail_spacing_m"]) > rules.permitted_cant_deficiency + 1e-9))


def track_shift_force(lateral_force):
    """|sum Y| of each wheelset (n, 4), N, in track axes, from the wheels' lateral forces on the rails (n, 8),
    each + toward its rail's field side (docs/output-format.md): the left wheel's + left, the right's + right."""
    q = np.asarray(lateral_force, dtype=float)
    return np.abs(q[:, 0::2] - q[:, 1::2])


@dataclass(frozen=True)
class Car:
    """What the margins take from the car and the run: flange height (m), the profile pair's largest
    contact angle (rad), static wheel load (N), the run's friction."""
    flange_height: float
    max_contact_angle: float
    static_wheel_load: float
    friction: float

    @property
    def nadal(self):
        from railderail_sim.contact.nadal import nadal_limit
        return float(nadal_limit(self.max_contact_angle, self.friction))

    def track_shift_limit(self, rules):
        """Prud'homme's limit alpha (10 + P0/3) kN in N, P0 the static axle load in kN."""
        return rules.track_shift_alpha * (10.0 + 2.0 * self.static_wheel_load / 1000.0 / 3.0) * 1000.0


def filtered_forces(arrays, rules):
    """(P, Q) of every wheel (n, 8), N: the vertical and the lateral force on the rail through the standards'
    force low-pass (`assessment.filters.force_low_pass`, EN 14363's 20 Hz) at the run's output rate, so that a
    margin is judged on the forces the standards judge; a record too short to filter is taken as it is."""
    from railderail_sim.assessment.filters import force_low_pass
    t = np.asarray(arrays["time"], dtype=float)
    vertical, lateral = (np.asarray(arrays[k], dtype=float) for k in ("vertical_force", "lateral_force"))
    if not rules.low_pass_forces or len(t) < 2:
        return vertical, lateral
    rate = sample_rate(t)
    return tuple(settled(force_low_pass(), x, rate) for x in (vertical, lateral))


def settled(analog, x, rate):
    """x (axis 0 time) through an `assessment.filters.AnalogFilter` at `rate` Hz, settled on the first sample:
    the filter is a periodic one (`AnalogFilter.apply`), so two seconds of the first sample go in front, where
    the record's end wraps round, and are cut off."""
    pad = int(round(2.0 * rate))
    return analog.apply(np.concatenate([np.repeat(x[:1], pad, axis=0), x]), rate)[pad:]


def stability_band(arrays, lateral):
    """Each wheelset's sum Y (n, 4), N, band-passed f0 +- 2 Hz (`assessment.filters.stability_band_pass`)
    about the run's instability frequency f0: the Welch peak of the four sums in EN 14363's search band
    (`en14363.INSTABILITY_BAND_HZ`); zeros for a record too short to have a spectrum."""
    from railderail_sim.assessment.en14363 import spectral_peak
    from railderail_sim.assessment.filters import stability_band_pass
    lateral = np.asarray(lateral, dtype=float)
    sum_y = lateral[:, 0::2] - lateral[:, 1::2]
    if len(sum_y) < 2:
        return np.zeros_like(sum_y)
    rate = sample_rate(arrays["time"])
    f0 = spectral_peak(sum_y, rate)
    return np.zeros_like(sum_y) if f0 is None else settled(stability_band_pass(f0), sum_y, rate)


def margin_q_over_p(vertical, lateral, position, car, rules):
    """Each wheel's Q/P (n, 8) as the core defines it (`Wheel.derailment_coefficient`: 0 on a wheel carrying
    too little to mean it), its mean over the margin's window."""
    loaded = vertical > ContactParameters().derailment_coefficient_min_load * car.static_wheel_load
    return sliding_mean(np.where(loaded, lateral / np.where(loaded, vertical, 1.0), 0.0), position,
                        rules.margin_window_m)


def margin_peaks(arrays, car, rules):
    """What the report shows of a run's margins beside their levels: the largest Q/P (the margin's 5 ft mean)
    against Nadal's limit at the run's friction and at 49 CFR 213.333's (`flange_climb_limits`), and the
    largest wheel lift as a share of the flange height (the lift level's sensitivity)."""
    qp = margin_q_over_p(*filtered_forces(arrays, rules), arrays["position"], car, rules)
    run_friction, cfr = flange_climb_limits(car)
    return dict(q_over_p_max=float(np.max(qp, initial=0.0)), nadal_run_friction=run_friction, nadal_cfr=cfr,
                lift_share_max=float(np.max(arrays["wheel_lift"], initial=0.0)) / car.flange_height)


def margins(arrays, car, rules):
    """{margin: (breached (n, channels) bool, the channels' places [(bogie, sides)])} of a run."""
    s = arrays["position"]
    wheel_places = [(BOGIE_OF_WHEELSET[k // 2], (k % 2,)) for k in range(8)]
    axle_places = [(BOGIE_OF_WHEELSET[w], (0, 1)) for w in range(4)]
    vertical, lateral = filtered_forces(arrays, rules)
    unloading = sliding_mean(unloading_ratio(vertical, car.static_wheel_load), s, rules.margin_window_m)
    qp = margin_q_over_p(vertical, lateral, s, car, rules)
    shift = sliding_mean(track_shift_force(lateral), s, rules.track_shift_window_m)
    instability = np.sqrt(sliding_mean(stability_band(arrays, lateral) ** 2, s, rules.instability_window_m))
    return {"wheel_unloading": (unloading >= rules.unloading_level, wheel_places),
            "flange_climb": (qp >= car.nadal, wheel_places),
            "track_shift": (shift >= car.track_shift_limit(rules), axle_places),
            "instability": (instability >= rules.instability_share * car.track_shift_limit(rules), axle_places),
            "wheel_lift": (np.asarray(arrays["wheel_lift"]) >= rules.lift_share * car.flange_height, wheel_places)}


def _episodes(mask, position, merge_m):
    """[(first, last)] sample ranges where `mask` holds, those less than merge_m of track apart merged."""
    idx = np.flatnonzero(mask)
    if not len(idx):
        return []
    breaks = np.flatnonzero(np.diff(idx) > 1)
    starts, ends = np.r_[idx[0], idx[breaks + 1]], np.r_[idx[breaks], idx[-1]]
    out = [[int(starts[0]), int(ends[0])]]
    for a, b in zip(starts[1:], ends[1:]):
        if position[a] - position[out[-1][1]] < merge_m:
            out[-1][1] = int(b)
        else:
            out.append([int(a), int(b)])
    return [tuple(x) for x in out]


def hazards(arrays, derailment, car, rules):
    """The run's hazards, in time order: dicts with kind ('derailment' or 'near_miss'), margin (for a near
    miss), time_s (the derailment, or the margin's fall), end_s, speed_m_s, position_m and places [(bogie,
    side)]."""
    t, s, v = arrays["time"], arrays["position"], arrays["speed"]
    out = []
    for name, (breached, places) in margins(arrays, car, rules).items():
        for k, (bogie, sides) in enumerate(places):
            for a, b in _episodes(breached[:, k], s, rules.merge_m):
                out.append(dict(kind="near_miss", margin=name, time_s=float(t[a]), end_s=float(t[b]),
                                speed_m_s=float(v[a]), position_m=float(s[a]),
                                places=[(bogie, side) for side in sides]))
    if derailment is not None:
        side = SIDES.index(derailment["wheel_side"])
        out.append(dict(kind="derailment", margin=derailment["mechanism"], time_s=float(derailment["time_s"]),
                        end_s=float(derailment["time_s"]), speed_m_s=float(derailment["speed_kmh"]) / 3.6,
                        position_m=float(derailment["car_body_position_m"]),
                        places=[(BOGIE_OF_WHEELSET[derailment["wheelset"]], side)]))
    return sorted(out, key=lambda h: (h["time_s"], h["kind"], h["margin"]))


def with_cure_leads(found, line, rules):
    """The hazards with `cure_lead_s`: the lead a warning at the hazard's speed needs to brake to its cure
    (`hazard_cure`), the larger of dry and wet rail. A hazard's window is at least this long (`window_of`):
    an alarm standing since then is a warning of use, however far ahead (a speed supervision's warning comes
    as far ahead as the braking to the cure takes), and the fixed window W alone would cap every lead below
    what a cure by braking from high speed needs (40 s to stop from 160 km/h on dry rail)."""
    out = []
    for h in found:
        cure = hazard_cure(rules, h, line)["speed_kmh"]
        lead = max(lead_needed(rules, h["speed_m_s"], cure, adhesion) for adhesion in ("dry", "wet"))
        out.append(dict(h, cure_lead_s=float(lead)))
    return out


def window_of(hazard, window_s):
    """The window (s) before a hazard at the window W = window_s: W, or the lead its cure needs where that is
    longer (`with_cure_leads`)."""
    return max(window_s, hazard.get("cure_lead_s", 0.0))


def windows(times, found, window_s, beyond=None):
    """Per place, the samples inside a hazard window of W = window_s (n,) bool, and each sample's label
    (n,): derailment within the hazard's window (`window_of`: W, or the lead its cure needs where longer)
    before a derailment, near miss from that window before a margin falls until it recovers, beyond
    permitted where `beyond` (n,) bool holds outside these, normal elsewhere."""
    t = np.asarray(times, dtype=float)
    label = np.full(len(t), NORMAL, dtype=np.int8)
    place = {p: np.zeros(len(t), dtype=bool) for p in PLACES}
    for h in found:
        inside = (t >= h["time_s"] - window_of(h, window_s)) & (t <= h["end_s"])
        kind = DERAILMENT if h["kind"] == "derailment" else NEAR_MISS
        label[inside] = np.maximum(label[inside], kind)
        for p in h["places"]:
            place[tuple(p)] |= inside
    if beyond is not None:
        label[(label == NORMAL) & np.asarray(beyond, dtype=bool)] = BEYOND_PERMITTED
    return place, label


def cant_deficiency(arrays, rail_spacing=1.5):
    """Cant deficiency (m) of each sample from its uncompensated acceleration in the track plane (EN 13803:
    D = e a / g on the rail spacing e)."""
    from railderail_sim.parameters import GRAVITY
    return np.asarray(arrays["uncompensated_acceleration"], dtype=float) * rail_spacing / GRAVITY
