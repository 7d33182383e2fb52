"""`railderail warnings --catalogue`: which criterion warns, how early, and how often falsely, over a
scenario catalogue (`catalogue`), each criterion swept over its thresholds.

Each run is the core at the monitor's 200 Hz (no ROS). For every criterion and threshold of THRESHOLDS the
alerts are those a monitor at that threshold would raise (`criteria.alert_indices`: the Detector's
decisions, with the shipped debounce and re-arm); the threshold named by the shipped parameter file
(`default_limits`) is always among them. On a run that derails, the first alert's lead before the
derailment (s, and m of track of the car-body centre); on a run that does not, every alert is a false
alarm, alerts of one criterion within `rearm_m` of track of each other counting as one. Scored over the
runs: the derailments warned (by mechanism), the median and the least lead, and the false alarms per
1000 km of the runs without derailment; the recommended threshold of a criterion is the one that warns
the most derailments, then with the longest median lead, within the false-alarm budget.

A run's result depends only on its catalogue entry, its seed and the code: it is cached on disk under
the hash of those (the package's source included), so an interrupted evaluation resumes and a larger one
reuses the runs it shares with an earlier one. Runs go in parallel processes or on Dask (`parallel`).
"""
from __future__ import annotations

import functools
import hashlib
import json
import math
import statistics
from pathlib import Path

import numpy as np

from railderail_sim import jsonout
from railderail_sim.atomic import atomic_write

from .climb_distance import climb_distance_ratio
from .criteria import (TIMED, alert_indices, critical_name, debounce, default_limits, front_attack_angle,
                       running_gear_unloading, sliding_mean, unloading_ratio)
from .warning_quality import RATE, run_to_end

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
FALSE_ALARMS_PER_1000_KM = 0.1


@functools.lru_cache(maxsize=1)
def source_hash():
    """SHA-256 of both packages' Python sources and the monitor's shipped parameter file (the model, the
    criteria and their levels): a cached run is valid for these only."""
    import railderail_sim
    digest = hashlib.sha256()
    for package in (Path(railderail_sim.__file__).parent, Path(__file__).parent):
        for path in sorted(package.rglob("*.py")):
            digest.update(path.read_bytes())
    digest.update((Path(__file__).parent / "config" / "monitor.yaml").read_bytes())
    return digest.hexdigest()


def criterion_values(arrays, limits):
    """{criterion: values (n, channels)} of a run, as the Monitor evaluates them."""
    unloading = unloading_ratio(arrays["vertical_force"], limits.static_wheel_load)
    qp = arrays["derailment_coefficient"]
    return {"attack_angle": front_attack_angle(arrays["attack_angle"])[:, None],
            "wheel_lift": arrays["wheel_lift"],
            "derailment_coefficient": qp,
            "derailment_coefficient_duration": qp,
            "derailment_coefficient_mean": sliding_mean(qp, arrays["position"], limits.sliding_mean_m),
            "wheel_unloading": unloading,
            "running_gear_unloading": running_gear_unloading(unloading),
            "flange_climb_distance": climb_distance_ratio(qp, arrays["attack_angle"], arrays["position"],
                                                          limits.climb_nadal_limit,
                                                          limits.climb_distance_scale, limits.climb_attack_angle_scale)}


def thresholds(criterion, limits):
    """The sweep of a criterion with its shipped levels, ascending."""
    shipped = [getattr(limits, criterion), getattr(limits, critical_name(criterion))]
    return sorted({float(x) for x in THRESHOLDS[criterion]} | {float(x) for x in shipped if math.isfinite(x)})


def score_run(arrays, limits):
    """({criterion: [{threshold, first: {time_s, position_m} or None, alerts}]}, {criterion: its largest value})
    of one run's arrays."""
    t, s = arrays["time"], arrays["position"]
    out, peaks = {}, {}
    for criterion, values in criterion_values(arrays, limits).items():
        peaks[criterion] = float(np.max(values))
        rows = []
        held, clock = debounce(criterion, limits), t if criterion in TIMED else None
        for thr in thresholds(criterion, limits):
            hits = sorted(i for k in range(values.shape[1])
                          for i in alert_indices(values[:, k], s, thr, held, limits.rearm_fraction, limits.rearm_m,
                                                 clock))
            events, last = 0, -math.inf
            for i in hits:                       # alerts of several wheels at one place are one false alarm
                if s[i] - last > limits.rearm_m:
                    events += 1
                last = s[i]
            first = dict(time_s=float(t[hits[0]]), position_m=float(s[hits[0]])) if hits else None
            rows.append(dict(threshold=thr, first=first, alerts=events))
        out[criterion] = rows
    return out, peaks


