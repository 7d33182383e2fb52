"""`railderail warnings --catalogue`: which criterion warns, how early and how usefully, and how often falsely,
over a scenario catalogue (`catalogue`), each criterion swept over its thresholds; the thresholds chosen on
one part of the catalogue and scored on the other (docs/warning-evaluation.md).

Each run is the core at the monitor's 200 Hz (no ROS), labelled by its hazards (`hazards`: derailment
windows, near misses by margin, normal running) and scored per criterion and threshold (`scoring`: the
alarms a monitor at that threshold would show, attributed to the hazard at their place or counted false
over the normal running). The runs are split by scenario and track (`catalogue.load`: an entry's runs all
in its part, no track sample or defect on both sides); `summarize` gives the table of one part, `recommend` chooses each criterion's WARNING and CRITICAL levels
on the train part under their false-alarm budgets and checks them on the test part, recommending nothing
where the exposure cannot resolve the budget or too few derailments are usefully warned.

Beside the ground-truth criteria, every criterion on measured signals (`onboard.measured`: the bogie-frame
instability rules, the car body's accelerations and roll, the roll-balance estimator's warnings), from the
shipped sensor set with its noise on, its seed the run's seed, applied to the run's output rows
(`sensors.measure.run_signals`), the monitor switched on after the simulation's start-up
(`sensors.measure.START_UP_S`). Each is evaluated on its own stamps (latency included) and held onto the
200 Hz rows for scoring: a row is in alarm when the criterion's last sample stamped at or before it is
(`rows_in_alarm`), so the alarm starts at the first row at or after the alert's stamp. Its channels are
mounts or running-gear sides (`scoring.channel_places`). On the test part's runs the sensors are applied
again to the same rows with the noise, the bias and the sample rate changed (`SENSOR_VARIANTS`), and the
measured criteria scored at their shipped levels: the sensor sensitivity table.

A run's result depends only on its catalogue entry, its seed and the code: it is cached on disk under
the hash of those (both packages' sources and the monitor's shipped parameter file included), so an
interrupted evaluation resumes and loses no finished run. Runs go in parallel processes or on Dask.
"""
from __future__ import annotations

import functools
import hashlib
import json
import math
import os
import statistics
import time
from pathlib import Path

import numpy as np

from railderail_sim import jsonout
from railderail_sim.parameters import VehicleParameters
from railderail_sim.ros.node import PARAMETERS

from ..warning.climb_distance import climb_distance_ratio
from ..warning.limits import TIMED, critical_name, debounce, default_limits, model_basis
from ..warning.quantities import front_attack_angle, running_gear_unloading, sliding_mean, unloading_ratio
from ..warning.alarms import nanoseconds
from .catalogue import PARTS
from .hazards import (BEYOND_PERMITTED, Car, HazardRules, beyond_permitted, cant_deficiency, hazard_cure, hazards,
                      lead_needed, margin_peaks, windows)
from ..onboard import measured
from .scoring import (channel_places, cluster_bootstrap, exposure, in_alarm, is_useful, rate_per_1000_km,
                      resolvable_km, score, share_interval)

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
CRITERIA = tuple(THRESHOLDS) + measured.CRITERIA
# what each criterion's signals are: the simulator's wheel forces and motions, or the on-board sensors'
SIGNALS = {criterion: "ground_truth" for criterion in THRESHOLDS} | {c: measured.SIGNALS for c in measured.CRITERIA}
# the sensor sensitivity: the shipped set (noise 1, bias 1, 200 Hz) and each change of one of them; the sample
# rate cannot exceed the simulator's output rate (sensors.sensor_set.Sampling), so 500 Hz is out of reach at 200 Hz
SENSOR_VARIANTS = (dict(noise=1.0, bias=1.0, rate_hz=200.0), dict(noise=0.0, bias=1.0, rate_hz=200.0),
                   dict(noise=3.0, bias=1.0, rate_hz=200.0), dict(noise=1.0, bias=0.0, rate_hz=200.0),
                   dict(noise=1.0, bias=3.0, rate_hz=200.0), dict(noise=1.0, bias=1.0, rate_hz=100.0),
                   dict(noise=1.0, bias=1.0, rate_hz=50.0))
