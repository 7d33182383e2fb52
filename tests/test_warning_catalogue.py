"""The warning evaluation over a scenario catalogue: the catalogue's checks, a small one evaluated (an over-speed
rollover, a kink that makes the outer wheel climb, ordinary running on irregular track; one scenario of each
per part), attribution at the derailed wheel, the split by scenario and track, the cache, Dask, the
recommended parameter file read back and re-scored, a recommendation re-scored on runs it was not chosen on
with the real budgets, the derailments expected per mechanism, and the shipped results' properties."""
import json
import math
from pathlib import Path

import pytest

from railderail_monitor.evaluation import (catalogue, catalogue_runs, over_catalogue as wc, recommendation, scoring,
                                          sweeps, tables)
from railderail_monitor.evaluation.hazards import HazardRules
from railderail_monitor.onboard import measured

ROOT = Path(__file__).resolve().parents[1]
SHIPPED_RESULT = ROOT / "docs" / "report" / "warnings-catalogue.json"
SMALL = """
scenarios:
  - {name: overspeed-300, family: overspeed, radius_m: 1000, speed_kmh: 300, seeds: [1]}
  - {name: overspeed-310, family: overspeed, radius_m: 1000, speed_kmh: 310, seeds: [2]}
  - {name: kink-50mm, family: defect, radius_m: 800, speed_kmh: 160, friction: 0.5, seeds: [1],
     defect: {kind: kink, amplitude_mm: 50, length_m: 5, at_m: 700}}
  - {name: kink-45mm, family: defect, radius_m: 800, speed_kmh: 160, friction: 0.5, seeds: [2],
     defect: {kind: kink, amplitude_mm: 45, length_m: 5, at_m: 700}}
  - {name: ordinary-a, family: ordinary, radius_m: 1000, speed_kmh: 160, irregularity: erri-high, line_length_m: 4000,
     seeds: [1]}
  - {name: ordinary-b, family: ordinary, radius_m: 1000, speed_kmh: 160, irregularity: erri-high, line_length_m: 4000,
     seeds: [2]}
"""
GENEROUS = {"warning": 3000.0, "critical": 2000.0}     # budgets a few km of running can resolve


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    folder = tmp_path_factory.mktemp("catalogue")
    (folder / "small.yaml").write_text(SMALL)
    entries = catalogue.load(folder / "small.yaml")
    result = wc.evaluate(entries, cache=folder / "cache", workers=2, progress=False, budgets=GENEROUS, min_share=0.0)
    return folder, entries, result


def _raw(small):
    """Every run's full result, from the cache."""
    folder, entries, _ = small
    return [catalogue_runs.run_one(item, cache=folder / "cache") for e in entries for item in e.runs()]


def test_each_run_shows_the_hazard_its_scenario_should(small):
    _, _, result = small
    runs = {r["scenario"]: r for r in result["runs"]}
    for over, kink, ordinary in (("overspeed-300", "kink-50mm", "ordinary-a"), ("overspeed-310", "kink-45mm",
                                                                                 "ordinary-b")):
        assert (runs[over]["hazard"], runs[over]["mechanism"]) == ("derailment", "wheel_unloading")
        kink = runs[kink]
        assert (kink["hazard"], kink["mechanism"]) == ("derailment", "flange_climbing")
        assert (kink["derailment"]["wheelset"], kink["derailment"]["wheel_side"]) == (0, "right")   # the outer wheel
        assert runs[ordinary]["km"] == pytest.approx(4.0, abs=1e-3)      # to the sample past the end
    # split by scenario: within each family the first entry trains, the second tests; no scenario in both
    assert result["split"]["train"] == ["kink-50mm", "ordinary-a", "overspeed-300"]
    assert result["split"]["test"] == ["kink-45mm", "ordinary-b", "overspeed-310"]
    assert result["mechanisms"]["over-speed unloading"] == {"train": {"expected": 0, "derailed": 1},
                                                           "test": {"expected": 0, "derailed": 1}}


def test_a_rollover_is_warned_by_the_unloading_seconds_ahead_but_not_usefully(small):
    """The unloading stands at the rollover a few seconds ahead; its cure is below the curve's critical
    derailment speed over 1.1 (260 km/h at R 1000 m, 175 mm), which needs 15.4 s at 300 km/h on dry rail
    and more on wet."""
    _, _, result = small
    over = next(r for r in result["runs"] if r["scenario"] == "overspeed-300")
    first = over["first_true_alert"]["wheel_unloading"]
    assert 1.0 < first["lead_s"] < 5.0 and not first["useful"]
    cure = first["hazard_cure"]
    assert cure["mechanism"] == "over-speed" and cure["speed_kmh"] == pytest.approx(260.3, abs=0.1)
    assert cure["permitted_speed_kmh"] == pytest.approx(166.0, abs=0.1)
    assert 14.0 < first["lead_needed_s"] < first["lead_needed_wet_s"]
    assert over["first_true_alert"]["attack_angle"] is None


