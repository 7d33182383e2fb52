"""The warning evaluation as Markdown (`over_catalogue.write`, docs/report/warnings-catalogue.md): what it
found, the ground-truth and the measured criteria side by side, what the catalogue can and cannot resolve,
the paper's 0.06 rad criterion judged, the recommended levels with their reasons, the sensitivity to the
window and to the braking rule, the measured criteria's sensitivity to the sensors' noise, bias and sample
rate, the runs and every criterion over its thresholds."""
from __future__ import annotations

import math
import statistics
from collections import Counter

from .scoring import count_interval, resolvable_km, share_interval


def _share(k, n, ci):
    if not n:
        return "-"
    return f"{k}/{n} ({100 * k / n:.0f} %, {100 * ci[0]:.0f}-{100 * ci[1]:.0f} %)"


def _rate(row):
    lo, hi = row["false_alarms_per_1000_km_ci95"]
    text = f"{row['false_alarms_per_1000_km']:.1f} ({lo:.1f}-{hi:.1f})"
    if "false_alarms_per_1000_km_boot95" in row:
        blo, bhi = row["false_alarms_per_1000_km_boot95"]
        text += f" [{_number(blo, '.1f')}-{_number(bhi, '.1f')}]"
    return text


def _number(x, fmt=".2f"):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, fmt)


def shipped_rows(result):
    """The criteria rows at each criterion's shipped WARNING level."""
    return [r for r in result["criteria"] if r["threshold"] == result["shipped_levels"][r["criterion"]]]


