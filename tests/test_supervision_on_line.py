"""The speed supervision of the monitor node (railderail_monitor/supervision/on_line.py, node.py): in each mode
(ground truth; the odometer with its modelled error and confidence interval) the same alerts at the same
samples as the batch path (`simulate --supervision [--odometer]`) on the same run; the live inputs move the
targets by their rules (a measured wind against the wind sites' characteristic wind curve, the measured
monitor's hunting alerts, a friction estimate), set as the node's parameters while it runs; the status the
planning area shows."""
import argparse
import json
import math

import numpy as np
import pytest
from rclpy.parameter import Parameter

from railderail_monitor.onboard.measured import CRITERIA as MEASURED_CRITERIA
from railderail_monitor.supervision.curves import INTERVENTION, KMH, OPEN_END_M, SupervisionLimits, target_limit
from railderail_monitor.supervision.loop import scenario_targets, simulate_supervised
from railderail_monitor.supervision.on_line import (HUNTING_CRITERIA, WIND_SITE_REACH_M, OnLineSupervision,
                                                    live_rules)
from railderail_monitor.supervision.supervisor import wind_speed_limit
from railderail_sim.ros import interface as m
from railderail_sim.ros.node import PARAMETERS, build_scenario
from railderail_sim.sensors.config import load as load_sensors
from railderail_sim.sensors.measure import SensorStream
from railderail_sim.sensors.sensor_set import ODOMETER, SensorSet
from railderail_sim.vehicle.layout import OutputRow
from railderail_sim.vehicle.simulate import output_arrays, simulate

from monitor_node import node_of, subscribed  # noqa: F401 (node_of: a fixture)

LIMITS = SupervisionLimits()
# the ROS test's run (tests/test_supervision_ros.py): R 1000 m at 320 km/h after 2500 m of straight, a survey
# of 270 km/h for its curve; the run derails, the supervisor intervenes on the approach
RUN = {"radius": 1000.0, "speed_mode": "constant", "speed_kmh": 320.0, "approach_m": 2500.0}
CRITICAL_KMH = 270.0
SHIPPED = load_sensors(None)
CWC = {"speed_kmh": [200.0, 250.0, 300.0, 350.0], "wind_speed_m_s": [48.0, 44.2, 42.7, 39.8]}


def _scenario():
    return build_scenario({**{spec.name: spec.default for spec in PARAMETERS}, **RUN})


def _survey(sc, **more):
    (target,) = scenario_targets(sc.track, CRITICAL_KMH * KMH, LIMITS)
    return dict(curves=[dict(start_m=target.start_m, end_m=target.end_m, safe_speed_kmh=target.speed_limit_m_s / KMH)],
                **more)


@pytest.fixture(scope="module")
def run():
    sc = _scenario()
    result = simulate(sc)
    assert result.status == "derailed"
    sensors = SensorSet(seed=SHIPPED.seed, odometer=SHIPPED.odometer).validated(sc.output_rate)
    odometer = SensorStream(sensors, sc).process(output_arrays(result.rows))[ODOMETER]
    return sc, result.rows, odometer


def _on_line(rows, odometer, supervision):
    """Feed a run's samples to the on-line supervision as the node gets them (the states and the odometer's
    messages in stamp order): its steps."""
    events = [(t, 0, k) for k, t in enumerate(rows[:, 0].tolist())]
    events += [(t, 1, k) for k, t in enumerate(np.asarray(odometer["time"]).tolist())]
    steps = []
    for t, kind, k in sorted(events):
        if kind == 0:
            steps += supervision.on_states(t, k, float(rows[k, OutputRow.position]), float(rows[k, OutputRow.speed]))
        else:
            steps += supervision.on_odometer(t, float(odometer["speed"][k]))
    return steps