def test_only_alarms_at_the_derailed_wheel_s_running_gear_and_side_warn_the_climb(small):
    """The kink's left wheels flange and lift too; only the right side of the front bogie counts."""
    for run in (r for r in _raw(small) if r["scenario"].startswith("kink")):
        (derailment,) = [h for h in run["hazards"] if h["kind"] == "derailment"]
        assert derailment["places"] == [[0, 1]]


def test_the_criteria_table_is_the_test_part_s_and_counts_per_km_and_hour(small):
    _, _, result = small
    rules = HazardRules()
    test = [r for r in _raw(small) if r["part"] == "test"]
    km = sum(r["windows"][str(rules.window_s)]["normal_km"] for r in test)
    assert result["exposure"]["test_km"] == pytest.approx(km)
    for row in result["criteria"]:
        assert row["derailments"] == 2                                # the test part's two derailments
        expected = 1000.0 * row["false_alarm_episodes"] / km
        assert row["false_alarms_per_1000_km"] == pytest.approx(expected)
        # the exact Garwood interval of the episodes over the part's normal km, and the scenario bootstrap's
        assert row["false_alarms_per_1000_km_ci95"] == pytest.approx(
            [1000.0 * x / km for x in scoring.count_interval(row["false_alarm_episodes"])])
        assert len(row["false_alarms_per_1000_km_boot95"]) == 2
        assert row["signals"] == ("measured" if row["criterion"] in measured.CRITERIA else "line_data"
                                  if row["criterion"] == "speed_supervision" else "ground_truth")
    assert {r["criterion"] for r in result["criteria"] if r["signals"] == "measured"} == set(measured.CRITERIA)


def test_a_second_evaluation_reads_every_run_from_the_cache(small, monkeypatch):
    """In this process (whatever the pool's start method): no run is simulated again."""
    folder, entries, result = small
    assert len([p for p in (folder / "cache").rglob("*.json") if "survey" not in p.parts]) == 6

    def no_simulation(*args, **kwargs):
        raise AssertionError("a cached run was simulated again")
    monkeypatch.setattr("railderail_sim.vehicle.simulate.run_to_stop", no_simulation)
    assert [r["scenario"] for r in _raw(small)] == ["overspeed-300", "overspeed-310", "kink-50mm", "kink-45mm",
                                                     "ordinary-a", "ordinary-b"]
    # a cache entry's file written whole: a killed evaluation leaves the others readable
    for path in (folder / "cache").rglob("*.json"):
        json.loads(path.read_text())


def test_a_measured_alarm_holds_from_the_first_row_at_or_after_its_sample_s_stamp():
    import numpy as np
    rows = np.arange(10) * 0.005                        # 200 Hz rows
    stamps = np.array([0.002, 0.012, 0.022, 0.032])      # 100 Hz samples, 2 ms late
    alarm = np.array([False, True, True, False])
    # the sample stamped 0.012 s alarms the rows from 0.015 s, the one at 0.032 s re-arms from 0.035 s
    last = catalogue_runs.last_sample(stamps, rows)
    assert catalogue_runs.rows_in_alarm(last, alarm).tolist() == [False] * 3 + [True] * 4 + [False] * 3
    # a sample stamped at a row's own instant alarms that row
    at_row = catalogue_runs.last_sample(rows[2:3], rows)
    assert catalogue_runs.rows_in_alarm(at_row, [True]).tolist() == [False] * 2 + [True] * 8


def _hunting_front_bogie(seconds=30.0, rate=200.0, speed=80.0, start_s=8.0):
    """Output arrays of a car at speed on level track whose front bogie frame oscillates laterally at 4 Hz,
    12 m/s^2, from start_s on (a hunting bogie), the rest at rest; and their sensors' signals (the shipped set
    but the air springs, with its noise)."""
    from dataclasses import replace

    import numpy as np
    from railderail_sim.parameters import GRAVITY
    from railderail_sim.sensors import config
    from railderail_sim.sensors.measure import named, SensorStream
    from railderail_sim.vehicle.layout import N_BODY, Body, BodyMotion
    from railderail_sim.vehicle.simulate import Scenario
    n = int(seconds * rate)
    t = np.arange(n) / rate
    motion = np.zeros((n, N_BODY, BodyMotion.size()))
    motion[:, :, BodyMotion.specific_force + 2] = GRAVITY
    motion[:, Body.front_bogie, BodyMotion.specific_force + 1] = 12.0 * np.sin(2 * np.pi * 4.0 * t) * (t >= start_s)
    arrays = dict(time=t, position=speed * t, speed=np.full(n, speed), body_motion=motion,
                  body_states=np.zeros((n, N_BODY, 5)))
    sensors = replace(config.default_set(), air_springs=None, seed=3)
    return arrays, named(SensorStream(sensors, replace(Scenario(), output_rate=rate)).process(arrays)), sensors


