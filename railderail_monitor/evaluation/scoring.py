"""Scoring a criterion's alarms against the hazards of a run (`hazards`), the way a real-time detector
benchmark scores (the Numenta Anomaly Benchmark's labelled windows), and its statistics over many runs.

A channel (a wheel, a wheelset or a running gear's side) is *in alarm* from the sample its alert is raised
until it re-arms (`warning.alarms.alarm_intervals`): what an operator sees. Then:
- **Place.** A channel matches a hazard at its place (its running gear, and its side: a channel of a wheel
  or a side matches a hazard of that side; a channel of a whole wheelset, the attack angle, either side of
  its running gear). A measured criterion has no wheel: a bogie frame's channel matches either side of its
  bogie, an estimated running-gear side its own side, and the car body's channels (its floor, roll and roll
  rate) either side of either bogie (`MEASURED_PLACES`).
- **Credit: only an alarm standing at the hazard.** A hazard is warned when a matching channel is in alarm
  at the hazard's last sample before its time (the derailment, or the margin's fall). Its lead runs from the
  start of that channel's alarm episode (the earliest of the matching channels standing), capped at the
  hazard's window (W, or the lead its cure needs where longer, `hazards.window_of`): an episode raised
  earlier counts from the window's start. An alarm that ended before the hazard
  is not a warning of it, and the hazard is unwarned unless a later one stands. It is *usefully* warned when
  the lead covers the lead needed to brake to the hazard's cure (`hazards.hazard_cure`, `hazards.lead_needed`,
  at the speed of the credited start).
- **True and false.** The credited episode from its (capped) start to the hazard, and a matching channel's
  alarm while the hazard lasts (a near miss until its margin recovers), are true; every other sample in
  alarm is false, in every run, derailing or not.
- **Exposure: one footing.** False alarms are counted over normal running only (`hazards.NORMAL`: outside
  every hazard window, within the line's permitted conditions), the running their rate is divided by: as
  episodes, the stretches of `EPISODE_M` of track along each run (a fixed grid from its start) in which some
  channel is in false alarm at a normal sample. False alarms inside a hazard's window (an alarm that ended
  before the hazard, or one at another place) are counted apart (`window_false_episodes`), and those beyond
  permitted running neither counted nor credited. A lower threshold keeps every alarm of a higher one (the
  detector's level and its re-arm level both fall), and no normal sample is ever true, so the episodes, the
  time and the distance in false alarm cannot fall as the threshold falls; a counted onset could (two alarms
  merge into one), which is why onsets are not counted.
- **Statistics.** Clopper-Pearson intervals on shares and exact Poisson (Garwood) intervals on rates, both
  95 %, which take the runs as independent; beside them a bootstrap over scenarios (`cluster_bootstrap`:
  the runs of one scenario resampled together, seeded), which holds for runs correlated within a scenario.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..warning.limits import BOGIE_PLACES, SIDES
from ..warning.alarms import alarm_intervals
from .hazards import BEYOND_PERMITTED, BOGIE_OF_WHEELSET, NORMAL, PLACES, lead_needed, useful_lead, window_of
from ..onboard import measured

EPISODE_M = 1000.0         # m: one false-alarm episode at most per km of a run's track (the grid of the count)
CONFIDENCE = 0.95
BOOTSTRAP_RESAMPLES = 2000
BOOTSTRAP_SEED = 20221111      # any fixed seed: the same runs give the same interval


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


def episode_start(alarm, k, opening):
    """The first sample of the alarm episode of one channel (n,) bool that is on at sample k, or `opening` if
    the episode started before it (only the samples from `opening` on are searched: a run is long, a window
    short)."""
    off = np.flatnonzero(~alarm[opening:k + 1])
    return opening + int(off[-1]) + 1 if len(off) else opening


class Samples(NamedTuple):
    """A run's output rows as the scoring reads them, made once (`of`) for the many `score` calls of one
    criteria table and for the exposure."""
    time: np.ndarray            # s
    speed: np.ndarray           # m/s
    dt: np.ndarray              # s: each row's time since the row before (0 at the first)
    ds: np.ndarray              # m: likewise its distance
    episode: np.ndarray         # int: the row's cell of the false-alarm grid (EPISODE_M from the run's start)

    @classmethod
    def of(cls, arrays):
        t, s, v = (np.asarray(arrays[k], dtype=float) for k in ("time", "position", "speed"))
        return cls(t, v, np.diff(t, prepend=t[0]), np.diff(s, prepend=s[0]),
                   np.floor((s - s[0]) / EPISODE_M).astype(np.int64))


def score(alarms, places, samples, found, window_s, label):
    """One criterion at one threshold in one run: alarms (channels, n) bool, their places, the run's rows
    (`Samples`), its hazards and each sample's label at the window W = window_s (`hazards.windows`). Returns
    {warnings: [(lead_s, speed at the credited start) or None per hazard], false_episodes, false_time_s,
    false_km (over normal running), window_false_episodes (inside hazard windows)}."""
    t, v = samples.time, samples.speed
    true = np.zeros_like(alarms, dtype=bool)
    warnings = []
    for h in found:
        matching = [c for c, ps in enumerate(places) if any(tuple(p) in ps for p in h["places"])]
        k = int(np.searchsorted(t, h["time_s"], "left")) - 1       # the hazard's last sample before its time
        opening = int(np.searchsorted(t, h["time_s"] - window_of(h, window_s), "left"))
        starts = []
        lasting = slice(int(np.searchsorted(t, h["time_s"], "left")), int(np.searchsorted(t, h["end_s"], "right")))
        for c in matching:
            if k >= 0 and alarms[c, k]:
                first = episode_start(alarms[c], k, opening)
                true[c, first:k + 1] = True
                starts.append(first)
            true[c, lasting] |= alarms[c, lasting]
        warnings.append((float(h["time_s"] - t[min(starts)]), float(v[min(starts)])) if starts else None)
    false = np.any(alarms & ~true, axis=0)
    normal = label == NORMAL
    inside = (label != NORMAL) & (label != BEYOND_PERMITTED)
    counted = false & normal
    return dict(warnings=warnings, false_episodes=int(len(np.unique(samples.episode[counted]))),
                false_time_s=float(np.sum(samples.dt[counted])), false_km=float(np.sum(samples.ds[counted])) / 1e3,
                window_false_episodes=int(len(np.unique(samples.episode[false & inside]))))


def exposure(samples, label, which=NORMAL):
    """(km, h) of a run's rows (`Samples`) labelled `which` (normal running by default)."""
    mine = label == which
    return float(np.sum(samples.ds[mine])) / 1e3, float(np.sum(samples.dt[mine])) / 3600.0


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
    """The exposure (km) below which even no false alarm leaves the rate's upper bound above the budget:
    1000 x 3.689 / budget at 95 % (the Garwood upper bound of a count of 0, -ln 0.025)."""
    return 1000.0 * count_interval(0, confidence)[1] / budget_per_1000_km


