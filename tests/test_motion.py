"""What ideal inertial sensors on the bodies read (vehicle.motion, the core's BodyMotion): closed cases of a car
nearly at rest on cant and in steady curving, and the rigid-body transfer to a point."""
from dataclasses import replace
import math

import numpy as np
import pytest

from railderail_sim.parameters import TrackParameters
from railderail_sim.vehicle.layout import N_BODY, BodyMotion, Body, Dof
from railderail_sim.vehicle.motion import point_motion
from railderail_sim.vehicle.simulate import constant_speed, scenario, simulate

G = 9.81


def _curve_end_rows(track, speed_kmh):
    """The run's arrays up to the end of the circular curve and the mask of its last 300 m but 30 (where the
    front wheelset meets the exit transition), where the car has settled after the entry transition."""
    sc = replace(scenario(radius=track.radius, speed_kmh=speed_kmh), track=track)
    end = track.straight_in + track.transition_in + track.curve_length
    a = simulate(replace(sc, speed_table=constant_speed(speed_kmh), end_position=end)).arrays()
    return a, (a["position"] > end - 300.0) & (a["position"] < end - 30.0)


@pytest.fixture(scope="module")
def creeping_on_cant():
    """30 km/h on a 20 km curve with 150 mm cant: the centripetal acceleration 0.0035 m/s^2, a car at rest
    on the cant to 0.04 % of g."""
    return _curve_end_rows(TrackParameters(radius=20000.0, cant_height=0.150), 30.0)


def test_a_car_at_rest_on_cant_reads_g_times_the_sine_of_its_roll_laterally(creeping_on_cant):
    a, last = creeping_on_cant
    cant = np.arcsin(0.150 / 1.5)
    force, rate = point_motion(a, "car_body", (0.0, 0.0, 0.0))
    roll = cant - a["body_states"][:, Body.car_body, Dof.roll]    # to the ground, low (left) side down
    # the car body still sways a little on its suspension: its mean reading; the
    # centripetal acceleration (0.0035 m/s^2) toward the curve's centre, the body's left
    centripetal = (30.0 / 3.6) ** 2 / 20000.0
    assert np.mean(-force[last, 1]) == pytest.approx(np.mean(G * np.sin(roll[last]) - centripetal * np.cos(roll[last])),
                                                     abs=5e-4)
    assert np.mean(force[last, 2]) == pytest.approx(np.mean(G * np.cos(roll[last]) + centripetal * np.sin(roll[last])),
                                                    abs=5e-4)
    turn = 30.0 / 3.6 / 20000.0
    # the track turns about its own z and y (negative: the right rail is the high one); the body sways
    assert np.mean(rate[last], axis=0) == pytest.approx([0.0, -turn * math.sin(cant), turn * math.cos(cant)], abs=1e-4)
    # the wheelsets follow the track: g sin(cant) to the rail's tilt
    ws_force, _ = point_motion(a, "wheelset_0", (0.0, 0.75, 0.0))
    assert np.allclose(-ws_force[last, 1], G * math.sin(cant), rtol=2e-3)


def test_steady_curving_reads_the_uncompensated_acceleration_and_the_closed_form_magnitude():
    track = TrackParameters(radius=1000.0)
    a, last = _curve_end_rows(track, 200.0)
    v = 200.0 / 3.6
    ws_force, ws_rate = point_motion(a, "wheelset_1", (0.0, -0.75, 0.0))
    # the axle box rolls with its wheelset (the outer wheel runs on a larger radius)
    roll = a["body_states"][:, Body.wheelset_1, Dof.roll]
    normal = G * np.cos(a["cant"]) + (v * v / 1000.0) * np.sin(a["cant"])
    expected = a["uncompensated_acceleration"] * np.cos(roll) + normal * np.sin(roll)
    assert np.mean(ws_force[last, 1]) == pytest.approx(np.mean(expected[last]), rel=5e-3)
    assert np.mean(ws_rate[last, 2]) == pytest.approx(np.mean(v / 1000.0 * np.cos(a["cant"][last])), rel=1e-3)
    for body in ("car_body", "front_bogie", "wheelset_0"):
        force, _ = point_motion(a, body, (1.0, 0.5, 1.0))
        magnitude = np.linalg.norm(force[last], axis=1)
        assert np.mean(magnitude) == pytest.approx(math.hypot(G, v * v / 1000.0), rel=5e-4)
        assert np.allclose(magnitude, math.hypot(G, v * v / 1000.0), rtol=0.01)


def test_a_point_of_a_turning_body_reads_its_centripetal_and_tangential_accelerations():
    """Synthetic motion: the car body at rest to the track turning about z at omega with angular acceleration
    alpha, its reference point in free fall (no specific force): a point 2 m ahead reads -omega^2 2 m along x
    and alpha 2 m along y."""
    n, omega, alpha = 3, 0.5, 0.2
    motion = np.zeros((n, N_BODY, BodyMotion.size()))
    motion[:, Body.car_body, BodyMotion.angular_velocity + 2] = omega
    motion[:, Body.car_body, BodyMotion.angular_acceleration + 2] = alpha
    arrays = dict(body_motion=motion, body_states=np.zeros((n, N_BODY, 5)))
    force, rate = point_motion(arrays, "car_body", (2.0, 0.0, 0.0))
    assert np.allclose(force, [[-omega**2 * 2.0, alpha * 2.0, 0.0]] * n)
    assert np.allclose(rate, [[0.0, 0.0, omega]] * n)
    # yawed by 90 deg to the track, the body's x axis is the track's y: the same reading in its own axes
    arrays["body_states"][:, Body.car_body, Dof.yaw] = math.pi / 2
    turned, _ = point_motion(arrays, "car_body", (2.0, 0.0, 0.0))
    assert np.allclose(turned, force)