def test_a_hunting_front_frame_warns_a_hazard_of_its_bogie_only_and_from_its_stamps():
    """The measured scoring path on synthetic rows: the frame rules of the hunting front bogie alarm, held onto
    the rows from their stamps, and are true warnings of a hazard at the front bogie (either side) standing at
    it and false for one at the rear bogie; the car body's channels (at rest here) never alarm."""
    import numpy as np
    from railderail_sim.parameters import VehicleParameters
    from railderail_sim.sensors.measure import START_UP_S, after
    arrays, signals, sensors = _hunting_front_bogie()
    results = measured.evaluate(after(signals, START_UP_S), VehicleParameters(), sweeps.shipped_measured_limits(),
                                measured.sample_rates(sensors))
    alarms = catalogue_runs.measured_alarms(results, arrays["time"], lambda c: [sweeps.shipped_level(c)])
    peak = alarms["bogie_peak"][sweeps.shipped_level("bogie_peak")]
    assert peak.shape == (2, len(arrays["time"])) and peak[0].any() and not peak[1].any()
    first = np.flatnonzero(peak[0])[0]
    m, limits = results["bogie_peak"], sweeps.shipped_measured_limits()
    raised = m.time[m.channel_intervals(None, limits.rearm_fraction, limits.rearm_m)[0][0][0]]   # its alert
    assert arrays["time"][first - 1] < raised <= arrays["time"][first]       # the first row at or after the stamp
    assert not any(a.any() for c in ("car_body_lateral", "car_body_roll_rate")
                   for a in alarms[c].values())

    def hazard(bogie):
        return dict(kind="derailment", margin="wheel_unloading", time_s=20.0, end_s=20.0, speed_m_s=80.0,
                    position_m=1600.0, places=[(bogie, 1)])
    front, rear = (catalogue_runs.scores(alarms, arrays, [hazard(b)], 20.0) for b in (0, 1))
    # UIC 515-5's count within 500 ms (more than 6 peaks) cannot see a 4 Hz hunting: half-waves 125 ms apart
    assert not any(a.any() for a in alarms["bids_peak_count"].values())
    for rule in ("bogie_rms", "bogie_peak", "bids_peak_count_china"):
        (row,) = front[rule]
        assert row["warnings"][0] is not None and 10.0 < row["warnings"][0][0] <= 12.0, rule
        assert rear[rule][0]["warnings"] == [None]
        # for the rear bogie's hazard the front frame's alarm in its window is false, counted apart from the
        # normal running's episodes (after the hazard, the same for both)
        assert rear[rule][0]["window_false_episodes"] > front[rule][0]["window_false_episodes"] == 0
        assert rear[rule][0]["false_episodes"] == front[rule][0]["false_episodes"] > 0


def test_the_measured_scores_follow_the_sensors_noise():
    """The same synthetic rows seen through the sensors with 3000 times their noise (2 m/s^2 r.m.s. on the
    car body's floor in EN 14363's 0.4-10 Hz band): the car body at rest raises false alarms it does not raise
    with the data sheets' noise."""
    import types
    from dataclasses import replace
    from railderail_sim.vehicle.simulate import Scenario
    arrays, _, sensors = _hunting_front_bogie()
    sim = types.SimpleNamespace(scenario=replace(Scenario(), output_rate=200.0), model=None, speed_table=None)
    rules = HazardRules()
    found = [dict(kind="derailment", margin="wheel_unloading", time_s=29.0, end_s=29.0, speed_m_s=80.0,
                  position_m=2320.0, places=[(0, 1)])]
    shipped, noisy = (dict(noise=x, bias=1.0, rate_hz=200.0) for x in (1.0, 3000.0))
    rows = catalogue_runs.sensor_sensitivity_run(sensors, sim, arrays, found, rules, (shipped, noisy))
    (calm,), (loud,) = (rows[sweeps.variant_name(v)]["car_body_lateral"] for v in (shipped, noisy))
    assert calm["false_episodes"] == 0 and calm["warnings"] == [None]
    assert loud["false_episodes"] >= 1 and loud["false_time_s"] > 0.0


def test_measured_criteria_warn_the_rollover_from_the_sensors_alone(small):
    """The roll-balance estimate of the running gear's unloading, on the sensors with their noise, warns the
    over-speed rollover at the derailed side, ahead of it; it has no channel for a wheel's flange climb."""
    _, _, result = small
    for run in (r for r in result["runs"] if r["scenario"].startswith("overspeed")):
        first = run["first_true_alert"]["estimated_running_gear_unloading"]
        assert first is not None and 0.5 < first["lead_s"] < 10.0
        assert run["peaks"]["estimated_running_gear_unloading"] > 0.9