RATE = next(spec.default for spec in PARAMETERS if spec.name == "publish_rate")   # Hz, as the node publishes
BUDGETS = {"warning": 10.0, "critical": 3.0}      # false-alarm episodes per 1000 km of each level by default
MIN_USEFUL_SHARE = 0.5     # a level is recommended only if it usefully warns at least this share of derailments
SPLIT = ("by scenario and track: each entry's runs in one part (its `part`, else alternating train and test "
         "within its family in the file's order); no track sample, irregularity file or defect on both sides")


@functools.lru_cache(maxsize=1)
def source_hash():
    """SHA-256 of both packages' Python sources and the monitor's shipped parameter file (the model, the
    criteria, the labelling and their levels): a cached run is valid for these only."""
    import railderail_sim
    digest = hashlib.sha256()
    monitor = Path(__file__).parents[1]
    for package in (Path(railderail_sim.__file__).parent, monitor):
        for path in sorted(package.rglob("*.py")):
            digest.update(path.read_bytes())
    digest.update((monitor / "config" / "monitor.yaml").read_bytes())
    from railderail_sim.sensors.config import SHIPPED as SENSORS
    digest.update(SENSORS.read_bytes())
    return digest.hexdigest()


@functools.lru_cache(maxsize=1)
def shipped_measured_limits():
    """The measured criteria's shipped levels and settings, of the shipped car (the catalogue's)."""
    return measured.measured_limits(VehicleParameters())


def shipped_level(criterion, limits=None):
    """A criterion's shipped WARNING level (the ground-truth monitor's parameter file, or the measured one's)."""
    if SIGNALS[criterion] == measured.SIGNALS:
        return float(getattr(shipped_measured_limits(), criterion))
    return float(getattr(limits or default_limits(), criterion))


def sensor_variant(sensors, variant):
    """The sensor set with a variant's noise and bias scales and sample rate (SENSOR_VARIANTS)."""
    return sensors.scaled(variant["noise"], variant["bias"]).resampled(variant["rate_hz"])


def variant_name(variant):
    return f"noise {variant['noise']:g}x, bias {variant['bias']:g}x, {variant['rate_hz']:g} Hz"


def rows_in_alarm(sample_time, sample_alarm, row_time):
    """(n rows,) bool: a row is in alarm when the last sample stamped at or before it is; no sample yet, no
    alarm. The alarm of a sample stamped t (its latency included) starts at the first row at or after t."""
    k = np.searchsorted(sample_time, row_time, "right") - 1
    return (k >= 0) & np.asarray(sample_alarm)[np.maximum(k, 0)]


def measured_alarms(results, row_time, sweep):
    """{criterion: {threshold: (channels, n rows) bool}} of every measured criterion from `measured.evaluate`'s
    results, each channel put through the monitor's alarm logic on its own stamps and odometer positions at
    each threshold of `sweep(criterion)`, then held onto the rows (`rows_in_alarm`); a criterion the results
    lack (its sensors missing, or a run too short) never alarms."""
    limits = shipped_measured_limits()
    out = {}
    for criterion in measured.CRITERIA:
        if criterion not in results:
            out[criterion] = {thr: np.zeros((len(measured.PLACES[criterion]), len(row_time)), dtype=bool)
                              for thr in sweep(criterion)}
            continue
        m = results[criterion]
        values = m.value if np.ndim(m.value) == 2 else m.value[:, None]
        out[criterion] = {thr: np.array([rows_in_alarm(m.time, in_alarm(values[:, k], m.position, thr, m.debounce,
                                                                         limits.rearm_fraction, limits.rearm_m),
                                                       row_time) for k in range(values.shape[1])])
                          for thr in sweep(criterion)}
    return out