def run_one(item, cache=None):
    """One catalogue run (entry, seed): its derailment, distance and scores (a module-level function for the
    process pool and Dask), from the cache when it holds it."""
    entry, seed = item
    key = hashlib.sha256(jsonout.dumps(dict(run=entry.key(seed), code=source_hash())).encode()).hexdigest()
    path = Path(cache, key[:2], key + ".json") if cache else None
    if path is not None and path.exists():
        return json.loads(path.read_text())
    from dataclasses import replace

    sim, arrays, error = run_to_end(replace(entry.scenario(seed), output_rate=RATE), 10.0)
    limits = default_limits()          # every run swept over the same thresholds: the shipped file's car
    event = sim.derailment()
    scores, peaks = score_run(arrays, limits)
    result = dict(scenario=entry.name, seed=seed, derailed=event is not None, diverged=error,
                  mechanism=event["mechanism"] if event else None,
                  derailment=None if event is None else dict(time_s=event["time_s"],
                                                              position_m=event["car_body_position_m"],
                                                              speed_kmh=event["speed_kmh"]),
                  distance_km=float(arrays["position"][-1] - arrays["position"][0]) / 1000.0,
                  scores=scores, peaks=peaks)
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        jsonout.write(path, result)
    return result


def first_alert(run, criterion, threshold):
    """The first alert of a criterion at a threshold in a run (None if it raised none)."""
    for row in run["scores"][criterion]:
        if row["threshold"] == threshold:
            return row
    raise ValueError(f"threshold {threshold:g} of {criterion} was not swept")


def summarize(runs, limits, budget=FALSE_ALARMS_PER_1000_KM):
    """The criteria table (one row per criterion and threshold) and the recommended thresholds."""
    derailing = [r for r in runs if r["derailed"]]
    safe = [r for r in runs if not r["derailed"] and not r["diverged"]]
    km = sum(r["distance_km"] for r in safe)
    table, recommended = [], []
    for criterion in THRESHOLDS:
        rows = []
        for thr in thresholds(criterion, limits):
            leads = []
            warned = {}
            for r in derailing:
                first = first_alert(r, criterion, thr)["first"]
                if first is not None:
                    leads.append((r["derailment"]["time_s"] - first["time_s"],
                                  r["derailment"]["position_m"] - first["position_m"]))
                    warned[r["mechanism"]] = warned.get(r["mechanism"], 0) + 1
            alarms = [first_alert(r, criterion, thr)["alerts"] for r in safe]
            rows.append(dict(criterion=criterion, threshold=thr, derailments=len(derailing),
                             derailments_warned=len(leads), warned_by_mechanism=warned,
                             lead_s_median=statistics.median(x for x, _ in leads) if leads else math.nan,
                             lead_s_min=min((x for x, _ in leads), default=math.nan),
                             lead_m_median=statistics.median(x for _, x in leads) if leads else math.nan,
                             runs_without_derailment=len(safe),
                             false_alarm_runs=sum(n > 0 for n in alarms),
                             false_alarms_per_1000_km=1000.0 * sum(alarms) / km if km > 0 else math.nan))
        table += rows
        within = [row for row in rows if row["false_alarms_per_1000_km"] <= budget and row["derailments_warned"]]
        if within:
            best = max(within, key=lambda row: (row["derailments_warned"], row["lead_s_median"]))
            recommended.append({k: best[k] for k in ("criterion", "threshold", "derailments_warned",
                                                     "lead_s_median", "false_alarms_per_1000_km")})
    return table, recommended


def evaluate(entries, cache=None, workers=None, scheduler=None, progress=True, budget=FALSE_ALARMS_PER_1000_KM):
    """The evaluation of a catalogue's entries: {runs, criteria, recommended} (the --json object)."""
    from railderail_sim.methods.parallel import run_all
    items = [run for e in entries for run in e.runs()]
    runs = run_all(functools.partial(run_one, cache=cache), items, workers=workers, scheduler=scheduler,
                   progress=progress, desc="warnings", unit="run")
    limits = default_limits()
    table, recommended = summarize(runs, limits, budget)
    for r in runs:
        r["first_alerts"] = {}
        for criterion in THRESHOLDS:
            first = first_alert(r, criterion, float(getattr(limits, criterion)))["first"]
            if first is not None:
                d = r["derailment"]
                lead = (d["time_s"] - first["time_s"], d["position_m"] - first["position_m"]) if r["derailed"] \
                    else (math.nan, math.nan)
                r["first_alerts"][criterion] = dict(time_s=first["time_s"], lead_s=lead[0], lead_m=lead[1])
    return dict(runs=[{k: r[k] for k in ("scenario", "seed", "derailed", "mechanism", "distance_km", "first_alerts",
                                         "diverged", "peaks")} for r in runs],
                criteria=table, recommended=recommended, false_alarm_budget_per_1000_km=budget)


