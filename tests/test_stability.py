"""The limit-cycle methods (bisection, ramp-down, the bifurcation branches), the kick shapes, the stability
study's cases and the hs19-a380yaw set's parameter table."""
import json

import numpy as np
import pytest

from railderail_sim.cli import main
from railderail_sim.methods import limit_cycle as lc
from railderail_sim.methods import stability
from railderail_sim.parameters import VEHICLE_SETS, vehicle_parameters
from railderail_sim.track.irregularity import lateral_kink
from railderail_sim.vehicle.simulate import KMH, Scenario


def test_s_kink_is_two_opposite_smooth_periods():
    k = lateral_kink(10.0, 20.0, 0.004, periods=2)
    s, left = k.s, k.values[:, 0]
    assert s[0] == 10.0 and s[-1] == 50.0
    assert left[s < 30.0].max() == pytest.approx(0.004) and left[s > 30.0].min() == pytest.approx(-0.004)
    assert np.all(k.values[:, 0] == k.values[:, 2])                  # both rails move together
    # C1: the slope is continuous through the sign change and zero at both ends
    assert np.max(np.abs(k.slopes[[0, -1], 0])) < 1e-12
    mid = np.argmin(np.abs(s - 30.0))
    assert abs(k.slopes[mid, 0]) < 1e-12 and abs(left[mid]) < 1e-12
    with pytest.raises(ValueError, match="periods"):
        lateral_kink(10.0, 20.0, 0.004, periods=3)


def test_descent_table_holds_each_speed_and_decelerates_between():
    table, holds = lc.descent_table([300.0, 250.0], hold_m=400.0, deceleration=0.5)
    assert holds[0].tolist() == [0.0, 400.0]
    change = ((300 * KMH) ** 2 - (250 * KMH) ** 2) / (2 * 0.5)
    assert holds[1] == pytest.approx([400.0 + change, 800.0 + change])
    assert np.interp(200.0, table[:, 0], table[:, 1]) == pytest.approx(300 * KMH)
    assert np.interp(holds[1, 0] + 1.0, table[:, 0], table[:, 1]) == pytest.approx(250 * KMH)
    with pytest.raises(ValueError, match="decrease"):
        lc.descent_table([250.0, 300.0])


def test_small_kick_dies_below_the_linear_critical_speed():
    """The upward branch's perturbation decays at 250 km/h, far below the linear critical speed (about 400)."""
    a = lc.final_amplitude(Scenario(), 250.0, amplitude=lc.SMALL_KICK_M)
    assert a < 0.01 * lc.SMALL_KICK_M


def test_ramp_down_json_and_the_downward_branch_below_the_upward(capsys):
    """One descent 300 -> 250 km/h after a 10 mm kink: the limit cycle holds at 300, where the small kick of the
    upward branch dies, so the subcritical branch reaches below the upward one, and the JSON carries both (the
    critical speed is a speed of the descent: the lowest step if the limit cycle held there too)."""
    assert main(["limit-cycle", "--method", "ramp-down", "--from-kmh", "250", "--to-kmh", "300", "--step-kmh", "50",
                 "--tolerance-kmh", "25", "--json"]) in (0, None)
    d = json.loads(capsys.readouterr().out)
    assert d["method"] == "ramp-down" and d["kick"] == dict(amplitude_m=0.01, length_m=20.0, shape="kink")
    up = {p["speed_kmh"]: p["amplitude_m"] for p in d["bifurcation"]["upward"]["points"]}
    down = {p["speed_kmh"]: p["amplitude_m"] for p in d["bifurcation"]["downward"]["points"]}
    assert set(up) == {250.0, 300.0} and {250.0, 300.0} <= set(down)
    assert down[300.0] > 1e-3 > lc.THRESHOLD_M > up[300.0]             # flange-contact limit cycle vs decay
    assert d["nonlinear_critical_speed_kmh"] in down
    onset = min((v for v, a in up.items() if a > lc.THRESHOLD_M), default=np.inf)
    assert d["nonlinear_critical_speed_kmh"] <= onset


def test_limit_cycle_rejects_unknown_method_and_shape():
    with pytest.raises(ValueError, match="method"):
        lc.limit_cycle(Scenario(), [200.0, 250.0], method="continuation")
    with pytest.raises(ValueError, match="shape"):
        lc.limit_cycle(Scenario(), [200.0, 250.0], shape="step")


