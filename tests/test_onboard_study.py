"""`railderail onboard-study` (railderail_monitor/evaluation/onboard_study.py): the bogie-instability rules of the on-board
monitor on every frame mount of a hunting car (both yaw dampers failed, straight erri-low track) against the
healthy car, the study's table and files, and its refusals."""
import json

import pytest

from railderail_monitor.evaluation import onboard_study as study

SPEED = 325.0        # km/h


@pytest.fixture(scope="module")
def runs():
    """The healthy and the hunting car at 325 km/h, the study's own runs (3 km, 33 s), in this process."""
    return {c.name: study.run_case((c, SPEED)) for c in study.CASES if c.name != "primary-spring-broken"}


CENTRES = ("bogie_front_frame", "bogie_rear_frame")


def test_the_rules_at_the_frame_centres_see_the_hunting_and_not_the_healthy_car_and_over_the_wheelsets_read_more(runs):
    """At 325 km/h on erri-low track (docs/report/onboard-study.md): with both yaw dampers failed every rule
    alarms at a frame centre (r.m.s. 5.76 of 5.31 m/s^2), the healthy car at none (4.72); over each wheelset
    (EN 14363's place) the frame's yaw adds to its centre's lateral acceleration, in quadrature for a
    hunting bogie, so it reads more there."""
    hunting, healthy = runs["yaw-dampers-failed"]["rules"], runs["healthy"]["rules"]
    for rule in ("bogie_rms", "bogie_peak", "bids_peak_count_china"):
        assert any(hunting[rule][m]["first_alarm"] is not None for m in CENTRES), rule
    assert all(healthy[rule][m]["first_alarm"] is None for rule in study.RULES for m in CENTRES)
    for centre, over in zip(CENTRES, (("bogie_frame_0", "bogie_frame_1"), ("bogie_frame_2", "bogie_frame_3"))):
        for case in (hunting, healthy):
            assert max(case["bogie_rms"][m]["peak"] for m in over) > case["bogie_rms"][centre]["peak"]
        assert hunting["bogie_rms"][centre]["peak"] > 1.1 * healthy["bogie_rms"][centre]["peak"]
    # the hunting's own frequency lies in the monitor's design band f0 +- 2 Hz
    f0 = study.measured_limits(study_vehicle()).hunting_frequency
    for m in CENTRES:
        assert abs(runs["yaw-dampers-failed"]["f0_record_hz"][m] - f0) < 2.0


def study_vehicle():
    from railderail_sim.parameters import VehicleParameters
    return VehicleParameters()


def test_the_study_writes_its_table_and_json(runs, tmp_path):
    result = study.summary(list(runs.values()), [c for c in study.CASES if c.name in runs])
    path = study.write(result, tmp_path)
    text = path.read_text()
    assert "| yaw-dampers-failed | 325 |" in text and "| healthy | 325 |" in text
    data = json.loads((tmp_path / "onboard-study.json").read_text())
    assert {r["case"] for r in data["runs"]} == {"healthy", "yaw-dampers-failed"}
    assert data["first_speed_kmh"]["yaw-dampers-failed"]["bogie_peak"] == SPEED
    assert set(data["runs"][0]["rules"]["bogie_rms"]) == set(study.FRAME_MOUNTS)


