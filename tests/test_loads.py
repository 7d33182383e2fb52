"""Aerodynamic loads of a crosswind (loads.aerodynamics, loads.wind) and the characteristic wind curves
(methods.cwc), against closed forms: the quasi-steady load formula, the car's roll balance, mirror
symmetry, the gust's shape."""
import math
import subprocess
import sys

import numpy as np
import pytest

from railderail_sim.loads.aerodynamics import aerodynamic_load
from railderail_sim.loads.layout import AeroLoad
from railderail_sim.loads.wind import Wind, pack_aero
from railderail_sim.methods import cwc
from railderail_sim.parameters import GRAVITY, AerodynamicParameters
from railderail_sim.vehicle.layout import N_BODY, OutputRow
from railderail_sim.vehicle.simulate import KMH, Scenario, constant_speed, simulate, straight_track

AERO = AerodynamicParameters()


def closed_form(speed, wind, direction_deg):
    """(beta, F_y, M_x) of the quasi-steady formula, with numpy's interpolation of the coefficient table."""
    theta = math.radians(direction_deg)
    ux, uy = speed + wind * math.cos(theta), wind * math.sin(theta)
    beta = math.atan2(uy, ux)
    table = np.array(AERO.coefficients())
    q = 0.5 * AERO.air_density * (ux * ux + uy * uy) * AERO.reference_area
    side = math.copysign(1.0, beta)
    return (beta, -side * q * np.interp(abs(beta), table[:, 0], table[:, 1]),
            side * q * AERO.reference_length * np.interp(abs(beta), table[:, 0], table[:, 3]))


@pytest.fixture(scope="module")
def windy_straight():
    """200 km/h on straight track in a steady 25 m/s wind from the left, for 20 s: the sudden wind sets the
    car rolling, lightly damped, so that only the mean over the last 5 s is at rest."""
    sc = Scenario(track=straight_track(), speed_table=constant_speed(200.0), wind=Wind(25.0, 90.0),
                  end_position=200.0 / 3.6 * 20.0, output_rate=100.0)
    return simulate(sc)


def test_the_side_force_and_rolling_moment_are_half_rho_v2_a_c(windy_straight):
    load = AeroLoad.split(windy_straight.rows[:, OutputRow.aerodynamics.columns])
    beta, fy, mx = closed_form(200.0 * KMH, 25.0, 90.0)
    assert load["wind_speed"][-1] == 25.0
    assert load["yaw_angle"][-1] == pytest.approx(beta, rel=1e-12)
    assert load["side_force"][-1] == pytest.approx(fy, rel=1e-9)
    assert load["rolling_moment"][-1] == pytest.approx(mx, rel=1e-9)
    assert fy < 0.0 < mx                                     # pushed to the right, rolled to the right


def test_a_steady_wind_shifts_the_wheel_loads_as_the_roll_balance_says(windy_straight):
    """About the track centre line at rail level, at rest: the wind's rolling moment and the weight of the
    displaced bodies are carried by the wheel loads at the contact points, M_x - g sum(m y) + sum(Q y_c) = 0;
    the lateral contact forces act at rail level. The predicted shift of the load from the left wheels to the
    right ones, (M_x - g sum(m y)) / b over the half distance b of the contact points, within 3 % (the issue
    asks for 10 %; what is left is the contact points' distance from b)."""
    r = windy_straight
    last = r.time >= r.time[-1] - 5.0
    load = AeroLoad.split(r.rows[last][:, OutputRow.aerodynamics.columns])
    mx = load["rolling_moment"].mean()
    from railderail_sim.vehicle.assemble import body_table
    from railderail_sim.vehicle.layout import BodyTable
    masses = body_table(r.scenario.vehicle)[:, BodyTable.mass]
    lateral = r.arrays()["body_states"][last][:, :, 0].mean(axis=0)
    b = r.scenario.contact.rolling_circle_half_distance
    predicted = (mx - GRAVITY * float(masses @ lateral)) / b
    q = r.wheel("vertical_force")[last].mean(axis=0)
    shift = q[1::2].sum() - q[0::2].sum()                   # right wheels minus left wheels
    assert len(masses) == N_BODY
    assert shift == pytest.approx(predicted, rel=0.03)
    assert shift > mx / b                                   # the lee-ward shift of the bodies adds to it


