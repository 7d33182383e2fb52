"""The derailment criteria (railderail_monitor.criteria): hand-computed cases, no ROS."""
import math
from dataclasses import replace

import numpy as np
import pytest

from railderail_monitor.warning.alarms import Detector, alert_indices, nanoseconds
from railderail_monitor.warning.alerts import lead_times
from railderail_monitor.warning.limits import SEVERITY_WARNING, default_limits
from railderail_monitor.warning.monitor import Monitor, alerts_of_run
from railderail_monitor.warning.quantities import (SlidingMean, front_attack_angle, rail_side, sliding_mean,
                                                   unloading_ratio)


def test_static_wheel_load_carries_the_car():
    """P0 against the dynamics: on straight track at a constant speed the core's eight vertical wheel
    forces, once the start transient has settled, carry the car with P0 each."""
    from railderail_sim.vehicle.simulate import Result, Simulation, scenario

    sim = Simulation(replace(scenario(radius=1000.0, speed_kmh=100.0), output_rate=200.0))
    rows = sim.advance(2.0)                                   # 56 m, all on the first straight
    p = Result(rows=rows, scenario=sim.scenario, status="").arrays()["vertical_force"][100:]
    assert p.mean() == pytest.approx(default_limits().static_wheel_load, rel=1e-6)


def test_unloading_ratio_by_hand():
    p0 = 56064.15
    assert unloading_ratio([p0, 0.0, 0.5 * p0, 0.4 * p0], p0) == pytest.approx([0.0, 1.0, 0.5, 0.6])
    assert unloading_ratio(1.2 * p0, p0) == pytest.approx(-0.2)       # an overloaded wheel
    with pytest.raises(ValueError, match="static wheel load"):
        unloading_ratio([1.0], 0.0)


def test_front_attack_angle_is_the_magnitude_of_wheelset_0():
    a = np.array([[0.01, 0.07, 0.0, 0.0], [-0.065, 0.0, 0.0, 0.0]])
    assert front_attack_angle(a) == pytest.approx([0.01, 0.065])


def test_rail_side():
    assert rail_side("left", 1e-3) == "inner"          # curve to the left: the left rail is inner
    assert rail_side("right", 1e-3) == "outer"
    assert rail_side("left", -1e-3) == "outer"
    assert rail_side("right", -1e-3) == "inner"
    assert rail_side("left", 0.0) == ""                # straight track


def test_default_levels_are_the_documented_ones():
    lim = default_limits()
    assert lim.levels("attack_angle") == [(SEVERITY_WARNING, 0.06)]                 # no critical level
    assert lim.levels("wheel_lift") == [(1, pytest.approx(0.027793 / 3, rel=1e-4)),
                                        (2, pytest.approx(2 * 0.027793 / 3, rel=1e-4))]
    assert lim.levels("derailment_coefficient") == [(1, 0.8), (2, pytest.approx(1.3193, abs=1e-4))]
    assert lim.levels("wheel_unloading") == [(1, 0.60), (2, 0.65)]
    assert lim.debounce_m == 2.0 and lim.rearm_fraction == 0.9 and lim.rearm_m == 50.0


def _limits(**changes):
    return replace(default_limits(), **changes)


def test_limits_validation():
    with pytest.raises(ValueError, match="attack_angle"):
        _limits(attack_angle=-0.06).validated()
    with pytest.raises(ValueError, match="rearm_fraction"):
        _limits(rearm_fraction=1.5).validated()
    with pytest.raises(ValueError, match="debounce_m"):
        _limits(debounce_m=-1.0).validated()
    with pytest.raises(ValueError, match="wheel_lift 0.02 must be below wheel_lift_critical 0.0185"):
        _limits(wheel_lift=0.02).validated()
    assert _limits(wheel_lift_critical=math.nan).levels("wheel_lift") == [(1, pytest.approx(0.009264, abs=2e-6))]


# --- debounce and hysteresis ------------------------------------------------------------------