def test_the_rules_alarm_on_the_hunting_bogie_s_frame_mounts_only_and_the_table_says_so(tmp_path):
    """Synthetic rows (tests/test_warning_catalogue.py): the front frame oscillating at 4 Hz, 12 m/s^2, from
    8 s on, the rest at rest. Every rule alarms on the front bogie's three frame mounts (no yaw: the same
    reading at its centre and over its wheelsets) a few seconds after the onset and never on the rear's; but
    UIC 515-5's count within 500 ms, which a 4 Hz hunting cannot reach (more than 6 half-waves 125 ms apart)."""
    from railderail_sim.parameters import VehicleParameters
    from test_warning_catalogue import _hunting_front_bogie
    _, signals, _ = _hunting_front_bogie()
    run = dict(case="yaw-dampers-failed", faults=[], speed_kmh=288.0, simulated_s=30.0, diverged="",
               **study.record(signals, VehicleParameters()))
    onset = 8.0 - study.START_UP_S
    seen = tuple(r for r in study.RULES if r != "bids_peak_count")
    assert all(a["first_alarm"] is None for a in run["rules"]["bids_peak_count"].values())
    for rule in seen:
        for mount in ("bogie_front_frame", "bogie_frame_0", "bogie_frame_1"):
            first = run["rules"][rule][mount]["first_alarm"]
            assert first is not None and onset < first["time_s"] < onset + 3.0, (rule, mount)
            assert first["distance_m"] == pytest.approx(80.0 * first["time_s"], abs=2.0)    # the odometer's
        for mount in ("bogie_rear_frame", "bogie_frame_2", "bogie_frame_3"):
            assert run["rules"][rule][mount]["first_alarm"] is None, (rule, mount)
    assert run["f0_record_hz"]["bogie_front_frame"] == pytest.approx(4.0, abs=0.25)
    assert run["measured_first_alerts"]["bogie_rms"]["place"] == "bogie_front_frame"
    result = study.summary([run], [study.CASES[1]])
    assert result["first_speed_kmh"]["yaw-dampers-failed"] == {rule: 288.0 if rule in seen else None
                                                               for rule in study.RULES}
    text = study.write(result, tmp_path).read_text()
    row = next(line for line in text.splitlines() if line.startswith("| yaw-dampers-failed | 288 | - |"))
    assert row.count("**") == 2 * len(seen) and "rear" not in row and "frame_2" not in row


@pytest.mark.parametrize("argv, message", [
    (["--speeds", "250,fast"], "--speeds '250,fast' is not a comma-separated list of numbers"),
    (["--speeds", "900"], "--speeds 900 km/h is outside the accepted range [30, 800] km/h"),
    (["--cases", "healthy,derailed"], "--cases: unknown case(s) derailed; the cases are healthy"),
    (["--estimator-error", "--seconds", "0.5"], "--seconds 0.5 s is outside the accepted range [1.5, 600] s"),
])
def test_bad_arguments_are_refused_with_one_line(argv, message, capsys):
    from railderail_sim.cli import main
    assert main(["onboard-study", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_the_estimator_error_is_per_side_with_the_wind_told_and_the_model_off():
    from railderail_monitor.evaluation import estimator_error as ee
    r = ee.run_kind((ee.KINDS[4], 1.6, None))       # the steady crosswind, 0.6 s after the start-up
    nominal, told = r["errors"]["nominal"], r["errors"]["told the wind"]
    assert set(nominal["unloading"]) == {"front_left", "front_right", "rear_left", "rear_right"}
    assert set(nominal["lateral_force"]) == {"front", "rear"}
    # the windward and the leeward side err the opposite ways when blind (why they are never pooled)
    assert nominal["unloading"]["front_left"]["bias"] < -0.1 < 0.1 < nominal["unloading"]["front_right"]["bias"]
    assert abs(told["unloading"]["front_left"]["bias"]) < 0.25 * abs(nominal["unloading"]["front_left"]["bias"])
    # a heavier car body in the estimator's model: a larger P0 against the same loads, more unloading everywhere
    heavier = r["mismatch"]["payload +10 %"]["unloading"]
    assert all(heavier[p]["bias"] > told["unloading"][p]["bias"] for p in heavier)
    assert "| steady-wind | told the wind | unloading | front_left |" in ee.markdown(
        dict(settings=dict(seconds=1.6, sensors="the shipped set", seed=1, settle_s=1.0,
                           mismatches=[m for m, _ in ee.MISMATCHES]), runs=[r]))


def test_the_estimator_error_with_the_realistic_sensors_differs_by_their_sensing_errors():
    """--sensors: the realistic set's scale factors and misalignment move the estimate (the same run, seed and
    noise otherwise)."""
    from railderail_monitor.evaluation import estimator_error as ee
    from railderail_sim.sensors.config import REALISTIC_FILE
    kind = ee.KINDS[0]                             # steady curving, where the quasi-static levels count
    shipped, realistic = (ee.run_kind((kind, 1.6, f))["errors"]["nominal"]["unloading"] for f in (None, REALISTIC_FILE))
    moved = [abs(realistic[p]["bias"] - shipped[p]["bias"]) for p in shipped]
    assert max(moved) > 0.005