def measured_results(sensors, sim, arrays):
    """`measured.evaluate` of a run seen through a sensor set, the monitor switched on after the simulation's
    start-up (`sensors.measure.START_UP_S`: a train in service never sees it)."""
    from railderail_sim.sensors.measure import START_UP_S, after, run_signals
    seen = after(run_signals(sensors, sim, arrays), START_UP_S)
    if any(len(v) < 2 for k, v in seen.items() if k.endswith("_time")):
        return {}           # a run ending before every sensor has given the monitor two samples: nothing said
    return measured.evaluate(seen, sim.scenario.vehicle, shipped_measured_limits(), measured.sample_rates(sensors))


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


def thresholds(criterion, limits=None):
    """The sweep of a criterion with its shipped levels, ascending."""
    if SIGNALS[criterion] == measured.SIGNALS:
        level = shipped_level(criterion)
        sweep = MEASURED_PEAKS if criterion in COUNTS else [f * level for f in MEASURED_FACTORS]
        return sorted({float(x) for x in sweep} | ({level} if math.isfinite(level) else set()))
    limits = limits or default_limits()
    shipped = [getattr(limits, criterion), getattr(limits, critical_name(criterion))]
    return sorted({float(x) for x in THRESHOLDS[criterion]} | {float(x) for x in shipped if math.isfinite(x)})


def scores(alarms, arrays, found, window_s, beyond=None):
    """{criterion: [{threshold, warnings, false_episodes, false_time_s, false_km, window_false_episodes}]} of
    alarms {criterion: {threshold: (channels, n) bool}} at the window W = window_s; `beyond` (n,) bool the
    samples beyond permitted running (`hazards.beyond_permitted`)."""
    label = windows(arrays["time"], found, window_s, beyond)[1]
    return {criterion: [dict(threshold=thr, **score(mask, channel_places(criterion, mask.shape[0]), arrays, found,
                                                    window_s, label))
                        for thr, mask in by_threshold.items()]
            for criterion, by_threshold in alarms.items()}


def score_run(arrays, found, limits, rules, measured_found=None, beyond=None):
    """{window_s: {normal_km, normal_h, beyond_km, criteria: {criterion: [{threshold, warnings, false_episodes,
    false_time_s, false_km, window_false_episodes}]}}} of one run's arrays and hazards, every criterion over
    its thresholds; the measured criteria's from `measured.evaluate`'s results `measured_found`; `beyond` the
    samples beyond permitted running."""
    s = arrays["position"]
    clock = nanoseconds(arrays["time"])
    alarms = {}
    for criterion, values in criterion_values(arrays, limits).items():
        held = debounce(criterion, limits)
        at = clock if criterion in TIMED else None
        alarms[criterion] = {thr: np.array([in_alarm(values[:, k], s, thr, held, limits.rearm_fraction,
                                                     limits.rearm_m, at) for k in range(values.shape[1])])
                             for thr in thresholds(criterion, limits)}
    if measured_found is not None:
        alarms.update(measured_alarms(measured_found, arrays["time"], thresholds))
    out = {}
    for w in rules.windows_s:
        label = windows(arrays["time"], found, w, beyond)[1]
        km, h = exposure(arrays, label)
        out[str(w)] = dict(normal_km=km, normal_h=h, beyond_km=exposure(arrays, label, BEYOND_PERMITTED)[0],
                           criteria=scores(alarms, arrays, found, w, beyond))
    return out


def sensor_sensitivity_run(sensors, sim, arrays, found, rules, variants=SENSOR_VARIANTS[1:], beyond=None):
    """{variant name: {criterion: [its row at the shipped level]}} at the window of the recommendation: the
    measured criteria of one run seen through each of `variants` (by default SENSOR_VARIANTS but the first,
    the shipped set, scored with the run itself), over the same rows: no re-simulation."""
    shipped = lambda criterion: [shipped_level(criterion)]
    return {variant_name(v): scores(measured_alarms(measured_results(sensor_variant(sensors, v), sim, arrays),
                                                    arrays["time"], shipped), arrays, found, rules.window_s, beyond)
            for v in variants}