def detect(values, positions, threshold, **behaviour):
    """Indices of the samples at which one channel's Detector raises its alert."""
    detector = Detector(threshold, **behaviour)
    return [i for i, (value, position) in enumerate(zip(values, positions)) if detector.update(value, position)]


def test_debounce_over_distance():
    # threshold 1, debounce 2 m, samples every 1 m: above from index 3 on -> alert at index 5
    values = [0, 0, 0, 1.2, 1.1, 1.3, 1.4, 1.5]
    positions = np.arange(len(values), dtype=float)
    assert detect(values, positions, 1.0, debounce=2.0) == [5]
    # a 1-m spike does not pass a 2-m debounce
    assert detect([0, 2, 2, 0, 0], np.arange(5.0), 1.0, debounce=2.0) == []
    # no debounce: the first sample at the level
    assert detect([0, 0.5, 1.0, 2.0], np.arange(4.0), 1.0, debounce=0.0) == [2]


def test_one_event_one_alert_with_hysteresis():
    thr = 1.0
    # 500 samples above the level (one event), then back below the re-arm level (0.9) over 60 m,
    # then above again: two alerts, not hundreds
    values = [1.5] * 500 + [0.5] * 60 + [1.5] * 10
    positions = np.arange(len(values), dtype=float)
    assert detect(values, positions, thr, debounce=0.0, rearm_m=50.0) == [0, 560]
    # dips to 0.95 (above the re-arm level) do not re-arm
    wobble = [1.5, 0.95, 1.5, 0.95, 1.5] * 40
    assert detect(wobble, np.arange(200.0), thr, debounce=0.0, rearm_m=0.0) == [0]
    # a dip below the re-arm level that is shorter than rearm_m does not re-arm either
    dip = [1.5] * 5 + [0.5] * 10 + [1.5] * 5
    assert detect(dip, np.arange(20.0), thr, debounce=0.0, rearm_m=50.0) == [0]
    assert detect(dip, np.arange(20.0), thr, debounce=0.0, rearm_m=5.0) == [0, 15]


# --- the monitor ------------------------------------------------------------------------------

def synthetic_run(n=400):
    """Arrays of a made-up run: the left wheels unload, then the front-left wheel lifts."""
    t = np.arange(n) * 0.005
    s = 100.0 + 80.0 * t
    p = np.full((n, 8), default_limits().static_wheel_load)
    p[:, 0::2] *= np.clip(1.0 - t[:, None] / 1.2, 0.0, 1.0)        # dP/P0 = t / 1.2
    lift = np.zeros((n, 8))
    lift[:, 0] = np.clip((t - 1.0) * 0.03, 0.0, None)            # 0.03 m/s from t = 1 s
    qp = np.zeros((n, 8))
    qp[:, 1] = 0.9 * np.sin(np.pi * t / t[-1])                   # Q/P up to 0.9 on ws0 right
    attack = np.zeros((n, 4))
    attack[:, 0] = np.where(t > 1.5, 0.07, 0.01)
    return dict(time=t, position=s, speed=np.full(n, 80.0), curvature=np.full(n, 1e-3), attack_angle=attack,
                wheel_lift=lift, derailment_coefficient=qp, vertical_force=p)


