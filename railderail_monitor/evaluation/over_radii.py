"""`railderail warnings`: how early, and how falsely, each criterion warns.

For each curve radius (default the paper's six, 800-1800 m) it runs the core directly (no ROS;
the same `warning.monitor.alerts_of_run` as the monitor node, at the same 200 Hz) over:

  trial      the paper's progressive staircase from 200 km/h until the derailment (the demo's run);
  critical   a constant speed equal to the critical derailment speed (the lowest constant speed
             that derails on the Table 2 line, from `--critical` = `railderail sweep --json` output,
             else found here by the progressive trial's bisection to 1 km/h);
  near       a constant speed 10 km/h below it (no derailment expected: the edge of safety);
  balance    the cant's balance speed (no cant deficiency);
  operating  the speed at 100 mm of cant deficiency (EN 13803's order of the limit for ordinary
             operation; 0.65 m/s^2 of uncompensated lateral acceleration).

For every run and every criterion level it reports the first alert; on a derailing run its lead
before the derailment (seconds and metres of track, car-body centre), on a run without a
derailment the number of alerts (false alarms). The summary gives, per criterion level, how many
derailments it warned of, the smallest and the median lead, and the false-alarm runs.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import replace
from pathlib import Path

from railderail_sim import jsonout
from railderail_sim.atomic import atomic_write
from railderail_sim.ranges import check_range
from railderail_sim.vehicle.simulate import RADIUS_RANGE

from ..warning.limits import CRITERIA, SEVERITY_NAMES, default_limits
from ..warning.monitor import alerts_of_run
from ..warning.alerts import lead_times
from .catalogue_runs import RATE
from .recommendation import BUDGETS

PAPER_RADII = (800.0, 1000.0, 1200.0, 1400.0, 1600.0, 1800.0)
CASES = ("trial", "critical", "near", "balance", "operating")
NEAR_BELOW_KMH = 10.0
OPERATING_CANT_DEFICIENCY = 0.100      # m
def levels():
    """Every enabled criterion level of the built-in limits, as 'criterion/severity'."""
    limits = default_limits()
    return [f"{c}/{SEVERITY_NAMES[s]}" for c in CRITERIA for s, _ in limits.levels(c)]


def cant_deficiency_speed_kmh(radius, deficiency_m):
    """Speed (km/h) on the Table 2 curve of this radius at a cant deficiency (m)."""
    from railderail_sim.parameters import TrackParameters
    return TrackParameters(radius=radius).speed_at_cant_deficiency(deficiency_m) * 3.6


def _scenario(radius, case, speed_kmh, friction):
    from railderail_sim.methods.progressive_trial import Staircase, staircase_scenario
    from railderail_sim.vehicle.simulate import scenario

    base = scenario(radius=radius, speed_kmh=300.0 if speed_kmh is None else speed_kmh, friction=friction)
    if case == "trial":
        base = staircase_scenario(base, radius, Staircase())
    return replace(base, output_rate=RATE)


def run_case(radius, case, speed_kmh, friction=0.3):
    """One run and its alerts (a module-level function for the process pool)."""
    from ..warning.limits import limits_for_model

    t0 = time.monotonic()
    from railderail_sim.vehicle.simulate import run_to_stop
    sim, arrays, error = run_to_stop(_scenario(radius, case, speed_kmh, friction), 5.0)
    limits = limits_for_model(sim.model, friction)
    alerts = alerts_of_run(arrays, limits)
    from ..warning.quantities import front_attack_angle, unloading_ratio
    peaks = dict(attack_angle_rad=float(front_attack_angle(arrays["attack_angle"]).max()),
                 wheel_lift_m=float(arrays["wheel_lift"].max()),
                 derailment_coefficient=float(arrays["derailment_coefficient"].max()),
                 unloading_ratio=float(unloading_ratio(arrays["vertical_force"], limits.static_wheel_load).max()))
    event = sim.derailment()
    derailment = None
    if event is not None:
        derailment = dict(event, track_position_m=event["car_body_position_m"])
    return dict(radius_m=radius, case=case, speed_kmh=speed_kmh if case != "trial" else None,
                derailed=derailment is not None, derailment=derailment, diverged=error,
                end_position_m=float(arrays["position"][-1]) if len(arrays["position"]) else 0.0,
                alerts=[a.as_dict() for a in alerts], first=lead_times(alerts, derailment), peaks=peaks,
                limits=limits.as_dict(), compute_s=time.monotonic() - t0)


def critical_speed(radius, friction=0.3, tolerance_kmh=1.0):
    from railderail_sim.methods.progressive_trial import progressive_trial
    from railderail_sim.vehicle.simulate import scenario

    r = progressive_trial(scenario(radius=radius, friction=friction), radius, refine=True, tolerance_kmh=tolerance_kmh)
    return radius, r.refined_speed_kmh if math.isfinite(r.refined_speed_kmh) else r.critical_derailment_speed_kmh


def load_critical(path):
    """{radius: speed} from `railderail sweep --json` / `railderail trial --json` output."""
    try:
        data = json.loads(Path(path).read_text())
    except OSError as error:
        raise ValueError(f"{path}: cannot read it ({error.strerror})") from None
    except json.JSONDecodeError as error:
        raise ValueError(f"{path} is not JSON ({error})") from None
    items = data if isinstance(data, list) else data.get("results", [data])
    out = {}
    for d in items:
        v = d.get("refined_speed_kmh")
        if v is None or not math.isfinite(v):
            v = d.get("critical_derailment_speed_kmh")
        if v is not None and math.isfinite(v):
            out[float(d["radius_m"])] = float(v)
    if not out:
        raise ValueError(f"{path}: no radius_m with a critical speed (refined_speed_kmh or "
                         "critical_derailment_speed_kmh) in it")
    return out


def summarize(runs):
    """Per criterion level: warned derailments, leads, false-alarm runs."""
    derailing = [r for r in runs if r["derailed"]]
    safe = [r for r in runs if not r["derailed"] and not r["diverged"]]
    out = {}
    for level in levels():
        leads = [r["first"][level] for r in derailing if level in r["first"] and r["first"][level]["lead_s"] >= 0]
        false_runs = [f"R{r['radius_m']:.0f}/{r['case']}" for r in safe if level in r["first"]]
        out[level] = dict(
            derailments=len(derailing), warned=len(leads),
            min_lead_s=min((x["lead_s"] for x in leads), default=math.nan),
            median_lead_s=statistics.median([x["lead_s"] for x in leads]) if leads else math.nan,
            min_lead_m=min((x["lead_m"] for x in leads), default=math.nan),
            median_lead_m=statistics.median([x["lead_m"] for x in leads]) if leads else math.nan,
            runs_without_derailment=len(safe), false_alarm_runs=len(false_runs), false_alarm_cases=false_runs)
    return out


def _cell(first, level, derailed):
    v = first.get(level)
    if v is None:
        return "-"
    if derailed:
        return f"{v['lead_s']:.2f} s/{v['lead_m']:.0f} m"
    return f"FA@{v['speed_kmh']:.0f}"


def table(runs):
    names = levels()
    head = ["R (m)", "case", "v (km/h)", "derailment", "peaks: attack angle ws0 (rad) / lift (mm) / Y/Q / ΔQ/Q0"] + names
    rows = []
    for r in runs:
        d = r["derailment"]
        what = (f"{d['speed_kmh']:.0f} km/h ws{d['wheelset']} {d['rail_side']} {d['mechanism'].split('_')[1]}"
                if d else ("diverged" if r["diverged"] else "none"))
        speed = f"{r['speed_kmh']:.0f}" if r["speed_kmh"] is not None else "staircase"
        p = r["peaks"]
        peaks = (f"{p['attack_angle_rad']:.4f} / {p['wheel_lift_m'] * 1e3:.1f} / {p['derailment_coefficient']:.2f} / "
                 f"{p['unloading_ratio']:.2f}")
        rows.append([f"{r['radius_m']:.0f}", r["case"], speed, what, peaks]
                    + [_cell(r["first"], level, r["derailed"]) for level in names])
    return head, rows


def markdown(runs, summary):
    head, rows = table(runs)
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    lines += ["", "| criterion level | derailments warned | min lead | median lead | false-alarm runs |",
              "|---|---|---|---|---|"]
    for level, s in summary.items():
        lead = (f"{s['min_lead_s']:.2f} s / {s['min_lead_m']:.0f} m" if s["warned"] else "-")
        med = (f"{s['median_lead_s']:.2f} s / {s['median_lead_m']:.0f} m" if s["warned"] else "-")
        lines.append(f"| {level} | {s['warned']}/{s['derailments']} | {lead} | {med} | "
                     f"{s['false_alarm_runs']}/{s['runs_without_derailment']} |")
    return "\n".join(lines)


def evaluate(radii, critical=None, cases=CASES, workers=None, friction=0.3, progress=None):
    critical = dict(critical or {})
    workers = workers or os.cpu_count() or 1
    with ProcessPoolExecutor(max_workers=workers) as pool:
        missing = [r for r in radii if r not in critical and {"critical", "near"} & set(cases)]
        for future in as_completed([pool.submit(critical_speed, r, friction) for r in missing]):
            r, v = future.result()
            critical[r] = v
            if progress:
                progress(f"critical derailment speed R = {r:g} m: {v:.1f} km/h")
        jobs = []
        for r in radii:
            speeds = {"trial": None, "critical": critical.get(r), "near": (critical.get(r) or 0) - NEAR_BELOW_KMH,
                      "balance": cant_deficiency_speed_kmh(r, 0.0),
                      "operating": cant_deficiency_speed_kmh(r, OPERATING_CANT_DEFICIENCY)}
            for case in cases:
                if case in ("critical", "near") and not speeds[case]:
                    continue
                jobs.append(pool.submit(run_case, r, case, speeds[case], friction))
        runs = []
        for future in as_completed(jobs):
            run = future.result()
            runs.append(run)
            if progress:
                progress(f"R = {run['radius_m']:g} m {run['case']}: {'derailed' if run['derailed'] else 'no derailment'}, "
                         f"{len(run['alerts'])} alerts ({run['compute_s']:.0f} s)")
    order = {c: i for i, c in enumerate(CASES)}
    runs.sort(key=lambda r: (r["radius_m"], order[r["case"]]))
    return dict(radii=list(radii), critical_speeds_kmh={str(k): v for k, v in critical.items()}, runs=runs,
                summary=summarize(runs))


def command(parser: argparse.ArgumentParser):
    parser.add_argument("--radii", default=",".join(f"{r:g}" for r in PAPER_RADII), help="curve radii, m")
    parser.add_argument("--critical", metavar="SWEEP.json",
                        help="critical speeds from `railderail sweep --json` (else computed here)")
    parser.add_argument("--cases", default=",".join(CASES), help=f"runs per radius, of {', '.join(CASES)}")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: CPU count)")
    parser.add_argument("--out", metavar="DIR", help="also write DIR/warnings.json and DIR/warnings.md")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--catalogue", nargs="?", const="shipped", metavar="FILE.yaml",
                        help="evaluate a scenario catalogue instead (railderail_monitor/evaluation/catalogue.py; no FILE: the "
                             "shipped one), every criterion over its thresholds")
    parser.add_argument("--cache", metavar="DIR", default=None,
                        help="with --catalogue: keep each run's result here (default OUT/cache, or none)")
    parser.add_argument("--scheduler", default=None, help="with --catalogue: a Dask scheduler's address")
    parser.add_argument("--warning-budget-per-1000-km", type=float, default=BUDGETS["warning"],
                        help="with --catalogue: the false-alarm budget of a recommended WARNING level "
                             "(default %(default)g)")
    parser.add_argument("--critical-budget-per-1000-km", type=float, default=BUDGETS["critical"],
                        help="with --catalogue: the false-alarm budget of a recommended CRITICAL level "
                             "(default %(default)g)")

    def run(args):
        if args.catalogue is not None:
            from .over_catalogue import command_line
            return command_line(args)
        try:
            radii = [float(x) for x in args.radii.split(",") if x]
        except ValueError:
            raise ValueError(f"--radii {args.radii!r} is not a comma-separated list of numbers") from None
        for r in radii:
            check_range("curve radius", r, *RADIUS_RANGE, "m")
        cases = [c for c in args.cases.split(",") if c]
        bad = [c for c in cases if c not in CASES]
        if bad:
            raise ValueError(f"unknown case(s) {', '.join(bad)}; choose from {', '.join(CASES)}")
        critical = load_critical(args.critical) if args.critical else None
        say = (lambda text: print(text, file=sys.stderr, flush=True))
        result = evaluate(radii, critical, cases, args.workers, progress=say)
        if args.out:
            out = Path(args.out)
            out.mkdir(parents=True, exist_ok=True)
            jsonout.write(out / "warnings.json", result)
            with atomic_write(out / "warnings.md") as handle:
                handle.write(markdown(result["runs"], result["summary"]) + "\n")
            say(f"wrote {out / 'warnings.json'} and {out / 'warnings.md'}")
        if args.json:
            print(jsonout.dumps(result, indent=1))
        else:
            print(markdown(result["runs"], result["summary"]))
    return run
