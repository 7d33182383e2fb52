"""What the demo prints and writes for an engineer: margins in km/h beside metres and seconds, the trial's
entry alerts set apart, the simulator's pace, the commands to review a run."""
import math
import sys

import pytest

from railderail_monitor import demo

DERAILMENT = dict(time_s=110.0, track_position_m=7000.0, speed_kmh=259.1)


def alert(criterion, speed_kmh, time_s, position_m, **more):
    return dict(criterion=criterion, severity=1, wheelset=0, wheel_side="left", rail_side="inner",
                speed=speed_kmh / 3.6, time_s=time_s, track_position=position_m, value=1.0, threshold=0.9, **more)


def test_leads_in_km_h_metres_and_seconds_and_the_entry_set_apart():
    entry_kmh = demo.entry_speed_kmh(dict(speed_mode="progressive", speed_kmh=200.0))
    assert entry_kmh == 205.0                       # the node's default step, 5 km/h
    assert demo.entry_speed_kmh(dict(speed_mode="constant", speed_kmh=280.0)) is None
    early, late = alert("wheel_unloading", 200.8, 3.1, 380.0), alert("wheel_lift", 254.1, 105.0, 6650.0)
    first, second = demo.lead_table([early, late], DERAILMENT, entry_kmh)
    assert "wheel unloading ΔQ/Q0" in first and "200.8 km/h" in first and first.endswith("entry: no warning")
    assert " 58.3 km/h    6620 m  106.90 s" in first
    assert "wheel lift h_p" in second and "  5.0 km/h     350 m    5.00 s" in second and "entry" not in second
    leads = demo.measured_leads([dict(early, place="car_body_front"), dict(late, place="air_springs")],
                                DERAILMENT, entry_kmh)
    assert leads["wheel_unloading at car_body_front"]["entry"] and not leads["wheel_lift at air_springs"]["entry"]
    assert leads["wheel_lift at air_springs"]["margin_kmh"] == pytest.approx(5.0)
    text = demo.measured_summary([dict(early, place="car_body_front")], None, entry_kmh)
    assert "no derailment followed" in text
    assert math.isnan(demo.measured_leads([dict(early, place="x")], None)["wheel_unloading at x"]["margin_kmh"])


def test_a_simulator_behind_its_rate_is_said():
    behind = demo.pace(dict(achieved_samples_per_s=134.5, requested_samples_per_s=600.0))
    assert behind["behind"]
    assert demo.pace_text(behind, 200.0).startswith(
        "WARNING: the simulator fell behind: 134.5 of the requested 600 samples/s (0.67 x real time instead of 3")
    on_time = demo.pace(dict(achieved_samples_per_s=598.0, requested_samples_per_s=600.0))
    assert not on_time["behind"] and not demo.pace_text(on_time, 200.0).startswith("WARNING")
    assert not demo.pace(dict(achieved_samples_per_s=50.0, requested_samples_per_s=0.0))["behind"]


def test_the_review_hint_names_the_command_that_was_run(monkeypatch):
    monkeypatch.setattr(sys, "argv", ["/home/me/railderail/.venv/bin/railderail", "demo"])
    assert demo.command_prefix() == "/home/me/railderail/.venv/bin/railderail"
    monkeypatch.setattr(sys, "argv", ["/x/railderail_sim/cli/__main__.py", "demo"])
    assert demo.command_prefix() == f"{sys.executable} -m railderail_sim.cli"
