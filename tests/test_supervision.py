"""The speed supervisor (railderail_monitor/supervision): the ETCS fixed values and margins, the curves'
order and distances, the levels of a train approaching a curve too fast at the places computed here from
the closed form, nothing at the permitted speed, hysteresis and the latched brake, the live inputs, the
odometer's confidence interval, the cost of a step."""
import json
import math
import timeit

import pytest

from railderail_monitor.supervision.curves import (INDICATION, INTERVENTION, NONE, WARNING, SupervisionLimits, Target,
                                                   TargetCurves, ramp, target_limit)
from railderail_monitor.supervision.loop import survey_on_track, targets_of_survey
from railderail_monitor.supervision.odometry import Odometry
from railderail_monitor.supervision.supervisor import (LiveInputs, LiveRules, Supervisor, friction_limit,
                                                       wind_speed_limit)
from railderail_sim.supervision.braking import BrakingModel

KMH = 1.0 / 3.6
LIMITS = SupervisionLimits().validated()
BRAKING = BrakingModel().validated()
RATE = 200.0


def test_the_etcs_fixed_values_and_margins():
    assert (LIMITS.t_warning_s, LIMITS.t_driver_s) == (2.0, 4.0)
    assert ramp(LIMITS.dv_ebi_kmh, 100 * KMH) == pytest.approx(7.5 * KMH)
    assert ramp(LIMITS.dv_ebi_kmh, 160 * KMH) == pytest.approx(11.25 * KMH)
    assert ramp(LIMITS.dv_ebi_kmh, 300 * KMH) == pytest.approx(15.0 * KMH)
    assert ramp(LIMITS.dv_sbi_kmh, 210 * KMH) == pytest.approx(10.0 * KMH)
    assert ramp(LIMITS.dv_warning_kmh, 125 * KMH) == pytest.approx(4.5 * KMH)
    assert ramp(LIMITS.speed_accuracy_kmh, 265 * KMH) == pytest.approx(7.0 * KMH)
    # the target speed under a physical limit leaves exactly dV_ebi to it, in each piece of the ramp
    for critical in (100.0, 180.0, 300.0):
        v = target_limit(critical * KMH, LIMITS)
        assert v + ramp(LIMITS.dv_ebi_kmh, v) == pytest.approx(critical * KMH, rel=1e-12)


def _ebd_distance(v, foot):
    """Emergency braking distance (m) from v down to foot (m/s), the bands written out (dry rail)."""
    edges = [0.0, 170 * KMH, 230 * KMH, 300 * KMH, math.inf]
    acc = [1.2, 1.05, 0.9, 0.85]
    return sum((min(v, hi) ** 2 - max(foot, lo) ** 2) / (2 * a)
               for lo, hi, a in zip(edges, edges[1:], acc) if min(v, hi) > max(foot, lo))


TARGET = Target(5000.0, 6400.0, target_limit(270 * KMH, LIMITS), "curve")


def _places(v):
    """(indication, warning, EBI) locations of TARGET at speed v, from the closed form and the fixed times."""
    foot = TARGET.speed_limit_m_s + 15 * KMH                # dV_ebi above 210 km/h
    ebi = TARGET.start_m - _ebd_distance(v, foot) - v * 2.0  # T_be 2 s
    sbi = ebi - v * 2.0                                     # T_bs 2 s
    return sbi - v * 4.0 - v * 9.0, sbi - v * 2.0, ebi     # T_indication = max(0.8 T_bs, 5) + T_driver


def test_the_curves_in_their_order():
    c = TargetCurves(TARGET, BRAKING, LIMITS)
    assert c.ebd(c.v_foot) == TARGET.start_m and c.v_foot == pytest.approx(270 * KMH)
    for kmh in (280, 300, 340):
        v = kmh * KMH
        i, p, w, sbi, ebi = c.locations(v)
        assert i < p < w < sbi < ebi < c.ebd(v) < TARGET.start_m
        assert (c.ebd(v) - ebi, ebi - sbi, sbi - w, sbi - p, p - i) == pytest.approx((2 * v, 2 * v, 2 * v, 4 * v, 9 * v))
        assert (i, w, ebi) == pytest.approx(_places(v))
    warning, sbi, ebi = c.ceiling
    assert warning < sbi < ebi == c.v_foot


def _run(supervisor, speed_of, start, end, error=(0.0, 0.0)):
    """Step a supervisor along the line at `speed_of(s)` at 200 Hz; (position, level) at each change."""
    s, t, changes, level = start, 0.0, [], NONE
    while s < end:
        v = speed_of(s)
        new = supervisor.step(t, s, v, *error)
        if new != level:
            changes.append((s, new))
            level = new
        s += v / RATE
        t += 1 / RATE
    return changes


