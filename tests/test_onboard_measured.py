"""The measured criteria as a whole (railderail_monitor.onboard.measured: the limits from the car, the batch
evaluation on each criterion's time base) and as a stream (onboard.monitor.MeasuredMonitor: the same alerts
fed whole or message by message, the units interleaved, samples lost), on a synthetic record from a fixed seed."""
import math

import numpy as np
import pytest

from railderail_sim.parameters import vehicle_parameters
from railderail_sim.sensors.sensor_set import AIR_SPRING_EFFECTIVE_AREA, MOUNTS
from railderail_monitor.warning.limits import SEVERITY_WARNING, default_limits
from railderail_monitor.onboard import criteria as oc
from railderail_monitor.onboard import estimator as est
from railderail_monitor.onboard import measured as me
from railderail_monitor.onboard.monitor import MeasuredMonitor

VP = vehicle_parameters("hs19")
SPEED = 250.0 / 3.6


def _record(seconds=5.0, seed=0, lost=0.01):
    """The shipped set's units at its rates (mounts 200 Hz, air springs 50 Hz, odometer 10 Hz), 2 ms latency,
    `lost` of the mounts' samples dropped; the frames hunt at 4 Hz from 2 s, the car body rolls at 1 Hz (its
    front springs twisted)."""
    rng = np.random.default_rng(seed)
    out = {}
    for unit in MOUNTS:
        t = np.arange(0.0, seconds, 1.0 / 200.0) + 0.002
        t = t[rng.random(len(t)) >= lost]
        acc = rng.normal(0.0, 0.3, (len(t), 3))
        acc[:, 2] += 9.81
        if "frame" in unit:
            acc[:, 1] += 9.0 * np.sin(2.0 * math.pi * 4.0 * t) * (t > 2.0)
        rate = rng.normal(0.0, 0.01, (len(t), 3))
        rate[:, 0] += 0.05 * np.sin(2.0 * math.pi * t)
        out.update({f"sensor_{unit}_time": t, f"sensor_{unit}_acceleration": acc, f"sensor_{unit}_angular_rate": rate})
    t = np.arange(0.0, seconds, 1.0 / 50.0) + 0.002
    d = rng.normal(0.0, 1e-3, (len(t), 4))
    d[:, 1] += 0.02 * np.sin(2.0 * math.pi * t) + 0.008          # the front springs twisted 8 mm besides
    d[:, 0] -= 0.02 * np.sin(2.0 * math.pi * t)
    p = np.full((len(t), 4), VP.car_body_mass * 9.81 / 4.0 / AIR_SPRING_EFFECTIVE_AREA) + rng.normal(0, 3e3, (len(t), 4))
    out.update(sensor_air_springs_time=t, sensor_air_springs_deflection=d, sensor_air_springs_pressure=p)
    t = np.arange(0.1, seconds, 0.1) + 0.002
    out.update(sensor_odometer_time=t, sensor_odometer_speed=SPEED + rng.normal(0.0, 0.5, len(t)))
    return out


# levels low enough that most criteria alert on the synthetic record (the test is the stream's, not the levels')
LOW = dict(bogie_rms=3.0, bogie_peak=6.0, bids_peak_limit=4.0, car_body_lateral=0.3, car_body_roll=0.01,
           car_body_roll_rate=0.02, estimated_running_gear_unloading=0.1, estimated_side_ratio=0.2,
           rms_window_m=50.0, qst_window_m=50.0, car_body_lateral_qst=0.01, bids_window=5.0, car_body_twist=0.002,
           twist_window_m=70.0)


def _key(alert):
    return alert.time_s, me.CRITERIA.index(alert.criterion), me.PLACES[alert.criterion].index(alert.place)


