"""Scoring a criterion's alarms against the hazards of a run (`hazards`), the way a real-time detector
benchmark scores (the Numenta Anomaly Benchmark's labelled windows), and its statistics over many runs.

A channel (a wheel, a wheelset or a running gear's side) is *in alarm* from the sample its alert is raised
until it re-arms (`warning.alarms.alarm_intervals`): what an operator sees. Then:
- **Attribution.** A channel in alarm inside a hazard's window, at the hazard's place (its running gear,
  and its side: a channel of a wheel or a side matches a hazard of that side; a channel of a whole
  wheelset, the attack angle, matches either side of its running gear), is a true warning of it; in alarm
  anywhere else it is a false alarm, in every run, derailing or not. A measured criterion has no wheel: a
  bogie frame's channel matches either side of its bogie, an estimated running-gear side its own side, and
  the car body's channels (its floor, roll and roll rate) either side of either bogie (`MEASURED_PLACES`).
- **Lead.** A hazard is warned when a matching channel is in alarm at some sample of its window before
  the hazard itself (the derailment, or the margin's fall); its lead is from the first such sample, so at
  most W: an alarm raised earlier and still on counts from the window's start, and its earlier part is a
  false alarm. It is *usefully* warned when that lead covers the time to react and brake
  (`hazards.useful_lead` at the speed of that sample).
- **Exposure.** False alarms are counted over normal running as episodes: the stretches of `EPISODE_M` of
  track along each run (a fixed grid from its start) in which some channel is in false alarm. A lower
  threshold keeps every alarm of a higher one (the detector's level and its re-arm level both fall), so the
  episodes, the time and the distance in alarm cannot fall as the threshold falls; a counted onset could
  (two alarms merge into one), which is why onsets are not counted.
- **Statistics.** Clopper-Pearson intervals on shares, exact Poisson (Garwood) intervals on rates, both
  95 %.
"""
from __future__ import annotations

import math

import numpy as np

from ..warning.limits import BOGIE_PLACES, SIDES
from ..warning.alarms import alarm_intervals
from .hazards import BOGIE_OF_WHEELSET, PLACES, useful_lead
from ..onboard import measured

EPISODE_M = 1000.0         # m: one false-alarm episode at most per km of a run's track (the grid of the count)
CONFIDENCE = 0.95


# The places a measured criterion's channel covers (onboard.measured.PLACES): a bogie frame's mount, both
# sides of its bogie (the frame's lateral acceleration has no side); an estimated running-gear side, itself;
# the car body's mounts, the air springs (its roll) and the twist between its bogies, either side of either
# bogie (the body carries both).
MEASURED_PLACES = {"bogie_front_frame": [(0, 0), (0, 1)], "bogie_rear_frame": [(1, 0), (1, 1)],
                   **{f"bogie_{bogie}_{side}": [(b, s)] for b, bogie in enumerate(("front", "rear"))
                      for s, side in enumerate(SIDES)},
                   **{unit: list(PLACES) for unit in ("car_body_front", "car_body_centre", "car_body_rear",
                                                      "air_springs", "front_minus_rear")}}