def test_monitor_by_hand():
    a = synthetic_run()
    alerts = alerts_of_run(a, _limits(debounce_m=0.0))
    first = {(x.criterion, x.severity, x.wheelset, x.wheel_side): x for x in alerts}
    # unloading 0.60 at t = 0.72 s and 0.65 at t = 0.78 s on every left wheel (inner: curve to the left)
    for ws in range(4):
        assert first[("wheel_unloading", 1, ws, "left")].time_s == pytest.approx(0.72, abs=0.006)
        assert first[("wheel_unloading", 2, ws, "left")].time_s == pytest.approx(0.78, abs=0.006)
        assert first[("wheel_unloading", 1, ws, "left")].rail_side == "inner"
    # lift 9.26 mm at t = 1 + 0.00926/0.03 = 1.309 s; Q/P 0.8 at asin(0.8/0.9)/pi * 1.995 = 0.70 s
    assert first[("wheel_lift", 1, 0, "left")].time_s == pytest.approx(1.309, abs=0.006)
    assert first[("derailment_coefficient", 1, 0, "right")].time_s == pytest.approx(0.70, abs=0.006)
    assert first[("attack_angle", 1, 0, "")].value == pytest.approx(0.07)
    # the running gear's mean of its two left wheels reaches EN 14067-6's 0.90 at t = 0.9 x 1.2 = 1.08 s
    for ws in (0, 2):
        assert first[("running_gear_unloading", 1, ws, "left")].time_s == pytest.approx(1.08, abs=0.006)
    # Q/P's 2 m sliding mean (25 ms at 80 m/s) lags the raw value by half its window: 0.8 at 0.70 + 0.0125 s
    assert first[("derailment_coefficient_mean", 1, 0, "right")].time_s == pytest.approx(0.7125, abs=0.006)
    # one alert per event and level: 4 + 4 unloading, 2 lift, 1 Q/P, 1 Q/P mean, 1 attack angle, 2 running
    # gears (Q/P stays below the duration rule's 1.0)
    assert len(alerts) == 15


@pytest.mark.parametrize("speed", [20.0, 80.0])
def test_the_duration_rule_counts_time_not_track(speed):
    """Q/P 1.2 on one wheel for 40 ms raises nothing, for 60 ms a warning after 50 ms, at any speed
    (AAR Chapter XI); the 2 m rule on the same values depends on the speed: at 80 m/s the 40 ms event
    covers 3.2 m and alerts after 2 m (25 ms), at 20 m/s neither event covers 2 m."""
    n = 200
    t = np.arange(n) * 0.005
    qp = np.zeros((n, 8))
    qp[(t >= 0.1) & (t < 0.14), 3] = 1.2                       # 40 ms (8 samples)
    qp[(t >= 0.5) & (t < 0.56), 3] = 1.2                       # 60 ms (12 samples)
    monitor = Monitor(_limits(derailment_coefficient_critical=1.32))
    alerts = []
    for i in range(n):
        alerts += monitor.on_forces(t[i], i, speed * t[i], speed, 0.0, qp[i],
                                    np.full(8, monitor.limits.static_wheel_load))
    duration = [a for a in alerts if a.criterion == "derailment_coefficient_duration"]
    assert [(a.time_s, a.wheelset, a.wheel_side) for a in duration] == [(pytest.approx(0.55), 1, "right")]
    track = [a.time_s for a in alerts if a.criterion == "derailment_coefficient" and a.severity == 1]
    assert track == ([pytest.approx(0.125)] if speed == 80.0 else [])


def arrival_orders(n):
    """Orders in which a monitor node may get the n samples' wheelset states and contact forces: each topic in
    its own order (a reliable topic keeps it), the two interleaved any way (DDS delivers the topics apart)."""
    states, forces = [("states", i) for i in range(n)], [("forces", i) for i in range(n)]

    def behind(first, second, lag):
        """`second` running `lag` samples behind `first` (0: sample by sample, `first`'s message first)."""
        return first[:lag] + [m for i in range(lag, n) for m in (first[i], second[i - lag])] + second[n - lag:]
    for lag in (0, 7, 40):
        yield f"forces {lag} samples behind the states", behind(states, forces, lag)
        yield f"states {lag} samples behind the forces", behind(forces, states, lag)
    pick = np.random.default_rng(43).permutation([0] * n + [1] * n)      # which topic delivers next
    queues = [iter(states), iter(forces)]
    yield "shuffled", [next(queues[k]) for k in pick]


