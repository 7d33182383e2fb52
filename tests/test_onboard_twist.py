"""The twist rule (onboard.criteria.CarBodyTwist, measured `car_body_twist`): the car body's roll to its front
bogie minus that to its rear, from the air springs' heights, sees a broken primary spring and is gated off on
a cant ramp by the car body's roll rate."""
from dataclasses import replace
import math

import numpy as np
import pytest

from railderail_sim.parameters import TrackParameters, vehicle_parameters
from railderail_sim.sensors import config
from railderail_sim.sensors.measure import SensorLog, after, START_UP_S
from railderail_sim.vehicle.simulate import constant_speed, scenario, simulate, straight_track
from railderail_monitor.onboard import criteria as oc
from railderail_monitor.onboard import measured as me

VP = vehicle_parameters("hs19")
RATE = 200.0
SPEED = 60.0


def _twist(deflection_mm, roll_rate, seconds=10.0, level=1e-3):
    """CarBodyTwist over a synthetic record at RATE: the front springs' difference `deflection_mm` (right
    minus left, mm), the rear level, the gyro's roll rate (rad/s), SPEED."""
    t = np.arange(0.0, seconds, 1.0 / RATE)
    d = np.zeros((len(t), 4))
    d[:, 1] = np.broadcast_to(deflection_mm, t.shape) * 1e-3
    s = SPEED * t
    twist = oc.CarBodyTwist(RATE, VP, level, 100.0, 10.0)
    return s, twist(d, np.broadcast_to(roll_rate, t.shape), s, np.full(len(t), SPEED))


def test_a_steady_twist_reads_after_the_window_and_a_roll_rate_gates_it():
    s, v = _twist(5.0, 0.0)
    # 5 mm over 2 b_s: the roll to the front bogie, the rear's 0
    assert np.nanmax(v) == pytest.approx(5e-3 / (2 * VP.air_spring_semi_spacing))
    assert np.all(np.isnan(v[s < 100.0]))                  # no complete window yet
    # the car body rolling as on a cant ramp from 4 s to 5 s (240-300 m) at 0.01 rad/s: 2.9 mrad between the
    # bogies while on it, its share of a 100 m window up to 1.75 mrad, over half the 1 mrad level: the windows
    # holding more than 17 m of it are not judged, the others are
    t = np.arange(0.0, 10.0, 1.0 / RATE)
    s, v = _twist(5.0, np.where((t >= 4.0) & (t < 5.0), 0.01, 0.0))
    gated = np.isnan(v) & (s > 120.0)
    assert gated.any() and not np.isnan(v[-1])
    assert 240.0 + 17.0 < s[gated][0] and s[gated][-1] < 300.0 + 100.0 - 17.0 + 10.0
    # a roll rate whose window mean stays under half the level gates nothing
    assert not np.isnan(_twist(5.0, 1e-3 * np.sin(2 * math.pi * t))[1][s > 120.0]).any()


def _run(sc):
    log = SensorLog(config.default_set())
    result = simulate(sc, observe=log.observe)
    return sc, after({**result.arrays(), **log.arrays()}, START_UP_S)


@pytest.fixture(scope="module")
def broken_spring():
    """250 km/h on straight smooth track, wheelset 0's left primary spring broken, 9 s."""
    return _run(replace(scenario(radius=1000.0, speed_kmh=250.0), track=straight_track(),
                        speed_table=constant_speed(250.0), start_position=100.0, end_position=100.0 + 625.0,
                        faults=("primary-spring-broken@0-left",)))


@pytest.fixture(scope="module")
def transition():
    """Into R 1000 m, 175 mm cant over the 200 m transition, healthy, 220 km/h, smooth: a cant ramp."""
    track = TrackParameters(radius=1000.0, cant_height=0.175)
    start = track.straight_in - 150.0
    return _run(replace(scenario(radius=1000.0, speed_kmh=220.0), track=track, speed_table=constant_speed(220.0),
                        start_position=start, end_position=start + 600.0))


def _alerts(run):
    sc, a = run
    lim = me.measured_limits(sc.vehicle)
    units = {k: v for k, v in a.items() if any(k.startswith(f"sensor_{u}_") for u in ("odometer", "air_springs",
                                                                                        "car_body_centre"))}
    found = me.evaluate(units, sc.vehicle, lim)
    return found["car_body_twist"], [x for x in me.alerts(found, lim) if x.criterion == "car_body_twist"], lim


def test_the_broken_primary_spring_is_seen(broken_spring):
    m, found, lim = _alerts(broken_spring)
    assert found and found[0].value > 5.0 * lim.car_body_twist


def test_a_cant_ramp_is_gated_off(transition):
    sc, a = transition
    m, found, lim = _alerts(transition)
    assert not found
    # ungated, the ramp's twist is over the level: the gate is what keeps the rule silent
    roll = oc.air_spring_roll(a["sensor_air_springs_deflection"], VP.air_spring_semi_spacing)
    position = oc.odometer_distance(a["sensor_odometer_time"], a["sensor_odometer_speed"], a["sensor_air_springs_time"])
    ungated = np.abs(oc.trailing_window(position, roll[:, 0] - roll[:, 1], lim.twist_window_m, lim.window_step_m, 1))
    assert np.nanmax(ungated) > 2.0 * lim.car_body_twist
    assert math.isfinite(np.nanmax(m.value))            # and it is not gated all the time