def run_one(item, cache=None):
    """One catalogue run (entry, seed): its hazards, distance and scores (a module-level function for the
    process pool and Dask), from the cache when it holds it."""
    entry, seed = item
    key = hashlib.sha256(jsonout.dumps(dict(run=entry.key(seed), code=source_hash())).encode()).hexdigest()
    path = Path(cache, key[:2], key + ".json") if cache else None
    if path is not None and path.exists():
        return json.loads(path.read_text())
    from dataclasses import replace

    from railderail_sim.sensors.config import load as load_sensors
    from railderail_sim.vehicle.simulate import run_to_stop

    started = time.process_time()
    sc = replace(entry.scenario(seed), output_rate=RATE)
    sim, arrays, error = run_to_stop(sc)
    simulated = time.process_time()
    limits, rules = default_limits(), HazardRules()     # every run swept over the same thresholds: the shipped car
    basis = model_basis(sim.model)
    car = Car(basis["flange_height"], basis["max_contact_angle"], basis["static_wheel_load"], entry.friction)
    event = sim.derailment()
    found = hazards(arrays, event, car, rules)
    line = entry.line()
    beyond = beyond_permitted(arrays, line, rules)
    deficiency = cant_deficiency(arrays, sc.track.rail_spacing)
    s, t = arrays["position"], arrays["time"]
    sensors = replace(load_sensors(), seed=seed)          # the shipped sensor set, its noise from the run's seed
    sensed = measured_results(sensors, sim, arrays)
    result = dict(scenario=entry.name, family=entry.family, seed=seed, part=entry.part_of(seed), line=line,
                  expected_mechanism=entry.mechanism, expect_derailment=entry.expect_derailment,
                  derailed=event is not None, diverged=error, derailment=None if event is None else dict(
                      time_s=event["time_s"], position_m=event["car_body_position_m"], speed_kmh=event["speed_kmh"],
                      wheelset=event["wheelset"], wheel_side=event["wheel_side"], mechanism=event["mechanism"]),
                  km=float(s[-1] - s[0]) / 1000.0, hours=float(t[-1] - t[0]) / 3600.0,
                  cant_deficiency_mm_max=float(np.max(deficiency, initial=0.0)) * 1e3,
                  hazards=[{**h, "places": [list(p) for p in h["places"]]} for h in found],
                  margin_peaks=margin_peaks(arrays, car, rules),
                  peaks={c: float(np.max(v, initial=0.0)) for c, v in criterion_values(arrays, limits).items()}
                  | {c: float(np.max(np.nan_to_num(m.value, nan=0.0), initial=0.0)) for c, m in sensed.items()},
                  windows=score_run(arrays, found, limits, rules, sensed, beyond))
    scored = time.process_time()
    result["sensor_variants"] = (sensor_sensitivity_run(sensors, sim, arrays, found, rules, beyond=beyond)
                                 if result["part"] == "test" else None)
    done = time.process_time()
    # process time of the simulation, the sensors with every criterion scored, and the sensor variants
    result["cpu_s"], result["cpu_split_s"] = done - started, dict(simulation=simulated - started,
                                                                  scoring=scored - simulated,
                                                                  sensor_variants=done - scored)
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        jsonout.write(path, result)
    return result


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


def _choice(rows, budget, km, above, min_share):
    """The threshold chosen on one part's rows of a criterion at a level's budget (the most derailments
    usefully warned, then the highest threshold: the farthest from the false alarms), or (None, reason)."""
    if km < resolvable_km(budget):
        return None, (f"{km:.0f} km of normal running cannot resolve {budget:g} false alarms per 1000 km "
                      f"(needs {resolvable_km(budget):.0f} km)")
    fit = [r for r in rows if r["threshold"] > above and r["false_alarms_per_1000_km_ci95"][1] <= budget
           and r["derailments"] and r["usefully_warned"] >= min_share * r["derailments"]]
    if not fit:
        return None, (f"no threshold usefully warns {min_share:.0%} of the derailments with the upper 95 % "
                      f"bound of its false alarms within {budget:g} per 1000 km")
    return max(fit, key=lambda r: (r["usefully_warned"], r["threshold"]))["threshold"], ""


