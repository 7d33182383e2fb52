"""The warning evaluation over a scenario catalogue: the catalogue's checks, the mechanisms, lead times and
false alarms of a small one (a kink that makes the outer wheel climb, an over-speed rollover, ordinary
running on irregular track), the cache."""
import json
import math
import shutil
from pathlib import Path

import pytest

from railderail_monitor import catalogue, warning_catalogue as wc

CONFIG = Path(catalogue.__file__).parent / "config"
SMALL = """
scenarios:
  - {name: overspeed, radius_m: 1000, speed_kmh: 300}
  - {name: kink, radius_m: 800, speed_kmh: 160, friction: 0.5, irregularity: kink-50mm-5m.csv}
  - {name: ordinary, radius_m: 1000, speed_kmh: 200, irregularity: erri-high, line_length_m: 4000, seeds: [1]}
"""


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    folder = tmp_path_factory.mktemp("catalogue")
    (folder / "small.yaml").write_text(SMALL)
    shutil.copy(CONFIG / "kink-50mm-5m.csv", folder)
    entries = catalogue.load(folder / "small.yaml")
    result = wc.evaluate(entries, cache=folder / "cache", workers=2, progress=False)
    return folder, entries, result


def test_each_run_derails_the_way_its_scenario_should(small):
    _, _, result = small
    runs = {r["scenario"]: r for r in result["runs"]}
    assert (runs["overspeed"]["derailed"], runs["overspeed"]["mechanism"]) == (True, "wheel_unloading")
    assert (runs["kink"]["derailed"], runs["kink"]["mechanism"]) == (True, "flange_climbing")
    assert not runs["ordinary"]["derailed"] and runs["ordinary"]["distance_km"] == pytest.approx(4.0, rel=1e-6)
    # the rollover is announced by the unloading seconds ahead, the climb by the lift only just before it
    assert runs["overspeed"]["first_alerts"]["wheel_unloading"]["lead_s"] > 1.0
    assert 0.0 <= runs["kink"]["first_alerts"]["wheel_lift"]["lead_s"] < 0.2
    assert "wheel_unloading" not in runs["kink"]["first_alerts"]


def test_the_criteria_table_counts_warnings_and_false_alarms_per_km(small):
    _, _, result = small
    rows = {(r["criterion"], r["threshold"]): r for r in result["criteria"]}
    lift = rows[("wheel_lift", 0.002)]
    assert (lift["derailments"], lift["derailments_warned"]) == (2, 2)
    assert lift["warned_by_mechanism"] == {"flange_climbing": 1, "wheel_unloading": 1}
    unloading = rows[("wheel_unloading", 0.6)]
    assert unloading["warned_by_mechanism"] == {"wheel_unloading": 1}
    # the ordinary run's alerts over its 4 km, per 1000 km
    assert unloading["false_alarm_runs"] == 1
    assert unloading["false_alarms_per_1000_km"] == pytest.approx(
        1000.0 * wc.first_alert(_raw(small, "ordinary"), "wheel_unloading", 0.6)["alerts"] / 4.0, rel=1e-6)
    assert unloading["false_alarms_per_1000_km"] > 0.0
    # a higher threshold never warns more nor alarms more
    for criterion in wc.THRESHOLDS:
        ordered = sorted((r for r in result["criteria"] if r["criterion"] == criterion), key=lambda r: r["threshold"])
        assert all(a["derailments_warned"] >= b["derailments_warned"] for a, b in zip(ordered, ordered[1:]))
    for rec in result["recommended"]:
        assert rec["false_alarms_per_1000_km"] <= result["false_alarm_budget_per_1000_km"]


def _raw(small, name):
    folder, entries, _ = small
    (entry,) = [e for e in entries if e.name == name]
    return wc.run_one((entry, entry.seeds[0]), cache=folder / "cache")


def test_a_second_evaluation_reads_every_run_from_the_cache(small, monkeypatch):
    folder, entries, result = small
    assert len(list((folder / "cache").rglob("*.json"))) == 3

    def no_simulation(*args, **kwargs):
        raise AssertionError("a cached run was simulated again")
    monkeypatch.setattr("railderail_sim.vehicle.simulate.Simulation", no_simulation)
    again = wc.evaluate(entries, cache=folder / "cache", workers=1, progress=False)
    assert json.dumps(again, sort_keys=True, default=str) == json.dumps(result, sort_keys=True, default=str)


