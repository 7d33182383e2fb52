"""The rails' deviations (track.rails): interpolation against closed forms, refusal of bad input, and the
invariance that makes them physics: a wheelset that follows displaced and turned rails exactly meets them
as a centred wheelset meets ideal rails."""
from dataclasses import replace

import numpy as np
import pytest

from railderail_sim.contact.geometry import rigid_contact
from railderail_sim.contact.layout import GeometryHeader, Wheel
from railderail_sim.track import rails as R
from railderail_sim.track.irregularity import Irregularity, lateral_kink, resolve, vertical_wave, write_csv
from railderail_sim.vehicle import dynamics as dyn
from railderail_sim.vehicle.layout import N_DOF, N_STATE, WHEELSETS, BodyTable, Dof, State
from railderail_sim.vehicle.simulate import (Simulation, output_arrays, scenario, simulate, static_state,
                                             straight_track)


def deviations_at(rails, s):
    return np.array([[*R.rail_deviation(rails, side, q)] for q in s for side in (0, 1)]).reshape(len(s), 2, 4)


def test_hermite_reproduces_a_cubic_exactly():
    rng = np.random.default_rng(1)
    s = np.cumsum(rng.uniform(0.1, 0.7, 40))
    c = rng.normal(size=(4, 4)) * 1e-3           # one cubic per rail value
    p = lambda u: np.stack([np.polyval(k, u) for k in c], -1)  # noqa: E731
    dp = lambda u: np.stack([np.polyval(np.polyder(k), u) for k in c], -1)  # noqa: E731
    rails = R.pack_rails(s, p(s), dp(s), R.HERMITE)
    q = np.sort(rng.uniform(s[0], s[-1], 200))
    got = deviations_at(rails, q)
    # (lateral, vertical, lateral slope, vertical slope) of the left rail = RailValues 0, 1
    for side, (lat, ver) in enumerate(((0, 1), (2, 3))):
        assert np.allclose(got[:, side, 0], p(q)[:, lat], rtol=0, atol=1e-15)
        assert np.allclose(got[:, side, 1], p(q)[:, ver], rtol=0, atol=1e-15)
        assert np.allclose(got[:, side, 2], dp(q)[:, lat], rtol=0, atol=1e-13)
        assert np.allclose(got[:, side, 3], dp(q)[:, ver], rtol=0, atol=1e-13)


def test_linear_is_numpys_interpolation_and_ideal_outside():
    s = np.array([10.0, 10.5, 12.0, 20.0])
    v = np.array([[1, 2, 3, 4], [2, 0, 1, 5], [-1, 1, 0, 0], [0, 3, 2, 1]], float) * 1e-3
    rails = R.pack_rails(s, v)
    q = np.linspace(10.0, 20.0, 301)
    got = deviations_at(rails, q)
    assert np.allclose(got[:, 0, 0], np.interp(q, s, v[:, 0]), atol=1e-16)
    assert np.allclose(got[:, 1, 1], np.interp(q, s, v[:, 3]), atol=1e-16)
    assert got[150, 0, 2] == pytest.approx((v[3, 0] - v[2, 0]) / 8.0)      # the slope of the piece
    for outside in (9.99, 20.01, -1e6):
        assert R.rail_deviation(rails, 0, outside) == (0.0, 0.0, 0.0, 0.0)
    assert R.rail_deviation(R.pack_rails(), 1, 15.0) == (0.0, 0.0, 0.0, 0.0)
    back = R.split_rails(rails)
    assert np.array_equal(back[0], s) and np.array_equal(back[1], v) and back[3] == R.LINEAR