def test_the_measured_criteria_s_scores_move_with_the_sensors(small):
    """The sensor sensitivity is the test part's measured criteria seen through each sensor variant over the
    same rows: the shipped set's rows are the criteria table's, and without noise or with three times the
    bias some score differs."""
    _, _, result = small
    sens = result["sensor_sensitivity"]
    assert {s["variant"] for s in sens} == {sweeps.variant_name(v) for v in sweeps.SENSOR_VARIANTS}
    base = {s["criterion"]: s for s in sens if s["variant"] == sweeps.variant_name(sweeps.SENSOR_VARIANTS[0])}
    table = {r["criterion"]: r for r in result["criteria"]
             if r["threshold"] == result["shipped_levels"][r["criterion"]] and r["signals"] == "measured"}
    assert set(base) == set(table) == set(measured.CRITERIA)
    keys = ("derailments", "warned", "usefully_warned", "lead_s_median", "false_alarm_episodes", "time_in_alarm_share")
    for c in base:
        assert [base[c][k] for k in keys] == pytest.approx([table[c][k] for k in keys], nan_ok=True)
    for v in sweeps.SENSOR_VARIANTS[1:]:
        assert all(s["derailments"] == 2 for s in sens if s["variant"] == sweeps.variant_name(v))

    def scores(variant):
        return [s[k] for s in sens if s["variant"] == sweeps.variant_name(variant) for k in keys]
    # the roll-balance estimate reads the air springs' pressures: their bias moves its scores
    biased = dict(noise=1.0, bias=3.0, rate_hz=200.0)
    assert scores(biased) != pytest.approx(scores(sweeps.SENSOR_VARIANTS[0]), nan_ok=True)


@pytest.mark.parametrize("text, message", [
    ("scenarios: []", "a non-empty list `scenarios:`"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000, speed_kmh: 300, sped: 1}",
     "scenario 1 (a): unknown key(s) sped"),
    ("scenarios:\n  - {name: a, family: overspeed, speed_kmh: 300}", "scenario 1 (a): radius_m is missing"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 90, speed_kmh: 300}", "scenario 1 (a): radius_m 90 m is outside"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000}", "give either speed_kmh"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000, speed_kmh: 300, seeds: [1, 1]}", "repeat a seed"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000, speed_kmh: fast}", "speed_kmh 'fast' is not a number"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000, speed_kmh: 300, irregularity: no.csv}",
     "no.csv does not exist"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000, speed_kmh: 300, faults: [brakes]}", "faults ['brakes']"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000, speed_kmh: 300}\n"
     "  - {name: a, family: overspeed, radius_m: 800, speed_kmh: 250}", "scenario name(s) a used more than once"),
    ("scenarios:\n  - {name: a, radius_m: 1000, speed_kmh: 300}", "scenario 1 (a): family None is not one of"),
    ("scenarios:\n  - {name: a, family: ordinary, radius_m: 1000, speed_kmh: 300}",
     "scenario 1 (a): an ordinary run's cant deficiency must be within the permitted 150 mm; at 300 km/h it is 880 mm"),
    ("scenarios:\n  - {name: a, family: ordinary, radius_m: .inf, speed_kmh: 250, irregularity: fra-6}",
     "scenario 1 (a): an ordinary run on fra-6 track must be within its class's permitted 177 km/h (49 CFR 213.9 / "
     "213.307); 250 km/h given"),
    ("scenarios:\n  - {name: a, family: defect, radius_m: 800, speed_kmh: 160, defect: {kind: dent}}",
     "scenario 1 (a): defect must be a mapping with kind one of kink, twist"),
    ("scenarios:\n  - {name: a, family: defect, radius_m: 800, speed_kmh: 160, defect: {kind: kink, amplitude_mm: 40}}",
     "scenario 1 (a): defect of kind kink takes amplitude_mm, length_m, at_m"),
    ("scenarios:\n  - {name: a, family: defect, radius_m: 800, speed_kmh: 160,\n"
     "     defect: {kind: kink, amplitude_mm: 400, length_m: 5, at_m: 700}}", "defect amplitude_mm 400 mm is outside"),
    ("scenarios:\n  - {name: a, family: gust, radius_m: 800, speed_kmh: 160, gust: tornado}", "gust 'tornado' is not one"),
    ("scenarios:\n  - {name: a, family: gust, radius_m: 800, speed_kmh: 160, part: validation}",
     "part 'validation' is not one of train, test"),
    ("scenarios:\n  - {name: a, family: gust, radius_m: 800, speed_kmh: 160, vehicle_set: crh3}",
     "scenario 1 (a): vehicle_set 'crh3' is not one of hs19, a380, zhai, hs19-a380yaw"),
])
def test_bad_catalogues_name_the_entry_and_the_key(tmp_path, text, message):
    (tmp_path / "bad.yaml").write_text(text)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")
                       .replace("]", r"\]")):
        catalogue.load(tmp_path / "bad.yaml")


