"""The sensitivity tables of the warning evaluation (`over_catalogue`) on the test part: each criterion at
its shipped level against the window W and the share of speed to brake off (`sensitivity`), and the measured
criteria against the sensor set's noise, bias and sample rate (`sensor_sensitivity`)."""
from __future__ import annotations

from ..onboard import measured
from .sweeps import CRITERIA, SENSOR_VARIANTS, SIGNALS, shipped_level, variant_name
from .tables import summarize

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
