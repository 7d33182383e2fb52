"""One run of the warning evaluation's catalogue (`over_catalogue`): the core at the monitor's 200 Hz (no
ROS), labelled by its hazards (`hazards`) and scored per criterion and threshold (`scoring`), the measured
criteria from the shipped sensor set (and, on the test part, its variants: `sensor_sensitivity_run`); cached
on disk under the hash of the entry, the seed and the code (`run_one`)."""
from __future__ import annotations

import functools
import hashlib
import json
import time
from pathlib import Path

import numpy as np

from railderail_sim import jsonout
from railderail_sim.ros.node import PARAMETERS

from ..onboard import measured
from ..warning.alarms import nanoseconds
from ..warning.climb_distance import climb_distance_ratio
from ..warning.limits import TIMED, debounce, default_limits, model_basis
from ..warning.quantities import front_attack_angle, running_gear_unloading, sliding_mean, unloading_ratio
from .hazards import (BEYOND_PERMITTED, Car, HazardRules, beyond_permitted, cant_deficiency, hazards, margin_peaks,
                      windows, with_cure_leads)
from .scoring import Samples, channel_places, exposure, in_alarm, score
from .supervision_score import CRITERION as SUPERVISION, supervision_of_run
from .sweeps import shipped_level, shipped_measured_limits, sensor_variant, thresholds, variant_name, SENSOR_VARIANTS

RATE = next(spec.default for spec in PARAMETERS if spec.name == "publish_rate")   # Hz, as the node publishes


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


def last_sample(sample_time, row_time):
    """(n rows,) the index of the last sample stamped at or before each row, -1 before the first."""
    return np.searchsorted(sample_time, row_time, "right") - 1


def rows_in_alarm(last, sample_alarm):
    """(n rows,) bool: a row is in alarm when the last sample stamped at or before it is (`last`, from
    `last_sample`: one search serves every level and channel of a criterion); no sample yet, no alarm. The
    alarm of a sample stamped t (its latency included) starts at the first row at or after t."""
    return (last >= 0) & np.asarray(sample_alarm)[np.maximum(last, 0)]


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
        last = last_sample(m.time, row_time)
        out[criterion] = {thr: np.array([rows_in_alarm(last, in_alarm(values[:, c], m.position, thr, m.debounce,
                                                                      limits.rearm_fraction, limits.rearm_m))
                                         for c in range(values.shape[1])])
                          for thr in sweep(criterion)}
    return out


def measured_results(sensors, sim, arrays, shared=None):
    """`measured.evaluate` of a run seen through a sensor set, the monitor switched on after the simulation's
    start-up (`sensors.measure.START_UP_S`: a train in service never sees it); `shared` the readings the set's
    variants share (`sensors.measure.shared_readings`) when already known."""
    from railderail_sim.sensors.measure import START_UP_S, after, run_signals
    seen = after(run_signals(sensors, sim, arrays, shared), START_UP_S)
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