def recommend(runs, rules, budgets=BUDGETS, min_share=MIN_USEFUL_SHARE):
    """Per criterion and level: the threshold chosen on the train part and confirmed on the test part, or
    null with the reason. A criterion's CRITICAL level is chosen above its WARNING level; no level depends on
    another criterion's. A measured criterion has a WARNING level only (an on-board unit's alarm,
    onboard.measured)."""
    train, test = split(runs)
    w = rules.window_s
    train_km = sum(r["windows"][str(w)]["normal_km"] for r in train)
    test_km = sum(r["windows"][str(w)]["normal_km"] for r in test)
    train_rows, test_rows = summarize(train, w, rules), summarize(test, w, rules)
    out = []
    for criterion in CRITERIA:
        mine = [r for r in train_rows if r["criterion"] == criterion]
        held_out = {r["threshold"]: r for r in test_rows if r["criterion"] == criterion}
        above = -math.inf
        for level in ("warning",) if SIGNALS[criterion] == measured.SIGNALS else ("warning", "critical"):
            budget = budgets[level]
            threshold, reason = _choice(mine, budget, train_km, above, min_share)
            if threshold is not None:
                check = held_out[threshold]
                if test_km < resolvable_km(budget):
                    threshold, reason = None, (f"the test part's {test_km:.0f} km of normal running cannot resolve "
                                               f"{budget:g} per 1000 km")
                elif check["false_alarms_per_1000_km_ci95"][1] > budget:
                    threshold, reason = None, (f"chosen {threshold:g} on the train part, its false alarms on the "
                                               f"test part reach {check['false_alarms_per_1000_km_ci95'][1]:.2f} "
                                               f"per 1000 km (upper 95 %), above {budget:g}")
                elif check["usefully_warned"] < min_share * max(check["derailments"], 1):
                    threshold, reason = None, (f"chosen {threshold:g} on the train part, it usefully warns "
                                               f"{check['usefully_warned']} of {check['derailments']} derailments of "
                                               "the test part")
            test_row = held_out.get(threshold) if threshold is not None else None
            out.append(dict(criterion=criterion, signals=SIGNALS[criterion], level=level, threshold=threshold,
                            reason=reason or None,
                            budget_per_1000_km=budget, test=None if test_row is None else {
                                k: test_row[k] for k in ("usefully_warned", "derailments", "usefully_warned_ci95",
                                                         "false_alarms_per_1000_km", "false_alarms_per_1000_km_ci95")}))
            if threshold is not None:
                above = threshold
    return out


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