def test_an_entry_runs_its_own_suspension_set(tmp_path):
    """`vehicle_set:` picks the car of the entry's runs (hs19 without it); the demo's node, which runs hs19
    only, refuses it."""
    from railderail_monitor.demo import catalogue_parameters
    from railderail_sim.parameters import vehicle_parameters
    (tmp_path / "sets.yaml").write_text(
        "scenarios:\n  - {name: a, family: ordinary, radius_m: 7000, cant_mm: 150, speed_kmh: 300, seeds: [1],"
        " vehicle_set: hs19-a380yaw}\n  - {name: b, family: ordinary, radius_m: 7000, cant_mm: 150, speed_kmh: 300,"
        " seeds: [2]}")
    a, b = catalogue.load(tmp_path / "sets.yaml")
    assert a.scenario(1).vehicle == vehicle_parameters("hs19-a380yaw")
    assert b.scenario(2).vehicle == vehicle_parameters("hs19")
    assert a.key(1)["vehicle_set"] != b.key(2)["vehicle_set"]
    with pytest.raises(ValueError, match="runs the suspension set hs19-a380yaw, which the simulator node"):
        catalogue_parameters(tmp_path / "sets.yaml", "a")


def test_the_line_speed_catalogue_is_ordinary_running_of_the_stable_set_at_250_to_300_km_h():
    """railderail_monitor/config/catalogue-line-speed.yaml (docs/report/hs19-a380yaw.md): loads (every run
    within the permitted cant deficiency) and is ordinary running of hs19-a380yaw at line speed."""
    entries = catalogue.load(Path(catalogue.SHIPPED).with_name("catalogue-line-speed.yaml"))
    assert {(e.family, e.vehicle_set) for e in entries} == {("ordinary", "hs19-a380yaw")}
    assert all(250.0 <= e.speed_kmh <= 300.0 for e in entries)


def test_the_shipped_catalogue_is_large_enough_to_mean_something():
    """Over 2000 km of ordinary running; every hazard family in both parts with at least 10 runs; at least
    10 runs expected to derail by each of the four mechanisms (known from the entries' families, without
    simulating), each mechanism's expected derailments in both parts; and the parts share no scenario and no
    random track (every entry on random track with seeds of its own)."""
    entries = catalogue.load()
    assert len({e.name for e in entries}) == len(entries)
    runs = [(e, seed) for e in entries for seed in e.seeds]
    ordinary_km = sum(e.scenario(seed).track.line_length for e, seed in runs if e.family == "ordinary") / 1000.0
    assert ordinary_km >= 2000.0
    # ordinary running at line speed, by the car stable there (issue 41), in both parts
    line_speed = [(e, seed) for e, seed in runs if e.family == "ordinary" and e.speed_kmh >= 250.0]
    assert {e.vehicle_set for e, _ in line_speed} == {"hs19-a380yaw"}
    assert {e.part_of(seed) for e, seed in line_speed} == {"train", "test"}
    families = {e.family for e in entries} - {"ordinary"}
    assert len(families) >= 4
    for f in families | {"ordinary"}:
        mine = [(e, seed) for e, seed in runs if e.family == f]
        assert len(mine) >= 10, f
        assert {e.part_of(seed) for e, seed in mine} == {"train", "test"}, f
    expected = {}
    for e, seed in runs:
        if e.expect_derailment:
            expected.setdefault(e.mechanism, []).append(e.part_of(seed))
    assert set(expected) == {"over-speed unloading", "flange climb at a defect", "gust overturning", "fault-driven"}
    for mechanism, parts in expected.items():
        assert len(parts) >= 10 and set(parts) == {"train", "test"}, (mechanism, parts)
    samples = [sample for e in entries for sample in e.track_samples()]
    assert len(samples) == len(set(samples))
    assert not {e.name for e in entries if e.part == "train"} & {e.name for e in entries if e.part == "test"}
    assert {e.track for e in entries if e.family == "ordinary"} == {"rigid", "elastic"}
    assert min(e.friction for e in entries) <= 0.2 and max(e.friction for e in entries) >= 0.6
    for e, seed in runs:
        e.scenario(seed)