@pytest.mark.parametrize("text, message", [
    ("scenarios: []", "a non-empty list `scenarios:`"),
    ("scenarios:\n  - {name: a, radius_m: 1000, speed_kmh: 300, sped: 1}", "scenario 1 (a): unknown key(s) sped"),
    ("scenarios:\n  - {name: a, speed_kmh: 300}", "scenario 1 (a): radius_m is missing"),
    ("scenarios:\n  - {name: a, radius_m: 90, speed_kmh: 300}", "scenario 1 (a): radius_m 90 m is outside"),
    ("scenarios:\n  - {name: a, radius_m: 1000}", "give either speed_kmh"),
    ("scenarios:\n  - {name: a, radius_m: 1000, speed_kmh: 300, seeds: [1, 1]}", "repeat a seed"),
    ("scenarios:\n  - {name: a, radius_m: 1000, speed_kmh: fast}", "speed_kmh 'fast' is not a number"),
    ("scenarios:\n  - {name: a, radius_m: 1000, speed_kmh: 300, irregularity: no.csv}", "no.csv does not exist"),
    ("scenarios:\n  - {name: a, radius_m: 1000, speed_kmh: 300, faults: [brakes]}", "faults ['brakes']"),
    ("scenarios:\n  - {name: a, radius_m: 1000, speed_kmh: 300}\n  - {name: a, radius_m: 800, speed_kmh: 250}",
     "scenario name(s) a used more than once"),
])
def test_bad_catalogues_name_the_entry_and_the_key(tmp_path, text, message):
    (tmp_path / "bad.yaml").write_text(text)
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")
                       .replace("]", r"\]")):
        catalogue.load(tmp_path / "bad.yaml")


def test_the_shipped_catalogue_loads_and_builds_every_scenario():
    entries = catalogue.load()
    assert len({e.name for e in entries}) == len(entries) >= 15
    for e in entries:
        for seed in e.seeds:
            e.scenario(seed)
    defects = {e.name for e in entries if e.irregularity.endswith(".csv")}
    assert defects == {"kink-r800", "twist-r150", "twist-r150-friction-0.4"}


def test_dask_and_local_processes_give_the_same_evaluation(small):
    from dask.distributed import LocalCluster
    _, entries, result = small
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = wc.evaluate(entries, scheduler=cluster.scheduler_address, progress=False)
    assert json.dumps(remote, sort_keys=True, default=str) == json.dumps(result, sort_keys=True, default=str)


def test_the_recommended_thresholds_become_a_parameter_file_the_monitor_reads(small, tmp_path):
    from railderail_monitor.criteria import critical_name, default_limits
    from railderail_monitor.monitor_params import read_limits
    _, _, result = small
    wc.write(result, tmp_path)
    assert (tmp_path / "warnings-catalogue.png").stat().st_size > 10_000
    limits = read_limits(tmp_path / "monitor-recommended.yaml")
    chosen = {row["criterion"]: row["threshold"] for row in result["recommended"]}
    assert chosen
    for criterion in wc.THRESHOLDS:
        level = getattr(limits, criterion)
        assert level == chosen[criterion] if criterion in chosen else math.isnan(level)
        if criterion in chosen and chosen[criterion] < getattr(default_limits(), critical_name(criterion)):
            assert getattr(limits, critical_name(criterion)) == getattr(default_limits(), critical_name(criterion))


@pytest.mark.parametrize("name", ["kink-r800", "line-r7000-erri-low", "overspeed-r1000-primary-spring-broken",
                                  "overspeed-r1000-wind-15"])
def test_a_catalogue_scenario_becomes_the_simulator_node_s_parameters(name):
    """`railderail demo --catalogue --scenario NAME`: the node's parameters of a scenario pass the node's own
    checks and build the scenario the evaluation runs (its track, speeds, rails, wind and faults)."""
    import numpy as np
    from railderail_monitor.demo import catalogue_parameters
    from railderail_sim.node import PARAMETERS, build_scenario
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
        catalogue_parameters(None, "line-straight-china-hsr")
    with pytest.raises(ValueError, match="--seed 9 is not one of the scenario's seeds"):
        catalogue_parameters(None, "overspeed-r1000-erri-high", 9)


def test_a_catalogue_without_a_derailment_is_still_reported(small):
    """Ordinary running only (the small catalogue's run, from the cache): the report's findings say what
    there is, with no derailment to take peaks or leads from."""
    folder, entries, _ = small
    result = wc.evaluate([e for e in entries if e.name == "ordinary"], cache=folder / "cache", workers=1,
                         progress=False)
    text = wc.markdown(result)
    assert "1 runs of 1 scenarios: 0 derailed" in text
    assert "it warned 0 of 0 derailments" in text