def test_a_wind_from_the_right_mirrors_the_load():
    left = pack_aero(AERO, Wind(20.0, 60.0), 0.0)
    right = pack_aero(AERO, Wind(20.0, -60.0), 0.0)
    w, beta, fy, fz, mx, my, mz = aerodynamic_load(left, 0.0, 70.0)
    w2, beta2, fy2, fz2, mx2, my2, mz2 = aerodynamic_load(right, 0.0, 70.0)
    assert (beta2, fy2, mx2, mz2) == (-beta, -fy, -mx, -mz)
    assert (w2, fz2, my2) == (w, fz, my)
    assert aerodynamic_load(pack_aero(AERO, None, 0.0), 0.0, 70.0) == (0.0,) * 7     # still air


def test_the_gust_peaks_at_its_speed_over_the_mean_wind():
    s, u = Wind(30.0, 90.0, "chinese-hat", peak_position=900.0).history(AERO, 0.0)
    a_i = AERO.gust_peak_factor * AERO.gust_turbulence_intensity
    assert np.all(np.diff(s) > 0.0)
    assert u[0] == 0.0 and s[0] == pytest.approx(900.0 - 6.0 * AERO.gust_length_scale - AERO.gust_ramp)
    assert u.max() == pytest.approx(30.0) and s[np.argmax(u)] == pytest.approx(900.0)
    assert u[-1] == pytest.approx(30.0 / (1.0 + a_i), rel=3e-3)          # the mean wind after the hat
    half = 30.0 / (1.0 + a_i) * (1.0 + a_i * math.exp(-1.0))
    assert np.interp(900.0 + AERO.gust_length_scale, s, u) == pytest.approx(half, rel=1e-3)


def test_the_characteristic_wind_speed_falls_as_the_vehicle_speed_rises():
    base = Scenario()
    slow, _ = cwc.characteristic_wind_speed(200.0, base, cwc.CwcCase(None), tolerance=2.0)
    fast, runs = cwc.characteristic_wind_speed(350.0, base, cwc.CwcCase(None), tolerance=2.0)
    assert 10.0 < fast < slow < 60.0
    below = [q for u, q in runs if u < fast - 1.0]
    assert below and max(below) < cwc.UNLOADING_LIMIT                    # the bracket holds


@pytest.mark.parametrize("option, value, message", [
    ("--wind-speed-m-s", "80", "wind speed 80 m/s is outside"),
    ("--wind-direction-deg", "200", "wind direction 200 deg is outside"),
])
def test_bad_wind_options_name_the_value_and_the_range(option, value, message):
    done = subprocess.run([sys.executable, "-m", "railderail_sim.cli", "simulate", option, value],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 2 and message in done.stderr, done.stderr


def test_a_tail_wind_faster_than_the_train_meets_the_car_from_behind():
    """Relative wind from 150 deg is the flow from 30 deg seen from the rear: the same side force and rolling
    moment, the yawing moment reversed."""
    from_behind = aerodynamic_load(pack_aero(AERO, Wind(40.0, 180.0 - 30.0), 0.0), 0.0, 0.0)
    from_ahead = aerodynamic_load(pack_aero(AERO, Wind(40.0, 30.0), 0.0), 0.0, 0.0)
    assert from_behind[1] == pytest.approx(math.radians(150.0)) and from_ahead[1] == pytest.approx(math.radians(30.0))
    assert from_behind[2] == pytest.approx(from_ahead[2]) and from_behind[4] == pytest.approx(from_ahead[4])
    assert from_behind[6] == pytest.approx(-from_ahead[6]) and from_ahead[6] != 0.0


def test_bad_aerodynamic_parameters_and_gust_places_are_refused():
    from dataclasses import replace
    with pytest.raises(ValueError, match="air_density -1 kg/m\\^3 is outside"):
        pack_aero(replace(AERO, air_density=-1.0), Wind(10.0), 0.0)
    with pytest.raises(ValueError, match="yaw_angle_step_deg 7 deg does not divide 90"):
        pack_aero(replace(AERO, yaw_angle_step_deg=7.0), Wind(10.0), 0.0)
    with pytest.raises(ValueError, match="gust peak at 100 m leaves no room"):
        pack_aero(AERO, Wind(10.0, gust="chinese-hat", peak_position=100.0), 0.0)
