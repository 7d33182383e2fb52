"""The on-board estimator of the running gears' side loads, unloading and lateral force
(railderail_monitor.onboard.estimator) against the simulator's wheel forces in steady curving at a cant
deficiency, with the sensors' noise and biases on, within bounds derived from its neglected terms."""
from dataclasses import replace

import numpy as np
import pytest

from railderail_sim.parameters import GRAVITY, TrackParameters, vehicle_parameters
from railderail_sim.sensors import config
from railderail_sim.sensors.sensor_set import AIR_SPRING_EFFECTIVE_AREA
from railderail_sim.sensors.measure import SensorLog
from railderail_sim.loads.wind import Wind
from railderail_sim.vehicle.simulate import constant_speed, scenario, simulate, straight_track
from railderail_monitor.onboard import estimator as est


@pytest.fixture(scope="module")
def steady_curving():
    """220 km/h on R 1000 m with 175 mm cant (a_nc 1.59 m/s^2), 6 s from 100 m into the circular curve."""
    track = TrackParameters(radius=1000.0, cant_height=0.175)
    start = track.straight_in + track.transition_in + 100.0
    sc = replace(scenario(radius=1000.0, speed_kmh=220.0), track=track, speed_table=constant_speed(220.0),
                 start_position=start, end_position=start + 220.0 / 3.6 * 6.0)
    log = SensorLog(config.default_set())
    result = simulate(sc, observe=log.observe)
    return {**result.arrays(), **log.arrays()}


def test_steady_curving_error_within_the_neglected_terms(steady_curving):
    vp = vehicle_parameters("hs19")
    err = est.estimator_error(steady_curving, vp, AIR_SPRING_EFFECTIVE_AREA)
    tru = est.truth(steady_curving, vp)
    assert np.min(tru["unloading"][200:, 0]) > 0.25         # the inner side well unloaded: a real test
    # the frames' roll on their primary springs, neglected: phi_p = b0 dP / (4 k_z b_p^2) with dP the
    # truth's side-load difference, tilts the half car body's and the bogie's weight into the lateral force
    dp = np.mean(tru["side_load"][200:, 1] - tru["side_load"][200:, 0])
    phi_p = est.CONTACT_SEMI_DISTANCE * dp / (4.0 * vp.primary_vertical_stiffness * vp.primary_semi_spacing ** 2)
    y_bound = (0.5 * vp.car_body_mass + vp.bogie_frame_mass) * GRAVITY * phi_p
    for bogie in est.BOGIES:
        assert abs(err["lateral_force"][bogie]["bias"]) < y_bound
    # the secondary lateral force F = m_c/2 a_nc placed at the air springs' height while the lateral bump stop
    # (0.3 m lower) may carry all of it: its moment over b0, shared by the two sides' loads, over 2 P0
    a_nc = np.mean(steady_curving["uncompensated_acceleration"][200:])
    unloading_bound = ((vp.secondary_height - vp.bump_stop_height) * 0.5 * vp.car_body_mass * a_nc
                       / est.CONTACT_SEMI_DISTANCE / 2.0 / (2.0 * vp.static_wheel_load))
    for side in est.PLACES["unloading"]:
        assert abs(err["unloading"][side]["bias"]) < unloading_bound
        assert err["unloading"][side]["rms"] < unloading_bound


def test_the_truth_is_the_wheel_forces_summed():
    vp = vehicle_parameters("hs19")
    p = np.full((1, 8), vp.static_wheel_load)
    q = np.zeros((1, 8))
    q[0, 1] = q[0, 3] = 10e3                       # both right wheels of the front bogie push their rail out
    t = est.truth({"vertical_force": p, "lateral_force": q, "time": np.zeros(1)}, vp)
    assert t["unloading"] == pytest.approx(np.zeros((1, 4)))
    assert t["lateral_force"][0] == pytest.approx([20e3, 0.0])
    assert t["derailment_coefficient"][0, :2] == pytest.approx([-20e3 / (2 * vp.static_wheel_load),
                                                                20e3 / (2 * vp.static_wheel_load)])


@pytest.fixture(scope="module")
def crosswind():
    """300 km/h on straight smooth track in a steady 30 m/s wind from the left (below the characteristic wind
    curve), 5 s from 100 m on."""
    sc = replace(scenario(radius=1000.0, speed_kmh=300.0), track=straight_track(), speed_table=constant_speed(300.0),
                 start_position=100.0, end_position=100.0 + 300.0 / 3.6 * 5.0, wind=Wind(speed=30.0, direction_deg=90.0))
    log = SensorLog(config.default_set())
    result = simulate(sc, observe=log.observe)
    return {**result.arrays(), **log.arrays()}


def test_a_given_wind_takes_the_crosswind_out_of_the_estimate(crosswind):
    vp = vehicle_parameters("hs19")
    tru = est.truth(crosswind, vp)
    assert np.mean(tru["unloading"][200:, 0]) > 0.3           # the windward (left) side well unloaded: a real test
    wind = est.GivenWind(0.0, 30.0, np.pi / 2)
    blind = est.estimator_error(crosswind, vp, AIR_SPRING_EFFECTIVE_AREA)
    told = est.estimator_error(crosswind, vp, AIR_SPRING_EFFECTIVE_AREA, wind=wind)
    # blind, the floors read about zero: the windward unloading and the bogies' lateral force are missed
    assert blind["unloading"]["front_left"]["bias"] < -0.1
    assert blind["lateral_force"]["front"]["bias"] < -20e3
    # told the wind, what is left is the order of steady curving's bias of the neglected terms (2-3 kN)
    for bogie in est.BOGIES:
        assert abs(told["lateral_force"][bogie]["bias"]) < 0.1 * abs(blind["lateral_force"]["front"]["bias"])
    for side in est.PLACES["unloading"]:
        assert abs(told["unloading"][side]["bias"]) < 0.05