def _row(result, criterion, threshold):
    return next(r for r in result["criteria"] if r["criterion"] == criterion and r["threshold"] == threshold)


def findings(result):
    """What the evaluation says, in sentences and two small tables: the runs, which criterion warns first for
    each mechanism, and what the paper's 0.06 rad attack-angle warning achieves."""
    runs, limits = result["runs"], default_limits()
    derailed = [r for r in runs if r["derailed"]]
    safe = [r for r in runs if not r["derailed"] and not r["diverged"]]
    mechanisms = sorted({r["mechanism"] for r in derailed})
    count = {m: sum(r["mechanism"] == m for r in derailed) for m in mechanisms}
    lines = [f"{len(runs)} runs of {len({r['scenario'] for r in runs})} scenarios: {len(derailed)} derailed ("
             + ", ".join(f"{m.replace('_', ' ')} {count[m]}" for m in mechanisms) + f"), {len(safe)} ran "
             f"{sum(r['distance_km'] for r in safe):.0f} km without derailing (every alert there is a false alarm)"
             + (f", {sum(r['diverged'] is not None for r in runs)} diverged" if any(r["diverged"] for r in runs)
                else "") + ".", "", "### Which criterion warns first", "",
             "At the shipped levels (`railderail_monitor/config/monitor.yaml`): per mechanism, the criterion whose "
             "first alert came earliest, in how many of its runs, its median lead, and the false alarms it raised "
             "at that level.", "",
             "| mechanism | first to warn (runs) | its median lead (s) | its false alarms / 1000 km |",
             "|---|---|---|---|"]
    for m in mechanisms:
        firsts = {}
        for r in (r for r in derailed if r["mechanism"] == m):
            if r["first_alerts"]:
                c = max(r["first_alerts"], key=lambda k: r["first_alerts"][k]["lead_s"])
                firsts.setdefault(c, []).append(r["first_alerts"][c]["lead_s"])
        for c, leads in sorted(firsts.items(), key=lambda kv: -len(kv[1])):
            fa = _row(result, c, float(getattr(limits, c)))["false_alarms_per_1000_km"]
            lines.append(f"| {m.replace('_', ' ')} | {c} ({len(leads)} of {count[m]}) | "
                         f"{statistics.median(leads):.2f} | {fa:.1f} |")
    largest = max((r["peaks"]["attack_angle"], r["scenario"], r["seed"]) for r in runs)
    before = [r["peaks"]["attack_angle"] for r in derailed]
    paper = _row(result, "attack_angle", 0.06)
    lines += ["", "### The paper's 0.06 rad attack-angle warning", "",
              f"The front wheelset's attack angle reached at most {largest[0] * 1e3:.1f} mrad in any run "
              f"({largest[1]}, seed {largest[2]})"
              + (f"; up to the derailment instant of the {len(derailed)} derailed runs its largest value was "
                 f"{statistics.median(before) * 1e3:.1f} mrad in the median and {max(before) * 1e3:.1f} mrad at most"
                 if derailed else "") +
              f". At 0.06 rad (Yu 2022) it warned {paper['derailments_warned']} of {paper['derailments']} "
              f"derailments and raised {paper['false_alarms_per_1000_km']:.1f} false alarms per 1000 km."]
    if derailed and paper["derailments_warned"] == 0:
        lines += ["A wheelset whose wheels are still on their rails cannot yaw that far: in a bogie its attack angle "
                  "is about half the wheelbase over the curve radius plus what the flange clearance allows over the "
                  "wheelbase, tens of mrad even at R 150 m, and the derailment (the wheel lifted to its flange "
                  "height) comes first. In this catalogue the paper's claim that the attack angle reaching 0.06 rad "
                  "announces the derailment does not hold: it could only describe the motion after the wheel has "
                  "left its rail, which this model stops at."]
    return lines


