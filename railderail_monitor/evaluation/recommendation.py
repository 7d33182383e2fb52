"""The recommendation of the warning evaluation (`over_catalogue`): each criterion's WARNING and CRITICAL
levels chosen on the train part under their false-alarm budgets and checked on the test part, nothing
recommended where the exposure cannot resolve the budget or too few derailments are usefully warned; the
monitor's limits at the recommended levels."""
from __future__ import annotations

import math

from ..onboard import measured
from ..warning.limits import critical_name, default_limits
from .scoring import resolvable_km
from .supervision_score import CRITERION as SUPERVISION
from .sweeps import CRITERIA, SIGNALS
from .tables import split, summarize

BUDGETS = {"warning": 10.0, "critical": 3.0}      # false-alarm episodes per 1000 km of each level by default
MIN_USEFUL_SHARE = 0.5     # a level is recommended only if it usefully warns at least this share of derailments


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
    # the speed supervision's levels are ETCS's (supervision.curves), not chosen from a sweep
    for criterion in (c for c in CRITERIA if c != SUPERVISION):
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