def feed(monitor, a, order):
    """The alerts of a Monitor fed the samples of `a` in `order` (arrival_orders), each message with its own
    sample's values, as the monitor node passes them on."""
    found = []
    for topic, i in order:
        at = (a["time"][i], i, a["position"][i], 80.0, a["curvature"][i])
        found += (monitor.on_states(*at, a["attack_angle"][i], a["wheel_lift"][i]) if topic == "states" else
                  monitor.on_forces(*at, a["derailment_coefficient"][i], a["vertical_force"][i]))
    return found


def test_a_sample_s_alerts_do_not_depend_on_the_order_its_messages_come_in():
    """Issue 43: live, a sample's states and forces come in any order against the other samples' (a CI run had
    the live alert at sample 650 with no rail side where the replay said inner). Each alert names its rail from
    its own sample's curvature, whatever came before it: here the curve turns the other way at every sample, so
    a rail side taken from any other sample is wrong; and the climb distance of a sample's forces waits for the
    attack angles of the sample before it, which change at every sample here, so that any other pairing moves
    its alerts. The alerts are the batch's, field for field."""
    a = synthetic_run()
    n = len(a["time"])
    a["curvature"] = np.where(np.arange(n) % 2 == 0, 1e-3, -1e-3)
    a["attack_angle"][:, 0] = np.where(np.arange(n) % 3 == 0, 0.07, 0.002)
    a["derailment_coefficient"][100:160, 1] = 1.2          # over Nadal's limit: the climb distance grows
    batch = alerts_of_run(a, default_limits())
    assert sum(x.criterion == "flange_climb_distance" for x in batch) >= 2
    assert all(x.rail_side == (rail_side(x.wheel_side, a["curvature"][x.sample]) if x.wheel_side else "")
               for x in batch)
    assert {x.rail_side for x in batch if x.wheel_side} == {"inner", "outer"} and len(batch) > 8
    key = lambda x: (x.sample, x.criterion, x.severity, x.wheelset, x.wheel_side)  # noqa: E731
    expected = [x.as_dict() for x in sorted(batch, key=key)]
    for name, order in arrival_orders(n):
        streamed = feed(Monitor(default_limits()), a, order)
        assert [x.as_dict() for x in sorted(streamed, key=key)] == expected, name


def test_lead_times_by_hand():
    alerts = [dict(criterion="wheel_unloading", severity=1, time_s=10.0, track_position=800.0, speed=80.0,
                   value=0.61, threshold=0.6, wheelset=1, wheel_side="left", rail_side="inner"),
              dict(criterion="wheel_unloading", severity=1, time_s=11.0, track_position=880.0, speed=80.0,
                   value=0.62, threshold=0.6, wheelset=3, wheel_side="left", rail_side="inner")]
    leads = lead_times(alerts, dict(time_s=12.5, track_position_m=1000.0, speed_kmh=300.0))
    assert leads["wheel_unloading/warning"]["lead_s"] == pytest.approx(2.5)
    assert leads["wheel_unloading/warning"]["margin_kmh"] == pytest.approx(12.0)       # 300 - 80 x 3.6
    assert leads["wheel_unloading/warning"]["lead_m"] == pytest.approx(200.0)
    assert leads["wheel_unloading/warning"]["speed_kmh"] == pytest.approx(288.0)
    assert math.isnan(lead_times(alerts, None)["wheel_unloading/warning"]["lead_s"])   # false alarm
    assert math.isnan(lead_times(alerts, None)["wheel_unloading/warning"]["margin_kmh"])


def test_what_a_user_reads_of_an_alert():
    from railderail_monitor.warning.alerts import describe, user_alert
    a = dict(criterion="derailment_coefficient", severity=1, time_s=10.0, track_position=800.0, speed=80.0)
    shown = user_alert(a)
    assert shown["speed_kmh"] == pytest.approx(288.0) and shown["track_position_m"] == 800.0
    assert "speed" not in shown and "track_position" not in shown
    text = describe("derailment_coefficient", 1, 0.8123, 0.8, 0, "left", "inner")
    assert text == "warning: derailment quotient Y/Q 0.812 >= 0.800 on wheelset 0 left (inner)"
    assert "ΔQ/Q0" in describe("wheel_unloading", 2, 0.9, 0.9, 1, "right", "outer")


