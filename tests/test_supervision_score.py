"""The speed supervision scored by the warning evaluation (railderail_monitor/evaluation/supervision_score.py),
on small hand-built cases: no simulation, no survey."""
import math

import numpy as np

from railderail_monitor.evaluation import supervision_score as ss
from railderail_monitor.evaluation.hazards import NORMAL, HazardRules, windows
from railderail_monitor.supervision.curves import INTERVENTION, KMH, WARNING, SupervisionLimits, Target
from railderail_monitor.supervision.supervisor import Supervisor
from railderail_sim.supervision.braking import BrakingModel

RATE = 200.0      # Hz, as the catalogue's runs


def _run(speed_kmh, length_m):
    """Arrays of a constant-speed run from 0 m (car body centre) over `length_m`."""
    v = speed_kmh * KMH
    t = np.arange(0.0, length_m / v, 1.0 / RATE)
    return dict(time=t, position=v * t, speed=np.full_like(t, v))


def _supervisor(limit_kmh, start_m):
    target = Target(start_m, start_m + 2000.0, limit_kmh * KMH, "a curve of the test")
    return Supervisor([target], BrakingModel(adhesion="dry"), SupervisionLimits())


def test_a_train_over_its_target_warns_then_intervenes_before_the_target_and_one_below_never_alarms():
    fast = _run(300.0, 6000.0)
    levels = ss.row_levels(_supervisor(250.0, 5000.0), fast, 0.0)
    first = {code: int(np.argmax(levels >= code)) for code in (WARNING, INTERVENTION)}
    assert levels.max() == INTERVENTION
    assert 0 < first[WARNING] < first[INTERVENTION]
    # the intervention comes before the target, by at least the braking distance from 300 km/h to the target's
    # speed with its intervention margin (dV_ebi 15 km/h at 250 km/h) at the braking model's 0.9 m/s^2
    stop = ((300 * KMH) ** 2 - (265 * KMH) ** 2) / (2 * 0.9)
    assert fast["position"][first[INTERVENTION]] < 5000.0 - stop
    # and stays on while the unbraked train is above the target (the open loop)
    assert np.all(levels[first[INTERVENTION]:] == INTERVENTION)
    slow = _run(240.0, 6000.0)
    assert ss.row_levels(_supervisor(250.0, 5000.0), slow, 0.0).max() < WARNING


def _hazard(t):
    return dict(kind="derailment", margin=None, time_s=t, end_s=t, speed_m_s=80.0, position_m=0.0,
                places=[[0, 0]])


def test_the_levels_are_scored_as_standing_alarms_with_their_lead_and_as_false_alarms_in_normal_running():
    arrays = _run(288.0, 3200.0)                     # 80 m/s, 40 s: the run ends at its derailment
    t = arrays["time"]
    levels = np.zeros(len(t), dtype=np.int8)
    levels[(t >= 20.0)] = WARNING
    levels[(t >= 25.0)] = INTERVENTION
    found = [_hazard(40.0)]
    label = windows(t, found, 20.0)[1]
    rows = {r["threshold"]: r for r in ss.scores(levels, arrays, found, 20.0, label)}
    assert set(rows) == set(ss.LEVELS)
    assert rows[float(WARNING)]["warnings"][0][0] == 20.0
    assert rows[float(INTERVENTION)]["warnings"][0][0] == 15.0
    assert rows[float(WARNING)]["false_episodes"] == 0
    # an alarm that ended before the hazard is not a warning of it, and is a false alarm where running is normal
    levels[:] = 0
    levels[(t >= 5.0) & (t < 10.0)] = INTERVENTION
    assert np.all(label[(t >= 5.0) & (t < 10.0)] == NORMAL)
    rows = {r["threshold"]: r for r in ss.scores(levels, arrays, found, 20.0, label)}
    assert rows[float(INTERVENTION)]["warnings"] == [None]
    assert rows[float(INTERVENTION)]["false_episodes"] == 1
    assert rows[float(WARNING)]["false_episodes"] == 1      # the warning level is on wherever intervention is