def findings(result):
    """What the evaluation says, in sentences and tables."""
    runs, exposure, w = result["runs"], result["exposure"], result["derailment_window_s"]
    hazard = Counter(r["hazard"] for r in runs)
    families = sorted({r["family"] for r in runs})
    lines = [f"{len(runs)} runs of {len({r['scenario'] for r in runs})} scenarios over {sum(r['km'] for r in runs):.0f} km: "
             f"{hazard['derailment']} derailed, {hazard['near_miss']} came near (a margin fell, no derailment), "
             f"{hazard['normal']} ran with every margin intact. Normal running (outside every hazard's window of "
             f"W = {w:g} s, within the line's permitted speed and cant deficiency) is {exposure['normal_km']:.0f} km and "
             f"{exposure['normal_h']:.1f} h: {exposure['train_km']:.0f} km in the train part, {exposure['test_km']:.0f} km "
             f"in the test part ({result['split']['how']}); {exposure['beyond_permitted_km']:.0f} km ran beyond the "
             "permitted conditions with every margin intact (neither exposure nor hazard).", "",
             "| family | runs | derailed | near misses | normal | mechanisms shown |", "|---|---|---|---|---|---|"]
    for f in families:
        mine = [r for r in runs if r["family"] == f]
        c = Counter(r["hazard"] for r in mine)
        shown = Counter(r["mechanism"] for r in mine)
        lines.append(f"| {f} | {len(mine)} | {c['derailment']} | {c['near_miss']} | {c['normal']} | "
                     + ", ".join(f"{m.replace('_', ' ')} ({n})" for m, n in shown.most_common()) + " |")
    lines += ["", *mechanisms(result)]
    rows = shipped_rows(result)
    lines += ["", "### Each criterion at its shipped level, on the test part", "",
              "The ground-truth criteria (signals `ground_truth`: the simulator's wheel forces and motions) and "
              "beside them the criteria an on-board unit computes from its sensors (`measured`: the shipped sensor "
              "set, noise on; the bogie frames' instability rules, the car body's accelerations and roll, the "
              "roll-balance estimator's warnings), each on its own samples, held onto the run's rows from the "
              "sample's stamp on (latency included). A measured channel has no wheel: a frame's alarm is true in a "
              "hazard window of its bogie, an estimated side's at its side, the car body's at either bogie.", "",
              "A hazard is warned only by an alarm standing at its place at its last sample before it, the lead from "
              "that alarm's start (at most W). Derailments usefully warned (the lead covers reaction, brake build-up "
              "and braking to the hazard's cure, `hazards.hazard_cure`, on dry rail), with the Clopper-Pearson 95 % "
              "interval and the scenario bootstrap's in brackets; on wet rail; warned at all; the median lead of those "
              "warned; false-alarm episodes (km of a run with a false alarm) per 1000 km of normal running with the "
              "exact Poisson 95 % interval and the scenario bootstrap's in brackets, per hour, the share of normal "
              "running time in false alarm, and the false-alarm episodes inside hazard windows (alarms that ended "
              "before the hazard, or at another place), counted apart.", "",
              "| criterion | signals | level | usefully warned | wet rail | warned | median lead (s) | near misses warned | "
              "false alarms / 1000 km (95 %) [bootstrap] | per hour | time in alarm | false in windows |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        boot = r.get("usefully_warned_share_boot95")
        lines.append(f"| {r['criterion']} | {r['signals']} | {r['threshold']:.4g} | "
                     f"{_share(r['usefully_warned'], r['derailments'], r['usefully_warned_ci95'])}"
                     + (f" [{_number(100 * boot[0] if boot[0] == boot[0] else None, '.0f')}-"
                        f"{_number(100 * boot[1] if boot[1] == boot[1] else None, '.0f')} %]" if boot else "")
                     + f" | {r['usefully_warned_wet']} | "
                     f"{r['warned']}/{r['derailments']} | {_number(r['lead_s_median'])} | "
                     f"{r['near_misses_warned']}/{r['near_misses']} | {_rate(r)} | {_number(r['false_alarms_per_hour'])} | "
                     f"{100 * r['time_in_alarm_share']:.2f} % | {r['window_false_episodes']} |")
    lines += ["", "Usefully warned by family (test part, shipped levels):", "",
              "| criterion | " + " | ".join(families) + " |", "|---" * (len(families) + 1) + "|"]
    for r in rows:
        by = r["usefully_warned_by_family"]
        lines.append(f"| {r['criterion']} | " + " | ".join(f"{by[f][0]}/{by[f][1]}" if f in by else "-" for f in families)
                     + " |")
    lines += ["", "### What the catalogue can and cannot resolve", ""]
    for level, budget in result["budgets_per_1000_km"].items():
        need = resolvable_km(budget)
        lines.append(f"- A {level.upper()} budget of {budget:g} false alarms per 1000 km needs {need:.0f} km of normal "
                     f"running in a part before even no false alarm proves it at 95 %: the train part has "
                     f"{exposure['train_km']:.0f} km, the test part {exposure['test_km']:.0f} km.")
    lines.append(f"- The smallest rate the test part can bound is "
                 f"{1000 * count_interval(0)[1] / max(exposure['test_km'], 1e-9):.1f} per "
                 "1000 km (no false alarm at all). An operator's budget for an alarm that stops a train is orders of "
                 "magnitude below any a simulated catalogue can resolve: the evaluation ranks criteria and bounds "
                 "their rates; it cannot certify a rate of, say, one per million km.")
    n = result["criteria"][0]["derailments"] if result["criteria"] else 0
    if n:
        lines.append(f"- {n} derailments in the test part: none of them warned has an upper 95 % bound of "
                     f"{100 * share_interval(0, n)[1]:.0f} %, all of them a lower bound of {100 * share_interval(n, n)[0]:.0f} %.")
    lines += ["", *paper_criterion(result)]
    return lines


def mechanisms(result):
    """Lines: the derailments expected and shown per mechanism and part, the flange-climb margin against both
    limits, and the lift level's sensitivity."""
    lines = ["### Derailments by mechanism", "",
             "Per mechanism (the entry's family: over-speed unloading, flange climb at a defect, gust overturning, "
             "fault-driven): the runs meant to derail (`expect_derailment`) and the runs that derailed, by part.", "",
             "| mechanism | train: expected | train: derailed | test: expected | test: derailed |", "|---|---|---|---|---|"]
    for mechanism, parts in result["mechanisms"].items():
        lines.append(f"| {mechanism} | {parts['train']['expected']} | {parts['train']['derailed']} | "
                     f"{parts['test']['expected']} | {parts['test']['derailed']} |")
    peaks = [r["margin_peaks"] for r in result["runs"]]
    if peaks:
        over_run = sum(p["q_over_p_max"] >= p["nadal_run_friction"] for p in peaks)
        over_cfr = sum(p["q_over_p_max"] >= p["nadal_cfr"] for p in peaks)
        lift = {share: sum(p["lift_share_max"] >= share for p in peaks) for share in (0.25, 0.5, 0.75)}
        lines += ["", f"The flange-climb margin is Nadal's limit at the run's friction (the simulator knows it, and the "
                  f"wheel climbs by it); 49 CFR 213.333's single-wheel L/V limit is Nadal's at friction 0.5. Of "
                  f"{len(peaks)} runs, the Y/Q's 5 ft mean reached the first in {over_run} and the second in {over_cfr}. "
                  "The lift level (half the flange height) has no standard value: the runs whose wheel lift reached "
                  + ", ".join(f"{share:g} of the flange height: {n}" for share, n in lift.items()) + "."]
    return lines


def paper_criterion(result):
    """Lines: the paper's 0.06 rad attack-angle warning on this basis."""
    runs = result["runs"]
    derailed = [r for r in runs if r["hazard"] == "derailment"]
    paper = next((r for r in result["criteria"] if r["criterion"] == "attack_angle" and r["threshold"] == 0.06), None)
    largest = max((r["peaks"]["attack_angle"], r["scenario"], r["seed"]) for r in runs)
    lines = ["### The paper's 0.06 rad attack-angle warning", "",
             f"The front wheelset's attack angle reached at most {largest[0] * 1e3:.1f} mrad in any run ({largest[1]}, "
             f"seed {largest[2]})"]
    if derailed:
        peaks = [r["peaks"]["attack_angle"] for r in derailed]
        lines[-1] += (f"; in the {len(derailed)} derailing runs, up to the derailment, {statistics.median(peaks) * 1e3:.1f} "
                      f"mrad in the median and {max(peaks) * 1e3:.1f} mrad at most")
    lines[-1] += "."
    if paper is not None:
        lines.append(f"At 0.06 rad (Yu 2022) it usefully warned {paper['usefully_warned']} of {paper['derailments']} "
                     f"derailments of the test part, warned {paper['warned']}, and raised "
                     f"{paper['false_alarms_per_1000_km']:.1f} false alarms per 1000 km.")
        if paper["derailments"] and paper["warned"] == 0:
            lines.append("A wheelset whose wheels are still on their rails cannot yaw that far: in a bogie its attack "
                         "angle is about half the wheelbase over the curve radius plus what the flange clearance allows "
                         "over the wheelbase, tens of mrad even at R 150 m, and the derailment (the wheel lifted to its "
                         "flange height) comes first. On this basis the paper's claim that the attack angle reaching "
                         "0.06 rad announces the derailment does not hold: it could only describe the motion after the "
                         "wheel has left its rail, which this model stops at.")
    return lines


def sensor_sensitivity(result):
    """Lines: the measured criteria at their shipped levels as the sensors' noise, bias and rate change."""
    sens = result["sensor_sensitivity"]
    variants = list(dict.fromkeys(s["variant"] for s in sens))
    lines = ["### Sensitivity of the measured criteria to the sensors", "",
             "Test part, shipped levels, W = " f"{result['derailment_window_s']:g} s: the same simulated rows seen "
             "through the shipped sensor set with its white-noise densities, its biases (the constant bias, its "
             "random walk and the odometer's radius error) scaled, or every mount sampled at a lower rate (the air "
             "springs and the odometer at the lower of theirs and it; no rate above the simulator's 200 Hz output "
             "rate). Each cell: derailments usefully warned / warned of all, false alarms per 1000 km, time in "
             "alarm.", "",
             "| criterion | " + " | ".join(variants) + " |", "|---" * (len(variants) + 1) + "|"]
    for criterion in dict.fromkeys(s["criterion"] for s in sens):
        cells = {s["variant"]: s for s in sens if s["criterion"] == criterion}
        lines.append(f"| {criterion} | " + " | ".join(
            f"{c['usefully_warned']}/{c['warned']}/{c['derailments']}, {_number(c['false_alarms_per_1000_km'], '.1f')}, "
            f"{100 * c['time_in_alarm_share']:.2f} %" for c in (cells[v] for v in variants)) + " |")
    return lines


def speed_supervision(result):
    """Lines: the speed supervision's derailments prevented per family, its interventions in ordinary running,
    the held-out goal and what it cannot see (docs/warning-evaluation.md, section 8a)."""
    sup = result["speed_supervision"]
    goal, ordinary = sup["held_out_goal"], sup["interventions_in_ordinary_running"]
    lines = ["### The speed supervision: derailments prevented", "",
             "Test part: each run that derailed without the supervisor run again with it in the closed loop (the "
             "emergency brake on its intervention, dry rail). Its WARNING and INTERVENTION levels are scored in the "
             "tables as `speed_supervision` 2 and 3.", "",
             "| family | prevented / derailments (95 %) |", "|---|---|"]
    for family, row in sup["prevented_by_family"].items():
        lines.append(f"| {family} | {_share(row['prevented'], row['derailments'], row['prevented_ci95'])} |")
    lines += ["", f"Interventions in ordinary running: {ordinary['episodes']} episodes over {ordinary['normal_km']:.0f} km "
              f"({_number(ordinary['per_1000_km'])} per 1000 km, {_number(ordinary['per_hour'])} per hour); "
              f"{ordinary['ordinary_runs_with_intervention']} of {ordinary['ordinary_runs']} ordinary runs.", "",
              "Held-out goal (every over-speed derailment usefully warned and prevented, no intervention in ordinary "
              f"running): {'met' if goal['met'] else 'not met'} over {goal['overspeed_derailments']} over-speed "
              "derailments" + (f"; not usefully warned: {', '.join(goal['not_usefully_warned'])}"
                               if goal["not_usefully_warned"] else "")
              + (f"; not prevented: {', '.join(goal['not_prevented'])}" if goal["not_prevented"] else "") + ".", "",
              "| what the supervisor cannot see | derailments | prevented as shipped | still prevented |",
              "|---|---|---|---|"]
    lines += [f"| {r['variant']} | {r['derailments']} | {r['prevented_as_shipped']} | {r['still_prevented']} |"
              for r in sup["sensitivity"]]
    return lines


def markdown(result):
    """The whole evaluation as Markdown."""
    budgets = result["budgets_per_1000_km"]
    lines = ["## Warning quality over the scenario catalogue (`railderail warnings --catalogue`)", "",
             *findings(result), "", "![usefully warned against false alarms](warnings-catalogue.png)", "",
             "### Recommended levels", "",
             f"Each level chosen on the train part (the most derailments usefully warned, then the highest threshold, "
             f"among the thresholds whose false alarms' upper 95 % bound is within the level's budget and that usefully "
             f"warn at least {result['min_useful_share']:.0%} of the derailments), then confirmed on the test part; budgets "
             f"{budgets['warning']:g} (WARNING) and {budgets['critical']:g} (CRITICAL) per 1000 km. A level without a "
             "recommendation is disabled in `monitor-recommended.yaml`.", "",
             "| criterion | level | threshold | test: usefully warned | test: false alarms / 1000 km (95 %) | reason |",
             "|---|---|---|---|---|---|"]
    for r in result["recommended"]:
        t = r["test"]
        lines.append(f"| {r['criterion']} | {r['level']} | {_number(r['threshold'], '.4g')} | "
                     + (f"{_share(t['usefully_warned'], t['derailments'], t['usefully_warned_ci95'])} | {_rate(t)} | "
                        if t else "- | - | ") + f"{r['reason'] or ''} |")
    lines += ["", "Many levels are tried on the train part; the test part scores only the level chosen there, one "
              "check per level, so its figures carry no selection effect; the train part's best of many levels is "
              "optimistic and is not reported as a result.",
              "", "### Sensitivity: the window W and the speed to brake off", "",
              "Derailments usefully warned at each criterion's shipped level, test part, for each derailment window W "
              "(s) and share of the speed to brake off before the hazard (1: to a stop).", ""]
    sens = result["sensitivity"]
    keys = sorted({(s["window_s"], s["safe_speed_reduction"]) for s in sens})
    lines += ["| criterion | " + " | ".join(f"W {w:g} s, {red:.0%}" for w, red in keys) + " |",
              "|---" * (len(keys) + 1) + "|"]
    for criterion in dict.fromkeys(s["criterion"] for s in sens):
        cells = {(s["window_s"], s["safe_speed_reduction"]): s for s in sens if s["criterion"] == criterion}
        lines.append(f"| {criterion} | " + " | ".join(f"{cells[k]['usefully_warned']}/{cells[k]['derailments']}"
                                                    for k in keys) + " |")
    lines += ["", *sensor_sensitivity(result), "", *speed_supervision(result)]
    lines += ["", "### The labelling rule and the braking model", "", "| name | value | unit | meaning | source | sure |",
              "|---|---|---|---|---|---|"]
    lines += [f"| {r['name']} | {r['value']} | {r['unit']} | {r['meaning']} | {r['source']} | {r['sure']} |"
              for r in result["rules"]]
    lines += ["", "### The runs", "",
              "| scenario | seed | part | family | km | max cant deficiency (mm) | hazard | mechanism | cure | first true "
              "alert at the shipped level (lead s / needed dry, wet s; * useful) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["runs"]:
        firsts = ", ".join(f"{c} {a['lead_s']:.1f}/{a['lead_needed_s']:.1f}, {a['lead_needed_wet_s']:.1f}"
                           f"{'*' if a['useful'] else ''}" for c, a in r["first_true_alert"].items() if a) or "-"
        cure = next((a["hazard_cure"] for a in r["first_true_alert"].values() if a), None)
        cure = (f"{cure['mechanism']}: {cure['speed_kmh']:.0f} km/h (permitted {cure['permitted_speed_kmh']:.0f})"
                if cure else "-")
        lines.append(f"| {r['scenario']} | {r['seed']} | {r['part']} | {r['family']} | {r['km']:.1f} | "
                     f"{r['cant_deficiency_mm_max']:.0f} | {r['hazard'].replace('_', ' ')} | {r['mechanism'].replace('_', ' ')} | "
                     f"{cure} | {firsts} |")
    lines += ["", "### Every criterion over its thresholds (test part)", "",
              "| criterion | signals | threshold | usefully warned | warned | median lead (s) | near misses warned | "
              "false-alarm episodes | false alarms / 1000 km (95 %) | per hour | time in alarm |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["criteria"]:
        lines.append(f"| {r['criterion']} | {r['signals']} | {r['threshold']:.4g} | "
                     f"{_share(r['usefully_warned'], r['derailments'], r['usefully_warned_ci95'])} | {r['warned']} | "
                     f"{_number(r['lead_s_median'])} | {r['near_misses_warned']}/{r['near_misses']} | "
                     f"{r['false_alarm_episodes']} | {_rate(r)} | {_number(r['false_alarms_per_hour'])} | "
                     f"{100 * r['time_in_alarm_share']:.2f} % |")
    return "\n".join(lines)
