"""The survey of a line's physical speed limits (methods/survey.py, `railderail survey`): the safety margin, the
supervisor's target profile from a hand-built result, the survey of the Table 2 curve against `trial` on the same
scenario, the command's JSON and its cache, and a defect's margins."""
import contextlib
import functools
import io
import json

import numpy as np
import pytest

from railderail_sim.cli import main
from railderail_sim.line.data import Curve, Defect, Line
from railderail_sim.line.file import line_as_dict
from railderail_sim.methods import survey as sv, survey_profile
from railderail_sim.methods.progressive_trial import Staircase, progressive_trial
from railderail_sim.methods.survey_cache import case_key
from railderail_sim.supervision.margin import SafetyMargin
from railderail_sim.vehicle.simulate import KMH, Scenario

TOLERANCE_KMH = 8.0          # coarse: the test compares like with like, not the speed's last km/h


def test_safety_margin_is_etcs_dv_ebi_over_the_safe_speed():
    m = SafetyMargin()
    assert m.safe_speed(300.0 * KMH) / KMH == pytest.approx(285.0)          # above V_ebi_max: 15 km/h
    assert m.safe_speed(100.0 * KMH) / KMH == pytest.approx(92.5)           # below V_ebi_min: 7.5 km/h
    for critical in (120.0, 150.0, 200.0, 222.0):                           # on the ramp between them
        v = m.safe_speed(critical * KMH)
        assert v + m.dv(v) == pytest.approx(critical * KMH)
    assert m.safe_speed(150.0 * KMH) / KMH == pytest.approx(150.75 / 1.075)


def _hand_built():
    line = Line("hand", "test", "C", 10000.0, 300.0,
                (Curve(2000.0, 250.0, 500.0, 250.0, 1200.0, 0.15, 1, 250.0),
                 Curve(5000.0, 250.0, 500.0, 250.0, 7000.0, 0.15)),
                ((0.0, 1000.0, 160.0),), (Defect(5500.0, "kink", 0.02, 10.0),)).validated()
    curves = [dict(index=0, start_m=2000.0, end_m=3000.0, radius_m=1200.0, permitted_speed_kmh=250.0,
                   critical_derailment_speed_kmh=262.0, derailed=True, margins_intact_up_to_kmh=255.0,
                   safe_speed_kmh=240.0),
              dict(index=1, start_m=5000.0, end_m=6000.0, radius_m=7000.0, permitted_speed_kmh=300.0,
                   critical_derailment_speed_kmh=450.0, derailed=False, margins_intact_up_to_kmh=450.0,
                   safe_speed_kmh=435.0)]
    defects = [dict(index=0, position_m=5500.0, end_m=5510.0, kind="kink", size_mm=20.0,
                    margins_intact_up_to_kmh=165.0, safe_speed_kmh=150.0)]
    return sv.SurveyResult(line=dict(name="hand", length_m=10000.0, file=line_as_dict(line)), settings={}, margin={},
                           curves=curves, defects=defects, wind_sites=[])


def test_targets_are_the_most_restrictive_profile(tmp_path):
    _hand_built().save(tmp_path / "survey.json")
    assert sv.SurveyResult.load(tmp_path / "survey.json").as_dict() == _hand_built().as_dict()
    targets = survey_profile.survey_targets(_hand_built())
    assert [(a, b, round(v / KMH, 9)) for a, b, v, _ in targets] == [
        (0.0, 1000.0, 160.0), (1000.0, 2000.0, 300.0), (2000.0, 3000.0, 240.0), (3000.0, 5475.0, 300.0),
        (5475.0, 5535.0, 150.0), (5535.0, 10000.0, 300.0)]
    reasons = [why for _, _, _, why in targets]
    assert reasons[0].startswith("speed limit") and reasons[1] == "line speed"
    assert reasons[2].startswith("curve 0 (R 1200 m): safe speed, margins intact up to 255.0 km/h") and reasons[4].startswith("defect 0 (kink 20 mm)")
    # the JSON form reads back to the same profile
    assert survey_profile.survey_targets(json.loads(json.dumps(_hand_built().as_dict()))) == targets
    old = _hand_built().as_dict()
    del old["curves"][0]["margins_intact_up_to_kmh"]          # a survey of the critical-speed rule's time
    with pytest.raises(ValueError, match="no margins_intact_up_to_kmh .* run the survey again"):
        survey_profile.survey_targets(old)
    permitted = survey_profile.permitted_profile(_hand_built())
    assert [(a, b, round(v / KMH, 9)) for a, b, v in permitted] == [
        (0.0, 1000.0, 160.0), (1000.0, 2000.0, 300.0), (2000.0, 3000.0, 250.0), (3000.0, 10000.0, 300.0)]