def _result(family, prevented, lead=None, intervention_rows=0, false=0, name="s", derailed=True):
    w = str(HazardRules().window_s)
    warn = None if lead is None else (lead, 300.0 * KMH)
    rows = [dict(threshold=float(WARNING), warnings=[warn], false_episodes=false),
            dict(threshold=float(INTERVENTION), warnings=[warn], false_episodes=false)]
    return dict(scenario=name, seed=1, family=family, derailed=derailed,
                hazards=[_hazard(30.0)] if derailed else [],
                line=dict(radius_m=1000.0, cant_m=0.175, rail_spacing_m=1.5, class_speed_kmh=300.0, gust_m_s=0.0,
                          defect=False, hunting=False, faults=[], critical_speed_kmh=math.nan),
                windows={w: dict(normal_km=100.0, normal_h=0.5)},
                supervision=dict(prevented=prevented if derailed else None, windows={w: rows},
                                 rows_at=dict(warning=intervention_rows, intervention=intervention_rows),
                                 sensitivity=None))


def test_prevented_by_family_counts_only_the_runs_that_derailed_without_the_loop():
    runs = [_result("overspeed", True), _result("overspeed", False), _result("defect", True),
            _result("ordinary", None, derailed=False)]
    table = ss.prevented_by_family(runs)
    assert set(table) == {"overspeed", "defect"}
    assert (table["overspeed"]["derailments"], table["overspeed"]["prevented"]) == (2, 1)
    lo, hi = table["overspeed"]["prevented_ci95"]
    assert 0.0 < lo < 0.5 < hi < 1.0
    assert (table["defect"]["derailments"], table["defect"]["prevented"]) == (1, 1)


def test_the_held_out_goal_needs_every_overspeed_derailment_usefully_warned_and_prevented_and_no_intervention():
    rules, w = HazardRules(), HazardRules().window_s
    good = [_result("overspeed", True, lead=60.0, name="a"), _result("ordinary", None, derailed=False)]
    assert ss.held_out_goal(good, w, rules)["met"]
    late = [_result("overspeed", True, lead=1.0, name="late")] + good
    goal = ss.held_out_goal(late, w, rules)
    assert not goal["met"] and goal["not_usefully_warned"] == ["late seed 1"] and goal["not_prevented"] == []
    derails = [_result("overspeed", False, lead=60.0, name="through")] + good
    assert ss.held_out_goal(derails, w, rules)["not_prevented"] == ["through seed 1"]
    braked = good + [_result("ordinary", None, derailed=False, intervention_rows=5, false=1, name="o")]
    goal = ss.held_out_goal(braked, w, rules)
    assert not goal["met"]
    assert goal["ordinary_interventions"]["ordinary_runs_with_intervention"] == 1
    assert goal["ordinary_interventions"]["episodes"] == 1


def test_the_sensitivity_counts_each_variant_over_the_derailments_it_applies_to():
    a, b = _result("defect", True, name="a"), _result("overspeed", True, name="b")
    a["supervision"]["sensitivity"] = dict.fromkeys(ss.VARIANTS) | {ss.VARIANTS[0]: False, ss.VARIANTS[3]: True}
    b["supervision"]["sensitivity"] = dict.fromkeys(ss.VARIANTS) | {ss.VARIANTS[3]: False}
    table = {row["variant"]: row for row in ss.sensitivity_table([a, b])}
    assert (table[ss.VARIANTS[0]]["derailments"], table[ss.VARIANTS[0]]["still_prevented"]) == (1, 0)
    assert (table[ss.VARIANTS[3]]["derailments"], table[ss.VARIANTS[3]]["still_prevented"],
            table[ss.VARIANTS[3]]["prevented_as_shipped"]) == (2, 1, 2)
    assert table[ss.VARIANTS[2]]["derailments"] == 0


