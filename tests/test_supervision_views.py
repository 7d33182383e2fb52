"""The speed supervision's views: the Rerun tab `supervision` (the driver's planning area, the speed, margin,
time to the last braking point and level over time) drawn from the monitor's supervision topics, live and from
a recording's .rrd; no tab without them; the braking curve drawn where the supervisor intervenes."""
import json

import numpy as np
import pytest
import rerun.blueprint as rrb

from railderail_monitor.recording.recorder import McapRecording
from railderail_monitor.recording.replay import read_recording, write_rrd
from railderail_monitor.supervision.curves import INTERVENTION, KMH, SupervisionLimits
from railderail_monitor.supervision.on_line import OnLineSupervision
from railderail_monitor.views.planning import X_SCALE, braking_curves
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
    # the braking curve drawn is the supervisor's: its EBI at 300 km/h is where the supervisor intervened
    intervention = supervision.supervisor.alerts[-1]
    assert viewer.planning.target == (4000.0, 5400.0, pytest.approx(255.0))
    ebi, driver = braking_curves(BrakingModel(), SupervisionLimits(), 4000.0, 5400.0, 255.0, 400.0, points=30)
    at_300 = next(x for x, y in ebi if y == pytest.approx(-300.0)) / X_SCALE
    assert intervention.position_m - SPEED / 200.0 < at_300 <= intervention.position_m
    assert next(x for x, y in driver if y == pytest.approx(-300.0)) / X_SCALE < at_300


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