ARGS = ["survey", "table2", "--frictions", "0.3", "--vehicle-sets", "hs19", "--tolerance-kmh", str(TOLERANCE_KMH),
        "--faults", "none", "--wind-speeds-m-s", "none", "--workers", "1", "--json"]


@pytest.fixture(scope="module")
def table2_survey(tmp_path_factory):
    """`railderail survey table2 --json` of one case (its stdout text) and its cache folder."""
    cache = tmp_path_factory.mktemp("survey-cache")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(ARGS + ["--cache", str(cache)]) == 0
    return out.getvalue(), cache


def test_survey_json_keys(table2_survey):
    result = json.loads(table2_survey[0])
    assert result["line"]["name"] == "table2" and result["line"]["length_m"] == 1800.0
    curve = result["curves"][0]
    for key in ("start_m", "end_m", "radius_m", "cant_mm", "critical_derailment_speed_kmh", "spread_kmh",
                "safe_speed_kmh", "cases", "crosswind", "faults", "lowest_case"):
        assert key in curve
    assert (curve["start_m"], curve["end_m"], curve["radius_m"], curve["cant_mm"]) == (200.0, 1600.0, 1000.0, 175.0)
    assert result["defects"] == [] and result["wind_sites"] == []
    # the safe speed is the highest speed with every margin intact, less dV_ebi: below the critical derailment speed
    assert curve["safe_speed_kmh"] == pytest.approx(curve["margins_intact_up_to_kmh"] - 15.0)
    assert curve["margins_intact_up_to_kmh"] < curve["critical_derailment_speed_kmh"]


def test_survey_gives_the_trial_speed_on_the_same_scenario(table2_survey):
    curve = json.loads(table2_survey[0])["curves"][0]
    trial = progressive_trial(Scenario(), 1000.0, Staircase(), tolerance_kmh=TOLERANCE_KMH)
    assert curve["derailed"] and curve["cases"][0]["method"] == "bisection"
    assert curve["critical_derailment_speed_kmh"] == trial.refined_speed_kmh
    assert curve["mechanism"] == trial.refined_mechanism


def test_survey_is_cached(table2_survey, capsys):
    text, cache = table2_survey
    assert any(cache.rglob("*.json"))
    assert main(ARGS + ["--cache", str(cache)]) == 0            # every case from the cache: seconds
    assert capsys.readouterr().out == text


def test_a_curve_s_case_is_shared_by_every_line_with_that_curve(table2_survey, tmp_path, capsys):
    """Another line with Table 2's curve placed elsewhere and a civil limit of its own: its case comes from
    table2's cache (no case computed, no file written) and gives the same rows; another shape is another case."""
    _, cache = table2_survey
    before = sorted(cache.rglob("*.json"))
    moved = ("name: moved\nsource: test\nsureness: C\nlength_m: 3000\nline_speed_kmh: 300\ncurves:\n"
             "  - {start_m: 900, transition_in_m: 200, arc_m: 1000, transition_out_m: 200, radius_m: 1000, "
             "cant_mm: 175, direction: left, permitted_speed_kmh: 250}\n")
    (tmp_path / "moved.yaml").write_text(moved)
    assert main(["survey", str(tmp_path / "moved.yaml")] + ARGS[2:] + ["--cache", str(cache)]) == 0
    curve, = json.loads(capsys.readouterr().out)["curves"]
    table2, = json.loads(table2_survey[0])["curves"]
    assert sorted(cache.rglob("*.json")) == before
    assert (curve["start_m"], curve["cases"]) == (900.0, table2["cases"])
    # the key reads the curve's shape: another cant or radius is another case
    data = line_as_dict(Line("two", "test", "C", 10000.0, 300.0, (Curve(2000.0, 250.0, 500.0, 250.0, 1200.0, 0.15, 1),
                                                                 Curve(5000.0, 250.0, 500.0, 250.0, 7000.0, 0.15)),
                             (), (Defect(5500.0, "kink", 0.02, 10.0),)).validated())
    settings = sv.Settings()
    key = functools.partial(case_key, line_data=data, base=Scenario(), settings=settings)
    other = dict(data, curves=[dict(data["curves"][1], start_m=100.0)])
    assert key(("curve", 1, "hs19", 0.3)) == key(("curve", 0, "hs19", 0.3), line_data=other)
    assert key(("curve", 0, "hs19", 0.3)) != key(("curve", 1, "hs19", 0.3))
    assert key(("curve", 1, "hs19", 0.3)) != key(("curve", 0, "hs19", 0.3),
                                                 line_data=dict(other, curves=[dict(other["curves"][0], cant_mm=160)]))


