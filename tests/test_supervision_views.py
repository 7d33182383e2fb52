"""The speed supervision's views: the Rerun tab `supervision` (the driver's planning area, the speed, margin,
time to the last braking point and level over time) drawn from the monitor's supervision topics, live and from
a recording's .rrd; no tab without them; the braking curve drawn where the supervisor intervenes. The braking
curves the monitor sends (/railderail/braking_curves) are the ones the Rerun area draws, where the supervisor
has them, sent when their target changes and once a simulated second."""
import json
import math

import numpy as np
import pytest
import rerun.blueprint as rrb

from railderail_monitor.recording.recorder import McapRecording
from railderail_monitor.recording.replay import read_recording, write_rrd
from railderail_monitor.supervision.curves import (APPROACH_SAMPLES, CURVES, INDICATION, INTERVENTION, KMH, NONE,
                                                   SAMPLES, WARNING, SupervisionLimits, Target, TargetCurves)
from railderail_monitor.supervision.on_line import OnLineSupervision, braking_curve_rows
from railderail_monitor.views.rerun_views import RunViewer
from railderail_sim.ros import interface as m
from railderail_sim.supervision.braking import BrakingModel
from rclpy.serialization import serialize_message
from test_viewer import entity_rows, views

# a curve of 255 km/h from 4000 to 5400 m, approached at 300 km/h from 0 m, 200 Hz
SURVEY = {"curves": [dict(start_m=4000.0, end_m=5400.0, safe_speed_kmh=255.0, critical_derailment_speed_kmh=270.0,
                          permitted_speed_kmh=350.0)]}
SPEED = 300 * KMH


def _steps(n=8000):
    supervision = OnLineSupervision(SURVEY, "survey.json")
    steps = [s for k in range(n) for s in supervision.on_states(k / 200.0, k, SPEED * k / 200.0 - 10.0, SPEED)]
    return supervision, steps


def _messages():
    supervision, steps = _steps()
    return supervision, [m.supervision_setup_message(supervision.setup())] + [
        m.supervision_status_message(s.status) for s in steps]


def test_the_supervision_tab_comes_with_the_first_status_and_not_without():
    viewer = RunViewer(flush_every=10**6)
    supervision, messages = _messages()
    viewer.on_supervision(messages[0])
    assert isinstance(viewer.blueprint().root_container, rrb.Vertical)      # what it supervises alone: no tab
    for message in messages[1:]:
        viewer.on_supervision_status(message)
    root = viewer.blueprint().root_container
    assert isinstance(root, rrb.Tabs) and [c.name for c in root.contents] == ["run", "supervision"]
    origins = {str(v.origin) for v in views(root.contents[1])}
    assert origins == {"/planning", "/supervision/speed_kmh", "/supervision/margin_kmh",
                       "/supervision/time_to_intervention_s", "/supervision/level"}
    times, margins = viewer.buffers["/supervision/margin_kmh"]
    assert len(times) == len(messages) - 1 and margins[0] == pytest.approx(255.0 - 300.0)
    _, levels = viewer.buffers["/supervision/level"]
    assert levels[-1] == INTERVENTION and {1, 2, 3} <= set(levels)
    # the braking curve drawn is the supervisor's: its EBI at 300 km/h (from the line's start) is where the
    # supervisor intervened, within what interpolating it gives (0.01 km/h: 0.3 m at this slope)
    intervention = supervision.supervisor.alerts[-1]
    assert viewer.planning.target == (4000.0, 5400.0, pytest.approx(255.0))
    curves = TargetCurves(Target(4000.0, 5400.0, 255.0 * KMH, "").validated(), BrakingModel(), SupervisionLimits())
    rows = m.braking_curves_dict(m.braking_curves_message(braking_curve_rows(curves, 0.0, SPEED, 450.0)))
    x, ebi, driver = rows["position_m"][:APPROACH_SAMPLES], rows["ebi_kmh"], rows["permitted_kmh"]
    at_300 = np.interp(-300.0, -ebi[:APPROACH_SAMPLES], x)
    assert abs(at_300 - intervention.position_m) < 1.0
    # the driver's curve T_bs + T_driver (2 s + 4 s) ahead of it
    assert np.interp(-300.0, -driver[:APPROACH_SAMPLES], x) == pytest.approx(at_300 - SPEED * (2.0 + 4.0), abs=1.0)


def test_a_recording_s_supervision_topics_are_in_its_rrd(tmp_path):
    _, messages = _messages()
    path = tmp_path / "run.mcap"
    with McapRecording(path) as rec:
        for topic in (m.ALERTS, m.SUPERVISION, m.SUPERVISION_STATUS):       # a railderail recording's topic
            rec.add_topic(topic, m.TOPICS[topic][0], m.TOPICS[topic][2])
        rec.write(m.ALERTS, serialize_message(m.Alert()))
        rec.write(m.SUPERVISION, serialize_message(messages[0]))
        for message in messages[1:]:
            rec.write(m.SUPERVISION_STATUS, serialize_message(message))
    rows = entity_rows(write_rrd(read_recording(path), tmp_path / "run.rrd"))
    n = len(messages) - 1
    for series in ("speed_kmh/speed", "margin_kmh", "level", "time_to_intervention_s"):
        assert rows[f"/supervision/{series}"] == n, series
    assert rows["/supervision/speed_kmh/target"] == n
    assert "/supervision/speed_kmh/limit" not in rows      # no target in force on the approach
    for entity in ("grid", "permitted", "targets", "critical", "braking"):
        assert rows[f"/planning/{entity}"] >= 1, entity
    assert n / 8 - 2 <= rows["/planning/train"] <= n / 8 + 2          # drawn at 25 Hz of a 200 Hz run