@pytest.mark.parametrize("text, message", [
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000, speed_kmh: 300, irregularity: erri-low, seeds: [1]}\n"
     "  - {name: b, family: overspeed, radius_m: 800, speed_kmh: 250, irregularity: erri-low, seeds: [1]}",
     "seed 1 of a random track is used by both a and b"),
    ("scenarios:\n  - {name: a, family: defect, radius_m: 800, speed_kmh: 160, defect: {kind: kink, amplitude_mm: 40, "
     "length_m: 5, at_m: 700}}\n  - {name: b, family: defect, radius_m: 800, speed_kmh: 150, defect: {kind: kink, "
     "amplitude_mm: 40, length_m: 5, at_m: 700}}", "b \\(test\\) and a \\(train\\) share a defect"),
    ("scenarios:\n  - {name: a, family: overspeed, radius_m: 1000, speed_kmh: 300}\n"
     "  - {name: b, family: overspeed, radius_m: 1000, speed_kmh: 300, seeds: [4]}", "share a run"),
])
def test_a_catalogue_whose_parts_share_a_track_is_refused(tmp_path, text, message):
    (tmp_path / "bad.yaml").write_text(text)
    with pytest.raises(ValueError, match=message):
        catalogue.load(tmp_path / "bad.yaml")


def _synthetic_run(name, part, km, warned_at, false_at):
    """A run's scored result without a simulation: one derailment at 180 km/h on straight track (its cure 10 %
    off, 7.5 s of lead), warned 12 s ahead by every criterion at thresholds up to `warned_at`, and at each
    threshold `false_at(criterion, threshold)` false-alarm episodes over `km` of normal running."""
    rules = HazardRules()
    line = dict(radius_m=math.inf, cant_m=0.0, rail_spacing_m=1.5, class_speed_kmh=math.inf, gust_m_s=0.0,
                defect=False, hunting=False, faults=[], critical_speed_kmh=math.nan)
    hazard = dict(kind="derailment", margin="wheel_unloading", time_s=100.0, end_s=100.0, speed_m_s=50.0,
                  position_m=5000.0, places=[[0, 1]])
    criteria = {c: [dict(threshold=thr, warnings=[(12.0, 50.0) if thr <= warned_at(c) else None],
                         false_episodes=false_at(c, thr), false_time_s=0.0, false_km=0.0, window_false_episodes=0)
                    for thr in sweeps.thresholds(c)] for c in sweeps.CRITERIA}
    return dict(scenario=name, family="overspeed", part=part, line=line, hazards=[hazard],
                windows={str(rules.window_s): dict(normal_km=km, normal_h=km / 180.0, beyond_km=0.0,
                                                   criteria=criteria)})


def test_a_recommendation_keeps_its_real_budgets_on_runs_it_was_not_chosen_on(tmp_path):
    """With the real budgets (10 and 3 per 1000 km) and enough running to resolve them (1400 km a part):
    Q/P's mean warns every derailment at 0.8 and below and alarms falsely only below 0.6 on both parts, so its
    WARNING level is chosen on the train part and kept on the test part; the wheel unloading is clean at 0.7 on
    the train part only, so its level is chosen there and refused by the test part. The recommended file,
    read back, is scored again on the test part's runs alone: every enabled level keeps its budget and warns
    at least the minimum share usefully."""
    from railderail_monitor.warning.limits import critical_name, read_limits
    from railderail_monitor.warning.monitor_params import limits_of_car, parameter_file

    def false_at(part):
        def count(criterion, thr):
            if criterion == "wheel_unloading" and part == "test" and thr >= 0.7:
                return 12                                    # the test part's own false alarms at 0.7
            return 0 if thr >= 0.6 or criterion != "derailment_coefficient_mean" else 40
        return count
    warned = lambda c: 0.8 if c == "derailment_coefficient_mean" else 0.7 if c == "wheel_unloading" else -1.0
    runs = [_synthetic_run(f"{part}-{k}", part, 140.0, warned, false_at(part)) for part in ("train", "test")
            for k in range(10)]
    rules = HazardRules()
    rows = {(r["criterion"], r["level"]): r for r in recommendation.recommend(runs, rules)}
    assert rows["derailment_coefficient_mean", "warning"]["threshold"] == 0.8
    assert rows["wheel_unloading", "warning"]["threshold"] is None
    assert "on the test part reach" in rows["wheel_unloading", "warning"]["reason"]
    limits, disabled = recommendation.recommended_limits(dict(recommended=list(rows.values())))
    (tmp_path / "recommended.yaml").write_text(parameter_file(limits, limits_of_car()[1], "a test"))
    limits = read_limits(tmp_path / "recommended.yaml")
    test = [r for r in runs if r["part"] == "test"]
    rescored = tables.summarize(test, rules.window_s, rules)
    enabled = 0
    for row in (r for r in rows.values() if r["signals"] == "ground_truth"):
        level = getattr(limits, row["criterion"] if row["level"] == "warning" else critical_name(row["criterion"]))
        if math.isnan(level):
            continue
        enabled += 1
        again = next(r for r in rescored if r["criterion"] == row["criterion"] and r["threshold"] == level)
        assert again["false_alarms_per_1000_km_ci95"][1] <= recommendation.BUDGETS[row["level"]], row
        assert again["usefully_warned"] >= recommendation.MIN_USEFUL_SHARE * again["derailments"], row
    assert enabled >= 1