def test_bad_line_file_is_one_line(tmp_path, capsys):
    path = tmp_path / "bad.yaml"
    path.write_text("name: x\nsource: y\nsureness: C\nlength_m: 1000\nline_speed_kmh: 200\n"
                    "curves:\n  - {start_m: 100, transition_in_m: 10, arc_m: 100, transition_out_m: 100, "
                    "radius_m: 1000, cant_mm: 150, direction: left}\n")
    assert main(["survey", str(path), "--json"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and f"{path}: curves[0]: transition_in_m 10 m is too short" in err


def test_defect_margins():
    """A 20 mm lateral kink in a 1000 m curve: passed at 120 km/h with every margin intact, a margin broken at
    200 km/h."""
    line = Line("kink", "test", "C", 3000.0, 300.0, (Curve(500.0, 200.0, 600.0, 200.0, 1000.0, 0.175, -1),),
                defects=(Defect(900.0, "kink", 0.020, 10.0),)).validated()
    assert sv.defect_run(line, 0, Scenario(), "hs19", 0.3, 120.0).outcome() == (True, "")
    ok, margin = sv.defect_run(line, 0, Scenario(), "hs19", 0.3, 200.0).outcome()
    assert not ok and margin in ("flange_climb", "wheel_unloading", "wheel_lift", "derailment")


def test_curve_row_takes_the_lowest_case_and_changes_against_the_reference():
    """Without the reference case among the cases (as with --quick), it is run on its own for the tables' changes
    and left out of the lowest."""
    line = Line("x", "test", "C", 3000.0, 300.0, (Curve(500.0, 200.0, 600.0, 200.0, 1000.0, 0.175),)).validated()
    settings = sv.Settings(frictions=(0.2, 0.6), vehicle_sets=("hs19", "zhai"), wind_speeds_m_s=(20.0,),
                           faults=("yaw-dampers-failed@both",))
    items = sv.cases(line, settings)
    assert ("curve", 0, "hs19", 0.3) in items and ("curve", 0, "hs19", 0.3, 20.0) in items
    assert len([i for i in items if i[0] == "curve"]) == 4 + 1 + 1 + 1

    def row(vehicle_set, friction, speed, wind=0.0, fault=None, intact=None):
        margins = {} if intact is None else dict(margins_intact_up_to_kmh=intact,
                                                 first_broken=dict(speed_kmh=intact + 1.0, margin="wheel_unloading"))
        return dict(vehicle_set=vehicle_set, friction=friction, wind_speed_m_s=wind, fault=fault, derailed=True,
                    critical_derailment_speed_kmh=speed, mechanism="wheel_unloading", side="inner", section="curve",
                    **margins)
    rows = [row("hs19", 0.2, 290.0, intact=280.0), row("hs19", 0.6, 291.0, intact=279.0),
            row("zhai", 0.2, 284.0, intact=276.0), row("zhai", 0.6, 286.0, intact=281.0),
            row("hs19", 0.3, 280.0, intact=270.0), row("hs19", 0.3, 260.0, wind=20.0),
            row("hs19", 0.3, 281.0, fault="yaw-dampers-failed@both")]
    c = sv._curve_row(line, 0, rows, settings)
    assert c["critical_derailment_speed_kmh"] == 284.0 and c["spread_kmh"] == 7.0
    assert c["lowest_case"] == dict(vehicle_set="zhai", friction=0.2) and len(c["cases"]) == 4
    # the safe speed from the lowest speed with every margin intact over the cases (not the reference's 270)
    assert c["margins_intact_up_to_kmh"] == 276.0 and c["margins_spread_kmh"] == 5.0
    assert c["margins_lowest_case"] == dict(vehicle_set="zhai", friction=0.2)
    assert c["first_broken"] == dict(speed_kmh=277.0, margin="wheel_unloading")
    assert c["safe_speed_kmh"] == pytest.approx(261.0)
    assert c["safe_speed_sensitivity_kmh"]["none"] == 276.0
    assert c["safe_speed_by_friction_kmh"] == pytest.approx({"0.2": 261.0, "0.6": 264.0})
    assert c["crosswind"][0]["change_kmh"] == -20.0 and c["faults"][0]["change_kmh"] == 1.0


def test_highest_intact_bisects_to_the_first_broken_margin():
    """The bisection that defects and curves share: the highest speed with every margin intact within the
    tolerance, the lowest speed tried that broke one, and the ends."""
    def run(v):
        return sv.Judged(v <= 203.7, "" if v <= 203.7 else "wheel_unloading")
    m = sv.highest_intact(run, 60.0, 450.0, 1.0)
    assert 202.7 <= m["margins_intact_up_to_kmh"] <= 203.7
    assert m["first_broken"]["margin"] == "wheel_unloading"
    assert 203.7 < m["first_broken"]["speed_kmh"] <= m["margins_intact_up_to_kmh"] + 1.0
    assert sv.highest_intact(run, 60.0, 200.0, 1.0) == dict(margins_intact_up_to_kmh=200.0, first_broken=None, runs=1)
    broken = sv.highest_intact(lambda v: sv.Judged(False, "derailment"), 60.0, 450.0, 1.0)
    assert broken["margins_intact_up_to_kmh"] == 0.0


def test_highest_intact_tries_the_floor_before_it_gives_a_stop():
    """Where the lowest speed breaks a margin, the floor is tried: kept, the bisection runs between them; broken
    too, the answer is 0 (a stop); a curve's search (`lo_assumed`) the same. The survey's floor is the slowest
    speed the simulator runs, below the margins' lowest."""
    from railderail_sim.parameters import SPEED_RANGE_KMH
    assert sv.MARGINS_FLOOR_KMH == SPEED_RANGE_KMH[0] < sv.RULES.margins_low_kmh
    for assumed in (False, True):
        def run(v):
            return sv.Judged(v <= 44.2, "" if v <= 44.2 else "flange_climb")
        m = sv.highest_intact(run, 60.0, 450.0, 1.0, lo_assumed=assumed, floor=30.0)
        assert 43.2 <= m["margins_intact_up_to_kmh"] <= 44.2 and m["first_broken"]["margin"] == "flange_climb"
        assert 44.2 < m["first_broken"]["speed_kmh"] <= m["margins_intact_up_to_kmh"] + 1.0
        stop = sv.highest_intact(lambda v: sv.Judged(False, "derailment"), 60.0, 450.0, 1.0, lo_assumed=assumed,
                                 floor=30.0)
        assert stop["margins_intact_up_to_kmh"] == 0.0 and stop["first_broken"]["speed_kmh"] == 30.0


def test_highest_intact_takes_the_lowest_speed_as_intact_until_it_must_run_it():
    """A curve's search (`lo_assumed`) does not run its lowest speed while a faster one keeps every margin, and
    gives what the search that runs it gives; where no faster speed keeps them it runs it, and gives 0 if it
    breaks a margin too."""
    for crossing in (203.7, 60.4, 30.0):
        calls = []

        def run(v):
            calls.append(v)
            return sv.Judged(v <= crossing, "" if v <= crossing else "wheel_unloading")
        full = sv.highest_intact(run, 60.0, 450.0, 1.0)
        assumed = sv.highest_intact(run, 60.0, 450.0, 1.0, lo_assumed=True)
        assert {k: assumed[k] for k in ("margins_intact_up_to_kmh", "first_broken")} == \
            {k: full[k] for k in ("margins_intact_up_to_kmh", "first_broken")}
        assert calls.count(60.0) == (1 if crossing == 203.7 else 2)
        if crossing == 203.7:
            assert assumed["runs"] == full["runs"] - 1


def test_curve_margins_judged_over_the_curve():
    """The Table 2 curve (R 1000 m): every margin intact at its permitted-like 250 km/h; at 280 km/h, below its
    critical derailment speed (about 285 km/h), the car does not derail but a margin is broken in the curve."""
    line = Line("t2", "test", "C", 1800.0, 350.0, (Curve(200.0, 200.0, 1000.0, 200.0, 1000.0, 0.175),)).validated()
    sc = line.scenario_for(line.curves[0], Scenario())
    assert sv.curve_run(sc, 250.0).outcome() == (True, "")
    assert sv.curve_run(sc, 280.0).outcome() == (False, "wheel_unloading")


def test_shipped_table2_survey_is_the_margins_survey():
    """The shipped survey of the Table 2 line (config/lines/table2-survey.json, what `demo --closed-loop`
    supervises): made at every default by the survey that takes a curve's safe speed from its margins, every
    figure of the curve's row following from its cases."""
    from railderail_monitor.supervision.demo_loop import SHIPPED_SURVEY
    from dataclasses import asdict
    result = json.loads(SHIPPED_SURVEY.read_text())
    assert result["settings"] == json.loads(json.dumps(asdict(sv.Settings())))
    (curve,) = result["curves"]
    cases = curve["cases"]
    assert len(cases) == len(sv.Settings().frictions) * len(sv.Settings().vehicle_sets)
    assert all(c["margins_intact_up_to_kmh"] <= c["critical_derailment_speed_kmh"] for c in cases)
    assert all(c["first_broken"]["speed_kmh"] <= c["critical_derailment_speed_kmh"] for c in cases)
    intact = min(c["margins_intact_up_to_kmh"] for c in cases)
    assert curve["margins_intact_up_to_kmh"] == intact
    assert curve["critical_derailment_speed_kmh"] == min(c["critical_derailment_speed_kmh"] for c in cases)
    assert curve["safe_speed_kmh"] == pytest.approx(sv.MARGIN.safe_speed(intact * KMH) / KMH)
    for f, v in curve["safe_speed_by_friction_kmh"].items():
        low = min(c["margins_intact_up_to_kmh"] for c in cases if c["friction"] == float(f))
        assert v == pytest.approx(sv.MARGIN.safe_speed(low * KMH) / KMH)
    # the point of it: a train held to ETCS's emergency brake curve (the target plus dV_ebi) meets the curve
    # with every margin intact, not at its critical derailment speed
    assert curve["safe_speed_kmh"] + sv.MARGIN.dv(curve["safe_speed_kmh"] * KMH) / KMH == pytest.approx(intact)
    assert intact < curve["critical_derailment_speed_kmh"]


TABLE2_CURVE = Line("t2", "test", "C", 1800.0, 350.0, (Curve(200.0, 200.0, 1000.0, 200.0, 1000.0, 0.175),)).validated()


def test_margins_run_stops_at_the_first_broken_margin_and_names_the_whole_runs():
    """The Table 2 curve at 292 km/h, above its critical derailment speed: judged every 10 m, `intact()` stops
    where the first margin breaks, well before the derailment; `outcome()` takes the run on and names what the
    whole run breaks (the derailment: the survey's `first_broken`), not the margin it stopped at."""
    run = sv.curve_run(TABLE2_CURVE.scenario_for(TABLE2_CURVE.curves[0], Scenario()), 292.0)
    run.PIECE_M = 10.0
    assert not run.intact()
    stopped_m = run.simulated_m
    assert run.outcome() == (False, "derailment")
    assert stopped_m < run.simulated_m - 20.0


def test_margins_judged_in_pieces_as_the_whole_run():
    """Where the verdict is closest (the Table 2 curve, hs19 at friction 0.3: every margin intact at
    258.609375 km/h, the wheel unloading broken at 259.5 km/h, the shipped survey's bracket), the run judged every
    10 m and stopped at its first broken margin gives the verdict of the run judged whole, and its rows are the
    whole run's to the bit."""
    sc = TABLE2_CURVE.scenario_for(TABLE2_CURVE.curves[0], Scenario())
    for speed, intact in ((258.609375, True), (259.5, False)):
        pieces, whole = sv.curve_run(sc, speed), sv.curve_run(sc, speed)
        pieces.PIECE_M, whole.PIECE_M = 10.0, 1.0e6
        assert pieces.intact() == intact
        assert whole.outcome() == pieces.outcome() == (intact, "" if intact else "wheel_unloading")
        for name, parts in whole._columns.items():
            assert np.concatenate(parts).tobytes() == np.concatenate(pieces._columns[name]).tobytes(), name


def test_the_trials_derailment_stands_for_the_margins_run_at_the_critical_speed(table2_survey):
    """The survey takes the margins' run at a case's critical derailment speed as broken by the trial's own
    derailment there, without running it: the margins' search gives what the search that runs it gives."""
    case = json.loads(table2_survey[0])["curves"][0]["cases"][0]
    sc = TABLE2_CURVE.scenario_for(TABLE2_CURVE.curves[0], sv._case_scenario(Scenario(), "hs19", 0.3))
    full = sv.highest_intact(functools.partial(sv.curve_run, sc), sv.RULES.margins_low_kmh,
                             case["critical_derailment_speed_kmh"], TOLERANCE_KMH)
    assert (full["margins_intact_up_to_kmh"], full["first_broken"]) == (case["margins_intact_up_to_kmh"],
                                                                         case["first_broken"])
