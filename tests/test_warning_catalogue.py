"""The warning evaluation over a scenario catalogue: the catalogue's checks, a small one evaluated (an over-speed
rollover, a kink that makes the outer wheel climb, ordinary running on irregular track; two seeds each, one
per part), attribution at the derailed wheel, the split, the cache, Dask, the recommended parameter file read
back and re-scored, and the shipped results' properties."""
import json
import math
from pathlib import Path

import pytest

from railderail_monitor.evaluation import catalogue, over_catalogue as wc
from railderail_monitor.evaluation.hazards import HazardRules
from railderail_monitor.onboard import measured

ROOT = Path(__file__).resolve().parents[1]
SHIPPED_RESULT = ROOT / "docs" / "report" / "warnings-catalogue.json"
SMALL = """
scenarios:
  - {name: overspeed, family: overspeed, radius_m: 1000, speed_kmh: 300, seeds: [1, 2]}
  - {name: kink, family: defect, radius_m: 800, speed_kmh: 160, friction: 0.5, seeds: [1, 2],
     defect: {kind: kink, amplitude_mm: 50, length_m: 5, at_m: 700}}
  - {name: ordinary, family: ordinary, radius_m: 1000, speed_kmh: 160, irregularity: erri-high, line_length_m: 4000,
     seeds: [1, 2]}
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
    return [wc.run_one(item, cache=folder / "cache") for e in entries for item in e.runs()]


def test_each_run_shows_the_hazard_its_scenario_should(small):
    _, _, result = small
    runs = {(r["scenario"], r["seed"]): r for r in result["runs"]}
    for seed in (1, 2):
        assert (runs["overspeed", seed]["hazard"], runs["overspeed", seed]["mechanism"]) == ("derailment",
                                                                                             "wheel_unloading")
        kink = runs["kink", seed]
        assert (kink["hazard"], kink["mechanism"]) == ("derailment", "flange_climbing")
        assert (kink["derailment"]["wheelset"], kink["derailment"]["wheel_side"]) == (0, "right")   # the outer wheel
        assert runs["ordinary", seed]["km"] == pytest.approx(4.0, abs=1e-3)      # to the sample past the end
    # split by seed: odd train, even test
    assert {r["part"] for r in result["runs"] if r["seed"] == 1} == {"train"}
    assert {r["part"] for r in result["runs"] if r["seed"] == 2} == {"test"}
    assert result["split"]["train"] == result["split"]["test"] == ["kink", "ordinary", "overspeed"]


def test_a_rollover_is_warned_by_the_unloading_seconds_ahead_but_not_usefully(small):
    _, _, result = small
    over = next(r for r in result["runs"] if r["scenario"] == "overspeed")
    first = over["first_true_alert"]["wheel_unloading"]
    assert 1.0 < first["lead_s"] < 5.0 and not first["useful"]      # 300 km/h needs 12.3 s to brake 10 %
    assert over["first_true_alert"]["attack_angle"] is None


def test_only_alarms_at_the_derailed_wheel_s_running_gear_and_side_warn_the_climb(small):
    """The kink's left wheels flange and lift too; only the right side of the front bogie counts."""
    rules = HazardRules()
    for run in (r for r in _raw(small) if r["scenario"] == "kink"):
        (derailment,) = [h for h in run["hazards"] if h["kind"] == "derailment"]
        assert derailment["places"] == [[0, 1]]
        for row in run["windows"][str(rules.window_s)]["criteria"]["wheel_lift"]:
            for h, w in zip(run["hazards"], row["warnings"]):
                assert w is None or 0.0 <= w[0] <= rules.window_s


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
        lo, hi = row["false_alarms_per_1000_km_ci95"]
        assert lo <= row["false_alarms_per_1000_km"] <= hi
        assert row["signals"] == ("measured" if row["criterion"] in measured.CRITERIA else "ground_truth")
    assert {r["criterion"] for r in result["criteria"] if r["signals"] == "measured"} == set(measured.CRITERIA)


def test_a_second_evaluation_reads_every_run_from_the_cache(small, monkeypatch):
    """In this process (whatever the pool's start method): no run is simulated again."""
    folder, entries, result = small
    assert len(list((folder / "cache").rglob("*.json"))) == 6

    def no_simulation(*args, **kwargs):
        raise AssertionError("a cached run was simulated again")
    monkeypatch.setattr("railderail_sim.vehicle.simulate.run_to_stop", no_simulation)
    assert [r["scenario"] for r in _raw(small)] == ["overspeed"] * 2 + ["kink"] * 2 + ["ordinary"] * 2
    # a cache entry's file written whole: a killed evaluation leaves the others readable
    for path in (folder / "cache").rglob("*.json"):
        json.loads(path.read_text())