def test_dask_and_local_processes_give_the_same_evaluation(small):
    """Every run simulated again on a Dask worker (its own empty cache): the same JSON but the throughput."""
    from dask.distributed import LocalCluster
    folder, entries, result = small
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = wc.evaluate(entries, scheduler=cluster.scheduler_address, progress=False, budgets=GENEROUS,
                             min_share=0.0, cache=folder / "dask-cache")
    assert len([p for p in (folder / "dask-cache").rglob("*.json") if "survey" not in p.parts]) == 6
    for r in (remote, result):
        r.pop("throughput")
    assert json.dumps(remote, sort_keys=True, default=str) == json.dumps(result, sort_keys=True, default=str)


def test_the_recommended_file_keeps_its_budgets_when_read_back_and_scored_again(small, tmp_path):
    """Each level of monitor-recommended.yaml, scored again on the test part, keeps its budget (the upper 95 %
    bound of its false alarms) and its share of derailments usefully warned; a level without a recommendation
    is disabled; a criterion's CRITICAL level lies above its WARNING level."""
    from railderail_monitor.warning.limits import critical_name
    from railderail_monitor.warning.limits import read_limits
    _, _, result = small
    wc.write(result, tmp_path)
    assert (tmp_path / "warnings-catalogue.png").stat().st_size > 10_000
    assert "### Recommended levels" in (tmp_path / "warnings-catalogue.md").read_text()
    limits = read_limits(tmp_path / "monitor-recommended.yaml")
    rules = HazardRules()
    test = [r for r in _raw(small) if r["part"] == "test"]
    rescored = tables.summarize(test, rules.window_s, rules)
    enabled = 0
    assert {r["criterion"] for r in result["recommended"] if r["signals"] == "measured"} == set(measured.CRITERIA)
    for row in (r for r in result["recommended"] if r["signals"] == "ground_truth"):
        name = row["criterion"] if row["level"] == "warning" else critical_name(row["criterion"])
        level = getattr(limits, name)
        if row["threshold"] is None:
            assert math.isnan(level) and row["reason"]
            continue
        enabled += 1
        again = next(r for r in rescored if r["criterion"] == row["criterion"] and r["threshold"] == level)
        assert again["false_alarms_per_1000_km_ci95"][1] <= GENEROUS[row["level"]]
        assert again["usefully_warned"] >= result["min_useful_share"] * again["derailments"]
    assert enabled > 0
    for criterion in sweeps.THRESHOLDS:
        warn, crit = getattr(limits, criterion), getattr(limits, critical_name(criterion))
        assert not (math.isfinite(warn) and math.isfinite(crit)) or warn < crit


def test_no_level_is_recommended_where_the_exposure_cannot_resolve_its_budget(small):
    _, _, result = small
    rows = recommendation.recommend(_raw(small), HazardRules(), {"warning": 10.0, "critical": 3.0})
    assert all(r["threshold"] is None and "cannot resolve" in r["reason"] for r in rows)


@pytest.mark.skipif(not SHIPPED_RESULT.exists(), reason="the shipped evaluation is made by railderail warnings "
                    "--catalogue --out docs/report")
def test_the_shipped_results_false_alarms_cannot_fall_as_a_threshold_falls():
    """On the shipped evaluation: for every criterion, a lower threshold has at least the false-alarm episodes,
    the time in alarm and the derailments usefully warned of a higher one; every recommended level keeps its
    budget on the test part; each part's normal running can resolve both budgets (issue 39), so that no level
    is left out for want of exposure."""
    from railderail_monitor.evaluation.scoring import resolvable_km
    result = json.loads(SHIPPED_RESULT.read_text())
    exposure, budgets = result["exposure"], result["budgets_per_1000_km"]
    assert min(exposure["train_km"], exposure["test_km"]) >= max(resolvable_km(b) for b in budgets.values())
    assert not any("cannot resolve" in row["reason"] for row in result["recommended"] if row["threshold"] is None)
    for criterion in dict.fromkeys(r["criterion"] for r in result["criteria"]):      # the measured ones too
        rows = sorted((r for r in result["criteria"] if r["criterion"] == criterion), key=lambda r: r["threshold"])
        assert len(rows) >= 2
        for low, high in zip(rows, rows[1:]):
            assert low["false_alarm_episodes"] >= high["false_alarm_episodes"], (criterion, low["threshold"])
            assert low["time_in_alarm_share"] >= high["time_in_alarm_share"], (criterion, low["threshold"])
            assert low["usefully_warned"] >= high["usefully_warned"], (criterion, low["threshold"])
    for row in result["recommended"]:
        if row["threshold"] is not None:
            assert row["test"]["false_alarms_per_1000_km_ci95"][1] <= row["budget_per_1000_km"]