# --- warning-quality scoring (railderail warnings) -----------------------------------------------

def test_operating_speeds_by_hand():
    from railderail_monitor.evaluation.over_radii import cant_deficiency_speed_kmh
    theta = math.asin(0.175 / 1.5)
    # balance: v^2 / R cos(theta) = g sin(theta) -> sqrt(1000 * 9.81 * tan(theta)) = 33.98 m/s = 122.3 km/h
    assert cant_deficiency_speed_kmh(1000.0, 0.0) == pytest.approx(122.3, abs=0.1)
    # 100 mm of cant deficiency: v^2 / R cos(theta) - g sin(theta) = 9.81 * 0.1 / 1.5 = 0.654 m/s^2
    v = math.sqrt(1000.0 * (9.81 * 0.1 / 1.5 + 9.81 * math.sin(theta)) / math.cos(theta))
    assert cant_deficiency_speed_kmh(1000.0, 0.1) == pytest.approx(v * 3.6, rel=1e-12)
    assert v * 3.6 == pytest.approx(153.2, abs=0.1)


def test_summary_counts_leads_and_false_alarms(tmp_path):
    from railderail_monitor.evaluation import over_radii as W
    lead = dict(lead_s=2.0, lead_m=160.0, time_s=1.0, speed_kmh=300.0)
    runs = [dict(radius_m=1000.0, case="critical", derailed=True, diverged="",
                 first={"wheel_unloading/warning": lead, "wheel_lift/warning": dict(lead, lead_s=0.5, lead_m=40.0)}),
            dict(radius_m=1200.0, case="critical", derailed=True, diverged="",
                 first={"wheel_unloading/warning": dict(lead, lead_s=4.0, lead_m=320.0)}),
            dict(radius_m=1000.0, case="near", derailed=False, diverged="",
                 first={"wheel_unloading/warning": dict(lead, lead_s=math.nan, lead_m=math.nan)}),
            dict(radius_m=1000.0, case="balance", derailed=False, diverged="", first={})]
    s = W.summarize(runs)
    assert s["wheel_unloading/warning"]["warned"] == 2 and s["wheel_unloading/warning"]["derailments"] == 2
    assert s["wheel_unloading/warning"]["min_lead_s"] == 2.0 and s["wheel_unloading/warning"]["median_lead_m"] == 240.0
    assert s["wheel_unloading/warning"]["false_alarm_runs"] == 1
    assert s["wheel_unloading/warning"]["false_alarm_cases"] == ["R1000/near"]
    assert s["wheel_lift/warning"]["warned"] == 1 and s["wheel_lift/warning"]["false_alarm_runs"] == 0
    assert s["attack_angle/warning"]["warned"] == 0
    crit = tmp_path / "sweep.json"
    crit.write_text('[{"radius_m": 800, "refined_speed_kmh": 265.0}, '
                    '{"radius_m": 1000, "refined_speed_kmh": null, "critical_derailment_speed_kmh": 300.0}]')
    assert W.load_critical(crit) == {800.0: 265.0, 1000.0: 300.0}
    crit.write_text("not json")
    with pytest.raises(ValueError, match="sweep.json is not JSON"):
        W.load_critical(crit)