def channel_places(criterion, channels):
    """The places (bogie, side) each channel of a criterion covers."""
    if criterion in measured.PLACES:
        return [MEASURED_PLACES[unit] for unit in measured.PLACES[criterion]]
    if criterion == "attack_angle":
        return [[(BOGIE_OF_WHEELSET[0], 0), (BOGIE_OF_WHEELSET[0], 1)]]
    if criterion == "running_gear_unloading":
        return [[(BOGIE_OF_WHEELSET[ws], 0 if side == "left" else 1)] for ws, side in BOGIE_PLACES]
    if channels == 8:
        return [[(BOGIE_OF_WHEELSET[k // 2], k % 2)] for k in range(8)]
    raise ValueError(f"criterion {criterion!r} with {channels} channels has no places")


def in_alarm(values, position, threshold, held, rearm_fraction, rearm_m, clock=None):
    """(n,) bool: the channel is in alarm (`warning.alarms.alarm_intervals`)."""
    mask = np.zeros(len(position), dtype=bool)
    for a, b in alarm_intervals(values, position, threshold, held, rearm_fraction, rearm_m, clock):
        mask[a:b] = True
    return mask


def score(alarms, places, arrays, found, window_s, place_windows, label):
    """One criterion at one threshold in one run: alarms (channels, n) bool, their places, the run's
    hazards and, for the window W = window_s, its windows (`hazards.windows`). Returns {warnings: [(lead_s, speed at its first sample) or None
    per hazard], false_episodes, false_time_s, false_km}."""
    t, s, v = (np.asarray(arrays[k], dtype=float) for k in ("time", "position", "speed"))
    true = np.array([np.any([place_windows[p] for p in ps], axis=0) for ps in places])
    false = np.any(alarms & ~true, axis=0)
    warnings = []
    for h in found:
        matching = [c for c, ps in enumerate(places) if any(tuple(p) in ps for p in h["places"])]
        inside = (t >= h["time_s"] - window_s) & (t < h["time_s"])
        hit = np.flatnonzero(inside & np.any(alarms[matching], axis=0)) if matching else []
        warnings.append(None if not len(hit) else (float(h["time_s"] - t[hit[0]]), float(v[hit[0]])))
    normal = label == 0
    dt = np.diff(t, prepend=t[0])
    ds = np.diff(s, prepend=s[0])
    bins = np.floor((s - s[0]) / EPISODE_M).astype(np.int64)
    return dict(warnings=warnings, false_episodes=int(len(np.unique(bins[false]))),
                false_time_s=float(np.sum(dt[false & normal])), false_km=float(np.sum(ds[false & normal])) / 1e3)


def exposure(arrays, label):
    """(normal km, normal h) of a run."""
    t, s = np.asarray(arrays["time"], dtype=float), np.asarray(arrays["position"], dtype=float)
    normal = label == 0
    return float(np.sum(np.diff(s, prepend=s[0])[normal])) / 1e3, float(np.sum(np.diff(t, prepend=t[0])[normal])) / 3600.0


def share_interval(k, n, confidence=CONFIDENCE):
    """Clopper-Pearson interval [lo, hi] of a share k of n ([nan, nan] for n = 0)."""
    if n == 0:
        return [math.nan, math.nan]
    from scipy.stats import beta
    a = 1.0 - confidence
    lo = 0.0 if k == 0 else float(beta.ppf(a / 2, k, n - k + 1))
    hi = 1.0 if k == n else float(beta.ppf(1 - a / 2, k + 1, n - k))
    return [lo, hi]


def count_interval(k, confidence=CONFIDENCE):
    """Exact (Garwood) Poisson interval [lo, hi] of a count k."""
    from scipy.stats import chi2
    a = 1.0 - confidence
    lo = 0.0 if k == 0 else float(chi2.ppf(a / 2, 2 * k)) / 2.0
    return [lo, float(chi2.ppf(1 - a / 2, 2 * k + 2)) / 2.0]


def rate_per_1000_km(k, km, confidence=CONFIDENCE):
    """(rate, [lo, hi]) of k events over km, per 1000 km (nan over no exposure)."""
    if not km > 0.0:
        return math.nan, [math.nan, math.nan]
    lo, hi = count_interval(k, confidence)
    return 1000.0 * k / km, [1000.0 * lo / km, 1000.0 * hi / km]


def resolvable_km(budget_per_1000_km, confidence=CONFIDENCE):
    """The exposure (km) below which even no false alarm leaves the rate's upper bound above the budget
    (about 3 / budget at 95 %)."""
    return 1000.0 * count_interval(0, confidence)[1] / budget_per_1000_km


def is_useful(warning, rules, reduction=None):
    """A warning (lead_s, speed) is of use (`hazards.useful_lead`)."""
    return warning is not None and warning[0] >= useful_lead(rules, warning[1], reduction)