def scores(alarms, arrays, found, window_s, beyond=None):
    """{criterion: [{threshold, warnings, false_episodes, false_time_s, false_km, window_false_episodes}]} of
    alarms {criterion: {threshold: (channels, n) bool}} at the window W = window_s; `beyond` (n,) bool the
    samples beyond permitted running (`hazards.beyond_permitted`)."""
    label = windows(arrays["time"], found, window_s, beyond)[1]
    samples = Samples.of(arrays)
    return {criterion: [dict(threshold=thr, **score(mask, channel_places(criterion, mask.shape[0]), samples, found,
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
    out, samples = {}, Samples.of(arrays)
    for w in rules.windows_s:
        label = windows(arrays["time"], found, w, beyond)[1]
        km, h = exposure(samples, label)
        out[str(w)] = dict(normal_km=km, normal_h=h, beyond_km=exposure(samples, label, BEYOND_PERMITTED)[0],
                           criteria=scores(alarms, arrays, found, w, beyond))
    return out


def sensor_sensitivity_run(sensors, sim, arrays, found, rules, variants=SENSOR_VARIANTS[1:], beyond=None,
                           shared=None):
    """{variant name: {criterion: [its row at the shipped level]}} at the window of the recommendation: the
    measured criteria of one run seen through each of `variants` (by default SENSOR_VARIANTS but the first,
    the shipped set, scored with the run itself), over the same rows: no re-simulation, and the ideal
    readings and noise draws (`shared`, or computed here) shared by the variants, whose mounts, units and seed
    are the set's."""
    from railderail_sim.sensors.measure import shared_readings
    shipped = lambda criterion: [shipped_level(criterion)]
    shared = shared_readings(sensors, sim, arrays) if shared is None else shared
    return {variant_name(v): scores(measured_alarms(measured_results(sensor_variant(sensors, v), sim, arrays, shared),
                                                    arrays["time"], shipped), arrays, found, rules.window_s, beyond)
            for v in variants}


def run_one(item, cache=None, surveys=None):
    """One catalogue run (entry, seed): its hazards, distance and scores, the speed supervision's among them
    over its survey in `surveys` ({key: survey}, `supervision_score.surveys`; a run's survey follows from its
    entry, seed and the code, so the cache's key holds it) (a module-level function for the process pool and
    Dask), from the cache when it holds it."""
    entry, seed = item
    key = hashlib.sha256(jsonout.dumps(dict(run=entry.key(seed), code=source_hash())).encode()).hexdigest()
    path = Path(cache, key[:2], key + ".json") if cache else None
    if path is not None and path.exists():
        return json.loads(path.read_text())
    from dataclasses import replace

    from railderail_sim.sensors.config import load as load_sensors
    from railderail_sim.sensors.measure import shared_readings
    from railderail_sim.vehicle.simulate import Checkpoints, run_to_stop

    started = time.process_time()
    sc = replace(entry.scenario(seed), output_rate=RATE)
    checkpoints = Checkpoints()     # where the supervision's closed loops go on from (their approach is this run)
    sim, arrays, error = run_to_stop(sc, checkpoints=checkpoints)
    simulated = time.process_time()
    limits, rules = default_limits(), HazardRules()     # every run swept over the same thresholds: the shipped car
    basis = model_basis(sim.model)
    car = Car(basis["flange_height"], basis["max_contact_angle"], basis["static_wheel_load"], entry.friction)
    event = sim.derailment()
    line = entry.line()
    found = with_cure_leads(hazards(arrays, event, car, rules), line, rules)
    beyond = beyond_permitted(arrays, line, rules)
    deficiency = cant_deficiency(arrays, sc.track.rail_spacing)
    s, t = arrays["position"], arrays["time"]
    sensors = replace(load_sensors(), seed=seed)          # the shipped sensor set, its noise from the run's seed
    shared = shared_readings(sensors, sim, arrays)
    sensed = measured_results(sensors, sim, arrays, shared)
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
    result["sensor_variants"] = (sensor_sensitivity_run(sensors, sim, arrays, found, rules, beyond=beyond,
                                                          shared=shared)
                                 if result["part"] == "test" else None)
    varied = time.process_time()
    result["supervision"] = supervision_of_run(entry, seed, sc, sim, arrays, found, rules, beyond, surveys,
                                               checkpoints)
    for w, rows in result["supervision"]["windows"].items():
        result["windows"][w]["criteria"][SUPERVISION] = rows
    done = time.process_time()
    # process time of the simulation, the sensors with every criterion scored, the sensor variants, and the
    # speed supervision with its closed-loop re-runs
    result["cpu_s"], result["cpu_split_s"] = done - started, dict(simulation=simulated - started,
                                                                  scoring=scored - simulated,
                                                                  sensor_variants=varied - scored,
                                                                  supervision=done - varied)
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        jsonout.write(path, result)
    return result