def test_a_train_too_fast_is_indicated_warned_and_braked_at_the_right_places():
    v = 320 * KMH
    sup = Supervisor([TARGET], BRAKING, LIMITS)
    changes = _run(sup, lambda s: v, 0.0, 4900.0)
    assert [lv for _, lv in changes] == [INDICATION, WARNING, INTERVENTION]
    for (s, _), place in zip(changes, _places(v)):
        assert place <= s < place + v / RATE
    assert [a.level for a in sup.alerts] == ["indication", "warning", "intervention"]
    first = sup.alerts[0]
    assert first.margin_kmh == pytest.approx(TARGET.speed_limit_m_s / KMH - 320)
    assert first.time_to_intervention_s == pytest.approx((_places(v)[2] - changes[0][0]) / v, abs=0.01)
    assert sup.release_speed == TARGET.speed_limit_m_s
    # the pessimistic end of the odometer's interval brings every level forward by the position error
    early = _run(Supervisor([TARGET], BRAKING, LIMITS), lambda s: v, 0.0, 4900.0, error=(50.0, 0.0))
    assert [s for s, _ in early] == pytest.approx([s - 50.0 for s, _ in changes], abs=v / RATE)


def test_nothing_at_the_permitted_speed():
    sup = Supervisor([TARGET], BRAKING, LIMITS)
    assert _run(sup, lambda s: TARGET.speed_limit_m_s, 0.0, 7000.0) == [] and sup.alerts == []


def test_the_brake_holds_to_its_release_speed_and_the_levels_do_not_flicker():
    sup = Supervisor([TARGET], BRAKING, LIMITS)
    v_t = TARGET.speed_limit_m_s
    assert sup.step(0.0, 5100.0, v_t + 20 * KMH) == INTERVENTION            # inside, above V_t + dV_ebi
    assert sup.step(0.1, 5110.0, v_t + 1 * KMH) == INTERVENTION             # held while above the release speed
    assert sup.step(0.2, 5120.0, v_t) == INDICATION                         # released, not yet 2 km/h clear
    assert sup.step(0.25, 5125.0, v_t - 2.5 * KMH) == NONE
    # a speed dithering 0.5 km/h about the ceiling's indication: one alert, left 2 km/h below it
    alerts = len(sup.alerts)
    levels = [sup.step(0.3 + 0.01 * k, 5130.0 + k, v_t + (0.5 if k % 2 else -0.5) * KMH) for k in range(20)]
    assert levels[1:] == [INDICATION] * 19 and len(sup.alerts) == alerts + 1
    assert sup.step(1.0, 5200.0, v_t - 1.0 * KMH) == INDICATION
    assert sup.step(1.1, 5201.0, v_t - 2.5 * KMH) == NONE


def test_live_inputs_move_the_targets():
    surveyed = Target(5000.0, 6400.0, 250 * KMH, "curve", ((0.2, 280 * KMH), (0.4, 260 * KMH), (0.6, 250 * KMH)))
    assert friction_limit(surveyed, None) == 250 * KMH
    assert friction_limit(surveyed, 0.3) == 260 * KMH and friction_limit(surveyed, 0.2) == 280 * KMH
    assert friction_limit(surveyed, 0.1) == 280 * KMH and friction_limit(surveyed, 0.9) == 250 * KMH
    cwc = ((200.0, 40.0), (300.0, 30.0), (350.0, 25.0))
    assert wind_speed_limit(cwc, 35.0) == pytest.approx(250 * KMH) and wind_speed_limit(cwc, 20.0) is None
    assert wind_speed_limit(cwc, 45.0) == pytest.approx(200 * KMH)
    rules = LiveRules(cwc=cwc, wind_stretches=((2000.0, 3000.0),), nonlinear_critical_speed_kmh=330.0)
    sup = Supervisor([surveyed], BRAKING, LIMITS, rules)
    v = 280 * KMH
    assert sup.step(0.0, 1300.0, v) == NONE
    sup.inputs(LiveInputs(wind_speed_m_s=35.0), 1300.0)     # 250 km/h on 2000-3000 m: its EBI at 280 km/h is behind
    assert sup.step(0.1, 1300.0, v) == INTERVENTION
    assert sup.release_speed == pytest.approx(target_limit(250 * KMH, LIMITS))
    hunting = Supervisor([], BRAKING, LIMITS, rules)
    hunting.inputs(LiveInputs(hunting=True), 800.0)
    # inside the hunting target from 800 m: above its limit + dV_ebi (= 330 km/h) the brake
    assert hunting.step(0.0, 810.0, 331 * KMH) == INTERVENTION and "hunting" in hunting.alerts[0].reason
    assert hunting.step(0.1, 811.0, target_limit(330 * KMH, LIMITS) - 3 * KMH) == NONE
    assert hunting.step(0.2, 812.0, target_limit(330 * KMH, LIMITS) + 1 * KMH) == INDICATION
    hunting.inputs(LiveInputs(hunting=False), 813.0)                          # its target gone, so is the level
    assert hunting.step(0.3, 813.0, target_limit(330 * KMH, LIMITS) + 1 * KMH) == NONE
    with pytest.raises(ValueError, match="vehicle speeds must rise"):
        LiveRules(cwc=((300.0, 30.0), (200.0, 40.0))).validated()