@pytest.mark.parametrize("signals", ["ground_truth", "odometer"])
def test_the_node_s_supervision_raises_the_batch_path_s_alerts(signals, run, tmp_path):
    sc, rows, odometer = run
    path = tmp_path / "survey.json"
    path.write_text(json.dumps(_survey(sc)))
    args = argparse.Namespace(adhesion="dry", supervision=str(path), critical_speed_kmh=None,
                              odometer=signals == "odometer", sensor_seed=None, closed_loop=False)
    batch, _ = simulate_supervised(args, sc)
    supervision = OnLineSupervision(_survey(sc), path, signals=signals, odometer=SHIPPED.odometer)
    steps = _on_line(rows, odometer, supervision)
    online = [a.as_dict() for a in supervision.supervisor.alerts]
    assert [a["level"] for a in online] == [a["level"] for a in batch["alerts"]] == ["indication", "warning",
                                                                                     "intervention"]
    for got, want in zip(online, batch["alerts"]):
        for key, value in want.items():
            assert got[key] == (value if isinstance(value, str) else pytest.approx(value, rel=1e-12, abs=1e-9)), key
    records = [r for s in steps for r in s.alerts]
    assert [r.time_s for r in records] == [a["time_s"] for a in online]
    assert [r.track_position + supervision.front_offset for r in records] == pytest.approx(
        [a["position_m"] for a in online], abs=1e-9)
    brakes = [s.brake for s in steps if s.brake is not None]
    assert brakes == [pytest.approx(sc_target_speed(sc))]
    # one step per odometer sample in the odometer mode, per states sample on ground truth
    assert len(steps) == (len(odometer["time"]) if signals == "odometer" else len(rows))


def sc_target_speed(sc):
    return scenario_targets(sc.track, CRITICAL_KMH * KMH, LIMITS)[0].speed_limit_m_s


def test_the_odometer_mode_reads_no_ground_truth_after_the_balise(run, tmp_path):
    """The same odometer samples with the ground truth's positions moved after the balise give the same
    alerts: the position is the odometer's integral; and the confidence interval grows with the distance run."""
    sc, rows, odometer = run
    out = []
    for shift in (0.0, 500.0):
        moved = rows.copy()
        moved[40:, OutputRow.position] += shift     # from 0.2 s: after the balise (the first odometer sample)
        supervision = OnLineSupervision(_survey(sc), "survey", signals="odometer", odometer=SHIPPED.odometer)
        steps = _on_line(moved, odometer, supervision)
        out.append([(a.time_s, a.position_m) for a in supervision.supervisor.alerts])
    assert out[0] == out[1]
    status = np.array([s.status for s in steps])
    error = status[:, m.SupervisionStatus.position_error_m]
    front = status[:, m.SupervisionStatus.front_m]
    assert error[0] == LIMITS.position_accuracy_m
    assert error[-1] == pytest.approx(LIMITS.position_accuracy_m + LIMITS.position_accuracy_share
                                      * (front[-1] - front[0]))


@pytest.mark.parametrize("signals", ["ground_truth", "odometer"])
def test_the_status_at_an_alert_gives_its_margin_and_time_to_the_last_braking_point(signals, run):
    sc, rows, odometer = run
    supervision = OnLineSupervision(_survey(sc), "survey", signals=signals, odometer=SHIPPED.odometer)
    status = m.SupervisionStatus.split(np.array([s.status for s in _on_line(rows, odometer, supervision)]))
    for a in supervision.supervisor.alerts:
        k = int(np.flatnonzero(status["time_s"] == a.time_s)[0])
        assert status["margin_kmh"][k] == pytest.approx(a.margin_kmh)
        assert status["time_to_intervention_s"][k] == pytest.approx(a.time_to_intervention_s)
        assert status["level"][k] == ["none", "indication", "warning", "intervention"].index(a.level)