def evaluate(entries, cache=None, workers=None, scheduler=None, progress=True, budgets=BUDGETS,
             min_share=MIN_USEFUL_SHARE):
    """The evaluation of a catalogue's entries (the --json object)."""
    from railderail_sim.methods.parallel import run_all
    items = [run for e in entries for run in e.runs()]
    started = time.perf_counter()
    runs = run_all(functools.partial(run_one, cache=cache), items, workers=workers, scheduler=scheduler,
                   progress=progress, desc="warnings", unit="run", cost=[e.expected_cost(seed) for e, seed in items])
    wall = time.perf_counter() - started
    # the part is the catalogue's (a cached run keeps its simulation, not its part)
    runs = [{**r, "part": e.part_of(seed)} for r, (e, seed) in zip(runs, items)]
    limits, rules = default_limits(), HazardRules()
    w = rules.window_s
    train, test = split(runs)
    return dict(
        derailment_window_s=w,
        exposure=dict(normal_km=sum(r["windows"][str(w)]["normal_km"] for r in runs),
                      normal_h=sum(r["windows"][str(w)]["normal_h"] for r in runs),
                      beyond_permitted_km=sum(r["windows"][str(w)]["beyond_km"] for r in runs),
                      train_km=sum(r["windows"][str(w)]["normal_km"] for r in train),
                      test_km=sum(r["windows"][str(w)]["normal_km"] for r in test)),
        split=dict(how=SPLIT, train=sorted({r["scenario"] for r in train}), test=sorted({r["scenario"] for r in test})),
        criteria=summarize(test, w, rules, bootstrap=True),
        mechanisms=mechanism_counts(runs),
        shipped_levels={c: shipped_level(c, limits) for c in CRITERIA},
        recommended=recommend(runs, rules, budgets, min_share),
        budgets_per_1000_km=dict(budgets), min_useful_share=min_share,
        rules=[dict(name=n, value=v, unit=u, meaning=m, source=s, sure=c) for n, v, u, m, s, c in rules.table()],
        sensitivity=sensitivity(test, limits, rules),
        sensor_sensitivity=sensor_sensitivity(test, rules),
        runs=[dict(scenario=r["scenario"], family=r["family"], seed=r["seed"], part=r["part"], km=r["km"],
                   hazard=hazard_of(r), mechanism=mechanism_of(r), derailment=r["derailment"],
                   expected_mechanism=r["expected_mechanism"], expect_derailment=r["expect_derailment"],
                   cant_deficiency_mm_max=r["cant_deficiency_mm_max"], diverged=r["diverged"], peaks=r["peaks"],
                   margin_peaks=r["margin_peaks"],
                   first_true_alert=first_true_alerts(r, limits, rules)) for r in runs],
        throughput=dict(wall_s=wall, cpu_s=sum(r["cpu_s"] for r in runs), km=sum(r["km"] for r in runs),
                        cpu_split_s={k: sum(r["cpu_split_s"][k] for r in runs) for k in runs[0]["cpu_split_s"]},
                        cores=os.cpu_count() if not scheduler else None))


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


def sensor_sensitivity(runs, rules):
    """Per sensor variant (SENSOR_VARIANTS) and measured criterion at its shipped level, over `runs` (the test
    part: only its runs carry the variants) at the recommendation's window: derailments usefully warned,
    warned, the median lead, false alarms per 1000 km and the time in alarm, from the same simulated rows."""
    shipped = lambda criterion: [shipped_level(criterion)]
    out = []
    for v in SENSOR_VARIANTS:
        name = variant_name(v)
        if v == SENSOR_VARIANTS[0]:
            table = [r for r in summarize(runs, rules.window_s, rules, criteria=measured.CRITERIA)
                     if r["threshold"] == shipped_level(r["criterion"])]
        else:
            seen = [{**r, "windows": {str(rules.window_s): {**r["windows"][str(rules.window_s)],
                                                            "criteria": r["sensor_variants"][name]}}} for r in runs]
            table = summarize(seen, rules.window_s, rules, criteria=measured.CRITERIA, sweep=shipped)
        out += [dict(variant=name, **v, **{k: row[k] for k in (
            "criterion", "threshold", "derailments", "warned", "usefully_warned", "usefully_warned_ci95",
            "lead_s_median", "false_alarm_episodes", "false_alarms_per_1000_km", "false_alarms_per_1000_km_ci95",
            "time_in_alarm_share")}) for row in table]
    return out


SENSITIVITY_REDUCTIONS = (0.05, 0.10, 0.20, 1.0)


def sensitivity(runs, limits, rules):
    """At each criterion's shipped WARNING level over `runs`: derailments usefully warned for every window W
    and for every share of the speed to brake off (1: to a stop)."""
    tables = {(w, reduction): summarize(runs, w, rules, reduction)      # every criterion's rows at once
              for w in rules.windows_s for reduction in SENSITIVITY_REDUCTIONS}
    out = []
    for criterion in CRITERIA:
        level = shipped_level(criterion, limits)
        for w in rules.windows_s:
            for reduction in SENSITIVITY_REDUCTIONS:
                row = next(r for r in tables[w, reduction] if r["criterion"] == criterion
                           and r["threshold"] == level)
                out.append(dict(criterion=criterion, signals=SIGNALS[criterion], threshold=level, window_s=w,
                                safe_speed_reduction=reduction,
                                derailments=row["derailments"], warned=row["warned"],
                                usefully_warned=row["usefully_warned"],
                                false_alarms_per_1000_km=row["false_alarms_per_1000_km"]))
    return out