def test_the_odometers_confidence_interval():
    odo = Odometry(LIMITS, 1000.0, 0.0, 80.0)
    for k in range(1, 101):
        odo.update(0.1 * k, 80.0)
    assert odo.position == pytest.approx(1800.0)
    assert odo.position_error == pytest.approx(5.0 + 0.05 * 800.0)
    assert odo.speed_error == pytest.approx(ramp(LIMITS.speed_accuracy_kmh, 80.0))
    odo.balise(1805.0, 10.0, 80.0)
    assert odo.position_error == 5.0


def test_a_step_costs_under_a_tenth_of_a_millisecond():
    targets = [Target(5000.0 + 3000 * k, 6000.0 + 3000 * k, (250 - 20 * k) * KMH, f"curve {k}") for k in range(5)]
    sup = Supervisor(targets, BRAKING, LIMITS)
    n = 2000
    cost = min(timeit.repeat(lambda: sup.step(0.0, 4000.0, 300 * KMH, 10.0, 2.0), number=n, repeat=3)) / n
    assert cost < 1e-4


def _read(path):
    return json.loads(path.read_text())


def test_a_surveys_targets(tmp_path):
    path = tmp_path / "survey.json"
    path.write_text(json.dumps(dict(curves=[dict(start_m=1000.0, end_m=2600.0, radius_m=1000.0, safe_speed_kmh=255.0,
                                                 safe_speed_by_friction_kmh={"0.2": 280.0, "0.6": 250.0})])))
    (target,) = targets_of_survey(_read(path), path)
    assert (target.start_m, target.end_m, target.speed_limit_m_s) == (1000.0, 2600.0, 255.0 * KMH)
    assert friction_limit(target, 0.3) == pytest.approx(250.0 * KMH)
    path.write_text(json.dumps(dict(curves=[dict(start_m=1000.0, end_m=900.0, safe_speed_kmh=255.0)])))
    with pytest.raises(ValueError, match="curve 0: target .* start 1000 m is not before its end 900 m"):
        targets_of_survey(_read(path), path)
    path.write_text("[]")
    with pytest.raises(ValueError, match="not a survey's JSON"):
        targets_of_survey(_read(path), path)


def test_a_whole_survey_is_supervised_as_its_most_restrictive_profile(tmp_path):
    """A survey with its line: the line speed, the civil limits, the curves' and the defects' safe speeds as
    targets, a curve's safe-speed piece with the curve's per-friction limits."""
    from railderail_sim.methods.survey_profile import survey_targets
    from test_survey import _hand_built
    data = _hand_built().as_dict()
    data["curves"][0]["safe_speed_by_friction_kmh"] = {"0.2": 250.0, "0.4": 240.0}
    path = tmp_path / "survey.json"
    path.write_text(json.dumps(data))
    targets = targets_of_survey(_read(path), path)
    assert [(t.start_m, t.end_m, t.speed_limit_m_s, t.reason) for t in targets] == survey_targets(data)
    (curve,) = [t for t in targets if t.limits_by_friction]
    assert (curve.start_m, curve.end_m) == (2000.0, 3000.0)
    assert friction_limit(curve, 0.2) == pytest.approx(250.0 * KMH)
    assert [t.speed_limit_m_s for t in targets if t.start_m == 5475.0] == [pytest.approx(150.0 * KMH)]   # the kink


def test_the_closed_loop_demo_places_the_survey_s_curve_on_its_own_approach(tmp_path):
    from railderail_monitor.supervision.demo_loop import SHIPPED_SURVEY, closed_loop_survey
    run = dict(radius=1000.0, speed_mode="constant", speed_kmh=320.0, approach_m=3000.0)
    (placed,) = json.loads(open(closed_loop_survey(SHIPPED_SURVEY, run, tmp_path)).read())["curves"]
    (shipped,) = json.loads(SHIPPED_SURVEY.read_text())["curves"]
    # Table 2's transitions of 200 m and arc of 1000 m, after the run's 3000 m of straight
    assert (placed["start_m"], placed["end_m"]) == (3000.0, 4400.0)
    assert placed["safe_speed_kmh"] == shipped["safe_speed_kmh"]
    with pytest.raises(ValueError, match="no curve of R 1200 m and 175 mm cant"):
        closed_loop_survey(SHIPPED_SURVEY, dict(run, radius=1200.0), tmp_path)


def test_simulate_supervises_a_survey_s_curve_where_the_run_has_it(tmp_path):
    """`simulate --supervision` with 3000 m of approach meets the shipped survey's curve on the run's own curve
    (3000-4400 m), not where the survey's own line has it (200-1600 m)."""
    from railderail_monitor.supervision.demo_loop import SHIPPED_SURVEY
    from railderail_sim.parameters import TrackParameters
    track = TrackParameters(straight_in=3000.0)
    (target,) = targets_of_survey(survey_on_track(SHIPPED_SURVEY, track), SHIPPED_SURVEY)
    (shipped,) = json.loads(SHIPPED_SURVEY.read_text())["curves"]
    assert (target.start_m, target.end_m) == (3000.0, 4400.0)
    assert target.speed_limit_m_s == pytest.approx(shipped["safe_speed_kmh"] * KMH)