@pytest.mark.parametrize("s, deviations, kwargs, message", [
    ([0.0, 1.0, 1.0], np.zeros((3, 4)), {}, "s must increase strictly (s = 1 m is followed by 1 m)"),
    ([0.0], np.zeros((1, 4)), {}, "one point is not a shape"),
    ([0.0, 1.0], [[0, 0, np.nan, 0], [0, 0, 0, 0]], {}, "must be finite"),
    ([0.0, 1.0], np.zeros((2, 4)), dict(interpolation=7), "interpolation 7 is not 0 (linear) or 1"),
    ([0.0, 1.0], np.zeros((2, 4)), dict(slopes=np.zeros((2, 4))), "takes its slopes from the deviations"),
])
def test_bad_rail_deviations_are_refused(s, deviations, kwargs, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        R.pack_rails(s, deviations, **kwargs)


def test_lateral_kink_is_one_smooth_cosine_period():
    rails = lateral_kink(50.0, 20.0, 0.01).pack()
    s = np.linspace(50.0, 70.0, 2001)
    got = deviations_at(rails, s)
    exact = 0.005 * (1.0 - np.cos(2.0 * np.pi * (s - 50.0) / 20.0))
    assert np.max(np.abs(got[:, 0, 0] - exact)) < 2.5e-9 and np.array_equal(got[:, 0], got[:, 1])
    slope = 0.005 * 2.0 * np.pi / 20.0 * np.sin(2.0 * np.pi * (s - 50.0) / 20.0)
    assert np.max(np.abs(got[:, 0, 2] - slope)) < 1e-7
    assert np.all(got[:, :, 1] == 0.0) and R.rail_deviation(rails, 0, 49.99) == (0.0, 0.0, 0.0, 0.0)


def _wheel_records(irregularity, follow):
    """The wheel records of one evaluation of the equations of motion on straight track at 200 km/h,
    every wheelset placed by `follow(s)` -> (y, z, yaw, lateral and vertical velocity)."""
    sc = replace(scenario(speed_kmh=200.0), track=straight_track(), start_position=300.0)
    x = Simulation(sc).x.copy()               # the state on ideal rails, moved by `follow` below
    sim = Simulation(replace(sc, irregularity=irregularity))
    for b in WHEELSETS:
        y, z, yaw, vy, vz = follow(x[State.s] + sim.model.bodies[b, BodyTable.station])
        o, ov = State.positions + N_DOF * b, State.velocities + N_DOF * b
        x[o + Dof.lateral] += y
        x[o + Dof.vertical] += z
        x[o + Dof.yaw] += yaw
        x[ov + Dof.lateral] += vy
        x[ov + Dof.vertical] += vz
    dyn.rhs(x, np.zeros(N_STATE), sim.model.arrays, sim.speed_table, sim.work.rhs, False)
    return Wheel.split(sim.work.rhs.recs.copy())


def test_a_wheelset_following_turned_rails_meets_them_as_ideal_ones():
    # both rails displaced by 4 mm to the left and 2 mm up and turned: 3 mrad in yaw, 1 mrad in pitch
    a, c, v = 3e-3, 1e-3, 200.0 / 3.6
    s = np.array([0.0, 1000.0])
    lateral, vertical = 4e-3 + a * (s - 300.0), 2e-3 + c * (s - 300.0)
    turned = Irregularity(s, np.column_stack((lateral, vertical, lateral, vertical)))
    got = _wheel_records(turned, lambda sw: (4e-3 + a * (sw - 300.0), 2e-3 + c * (sw - 300.0), a, a * v, c * v))
    ideal = _wheel_records(None, lambda sw: (0.0, 0.0, 0.0, 0.0, 0.0))
    assert ideal["vertical_force"].min() > 5e4                  # the wheels are loaded
    for name, tol in (("vertical_force", 1.0), ("lateral_force", 1.0), ("wheel_lift", 1e-9),
                      ("contact_position", 1e-9)):
        assert np.allclose(got[name], ideal[name], rtol=0, atol=tol), name
    # to first order in the angles: the longitudinal creepage feels a^2 (9e-6) times the creep coefficient
    assert np.allclose(got["longitudinal_force"], ideal["longitudinal_force"], rtol=0, atol=150.0)
    # the same lateral motion on ideal rails: off-centre at 3 mrad, the records differ by far more
    off = _wheel_records(None, lambda sw: (4e-3 + a * (sw - 300.0), 0.0, a, a * v, 0.0))
    assert np.max(np.abs(off["lateral_force"] - ideal["lateral_force"])) > 5e3


def test_a_run_starts_with_its_wheelsets_on_the_rails():
    # the rails 4 mm to the left, 2 mm up and 3 mrad turned where the car stands: its first sample's wheel
    # loads are those on ideal rails (simulate.on_the_rails), not a 2 mm interpenetration
    s = np.array([0.0, 1000.0])
    lateral, vertical = 4e-3 + 3e-3 * (s - 300.0), 2e-3 + 1e-3 * (s - 300.0)
    turned = Irregularity(s, np.column_stack((lateral, vertical, lateral, vertical)))
    sc = replace(scenario(speed_kmh=200.0), track=straight_track(), start_position=300.0)
    first = output_arrays(Simulation(replace(sc, irregularity=turned)).advance(0.0))
    ideal = output_arrays(Simulation(sc).advance(0.0))
    assert np.allclose(first["vertical_force"], ideal["vertical_force"], rtol=0, atol=1.0)
    assert np.allclose(first["lateral_force"], ideal["lateral_force"], rtol=0, atol=1.0)


def test_an_outward_kink_makes_the_outer_wheel_climb(tmp_path):
    # a measured-record file: both rails 50 mm toward the outside of an 800 m left curve and back over 5 m,
    # a point every 0.25 m; 160 km/h, friction 0.5: the leading outer wheel is thrown onto its flange
    s = np.arange(700.0, 705.001, 0.25)
    lateral = -0.025 * (1.0 - np.cos(2.0 * np.pi * (s - 700.0) / 5.0))
    zero = np.zeros_like(s)
    write_csv(Irregularity(s, np.column_stack((lateral, zero, lateral, zero))), tmp_path / "kink.csv")
    kink = resolve(str(tmp_path / "kink.csv"), 0, 1800.0)
    sc = replace(scenario(radius=800.0, speed_kmh=160.0, friction=0.5), irregularity=kink, start_position=550.0,
                 end_position=760.0)
    event = simulate(sc).derailment
    assert event is not None and event["mechanism"] == "flange_climbing", event
    assert (event["wheelset"], event["wheel_side"], event["rail_side"]) == (0, "right", "outer")
    # toward its rail, front turned toward the outer rail, last touching the rail on its gauge side
    assert -0.040 < event["lateral_displacement_m"] < -0.005 and event["attack_angle_rad"] > 0.01
    assert event["contact_position_m"] < -0.020


def test_a_twist_in_a_sharp_curve_makes_the_outer_wheel_climb_over_its_flange_tip(tmp_path):
    # the outer (right) rail of a 150 m left curve down 20 mm over 5 m (a 1:250 twist), held for 20 m; 30 km/h
    # with 150 mm of cant, friction 0.6: the leading outer wheel, already flanging near Nadal's limit, loses load
    # and climbs. Near the flange tip its contact angle falls below half the flange angle, the wheel is still
    # climbing: the mechanism stays flange climbing (it read wheel unloading before the fix)
    s = np.arange(600.0, 630.001, 0.25)
    drop = -0.020 * np.clip(np.minimum(s - 600.0, 630.0 - s) / 5.0, 0.0, 1.0)
    zero = np.zeros_like(s)
    write_csv(Irregularity(s, np.column_stack((zero, zero, zero, drop))), tmp_path / "twist.csv")
    twist = resolve(str(tmp_path / "twist.csv"), 0, 1800.0)
    sc = replace(scenario(radius=150.0, speed_kmh=30.0, friction=0.6),
                 track=replace(scenario(radius=150.0).track, cant_height=0.150), irregularity=twist,
                 start_position=150.0, end_position=640.0)      # from the straight: no settled start in the curve
    result = simulate(sc)
    event = result.derailment
    assert event is not None and event["mechanism"] == "flange_climbing", event
    assert (event["wheelset"], event["wheel_side"], event["rail_side"]) == (0, "right", "outer")
    angle = result.wheel("contact_angle")[:, 1]
    assert angle.min() < 0.5 * angle.max()           # the climb passed the flange's steep face


def test_a_vertical_rail_wave_loads_the_wheels_as_the_unsprung_mass_says():
    # both rails in a 0.2 mm, 2 m vertical sine at 250 km/h (34.7 Hz): each wheel's load swings by its share
    # of the wheelset's inertia, the axle box's spring and damper, raised by the Hertz contact's compliance
    amplitude, wavelength, v = 2e-4, 2.0, 250.0 / 3.6
    k = 2.0 * np.pi / wavelength
    sc = replace(scenario(speed_kmh=250.0), track=straight_track(), end_position=600.0,
                 irregularity=vertical_wave(amplitude, wavelength, 700.0, 0.05))
    result = simulate(sc)
    load = result.wheel("vertical_force")[result.position > 300.0]
    swing = 0.5 * (load.max(axis=0) - load.min(axis=0))
    vehicle, model = sc.vehicle, Simulation(sc).model
    omega = k * v
    half_mass = 0.5 * vehicle.wheelset_mass
    box = np.hypot(half_mass * omega**2 - vehicle.primary_vertical_stiffness, vehicle.primary_vertical_damping * omega)
    # Hertz: N ~ d^1.5, so the contact's stiffness at the static load P0 and approach d0 is 1.5 P0 / d0
    z0, _ = static_state(model)
    gap, ys = np.zeros(int(model.cg[GeometryHeader.wheel_points])), np.zeros(int(model.cg[GeometryHeader.wheel_points]))
    z_rigid, _, _, _ = rigid_contact(model.cg, 0.0, 0.0, gap, ys)
    contact = 1.5 * model.static_wheel_load / (z_rigid - z0)
    expected = box * amplitude / (1.0 - half_mass * omega**2 / contact)
    assert swing == pytest.approx(np.full(8, expected), rel=0.02)