def test_the_status_gives_the_target_and_the_time_to_its_last_braking_point(run):
    sc, rows, odometer = run
    supervision = OnLineSupervision(_survey(sc), "survey")
    steps = _on_line(rows, odometer, supervision)
    status = m.SupervisionStatus.split(np.array([s.status for s in steps]))
    target = scenario_targets(sc.track, CRITICAL_KMH * KMH, LIMITS)[0]
    before = status["front_m"] < target.start_m
    assert np.all(status["target_start_m"][before] == target.start_m)
    assert np.all(status["target_speed_kmh"][before] == pytest.approx(target.speed_limit_m_s / KMH))
    assert np.all(np.isnan(status["limit_kmh"][before]))        # no target in force on the approach
    # the time to the last braking point runs down at one second a second at constant speed until the EBI
    t, left = status["time_s"], status["time_to_intervention_s"]
    intervened = supervision.supervisor.alerts[-1].time_s
    ahead = t < intervened
    assert np.all(np.abs(np.diff(t[ahead] + left[ahead])) < 1e-6) and left[ahead][-1] < 0.01
    after = t >= intervened
    assert np.all(status["level"][after] == INTERVENTION) and np.all(status["braking"][after] == 1.0)
    assert not np.any(status["braking"][ahead])


def _windy_survey(sc):
    survey = _survey(sc)
    curve = survey["curves"][0]
    return dict(survey, wind_sites=[
        dict(position_m=0.5 * (curve["start_m"] + curve["end_m"]), name="embankment", curve=CWC),
        dict(position_m=100.0, name="viaduct", curve=dict(CWC, wind_speed_m_s=[50.0, 45.0, 40.0, None]))])


def test_live_rules_of_a_survey_s_wind_sites(run):
    sc, _, _ = run
    survey = _windy_survey(sc)
    rules = live_rules(survey, 234.375)
    # the lowest of the sites' curves at each speed; the viaduct reached no unloading at 350 km/h
    assert rules.cwc == ((200.0, 48.0), (250.0, 44.2), (300.0, 40.0), (350.0, 39.8))
    curve = survey["curves"][0]
    assert rules.wind_stretches == ((curve["start_m"], curve["end_m"]), (0.0, 100.0 + WIND_SITE_REACH_M))
    assert live_rules(_survey(sc)).wind_stretches == ()