def test_the_limits_come_from_the_car_and_the_ground_truth_monitor():
    lim = me.measured_limits(VP)
    assert me.bogie_mass(VP) == pytest.approx(6860.0)
    assert (lim.bogie_peak, lim.bogie_rms) == pytest.approx((10.628, 5.314))
    assert lim.car_body_roll == pytest.approx(0.035 / 1.23)
    # the rigid bogie's kinematic frequency: 300 km/h, conicity 0.1164, b0 0.7465 m, r0 0.46 m, a 1.25 m
    v = 300.0 / 3.6
    assert lim.hunting_frequency == pytest.approx(v / (2 * math.pi) * math.sqrt(
        0.1164 * 0.7465 / (0.46 * (0.7465 ** 2 + 1.25 ** 2))))
    assert lim.estimated_running_gear_unloading == default_limits().running_gear_unloading
    assert lim.estimated_side_ratio == pytest.approx(0.765 * default_limits().derailment_coefficient)
    # 3 sigma of the twist the four height sensors' 0.5 mm offsets make over 2 b_s (sqrt(4) x 0.5 mm / 2.46 m)
    assert lim.car_body_twist == pytest.approx(3.0 * 2.0 * 0.5e-3 / (2.0 * 1.23))
    assert lim.levels("bogie_rms") == [(SEVERITY_WARNING, lim.bogie_rms)]
    assert me.measured_limits(VP, car_body_lateral=math.nan).levels("car_body_lateral") == []
    with pytest.raises(ValueError, match="bids_band_low 9 Hz must be below bids_band_high 8 Hz"):
        me.measured_limits(VP, bids_band_low=9.0)
    with pytest.raises(ValueError, match="hunting_frequency 1"):
        me.measured_limits(VP, hunting_frequency=1.0)


def test_each_criterion_on_its_own_time_base():
    a = _record()
    found = me.evaluate(a, VP, me.measured_limits(VP, **LOW))
    assert set(found) == set(me.CRITERIA)
    frames = np.union1d(a["sensor_bogie_front_frame_time"], a["sensor_bogie_rear_frame_time"])
    assert np.array_equal(found["bogie_rms"].time, frames)                 # merged: each lost sample held
    assert len(frames) > len(a["sensor_bogie_front_frame_time"])
    assert np.array_equal(found["car_body_roll"].time, a["sensor_air_springs_time"])
    assert np.array_equal(found["car_body_roll_rate"].time, a["sensor_car_body_centre_time"])
    start = max(a[f"sensor_{u}_time"][0] for u in me.est.INPUTS)
    centre = a["sensor_car_body_centre_time"]
    assert np.array_equal(found["estimated_side_ratio"].time, centre[centre >= start])
    assert found["estimated_side_ratio"].value.shape == (len(centre[centre >= start]), 4)
    # the 4 Hz hunting of 9 m/s^2 in f0 +- 2 Hz (f0 3.96 Hz): its r.m.s. near 9 / sqrt 2 once a window is past
    late = found["bogie_rms"].position > found["bogie_rms"].position[-1] - 10.0
    gain = oc.filters.stability_band_pass(me.measured_limits(VP).hunting_frequency).gain(4.0)[0]
    assert found["bogie_rms"].value[late] == pytest.approx(gain * 9.0 / math.sqrt(2.0), rel=0.05)
    # no odometer, no criterion; no air springs, neither the roll nor the estimator nor the twist: each said
    with pytest.warns(UserWarning, match="bogie_rms left out: no odometer"):
        assert me.evaluate({k: v for k, v in a.items() if "odometer" not in k}, VP) == {}
    with pytest.warns(UserWarning, match="car_body_roll left out: no air_springs; .*car_body_twist left out: no "
                                         "air_springs"):
        left = me.evaluate({k: v for k, v in a.items() if "air_springs" not in k}, VP)
    assert "car_body_roll" not in left and "estimated_side_ratio" not in left and "bogie_rms" in left
    assert MeasuredMonitor(VP, rates={u: r for u, r in me.sample_rates().items() if u != "air_springs"}).left_out[0] == {
        c: ["air_springs"] for c in ("car_body_roll", "estimated_running_gear_unloading", "estimated_side_ratio",
                                     "car_body_twist")}
    rates = me.sample_rates()
    del rates["bogie_rear_frame"]
    with pytest.raises(ValueError, match="no sample rate for sensor unit.s. bogie_rear_frame"):
        me.evaluate(a, VP, rates=rates)


def test_the_odometer_position_uses_no_later_sample():
    a = _record(2.0)
    t, v = a["sensor_odometer_time"], a["sensor_odometer_speed"]
    at = np.linspace(0.0, 2.0, 401)
    s = oc.odometer_distance(t, v, at)
    changed = v.copy()
    changed[10:] += 5.0                       # from t[10] on
    s2 = oc.odometer_distance(t, changed, at)
    assert np.array_equal(s[at < t[10]], s2[at < t[10]]) and not np.array_equal(s, s2)
    assert np.all(np.diff(s) >= 0.0) and s[at < t[0]].max() == 0.0
    assert s[-1] == pytest.approx(SPEED * (2.0 - t[0]), rel=0.02)