def markdown(result):
    """The evaluation as Markdown: what it found (`findings`), the runs, the recommended thresholds, the
    criteria over their thresholds."""
    lines = ["## Warning quality over the scenario catalogue (`railderail warnings --catalogue`)", "",
             *findings(result), "", "![detection against false alarms](warnings-catalogue.png)", "",
             "### The runs", "",
             "| scenario | seed | derailed | mechanism | km | first alert of each criterion at its shipped level "
             "(lead s) |", "|---|---|---|---|---|---|"]
    for r in result["runs"]:
        firsts = ", ".join(f"{c} {a['lead_s']:.2f}" if r["derailed"] else f"{c} FA"
                           for c, a in r["first_alerts"].items()) or "-"
        lines.append(f"| {r['scenario']} | {r['seed']} | {'yes' if r['derailed'] else 'no'} | "
                     f"{r['mechanism'] or '-'} | {r['distance_km']:.1f} | {firsts} |")
    lines += ["", "### Recommended thresholds", "",
              f"Recommended at {result['false_alarm_budget_per_1000_km']:g} false alarms per 1000 km:", "",
              "| criterion | threshold | derailments warned | median lead (s) | false alarms / 1000 km |",
              "|---|---|---|---|---|"]
    for row in result["recommended"]:
        lines.append(f"| {row['criterion']} | {row['threshold']:g} | {row['derailments_warned']} | "
                     f"{row['lead_s_median']:.2f} | {row['false_alarms_per_1000_km']:.2f} |")
    lines += ["", "### Every criterion over its thresholds", "",
              "| criterion | threshold | warned / derailments | by mechanism | median / least lead (s) | "
              "false-alarm runs | false alarms / 1000 km |", "|---|---|---|---|---|---|---|"]
    for row in result["criteria"]:
        mech = ", ".join(f"{k} {v}" for k, v in sorted(row["warned_by_mechanism"].items())) or "-"
        lines.append(f"| {row['criterion']} | {row['threshold']:g} | {row['derailments_warned']}/{row['derailments']}"
                     f" | {mech} | {row['lead_s_median']:.2f} / {row['lead_s_min']:.2f} | "
                     f"{row['false_alarm_runs']}/{row['runs_without_derailment']} | "
                     f"{row['false_alarms_per_1000_km']:.2f} |")
    return "\n".join(lines)


def recommended_limits(result):
    """The shipped limits with each criterion's WARNING level at its recommended threshold, and the WARNING
    level of a criterion without one (none warned within the budget) disabled; (Limits, the criteria
    disabled). A recommendation at or above the criterion's CRITICAL level disables that level."""
    from dataclasses import replace
    limits = default_limits()
    chosen = {row["criterion"]: row["threshold"] for row in result["recommended"]}
    changes, disabled = {}, []
    for criterion in THRESHOLDS:
        if criterion in chosen:
            changes[criterion] = chosen[criterion]
            if not chosen[criterion] < getattr(limits, critical_name(criterion)):
                changes[critical_name(criterion)] = math.nan
        else:
            changes[criterion] = math.nan
            disabled.append(criterion)
    return replace(limits, **changes).validated(), disabled


def write(result, out):
    """OUT/warnings-catalogue.json and .md, the figure OUT/warnings-catalogue.png and the monitor's parameter
    file of the recommended thresholds, OUT/monitor-recommended.yaml (`--ros-args --params-file`)."""
    from railderail_sim import plotting

    from .monitor_params import limits_of_car, parameter_file
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    jsonout.write(out / "warnings-catalogue.json", result)
    with atomic_write(out / "warnings-catalogue.md") as handle:
        handle.write(markdown(result) + "\n")
    plotting.warning_quality_figure(result["criteria"], result["runs"], out / "warnings-catalogue.png")
    limits, disabled = recommended_limits(result)
    made_by = (f"railderail warnings --catalogue (the recommended thresholds at "
               f"{result['false_alarm_budget_per_1000_km']:g} false alarms per 1000 km; WARNING levels disabled for "
               f"{', '.join(disabled) or 'none'})")
    with atomic_write(out / "monitor-recommended.yaml") as handle:
        handle.write(parameter_file(limits, limits_of_car()[1], made_by))
    return out / "warnings-catalogue.md"


def bench():
    """`railderail bench --only warnings`: warnings_catalogue_s, the shipped catalogue evaluated on this
    machine's cores without a cache, and warnings_catalogue_cached_s, the same again from the cache it
    left; warnings_catalogue_runs."""
    import tempfile
    import time

    from . import catalogue
    entries = catalogue.load()
    with tempfile.TemporaryDirectory() as cache:
        t = time.perf_counter()
        result = evaluate(entries, cache=cache, progress=False)
        cold = time.perf_counter() - t
        t = time.perf_counter()
        evaluate(entries, cache=cache, progress=False)
        warm = time.perf_counter() - t
    return dict(warnings_catalogue_s=cold, warnings_catalogue_cached_s=warm,
                warnings_catalogue_runs=len(result["runs"]))