def test_the_live_inputs_move_the_targets(run):
    sc, rows, odometer = run
    survey = _windy_survey(sc)
    curve = survey["curves"][0]
    by_friction = {"0.2": 280.0, "0.4": 265.0, "0.6": 250.0}
    survey["curves"][0] = dict(curve, safe_speed_by_friction_kmh=by_friction)
    supervision = OnLineSupervision(survey, "survey", nonlinear_critical_speed_kmh=234.375)

    def limit_at(x):
        limits = [c.v_target for c in supervision.supervisor.curves if c.target.start_m <= x < c.target.end_m]
        return min(limits) / KMH if limits else None

    inside = curve["start_m"] + 10.0
    assert limit_at(inside) == pytest.approx(250.0)            # no friction estimate: the lowest
    supervision.inputs(friction=0.3)
    assert limit_at(inside) == pytest.approx(265.0)            # the lower of 0.2's and 0.4's
    supervision.inputs(friction=0.2)
    assert limit_at(inside) == pytest.approx(280.0)
    supervision.inputs(friction=0.6)
    assert limit_at(inside) == pytest.approx(250.0)
    supervision.inputs(friction=None, wind_speed_m_s=30.0)     # below the curve at its top speed
    assert limit_at(inside) == pytest.approx(250.0) and limit_at(50.0) is None
    supervision.inputs(wind_speed_m_s=45.0)
    v_wind = wind_speed_limit(live_rules(survey).cwc, 45.0)
    assert v_wind == pytest.approx((200.0 + (48.0 - 45.0) / (48.0 - 44.2) * 50.0) * KMH)   # interpolated
    assert limit_at(inside) == pytest.approx(target_limit(v_wind, LIMITS) / KMH)
    assert limit_at(50.0) == pytest.approx(target_limit(v_wind, LIMITS) / KMH)      # the viaduct's stretch
    supervision.inputs(wind_speed_m_s=None)
    assert limit_at(inside) == pytest.approx(250.0)
    # hunting: only the bogie-instability rules start it, from the front's place to the end of the line
    assert set(HUNTING_CRITERIA) <= set(MEASURED_CRITERIA)
    steps = [s for k in range(10) for s in supervision.on_states(0.005 * k, k, 100.0 + 0.5 * k, 300 * KMH)]
    assert not supervision.on_onboard_alert("car_body_lateral")
    assert not any(c.target.end_m == math.inf for c in supervision.supervisor.curves)
    assert supervision.on_onboard_alert("bogie_rms")
    (hunting,) = [c for c in supervision.supervisor.curves if c.target.end_m == math.inf]
    assert hunting.target.start_m == steps[-1].status[m.SupervisionStatus.front_m]
    assert hunting.v_target == pytest.approx(target_limit(234.375 * KMH, LIMITS))
    # running at 300 km/h inside it: the emergency brake
    (step,) = supervision.on_states(0.05, 10, 105.0, 300 * KMH)
    assert step.status[m.SupervisionStatus.level] == INTERVENTION and step.brake == pytest.approx(hunting.v_target)
    assert supervision.setup()["live"]["hunting"] is True
    # its braking curves, sent at once (a new target): the target without an end drawn OPEN_END_M past the front
    positions = step.curves[m.BrakingCurves.position_m]
    front = step.status[m.SupervisionStatus.front_m]
    assert positions[0] == front and positions[-1] == front + OPEN_END_M and np.all(np.isfinite(positions))
    assert np.all(step.curves[m.BrakingCurves.permitted_kmh] == pytest.approx(hunting.v_target / KMH))


def test_the_node_s_live_input_parameters_and_hunting_alerts(run, tmp_path, node_of):
    sc, _, _ = run
    path = tmp_path / "survey.json"
    path.write_text(json.dumps(_windy_survey(sc)))
    node = node_of(f"supervision:={path}", "supervision_wind_speed:=45.0")
    sup = node.supervision.supervisor
    assert sup.live.wind_speed_m_s == 45.0 and sup.live.friction is None
    assert m.ONBOARD_ALERTS in subscribed(node)
    assert node.set_parameters([Parameter("supervision_friction", value=0.3)])[0].successful
    assert sup.live.friction == 0.3
    assert node.set_parameters([Parameter("supervision_wind_speed", value=math.nan)])[0].successful
    assert sup.live.wind_speed_m_s is None
    refused = node.set_parameters([Parameter("supervision_friction", value=1.5)])[0]
    assert not refused.successful and "supervision_friction" in refused.reason
    alert = m.Alert()
    alert.criterion = "bids_peak_count"
    node.on_onboard_alert(alert)
    assert sup.live.hunting
    assert json.loads(m.supervision_setup_message(node.supervision.setup()).data)["live"]["hunting"] is True


def test_the_node_s_odometer_mode_subscribes_to_the_odometer(tmp_path, node_of, run):
    sc, _, _ = run
    path = tmp_path / "survey.json"
    path.write_text(json.dumps(_survey(sc)))
    node = node_of(f"supervision:={path}", "supervision_signals:=odometer")
    assert f"{m.SENSORS_NS}/{ODOMETER}" in subscribed(node)
    assert node.supervision.signals == "odometer"


def test_the_hunting_target_s_speed_is_the_warning_evaluation_s_nonlinear_critical_speed():
    from railderail_monitor.evaluation.hazards import HazardRules
    from railderail_monitor.node import SUPERVISION_SETUP

    (spec,) = [s for s in SUPERVISION_SETUP if s.name == "supervision_nonlinear_critical_speed_kmh"]
    assert spec.default == HazardRules().nonlinear_critical_speed_kmh