@pytest.mark.parametrize("chunk", [1, 3, 17, 1000])
def test_the_processors_give_the_same_numbers_whatever_the_chunks(chunk):
    rng = np.random.default_rng(3)
    n = 700
    x = rng.normal(0.0, 5.0, n) + 3.0 * np.sin(np.arange(n) / 7.0)
    s = np.cumsum(rng.uniform(0.2, 0.4, n))
    made = [lambda: oc.BogieRms(200.0, 4.0, 20.0, 2.0), lambda: oc.PeakCount(200.0, (4.0, 8.0), 4.0),
            lambda: oc.PeakCount(200.0, (4.0, 8.0), 4.0, 0.1),
            lambda: oc.CarBodyLateralQst(200.0, 15.0, 1.5), lambda: oc.CarBodyLateral(200.0)]
    for make in made:
        whole = make()(x, s)
        p = make()
        parts = np.concatenate([p(x[i:i + chunk], s[i:i + chunk]) for i in range(0, n, chunk)])
        assert np.array_equal(whole, parts, equal_nan=True), make
    roll = np.stack([x, -x, 0.5 * x, x], axis=1) * 1e-3
    p = oc.CarBodyRoll(50.0, VP)
    parts = np.concatenate([p(roll[i:i + chunk], None) for i in range(0, n, chunk)])
    assert np.array_equal(oc.CarBodyRoll(50.0, VP)(roll, None), parts)


def test_the_stream_gives_the_batch_alerts_fed_whole_or_message_by_message():
    a = _record()
    lim = me.measured_limits(VP, **LOW)
    batch = me.alerts(me.evaluate(a, VP, lim), lim)
    assert {x.criterion for x in batch} >= {"bogie_rms", "bogie_peak", "bids_peak_count", "car_body_lateral",
                                             "car_body_roll", "car_body_roll_rate", "estimated_side_ratio",
                                             "estimated_running_gear_unloading", "car_body_twist"}
    units = me.units_of(a)
    whole = MeasuredMonitor(VP, lim)
    found = []
    for unit, signals in units.items():
        found += whole.feed(unit, signals["time"], **{k: v for k, v in signals.items() if k != "time"})
    found += whole.finish()
    assert sorted(found, key=_key) == batch
    # message by message in stamp order, the units of one instant in a shuffled order
    rng = np.random.default_rng(7)
    events = [(t, rng.random(), unit, i) for unit, signals in units.items() for i, t in enumerate(signals["time"])]
    stream = MeasuredMonitor(VP, lim)
    found, decided_late = [], 0
    for t, _, unit, i in sorted(events):
        new = stream.feed(unit, t, **{k: v[i] for k, v in units[unit].items() if k != "time"})
        decided_late += sum(x.time_s < t - 0.01 for x in new)
        found += new
    found += stream.finish()
    assert sorted(found, key=_key) == batch
    assert decided_late == 0            # each alert raised within 10 ms of its stamp's samples


def test_the_stream_refuses_samples_out_of_order_and_unknown_units():
    m = MeasuredMonitor(VP)
    m.feed("bogie_front_frame", 1.0, acceleration=[0.0, 0.0, 9.81], angular_rate=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="bogie_front_frame: stamp 0.5"):
        m.feed("bogie_front_frame", 0.5, acceleration=[0.0, 0.0, 9.81], angular_rate=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="unknown sensor unit 'roof'"):
        m.feed("roof", 1.0, acceleration=[0.0, 0.0, 9.81])


def test_the_stream_told_a_wind_gives_the_batch_alerts():
    a = _record()
    lim = me.measured_limits(VP, **LOW)
    wind = est.GivenWind([0.0, 2.0], [10.0, 30.0], math.pi / 2)
    batch = me.alerts(me.evaluate(a, VP, lim, wind=wind), lim)
    assert batch != me.alerts(me.evaluate(a, VP, lim), lim)     # the wind changes the estimator's alerts
    stream = MeasuredMonitor(VP, lim, wind=wind)
    found = []
    for unit, signals in me.units_of(a).items():
        found += stream.feed(unit, signals["time"], **{k: v for k, v in signals.items() if k != "time"})
    found += stream.finish()
    assert sorted(found, key=_key) == batch
