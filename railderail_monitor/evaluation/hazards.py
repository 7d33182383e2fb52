"""Ground truth of the warning evaluation: every sample of a run labelled by hazard, from the simulator's own
physics at the run's own friction, and the time a warning must come ahead to be of use.

Labels (for a derailment window W, `HazardRules.windows_s`):
  derailment  the last W before the derailment the core declared (`Simulation.derailment`);
  near miss   a safety margin fallen below its stated level (`MARGINS`), from W before it falls until it
              recovers, in a run that derails or not;
  normal      everything else: the exposure over which false alarms are counted.
A run is labelled by its margins, never by "it did not derail": a car running far beyond the line's
permitted cant deficiency whose margins hold is in normal running, and one whose margins fall is a near
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

Useful lead: a warning is of use when it comes early enough for the train to react and brake to a safe
speed before the hazard: reaction_s + brake_buildup_s + the braking time from the speed at the warning
to (1 - safe_speed_reduction) of it at the emergency deceleration of its speed band (`braking_time`).
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

from railderail_sim.assessment.en14363 import RMS_WINDOW_M
from railderail_sim.parameters import ContactParameters
from railderail_sim.supervision.braking import BrakingModel
from railderail_sim.vehicle.layout import RUNNING_GEARS

from ..onboard.criteria import sample_rate
from ..warning.quantities import sliding_mean, unloading_ratio

FOOT = 0.3048                        # m
NORMAL, NEAR_MISS, DERAILMENT = 0, 1, 2
LABELS = ("normal", "near_miss", "derailment")
SIDES = ("left", "right")
BOGIE_OF_WHEELSET = {ws: g for g, gear in enumerate(RUNNING_GEARS) for ws in gear}
PLACES = tuple((bogie, side) for bogie in range(len(RUNNING_GEARS)) for side in range(2))   # (bogie, 0 left/1 right)


def _rule(value, unit, meaning, source, sure):
    return field(default=value, metadata=dict(unit=unit, meaning=meaning, source=source, sure=sure))


def _braking(name):
    """A rule whose value, unit, source and sureness are the braking model's (railderail_sim.supervision)."""
    f = next(f for f in fields(BrakingModel) if f.name == name)
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
    unloading_level: float = _rule(0.90, "-", "near miss: a wheel's unloading dQ/Q0 at or above",
                                   "49 CFR 213.333 (single-wheel vertical load ratio >= 0.10); EN 14067-6 "
                                   "running-gear unloading 0.90", "B")
    margin_window_m: float = _rule(5.0 * FOOT, "m", "track over which the wheel margins are averaged",
                                   "49 CFR 213.333: the 5 ft window of the wheel-force limits", "B")
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
    lift_share: float = _rule(0.5, "-", "near miss: a wheel's lift at or above this share of the flange height",
                              "no standard value: half way up the flange (a modelling choice)", "-")
    low_pass_forces: bool = _rule(True, "-", "the wheel forces low-passed 20 Hz before their margins are judged",
                                 "EN 14363 / UIC 518: Y and Q through a 20 Hz low-pass (49 CFR 213.333: a cut-off "
                                 "of at least 25 Hz); unfiltered, the rigid track's wheel-force spikes of a few ms "
                                 "read as margins falling in ordinary running", "B")
    merge_m: float = _rule(50.0, "m", "near misses of one margin at one place closer than this are one",
                           "the monitor's re-arm distance (warning.limits.Limits.rearm_m)", "-")
    reaction_s: float = _braking("reaction_s")
    brake_buildup_s: float = _braking("buildup_s")
    deceleration_bands: tuple = _braking("emergency_bands")
    safe_speed_reduction: float = _rule(0.10, "-", "share of the speed to brake off before the hazard",
                                        "a modelling choice: the quasi-static curving loads fall with v^2 (19 % "
                                        "for 10 %); the report shows 0.05, 0.2 and 1 (stopping)", "-")
    permitted_cant_deficiency: float = _rule(0.150, "m", "the largest cant deficiency of ordinary running",
                                             "EN 13803 / TSI INF for high-speed lines (as quoted)", "C")

    def validated(self):
        for name in ("window_s", "unloading_level", "margin_window_m", "track_shift_alpha", "track_shift_window_m",
                     "instability_share", "instability_window_m", "lift_share", "reaction_s", "brake_buildup_s",
                     "permitted_cant_deficiency"):
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


def braking(rules):
    """The braking model of the rules' deceleration bands and times."""
    return BrakingModel(emergency_bands=rules.deceleration_bands, buildup_s=rules.brake_buildup_s,
                        reaction_s=rules.reaction_s)


def braking_time(rules, speed, reduction=None):
    """Time (s) to brake from `speed` (m/s) by `reduction` (the rules' share by default) of it, band by band."""
    reduction = rules.safe_speed_reduction if reduction is None else reduction
    return braking(rules).deceleration_time(speed, (1.0 - reduction) * speed)


def useful_lead(rules, speed, reduction=None):
    """The lead (s) a warning at `speed` (m/s) needs to be of use: reaction, brake build-up and braking."""
    return rules.reaction_s + rules.brake_buildup_s + braking_time(rules, speed, reduction)


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


def margins(arrays, car, rules):
    """{margin: (breached (n, channels) bool, the channels' places [(bogie, sides)])} of a run."""
    s = arrays["position"]
    wheel_places = [(BOGIE_OF_WHEELSET[k // 2], (k % 2,)) for k in range(8)]
    axle_places = [(BOGIE_OF_WHEELSET[w], (0, 1)) for w in range(4)]
    vertical, lateral = filtered_forces(arrays, rules)
    unloading = sliding_mean(unloading_ratio(vertical, car.static_wheel_load), s, rules.margin_window_m)
    # Q/P as the core defines it (`Wheel.derailment_coefficient`): 0 on a wheel carrying too little to mean it
    loaded = vertical > ContactParameters().derailment_coefficient_min_load * car.static_wheel_load
    qp = sliding_mean(np.where(loaded, lateral / np.where(loaded, vertical, 1.0), 0.0), s, rules.margin_window_m)
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


def windows(times, found, window_s):
    """Per place, the samples inside a hazard window of W = window_s (n,) bool, and each sample's label
    (n,): derailment within W before a derailment, near miss from W before a margin falls until it
    recovers, normal elsewhere."""
    t = np.asarray(times, dtype=float)
    label = np.full(len(t), NORMAL, dtype=np.int8)
    place = {p: np.zeros(len(t), dtype=bool) for p in PLACES}
    for h in found:
        inside = (t >= h["time_s"] - window_s) & (t <= h["end_s"])
        kind = DERAILMENT if h["kind"] == "derailment" else NEAR_MISS
        label[inside] = np.maximum(label[inside], kind)
        for p in h["places"]:
            place[tuple(p)] |= inside
    return place, label


def cant_deficiency(arrays, rail_spacing=1.5):
    """Cant deficiency (m) of each sample from its uncompensated acceleration in the track plane (EN 13803:
    D = e a / g on the rail spacing e)."""
    from railderail_sim.parameters import GRAVITY
    return np.asarray(arrays["uncompensated_acceleration"], dtype=float) * rail_spacing / GRAVITY