@pytest.mark.parametrize("seed", range(6))
def test_alert_indices_are_what_the_detector_says(seed):
    """The run-based search of a threshold sweep gives the Detector's alerts, sample for sample, on a noisy
    signal crossing its level many times (position-debounced, and time-debounced with a track re-arm)."""
    rng = np.random.default_rng(seed)
    n = 3000
    position = np.cumsum(rng.uniform(0.0, 0.8, n))                 # stops and runs: non-decreasing
    clock = np.arange(n) * 0.005
    values = np.sin(np.arange(n) / rng.uniform(15.0, 60.0)) + rng.normal(0.0, 0.3, n)
    counts = []
    for threshold, debounce, rearm_fraction, rearm_m, time_based in [(0.5, 2.0, 0.9, 50.0, False),
                                                                       (0.8, 0.0, 0.5, 5.0, False),
                                                                       (0.3, 0.05, 0.9, 20.0, True)]:
        detector = Detector(threshold, debounce, rearm_fraction, rearm_m)
        expected = [i for i in range(n)
                    if detector.update(values[i], position[i], clock[i] if time_based else None)]
        found = alert_indices(values, position, threshold, debounce, rearm_fraction, rearm_m,
                                clock if time_based else None)
        assert found == expected
        counts.append(len(expected))
    assert min(counts) >= 1 and sum(counts) >= 6


def test_the_sliding_mean_of_q_p_is_en_14363_s_and_the_monitor_s():
    """The 2 m sliding mean by hand on a short record, and the monitor's running version equal to the whole
    run's, bit for bit, on a noisy one with stops."""
    position = np.array([0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 4.0])
    q = np.array([[0.0], [1.0], [2.0], [3.0], [4.0], [5.0], [6.0]])
    expected = [0.0, 0.5, 1.0, 1.5, 2.5, 3.5, 5.5]                 # samples with s > s_i - 2 m
    assert sliding_mean(q, position, 2.0)[:, 0].tolist() == expected
    rng = np.random.default_rng(3)
    s = np.cumsum(rng.uniform(0.0, 0.6, 2000))
    values = rng.uniform(0.0, 1.2, (2000, 8))
    running = SlidingMean(2.0, 8)
    online = np.array([running.update(values[i], s[i]) for i in range(2000)])
    assert np.array_equal(online, sliding_mean(values, s, 2.0))


def test_the_duration_rule_decides_alike_on_the_simulator_s_clock_and_on_the_node_s_stamps():
    """The node sees each sample's time as a stamp (integer nanoseconds, then sec + 1e-9 nanosec), a batch
    the simulator's float clock: on floats, a 50 ms span of 10 samples is >= 50 ms on one clock and not on the
    other for many spans; on the integer nanoseconds of both the monitor raises the same alerts."""
    from railderail_sim.ros.interface import seconds, set_time
    from builtin_interfaces.msg import Time
    n = 3000
    t_sim = np.cumsum(np.full(n, 0.005)) + 4.0                     # the simulator's float clock
    t_node = np.array([seconds(set_time(Time(), x)) for x in t_sim])
    spans = [(i, i + 10) for i in range(n - 10)]
    differ = sum((t_sim[j] - t_sim[i] >= 0.05) != (t_node[j] - t_node[i] >= 0.05) for i, j in spans)
    assert differ > 0                                             # why the clock is integer nanoseconds
    assert np.array_equal(nanoseconds(t_sim), nanoseconds(t_node))
    rng = np.random.default_rng(3)
    qp = np.full((n, 8), 0.2)
    for k in range(8):                      # excursions of 8-12 samples (35-55 ms), 130-200 samples apart (re-armed)
        i = int(rng.integers(0, 100))
        while i < n:
            qp[i:i + int(rng.integers(8, 13)), k] = 1.4
            i += int(rng.integers(130, 200))
    alerts = {}
    for name, clock in (("sim", t_sim), ("node", t_node)):
        monitor = Monitor(default_limits())
        alerts[name] = [(a.sample, a.criterion, a.severity, a.wheelset, a.wheel_side)
                        for i in range(n) for a in monitor.on_forces(clock[i], i, 80.0 * i * 0.005, 80.0, 0.0, qp[i],
                                                                       np.full(8, monitor.limits.static_wheel_load))]
    timed = [x for x in alerts["sim"] if x[1] == "derailment_coefficient_duration"]
    assert len(timed) > 10 and alerts["sim"] == alerts["node"]