def test_every_study_case_is_a_valid_change():
    for name, value, vehicle, contact, source, sure in stability.cases():
        sc = stability._scenario(vehicle=vehicle, contact=contact)
        assert vehicle or contact, name
        for k, v in vehicle.items():
            assert getattr(sc.vehicle, k) == v
        assert sure in ("V", "S", "A", "S/U") and source


def test_hs19_a380yaw_is_hs19_with_the_a380_yaw_damper_sourced():
    assert "hs19-a380yaw" in VEHICLE_SETS
    new, hs19, a380 = (vehicle_parameters(n) for n in ("hs19-a380yaw", "hs19", "a380"))
    rows = {r[0]: r for r in new.describe()}
    changed = {r[0] for r in new.describe()} - {"name"}
    changed = {k for k in changed if not k.endswith("_inertia") and getattr(new, k) != getattr(hs19, k)}
    assert changed == {"yaw_damper_knee_velocity", "yaw_damper_damping", "yaw_damper_damping_after_knee",
                       "yaw_damper_series_stiffness"}
    for k in changed:
        assert getattr(new, k) == getattr(a380, k)
        assert rows[k][3] == "A380" and rows[k][4] == "S"
    assert rows["primary_lateral_stiffness"][3] == "HS19"


def test_study_cache_computes_once_and_returns_the_same_value(tmp_path):
    cache = stability.Cache(str(tmp_path))
    calls = []

    def compute():
        calls.append(1)
        return dict(nonlinear_kmh=float("nan"), points=np.array([1.0, 2.0]))

    first = cache.get(dict(case="x", grid=stability.GRID), compute)
    again = cache.get(dict(case="x", grid=stability.GRID), compute)
    other = cache.get(dict(case="y", grid=stability.GRID), compute)
    assert len(calls) == 2 and first == again == other == dict(nonlinear_kmh=None, points=[1.0, 2.0])


def test_the_report_of_another_set_runs_that_set_and_puts_the_other_whole_sets_beside_it():
    """`railderail report --vehicle-set`: the sensitivity starts from the report's set, the whole public sets
    beside it are the others; the derailment process runs its car."""
    from railderail_sim.methods import report
    for name in ("hs19", "hs19-a380yaw"):
        variants = report.sensitivity_variants(name)
        assert variants[0] == (f"reference ({name}, LM, Hertz, mu 0.3)", dict(vehicle_set=name))
        whole = [c["vehicle_set"] for _, c in variants if c["vehicle_set"] != name]
        assert whole == [s for s in report.SUSPENSION_SETS if s != name]
        assert all(set(c) <= {"vehicle_set", "vehicle", "contact"} for _, c in variants)
    assert [label for label, _ in report.sensitivity_variants("hs19")][6:8] == ["suspension set a380",
                                                                                "suspension set zhai"]
    assert [(c.radius_m, c.vehicle_set) for c in report.headline_cases(False, "hs19-a380yaw")] == \
        [(r, "hs19-a380yaw") for r in (800.0, 1000.0, 1200.0, 1400.0, 1600.0, 1800.0)]
    car = vehicle_parameters("hs19-a380yaw")
    (run,) = report.process_runs([dict(radius_m=1000.0, refined_speed_kmh=200.0)], car).values()
    assert run.scenario.vehicle == car and run.speed[0] * 3.6 == pytest.approx(200.0)


def test_the_report_says_none_where_a_method_found_no_critical_speed():
    from railderail_sim.methods import report
    assert report._critical(float("nan"), "none: stable to 600 km/h") == "none: stable to 600 km/h"
    assert report._critical(403.2, "none") == "403 km/h"
    assert report._below(float("nan"), float("nan"), 500.0, 600.0) == "No limit cycle after the kink up to 500 km/h."
    assert "420 km/h; the centred running stays damped to 600 km/h" in report._below(420.0, float("nan"), 500.0,
                                                                                     600.0)
    assert report._below(234.0, 403.0, 500.0, 600.0).startswith("Nonlinear below linear: yes (234 <= 403 km/h)")
    assert report._pct(float("nan"), 380.0) == "-"