@pytest.mark.skipif(not SHIPPED_RESULT.exists(), reason="the shipped evaluation is made by railderail warnings "
                    "--catalogue --out docs/report")
def test_the_shipped_recommendation_holds_on_the_runs_it_was_not_chosen_on():
    """The shipped monitor-recommended.yaml judged on the test part's scores (runs it was not chosen on) with
    the real budgets: its levels are the evaluation's recommended rows; an enabled level keeps its budget and
    usefully warns the minimum share there; a disabled one is disabled on the held-out runs too: no threshold
    of the test part both keeps that level's budget and usefully warns the minimum share (else the two parts
    disagree and the catalogue is too small to choose on)."""
    from railderail_monitor.warning.limits import critical_name, read_limits
    result = json.loads(SHIPPED_RESULT.read_text())
    assert result["budgets_per_1000_km"] == recommendation.BUDGETS
    assert result["min_useful_share"] == recommendation.MIN_USEFUL_SHARE
    limits = read_limits(SHIPPED_RESULT.parent / "monitor-recommended.yaml")
    share = result["min_useful_share"]
    for row in result["recommended"]:
        budget = result["budgets_per_1000_km"][row["level"]]
        held_out = [r for r in result["criteria"] if r["criterion"] == row["criterion"]]
        keeps = [r for r in held_out if r["false_alarms_per_1000_km_ci95"][1] <= budget
                 and r["derailments"] and r["usefully_warned"] >= share * r["derailments"]]
        if row["signals"] == "ground_truth":
            level = getattr(limits, row["criterion"] if row["level"] == "warning" else critical_name(row["criterion"]))
            assert (math.isnan(level) if row["threshold"] is None else level == row["threshold"]), row
        if row["threshold"] is None:
            assert not keeps, (row["criterion"], row["level"], [r["threshold"] for r in keeps])
        else:
            assert row["threshold"] in [r["threshold"] for r in keeps], row


@pytest.mark.parametrize("name", ["line-r1000-erri-low-160", "staircase-r1000-erri-low", "line-r7000-wind-15-210",
                                  "line-r2000-air-spring-deflated-160"])
def test_a_catalogue_scenario_becomes_the_simulator_node_s_parameters(name):
    """`railderail demo --catalogue --scenario NAME`: the node's parameters of a scenario pass the node's own
    checks and build the scenario the evaluation runs (its track, speeds, rails, wind and faults)."""
    import numpy as np
    from railderail_monitor.demo import catalogue_parameters
    from railderail_sim.ros.node import PARAMETERS, build_scenario
    table = {spec.name: spec for spec in PARAMETERS}
    given = catalogue_parameters(None, name)
    p = {spec.name: spec.default for spec in PARAMETERS}
    p.update({k: table[k].checked(v) for k, v in given.items()})
    node = build_scenario(p)
    (entry,) = [e for e in catalogue.load() if e.name == name]
    ours = entry.scenario(entry.seeds[0])
    assert node.track == ours.track and np.array_equal(node.speed_table, ours.speed_table)
    assert (node.wind, node.faults, node.track_model) == (ours.wind, ours.faults, ours.track_model)
    assert node.contact.friction_coefficient == ours.contact.friction_coefficient
    assert (node.irregularity is None) == (ours.irregularity is None)
    if ours.irregularity is not None:
        assert np.array_equal(node.irregularity.pack(), ours.irregularity.pack())


def test_the_demo_refuses_what_the_node_cannot_run():
    from railderail_monitor.demo import catalogue_parameters
    with pytest.raises(ValueError, match="--scenario 'nothing' is not in the catalogue"):
        catalogue_parameters(None, "nothing")
    with pytest.raises(ValueError, match="straight track, which the simulator node does not model"):
        catalogue_parameters(None, "line-straight-china-hsr-210")
    with pytest.raises(ValueError, match="a track defect or a longer approach"):
        catalogue_parameters(None, "kink-35mm-5m")
    with pytest.raises(ValueError, match="--seed 9 is not one of the scenario's seeds"):
        catalogue_parameters(None, "line-r1000-erri-low-160", 9)


def test_a_catalogue_without_a_derailment_is_still_reported(small):
    """Ordinary running only (from the cache): the report says what there is."""
    from railderail_monitor.evaluation.report import markdown
    folder, entries, _ = small
    result = wc.evaluate([e for e in entries if e.name.startswith("ordinary")], cache=folder / "cache", workers=1,
                         progress=False)
    text = markdown(result)
    assert "2 runs of 2 scenarios over 8 km: 0 derailed" in text
    assert "At 0.06 rad (Yu 2022) it usefully warned 0 of 0 derailments" in text