def test_the_setup_message_carries_the_survey_s_profile():
    supervision, messages = _messages()
    setup = json.loads(messages[0].data)
    assert setup["targets"] == [dict(start_m=4000.0, end_m=5400.0, speed_kmh=pytest.approx(255.0),
                                     reason="curve 0 of survey.json: safe speed 255.0 km/h (survey)")]
    assert setup["curves"][0]["critical_derailment_speed_kmh"] == 270.0 and setup["signals"] == "ground_truth"
    status = m.supervision_status_dict(messages[1])
    assert list(status) == m.SupervisionStatus.names() and status["speed_kmh"] == pytest.approx(300.0)
    assert np.isnan(status["limit_kmh"])


def test_the_braking_curves_sent_are_the_ones_the_rerun_area_draws():
    supervision, steps = _steps()
    sent = [s for s in steps if s.curves is not None]
    assert [s.time_s for s in sent] == pytest.approx(range(40))         # once a simulated second, one target
    setup = m.supervision_setup_message(supervision.setup())
    for step in sent[::6]:
        viewer = RunViewer(flush_every=10**6)
        viewer.on_supervision(setup)
        viewer.on_supervision_status(m.supervision_status_message(step.status))
        drawn = viewer.planning.curves
        message = m.braking_curves_message(step.curves)
        assert [(d.label, d.size) for d in message.layout.dim] == [(",".join(m.BrakingCurves.names()), 8),
                                                                    ("sample", SAMPLES)]
        for name, row in m.braking_curves_dict(message).items():
            # the area's target speed is the status's km/h: a rounding apart
            np.testing.assert_allclose(drawn[m.BrakingCurves[name]], row, rtol=1e-12, err_msg=name)
        assert drawn[m.BrakingCurves.position_m][0] == step.status[m.SupervisionStatus.front_m]
        assert drawn[m.BrakingCurves.speed_kmh][0] == pytest.approx(300.0)


def test_the_curves_along_the_line_are_where_the_supervisor_raises_its_levels():
    limits, hair = SupervisionLimits(), 0.01 * KMH
    top = 450.0 * KMH
    for adhesion, front in (("dry", 500.0), ("wet", 500.0), ("dry", -8000.0)):
        curves = TargetCurves(Target(4000.0, 5400.0, 255.0 * KMH, "").validated(), BrakingModel(adhesion=adhesion),
                              limits)
        positions, speeds = curves.along(front, top)
        assert positions.size == SAMPLES and positions[0] == front and positions[APPROACH_SAMPLES] == 4000.0
        assert positions[-1] == 5400.0 and np.all(np.diff(positions) >= 0.0)
        for k, name in enumerate(CURVES):
            def located(v):                     # the curve's location at speed v, as the supervisor has it
                return curves.ebd(v) if name == "ebd" else curves.locations(v)[5 - k]
            low = curves.v_foot if name == "ebd" else curves.v_target
            for x, v in zip(positions[:APPROACH_SAMPLES + 1], speeds[name]):
                if math.isnan(v):
                    assert located(top) > x                 # above the area's top there
                    continue
                assert located(v + hair) < x, (name, x)     # a hair faster the train is beyond it
                assert located(v - hair) > x if v > low + hair else located(low) <= x, (name, x)
            # 12 km before the target every curve is above 450 km/h, 3.5 km before none
            assert np.isnan(speeds[name][0]) == (front < 0.0)
        # from the target's start its ceiling: the levels of a train a hair either side of each (up to its end)
        inside = positions[APPROACH_SAMPLES + 1:-1]
        for name, level in (("ebi", INTERVENTION), ("warning", WARNING), ("permitted", INDICATION)):
            for x, v in zip(inside, speeds[name][APPROACH_SAMPLES + 1:]):
                assert curves.level(x, v + hair) >= level > curves.level(x, v - hair), (name, x)
        assert curves.level(4000.0, speeds["permitted"][-1] - hair) == NONE


def test_the_curves_are_sent_when_their_target_changes_and_none_once_past_it():
    supervision = OnLineSupervision(SURVEY, "survey.json")
    viewer = RunViewer(flush_every=10**6)
    viewer.on_supervision(m.supervision_setup_message(supervision.setup()))
    sent, drawn = [], []
    for k in range(600):                        # the front from 5200 m to 5700 m: the target ends at 5400 m
        for step in supervision.on_states(k / 200.0, k, 5190.0 + SPEED * k / 200.0, SPEED):
            if step.curves is not None:
                sent.append((step.time_s, step.curves.shape[1]))
            viewer.on_supervision_status(m.supervision_status_message(step.status))
            drawn.append(viewer.planning.curves is not None)
        if k == 30:
            supervision.inputs(friction=0.3)    # a live input: the targets rebuilt, sent at the next sample
    assert sent[:3] == [(0.0, SAMPLES), (pytest.approx(0.155), SAMPLES), (pytest.approx(1.155), SAMPLES)]
    assert sent[-2:] == [(pytest.approx(2.155), SAMPLES), (pytest.approx(200.0 / SPEED, abs=0.006), 0)]
    # the Rerun area's curves go with them (cleared once past the target, at its next drawing)
    assert drawn[0] and not drawn[-1] and drawn.index(False) == pytest.approx(480, abs=8)