def recommended_limits(result):
    """The shipped limits with each criterion's levels at their recommended thresholds, a level without one
    disabled (NaN); (Limits, the levels disabled)."""
    from dataclasses import replace
    changes, disabled = {}, []
    for row in (r for r in result["recommended"] if r["signals"] == "ground_truth"):
        name = row["criterion"] if row["level"] == "warning" else critical_name(row["criterion"])
        changes[name] = math.nan if row["threshold"] is None else row["threshold"]
        if row["threshold"] is None:
            disabled.append(name)
    return replace(default_limits(), **changes).validated(), disabled


def write(result, out):
    """OUT/warnings-catalogue.json and .md, the figure OUT/warnings-catalogue.png and the monitor's parameter
    file of the recommended levels, OUT/monitor-recommended.yaml (`--ros-args --params-file`)."""
    from railderail_sim import plotting
    from railderail_sim.atomic import atomic_write

    from ..warning.monitor_params import limits_of_car, parameter_file
    from .report import markdown
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    jsonout.write(out / "warnings-catalogue.json", result)
    with atomic_write(out / "warnings-catalogue.md") as handle:
        handle.write(markdown(result) + "\n")
    plotting.warning_quality_figure(result["criteria"], result["runs"], out / "warnings-catalogue.png")
    limits, disabled = recommended_limits(result)
    made_by = (f"railderail warnings --catalogue (the levels chosen on the train part and confirmed on the test "
               f"part at {result['budgets_per_1000_km']['warning']:g} / {result['budgets_per_1000_km']['critical']:g} "
               f"false alarms per 1000 km; disabled: {', '.join(disabled) or 'none'})")
    with atomic_write(out / "monitor-recommended.yaml") as handle:
        handle.write(parameter_file(limits, limits_of_car()[1], made_by))
    return out / "warnings-catalogue.md"


def bench():
    """`railderail bench --only warnings`: the shipped catalogue evaluated on this machine's cores without a
    cache (warnings_catalogue_s, warnings_catalogue_km_per_min, catalogue_cpu_efficiency: the runs'
    process time over wall time x cores) and again from the cache it left (warnings_catalogue_cached_s)."""
    import tempfile

    from . import catalogue
    entries = catalogue.load()
    with tempfile.TemporaryDirectory() as cache:
        t = time.perf_counter()
        result = evaluate(entries, cache=cache, progress=False)
        cold = time.perf_counter() - t
        t = time.perf_counter()
        evaluate(entries, cache=cache, progress=False)
        warm = time.perf_counter() - t
    through = result["throughput"]
    return dict(warnings_catalogue_s=cold, warnings_catalogue_cached_s=warm, warnings_catalogue_runs=len(result["runs"]),
                warnings_catalogue_km=through["km"], warnings_catalogue_km_per_min=60.0 * through["km"] / cold,
                catalogue_cpu_efficiency=through["cpu_s"] / (through["wall_s"] * through["cores"]))


def command_line(args):
    """`railderail warnings --catalogue [FILE]` (the arguments of over_radii.command)."""
    import sys

    from railderail_sim.ranges import check_range

    from . import catalogue
    from .report import markdown
    budgets = dict(warning=check_range("--warning-budget-per-1000-km", args.warning_budget_per_1000_km, 0.0, 1.0e6,
                                       lo_open=True),
                   critical=check_range("--critical-budget-per-1000-km", args.critical_budget_per_1000_km, 0.0,
                                        1.0e6, lo_open=True))
    entries = catalogue.load(None if args.catalogue == "shipped" else args.catalogue)
    cache = args.cache or (str(Path(args.out) / "cache") if args.out else None)
    result = evaluate(entries, cache=cache, workers=args.workers, scheduler=args.scheduler, progress=not args.json,
                      budgets=budgets)
    if args.out:
        print(f"wrote {write(result, args.out)}", file=sys.stderr)
    print(jsonout.dumps(result, indent=1) if args.json else markdown(result))