def test_a_run_is_supervised_over_its_own_line_with_its_defect_known_or_not():
    from railderail_monitor.evaluation import catalogue
    entry = catalogue.Entry(name="kink", family="defect", radius_m=800.0, speed_kmh=160.0, friction=0.5,
                            defect=("kink", 0.05, 10.0, 700.0, 0.0), approach_m=3000.0)
    line = ss.run_line(entry, 1)
    assert [(c.radius_m, c.start_m) for c in line.curves] == [(800.0, 3000.0)]
    assert [(d.kind, d.position_m, d.size_m) for d in line.defects] == [("kink", 700.0, 0.05)]
    assert ss.run_line(entry, 1, with_defect=False).defects == ()
    assert ss.survey_key(line, 0.5) != ss.survey_key(ss.run_line(entry, 1, with_defect=False), 0.5)


def test_runs_on_curves_of_one_shape_share_one_survey_placed_on_each_run_s_own_line():
    from railderail_monitor.evaluation import catalogue
    near = catalogue.Entry(name="a", family="overspeed", radius_m=1000.0, speed_kmh=300.0, approach_m=3000.0)
    long = catalogue.Entry(name="b", family="ordinary", radius_m=1000.0, speed_kmh=160.0, line_length_m=30000.0)
    other = catalogue.Entry(name="c", family="ordinary", radius_m=1000.0, cant_mm=150.0, speed_kmh=160.0)
    straight = catalogue.Entry(name="d", family="ordinary", radius_m=math.inf, speed_kmh=160.0)
    lines = [ss.run_line(e, 1) for e in (near, long, other)]
    assert ss.survey_key(lines[0], 0.3) == ss.survey_key(lines[1], 0.3) != ss.survey_key(lines[2], 0.3)
    assert ss.survey_key(lines[0], 0.3) != ss.survey_key(lines[0], 0.4)
    # a run is surveyed with its own car
    assert ss.survey_key(lines[0], 0.3) != ss.survey_key(lines[0], 0.3, "hs19-a380yaw")
    assert ss.survey_settings(0.3, "hs19-a380yaw").vehicle_sets == ("hs19-a380yaw",)
    assert ss.survey_key(ss.run_line(straight, 1), 0.3) is None
    cut = ss.surveyed_line(lines[1]).curves[0]
    survey = dict(line=dict(name="x", length_m=0.0, file={}), defects=[],
                  curves=[dict(start_m=cut.start_m, end_m=cut.end_m, safe_speed_kmh=200.0)])
    for line in lines[:2]:
        placed = ss.placed(survey, line)
        assert (placed["curves"][0]["start_m"], placed["curves"][0]["end_m"]) == (line.curves[0].start_m,
                                                                                  line.curves[0].end_m)
        assert placed["line"]["length_m"] == line.length_m


def test_a_defect_the_car_cannot_pass_even_slowly_stays_a_stop_named_by_the_margin_it_broke():
    from railderail_monitor.evaluation import catalogue
    from railderail_sim.methods.survey_profile import _stop
    entry = catalogue.Entry(name="kink", family="defect", radius_m=800.0, speed_kmh=160.0,
                            defect=("kink", 0.05, 10.0, 700.0, 0.0))
    line = ss.run_line(entry, 1)
    stop = dict(safe_speed_kmh=0.0, first_broken=dict(speed_kmh=30.0, margin="derailment"))
    survey = dict(line=dict(name="x", length_m=0.0, file={}), curves=[dict(safe_speed_kmh=242.5)],
                  defects=[stop, dict(safe_speed_kmh=72.3)])
    placed = ss.placed(survey, line)
    assert [d["safe_speed_kmh"] for d in placed["defects"]] == [0.0, 72.3]
    assert placed["curves"][0]["safe_speed_kmh"] == 242.5
    assert _stop("defect 0", stop) == ("defect 0: stop before it, no speed tried kept the margins (derailment at "
                                       "30.0 km/h, the survey's lowest)")
    assert _stop("defect 1", placed["defects"][1]) == ""