def is_useful(warning, rules, cure_kmh, reduction=None, adhesion="dry"):
    """A warning (lead_s, speed) is of use: its lead covers the lead needed to brake to the hazard's cure speed
    (`hazards.lead_needed`), or with `reduction` given, to brake that share off (`hazards.useful_lead`: the
    braking sensitivity)."""
    if warning is None:
        return False
    if reduction is not None:
        return warning[0] >= useful_lead(rules, warning[1], reduction, adhesion)
    return warning[0] >= lead_needed(rules, warning[1], cure_kmh, adhesion)


def cluster_bootstrap(clusters, statistic, resamples=BOOTSTRAP_RESAMPLES, seed=BOOTSTRAP_SEED,
                      confidence=CONFIDENCE):
    """Percentile interval [lo, hi] of `statistic(totals)` over resamples of whole clusters: `clusters` (m, k)
    the per-cluster sums of k quantities (a scenario's runs together), `statistic` of the (resamples, k)
    totals; [nan, nan] without clusters or where the statistic is undefined in over half the resamples."""
    clusters = np.asarray(clusters, dtype=float)
    if not len(clusters):
        return [math.nan, math.nan]
    pick = np.random.default_rng(seed).integers(0, len(clusters), size=(resamples, len(clusters)))
    values = np.asarray(statistic(clusters[pick].sum(axis=1)), dtype=float)
    values = values[np.isfinite(values)]
    if len(values) < resamples / 2:
        return [math.nan, math.nan]
    a = 1.0 - confidence
    return [float(np.quantile(values, a / 2)), float(np.quantile(values, 1 - a / 2))]
