"""The speed profiles a survey gives along its line (railderail_sim.methods.survey): the civil one
(`permitted_profile`) and the most restrictive one, the speed supervisor's targets (`survey_targets`)."""
from ..line.file import line_from_dict
from ..vehicle.simulate import KMH
from .survey import RULES, SurveyResult


def _line(result):
    return line_from_dict((SurveyResult.from_dict(result) if isinstance(result, dict) else result).line["file"])


def permitted_profile(result):
    """The civil profile alone: [(start m, end m, permitted speed m/s)] (`Line.permitted_speed_at`)."""
    line = _line(result)
    edges = sorted({0.0, line.length_m, *(x for a, b, _ in line.speed_limits for x in (a, b)),
                    *(x for c in line.curves for x in c.extent)})
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        v = line.permitted_speed_at(0.5 * (a + b))
        if out and out[-1][2] == v and out[-1][1] == a:
            out[-1] = (out[-1][0], b, v)
        else:
            out.append((a, b, v))
    return out


def _stop(name, row):
    """The reason of a stop target (safe speed 0): a curve's or defect's row whose margins no speed tried kept."""
    if row["safe_speed_kmh"] > 0.0:
        return ""
    broken = row["first_broken"]
    return (f"{name}: stop before it, no speed tried kept the margins ({broken['margin']} at "
            f"{broken['speed_kmh']:.1f} km/h, the survey's lowest)")


def survey_targets(result):
    """The most restrictive speed profile along the line: [(start m, end m, speed limit m/s, reason)] in order,
    covering the line: the lowest at each place of the line speed, the civil speed limits, each curve's
    permitted speed and safe speed over its extent (from the start of its entry transition to the end of its
    exit transition) and each defect's safe speed from `defect_guard_m` before it to as far after it.
    `result` is a SurveyResult or its dict."""
    if isinstance(result, dict):
        result = SurveyResult.from_dict(result)
    line = _line(result)
    limits = [(0.0, line.length_m, line.line_speed_kmh, "line speed")]
    limits += [(a, b, v, f"speed limit {a / 1000:.3f}-{b / 1000:.3f} km") for a, b, v in line.speed_limits]
    for c in result.curves:
        name = f"curve {c['index']} (R {c['radius_m']:g} m)"
        limits.append((c["start_m"], c["end_m"], c["permitted_speed_kmh"], f"{name}: permitted speed"))
        limits.append((c["start_m"], c["end_m"], c["safe_speed_kmh"],
                       _stop(name, c) or f"{name}: safe speed, margins intact up to "
                       f"{c['margins_intact_up_to_kmh']:.1f} km/h less dV_ebi (critical derailment speed "
                       f"{c['critical_derailment_speed_kmh']:.1f} km/h"
                       + ("" if c["derailed"] else ", no derailment up to it") + ")"))
    for d in result.defects:
        name = f"defect {d['index']} ({d['kind']} {d['size_mm']:g} mm)"
        limits.append((max(0.0, d["position_m"] - RULES.defect_guard_m),
                       min(line.length_m, d["end_m"] + RULES.defect_guard_m), d["safe_speed_kmh"],
                       _stop(name, d) or f"{name}: safe speed, margins intact up to "
                       f"{d['margins_intact_up_to_kmh']:.1f} km/h less dV_ebi"))
    edges = sorted({x for a, b, _, _ in limits for x in (a, b)})
    profile = []
    for a, b in zip(edges[:-1], edges[1:]):
        covering = [(v, why) for lo, hi, v, why in limits if lo <= a and b <= hi]
        v, why = min(covering, key=lambda x: x[0])
        if profile and profile[-1][2] == v * KMH and profile[-1][3] == why and profile[-1][1] == a:
            profile[-1] = (profile[-1][0], b, v * KMH, why)
        else:
            profile.append((a, b, v * KMH, why))
    return profile

