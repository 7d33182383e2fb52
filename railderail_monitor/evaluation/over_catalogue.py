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

The speed supervision (`supervision_score`) is one more criterion: each run's line is surveyed first (once
per curve shape and friction, cached), the supervisor scored beside the run, and a run that derailed run
again with the supervisor braking it (`prevented`).
"""
from __future__ import annotations

import functools
import os
import time
from pathlib import Path

from railderail_sim import jsonout

from ..warning.limits import default_limits
from .catalogue_runs import run_one
from .hazards import HazardRules
from .recommendation import BUDGETS, MIN_USEFUL_SHARE, recommend, recommended_limits
from .sensitivities import sensitivity, sensor_sensitivity
from .sweeps import CRITERIA, shipped_level
from . import supervision_score as supervision
from .tables import first_true_alerts, hazard_of, mechanism_counts, mechanism_of, split, summarize

# issue 44's target for `bench` (on 2 cores) and why the figure falls short (docs/performance.md)
TARGETS = {"warnings_catalogue_km_per_min": (100.0, "the runs' simulation is three quarters of the process time, the "
                                                     "ordinary runs on irregular track most of it: the core's "
                                                     "right-hand side, as real_time_factor_rigid_irregular")}
SPLIT = ("by scenario and track: each entry's runs in one part (its `part`, else alternating train and test "
         "within its family in the file's order); no track sample, irregularity file or defect on both sides")


def evaluate(entries, cache=None, workers=None, scheduler=None, progress=True, budgets=BUDGETS,
             min_share=MIN_USEFUL_SHARE):
    """The evaluation of a catalogue's entries (the --json object)."""
    from railderail_sim.methods.parallel import run_all
    items = [run for e in entries for run in e.runs()]
    started = time.perf_counter()
    surveyed, survey_cpu = supervision.surveys(entries, cache=cache, workers=workers, scheduler=scheduler,
                                               progress=progress)
    survey_wall = time.perf_counter() - started
    runs = run_all(functools.partial(run_one, cache=cache, surveys=surveyed), items, workers=workers,
                   scheduler=scheduler, progress=progress, desc="warnings", unit="run",
                   cost=[e.expected_cost(seed) for e, seed in items])
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
        speed_supervision=dict(prevented_by_family=supervision.prevented_by_family(test),
                               prevented_by_family_train=supervision.prevented_by_family(train),
                               interventions_in_ordinary_running=supervision.interventions_in_ordinary_running(test, w),
                               held_out_goal=supervision.held_out_goal(test, w, rules),
                               sensitivity=supervision.sensitivity_table(test),
                               surveys=len(surveyed), survey_settings=supervision.survey_settings_row()),
        runs=[dict(scenario=r["scenario"], family=r["family"], seed=r["seed"], part=r["part"], km=r["km"],
                   hazard=hazard_of(r), mechanism=mechanism_of(r), derailment=r["derailment"],
                   expected_mechanism=r["expected_mechanism"], expect_derailment=r["expect_derailment"],
                   cant_deficiency_mm_max=r["cant_deficiency_mm_max"], diverged=r["diverged"], peaks=r["peaks"],
                   margin_peaks=r["margin_peaks"],
                   first_true_alert=first_true_alerts(r, limits, rules),
                   prevented=r["supervision"]["prevented"]) for r in runs],
        throughput=dict(wall_s=wall, survey_wall_s=survey_wall, survey_cpu_s=survey_cpu,
                        cpu_s=sum(r["cpu_s"] for r in runs),
                        km=sum(r["km"] for r in runs),
                        cpu_split_s={k: sum(r["cpu_split_s"][k] for r in runs) for k in runs[0]["cpu_split_s"]},
                        cores=os.cpu_count() if not scheduler else None))


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