def test_a_measured_alarm_holds_from_the_first_row_at_or_after_its_sample_s_stamp():
    import numpy as np
    rows = np.arange(10) * 0.005                        # 200 Hz rows
    stamps = np.array([0.002, 0.012, 0.022, 0.032])      # 100 Hz samples, 2 ms late
    alarm = np.array([False, True, True, False])
    # the sample stamped 0.012 s alarms the rows from 0.015 s, the one at 0.032 s re-arms from 0.035 s
    assert wc.rows_in_alarm(stamps, alarm, rows).tolist() == [False] * 3 + [True] * 4 + [False] * 3


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
    the rows from their stamps, and are true warnings of a hazard at the front bogie (either side) in its
    window and false for one at the rear bogie; the car body's channels (at rest here) never alarm."""
    import numpy as np
    from railderail_sim.parameters import VehicleParameters
    from railderail_sim.sensors.measure import START_UP_S, after
    arrays, signals, sensors = _hunting_front_bogie()
    results = measured.evaluate(after(signals, START_UP_S), VehicleParameters(), wc.shipped_measured_limits(),
                                measured.sample_rates(sensors))
    alarms = wc.measured_alarms(results, arrays["time"], lambda c: [wc.shipped_level(c)])
    peak = alarms["bogie_peak"][wc.shipped_level("bogie_peak")]
    assert peak.shape == (2, len(arrays["time"])) and peak[0].any() and not peak[1].any()
    first = np.flatnonzero(peak[0])[0]
    m, limits = results["bogie_peak"], wc.shipped_measured_limits()
    raised = m.time[m.channel_intervals(None, limits.rearm_fraction, limits.rearm_m)[0][0][0]]   # its alert
    assert arrays["time"][first - 1] < raised <= arrays["time"][first]       # the first row at or after the stamp
    assert not any(a.any() for c in ("car_body_lateral", "car_body_roll_rate")
                   for a in alarms[c].values())

    def hazard(bogie):
        return dict(kind="derailment", margin="wheel_unloading", time_s=20.0, end_s=20.0, speed_m_s=80.0,
                    position_m=1600.0, places=[(bogie, 1)])
    front, rear = (wc.scores(alarms, arrays, [hazard(b)], 20.0) for b in (0, 1))
    # UIC 515-5's count within 500 ms (more than 6 peaks) cannot see a 4 Hz hunting: half-waves 125 ms apart
    assert not any(a.any() for a in alarms["bids_peak_count"].values())
    for rule in ("bogie_rms", "bogie_peak", "bids_peak_count_china"):
        (row,) = front[rule]
        assert row["warnings"][0] is not None and 10.0 < row["warnings"][0][0] <= 12.0, rule
        assert rear[rule][0]["warnings"] == [None]
        assert rear[rule][0]["false_episodes"] > front[rule][0]["false_episodes"] > 0


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
    rows = wc.sensor_sensitivity_run(sensors, sim, arrays, found, rules, (shipped, noisy))
    (calm,), (loud,) = (rows[wc.variant_name(v)]["car_body_lateral"] for v in (shipped, noisy))
    assert calm["false_episodes"] == 0 and calm["warnings"] == [None]
    assert loud["false_episodes"] >= 1 and loud["false_time_s"] > 0.0


def test_measured_criteria_warn_the_rollover_from_the_sensors_alone(small):
    """The roll-balance estimate of the running gear's unloading, on the sensors with their noise, warns the
    over-speed rollover at the derailed side, ahead of it; it has no channel for a wheel's flange climb."""
    _, _, result = small
    for run in (r for r in result["runs"] if r["scenario"] == "overspeed"):
        first = run["first_true_alert"]["estimated_running_gear_unloading"]
        assert first is not None and 0.5 < first["lead_s"] < 10.0
        assert run["peaks"]["estimated_running_gear_unloading"] > 0.9


