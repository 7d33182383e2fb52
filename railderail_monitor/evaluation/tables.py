"""The tables of the warning evaluation (`over_catalogue`) over its runs: per criterion and threshold the
derailments usefully warned, the near misses warned and the false alarms (`summarize`); each run's worst
hazard and mechanism, and the first hazard each criterion warned at its shipped level (`first_true_alerts`);
the derailments per mechanism and part."""
from __future__ import annotations

import math
import statistics

import numpy as np

from .catalogue import PARTS
from .hazards import hazard_cure, lead_needed
from .scoring import cluster_bootstrap, is_useful, rate_per_1000_km, share_interval
from .sweeps import CRITERIA, SIGNALS, shipped_level, thresholds

def hazard_of(run):
    """'derailment', 'near_miss' or 'normal': the worst hazard of a run."""
    kinds = {h["kind"] for h in run["hazards"]}
    return "derailment" if "derailment" in kinds else "near_miss" if kinds else "normal"


def mechanism_of(run):
    """What the run shows: the derailment's mechanism, else the margins that fell, else none."""
    if run["derailed"]:
        return run["derailment"]["mechanism"]
    margins = sorted({h["margin"] for h in run["hazards"]})
    return "near miss: " + ", ".join(m.replace("_", " ") for m in margins) if margins else "none"


def _rows(run, window, criterion):
    return run["windows"][str(window)]["criteria"][criterion]


def cures(run, rules):
    """The cure speed (km/h) of each of a run's hazards (`hazards.hazard_cure`)."""
    return [hazard_cure(rules, h, run["line"])["speed_kmh"] for h in run["hazards"]]


def summarize(runs, window, rules, reduction=None, criteria=CRITERIA, sweep=thresholds, bootstrap=False):
    """Per criterion and threshold (of `sweep(criterion)`, the runs' rows in its order) over `runs` at the
    window W: derailments usefully warned (share and interval; on wet rail beside), warned, the median lead,
    near misses warned, false-alarm episodes per 1000 km and per hour (interval), the share of normal time in
    false alarm, and the false alarms inside hazard windows, counted apart. With `bootstrap`, beside the exact
    intervals the scenario bootstrap's (`scoring.cluster_bootstrap`)."""
    km = sum(r["windows"][str(window)]["normal_km"] for r in runs)
    hours = sum(r["windows"][str(window)]["normal_h"] for r in runs)
    cure = [cures(r, rules) for r in runs]
    scenarios = sorted({r["scenario"] for r in runs})
    table = []
    for criterion in criteria:
        for i, thr in enumerate(sweep(criterion)):
            derail, near, episodes, alarm_s, family, useful, wet, stale = [], [], 0, 0.0, {}, 0, 0, 0
            cluster = {name: np.zeros(4) for name in scenarios}     # usefully warned, derailments, episodes, km
            for r, speeds in zip(runs, cure):
                row = _rows(r, window, criterion)[i]
                for h, w, v in zip(r["hazards"], row["warnings"], speeds):
                    (derail if h["kind"] == "derailment" else near).append(w)
                    if h["kind"] == "derailment":
                        ok = is_useful(w, rules, v, reduction)
                        useful += ok
                        wet += is_useful(w, rules, v, reduction, "wet")
                        count = family.setdefault(r["family"], [0, 0])
                        count[0] += ok
                        count[1] += 1
                        cluster[r["scenario"]][:2] += (ok, 1)
                episodes += row["false_episodes"]
                alarm_s += row["false_time_s"]
                stale += row["window_false_episodes"]
                cluster[r["scenario"]][2:] += (row["false_episodes"], r["windows"][str(window)]["normal_km"])
            warned = [w for w in derail if w is not None and w[0] > 0.0]
            rate, ci = rate_per_1000_km(episodes, km)
            extra = {}
            if bootstrap:
                sums = np.array([cluster[name] for name in scenarios])
                with np.errstate(divide="ignore", invalid="ignore"):
                    extra = dict(usefully_warned_share_boot95=cluster_bootstrap(sums, lambda x: x[:, 0] / x[:, 1]),
                                 false_alarms_per_1000_km_boot95=cluster_bootstrap(
                                     sums, lambda x: 1000.0 * x[:, 2] / x[:, 3]))
            table.append(dict(
                criterion=criterion, threshold=thr, signals=SIGNALS[criterion], derailments=len(derail),
                warned=len(warned), usefully_warned=useful, usefully_warned_ci95=share_interval(useful, len(derail)),
                usefully_warned_wet=wet, usefully_warned_by_family=family,
                lead_s_median=statistics.median(w[0] for w in warned) if warned else math.nan,
                near_misses=len(near), near_misses_warned=sum(w is not None and w[0] > 0.0 for w in near),
                false_alarm_episodes=episodes, false_alarms_per_1000_km=rate, false_alarms_per_1000_km_ci95=ci,
                false_alarms_per_hour=episodes / hours if hours > 0 else math.nan,
                time_in_alarm_share=alarm_s / (3600.0 * hours) if hours > 0 else math.nan,
                window_false_episodes=stale, **extra))
    return table


def split(runs):
    """(train runs, test runs)."""
    return [r for r in runs if r["part"] == "train"], [r for r in runs if r["part"] == "test"]


def first_true_alerts(run, limits, rules):
    """{criterion: {lead_s, useful, hazard_cure, lead_needed_s, lead_needed_wet_s, useful_wet} or None}: the
    first hazard each criterion warned at its shipped WARNING level, in the window of the recommendation (the
    derailment if it warned it, else the first near miss), with what cures that hazard and the lead it needs
    to brake to it at the warning's speed, on dry and on wet rail."""
    out = {}
    order = sorted(range(len(run["hazards"])), key=lambda i: run["hazards"][i]["kind"] != "derailment")
    for criterion in CRITERIA:
        level = shipped_level(criterion, limits)
        rows = [r for r in _rows(run, rules.window_s, criterion) if r["threshold"] == level]
        hits = [i for i in order if rows and rows[0]["warnings"][i] is not None and rows[0]["warnings"][i][0] > 0.0]
        if not hits:
            out[criterion] = None
            continue
        (lead, speed), cure = rows[0]["warnings"][hits[0]], hazard_cure(rules, run["hazards"][hits[0]], run["line"])
        dry, wet = (lead_needed(rules, speed, cure["speed_kmh"], adhesion) for adhesion in ("dry", "wet"))
        out[criterion] = dict(lead_s=lead, useful=lead >= dry, hazard_cure=cure, lead_needed_s=dry,
                              lead_needed_wet_s=wet, useful_wet=lead >= wet)
    return out


def mechanism_counts(runs):
    """Per expected mechanism (`catalogue.Entry.mechanism`) and part: the runs expected to derail, and those
    that did."""
    out = {}
    for r in runs:
        if r["expected_mechanism"] is None:
            continue
        row = out.setdefault(r["expected_mechanism"], {p: dict(expected=0, derailed=0) for p in PARTS})
        row[r["part"]]["expected"] += bool(r["expect_derailment"])
        row[r["part"]]["derailed"] += bool(r["derailed"])
    return out