def test_the_measured_criteria_s_scores_move_with_the_sensors(small):
    """The sensor sensitivity is the test part's measured criteria seen through each sensor variant over the
    same rows: the shipped set's rows are the criteria table's, and without noise or with three times the
    bias some score differs."""
    _, _, result = small
    sens = result["sensor_sensitivity"]
    assert {s["variant"] for s in sens} == {wc.variant_name(v) for v in wc.SENSOR_VARIANTS}
    base = {s["criterion"]: s for s in sens if s["variant"] == wc.variant_name(wc.SENSOR_VARIANTS[0])}
    table = {r["criterion"]: r for r in result["criteria"]
             if r["threshold"] == result["shipped_levels"][r["criterion"]] and r["signals"] == "measured"}
    assert set(base) == set(table) == set(measured.CRITERIA)
    keys = ("derailments", "warned", "usefully_warned", "lead_s_median", "false_alarm_episodes", "time_in_alarm_share")
    for c in base:
        assert [base[c][k] for k in keys] == pytest.approx([table[c][k] for k in keys], nan_ok=True)
    for v in wc.SENSOR_VARIANTS[1:]:
        assert all(s["derailments"] == 2 for s in sens if s["variant"] == wc.variant_name(v))

    def scores(variant):
        return [s[k] for s in sens if s["variant"] == wc.variant_name(variant) for k in keys]
    # the roll-balance estimate reads the air springs' pressures: their bias moves its scores
    biased = dict(noise=1.0, bias=3.0, rate_hz=200.0)
    assert scores(biased) != pytest.approx(scores(wc.SENSOR_VARIANTS[0]), nan_ok=True)


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
])
def test_bad_catalogues_name_the_entry_and_the_key(tmp_path, text, message):
    (tmp_path / "bad.yaml").write_text(text)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")
                       .replace("]", r"\]")):
        catalogue.load(tmp_path / "bad.yaml")


def test_the_shipped_catalogue_is_large_enough_to_mean_something():
    """Over 2000 km of ordinary running; at least four hazard families of at least 10 runs each, every family
    in both parts."""
    entries = catalogue.load()
    assert len({e.name for e in entries}) == len(entries)
    runs = [(e, seed) for e in entries for seed in e.seeds]
    ordinary_km = sum(e.scenario(seed).track.line_length for e, seed in runs if e.family == "ordinary") / 1000.0
    assert ordinary_km >= 2000.0
    families = {e.family for e in entries} - {"ordinary"}
    assert len(families) >= 4
    for f in families | {"ordinary"}:
        mine = [(e, seed) for e, seed in runs if e.family == f]
        assert len(mine) >= 10, f
        assert {e.part_of(seed) for e, seed in mine} == {"train", "test"}, f
    assert {e.track for e in entries if e.family == "ordinary"} == {"rigid", "elastic"}
    assert min(e.friction for e in entries) <= 0.2 and max(e.friction for e in entries) >= 0.6
    for e, seed in runs:
        e.scenario(seed)


def test_dask_and_local_processes_give_the_same_evaluation(small):
    """Every run simulated again on a Dask worker (its own empty cache): the same JSON but the throughput."""
    from dask.distributed import LocalCluster
    folder, entries, result = small
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = wc.evaluate(entries, scheduler=cluster.scheduler_address, progress=False, budgets=GENEROUS,
                             min_share=0.0, cache=folder / "dask-cache")
    assert len(list((folder / "dask-cache").rglob("*.json"))) == 6
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
    rescored = wc.summarize(test, rules.window_s, rules)
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
    for criterion in wc.THRESHOLDS:
        warn, crit = getattr(limits, criterion), getattr(limits, critical_name(criterion))
        assert not (math.isfinite(warn) and math.isfinite(crit)) or warn < crit


def test_no_level_is_recommended_where_the_exposure_cannot_resolve_its_budget(small):
    _, _, result = small
    rows = wc.recommend(_raw(small), HazardRules(), {"warning": 10.0, "critical": 3.0})
    assert all(r["threshold"] is None and "cannot resolve" in r["reason"] for r in rows)


@pytest.mark.skipif(not SHIPPED_RESULT.exists(), reason="the shipped evaluation is made by railderail warnings "
                    "--catalogue --out docs/report")
def test_the_shipped_results_false_alarms_cannot_fall_as_a_threshold_falls():
    """On the shipped evaluation: for every criterion, a lower threshold has at least the false-alarm episodes,
    the time in alarm and the derailments usefully warned of a higher one; every recommended level keeps its
    budget on the test part."""
    result = json.loads(SHIPPED_RESULT.read_text())
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
    result = wc.evaluate([e for e in entries if e.name == "ordinary"], cache=folder / "cache", workers=1,
                         progress=False)
    text = markdown(result)
    assert "2 runs of 1 scenarios over 8 km: 0 derailed" in text
    assert "At 0.06 rad (Yu 2022) it usefully warned 0 of 0 derailments" in text
