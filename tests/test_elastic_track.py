"""The elastic track (track.elastic): the co-running rails carry the wheels' forces as their springs say
(Newton's third law and the spring laws in steady curving), they bounce under a rail wave as the closed-form
wheel-rail-track receptances say, their Winkler reduction matches the beam's closed form, and on rigid
track they stay at zero without entering the error control."""
from dataclasses import replace
import math

import numpy as np
import pytest

from railderail_sim.contact.layout import ContactConstants
from railderail_sim.parameters import ElasticTrackParameters
from railderail_sim.track.layout import ElasticTrack
from railderail_sim.track.irregularity import vertical_wave
from railderail_sim.vehicle.assemble import static_contact
from railderail_sim.vehicle.layout import State
from railderail_sim.vehicle.simulate import (Simulation, output_arrays, scenario, simulate, state_tolerances,
                                             straight_track)


def test_the_winkler_reduction_is_the_beams_closed_form():
    # a rail (EI) on seats k every a: foundation modulus k/a, point stiffness 2 (k/a) / beta, beta^4 = k/(4 a EI);
    # numerically: Zhai's three layers in series give 28.1 MN/m per seat, 81 MN/m under a wheel
    e = ElasticTrackParameters()
    seat = 1.0 / (1.0 / 6.5e7 + 1.0 / 1.3775e8 + 1.0 / 7.75e7)
    beta = (seat / 0.6 / (4.0 * 2.059e11 * 3.217e-5)) ** 0.25
    mass, stiffness, damping = e.vertical
    assert stiffness == pytest.approx(2.0 * seat / 0.6 / beta, rel=1e-12)
    assert seat == pytest.approx(28.1e6, rel=2e-3) and stiffness == pytest.approx(81.3e6, rel=2e-3)
    # the beam's static shape w = exp(-beta|x|)(cos beta x + sin beta|x|): its square integrates to 3/(2 beta)
    x = np.linspace(-20.0, 20.0, 400001)
    w = np.exp(-beta * np.abs(x)) * (np.cos(beta * x) + np.sin(beta * np.abs(x)))
    assert np.trapezoid(w * w, x) == pytest.approx(1.5 / beta, rel=1e-6)
    assert mass > 1.5 * 60.64 / beta                   # the rail, and a share of sleeper and ballast
    # layers in series: each damper dissipates at its spring's share of the deflection
    k, c = e._series((2.0, 3.0), (2.0, 5.0))
    assert (k, c) == pytest.approx((1.0, 3.0 / 4.0 + 5.0 / 4.0), rel=1e-12)


def test_rigid_track_keeps_the_rails_at_zero_outside_the_error_control():
    tol = state_tolerances(1e-8)
    assert np.all(np.isinf(tol[State.rail_deflections.columns])) and np.all(np.isinf(tol[State.rail_rates.columns]))
    assert np.all(np.isfinite(tol[:State.rail_deflections]))
    rows = Simulation(scenario(radius=1000.0, speed_kmh=250.0)).advance(0.5)
    assert np.all(output_arrays(rows)["rails"] == 0.0)


def test_in_steady_curving_each_rail_carries_its_wheels_force_on_its_springs():
    sc = replace(scenario(radius=1000.0, speed_kmh=200.0), track_model="elastic", start_position=500.0,
                 end_position=900.0)
    result = simulate(sc)
    sup = Simulation(sc).model.support
    a = output_arrays(result.rows)
    last = -1                                           # 500 m into the circular curve: quasi-static
    rails = a["rails"][last]
    P, Q, e = a["vertical_force"][last], a["lateral_force"][last], a["contact_position"][last]
    assert np.all(P > 2e4)
    side = np.array([1.0, -1.0] * 4)                   # the field side: + left for the left rails
    # vertical: the rail is pressed down by the wheel's load; lateral: pushed toward the field side by Q
    assert np.allclose(-sup[ElasticTrack.vertical_stiffness] * rails[:, 1], P, rtol=2e-3, atol=50.0)
    assert np.allclose(side * sup[ElasticTrack.lateral_stiffness] * rails[:, 0], Q, rtol=2e-2, atol=150.0)
    # roll about the torsion centre (rail-top contacts: P at e from the head axis, Q at the centre's depth)
    tread = np.abs(e) < 0.008
    assert tread.sum() >= 3
    moment = -side * (e * P + sup[ElasticTrack.roll_centre_depth] * Q)
    assert np.allclose(sup[ElasticTrack.roll_stiffness] * rails[tread, 2], moment[tread], rtol=0.05, atol=20.0)


def test_a_vertical_rail_wave_bounces_wheel_and_rail_as_their_receptances_say():
    # both rails in a 0.2 mm, 1 m vertical sine at 250 km/h (69 Hz, above the 41 Hz P2 resonance): the
    # contact force swings by r / (contact + rail + wheel receptances), the rail a mass on its spring and
    # damper (and its roll seen at the contact's offset), the wheel its share of the wheelset on the axle box
    amplitude, wavelength, v = 2e-4, 1.0, 250.0 / 3.6
    k = 2.0 * np.pi / wavelength
    sc = replace(scenario(speed_kmh=250.0), track=straight_track(), end_position=600.0, track_model="elastic",
                 irregularity=vertical_wave(amplitude, wavelength, 700.0, 0.025))
    result = simulate(sc)
    after = result.position > 300.0
    load = result.wheel("vertical_force")[after]
    swing = 0.5 * (load.max(axis=0) - load.min(axis=0))
    model = Simulation(sc).model
    vehicle, sup = sc.vehicle, model.support
    w = k * v
    E = ElasticTrack
    P0 = model.static_wheel_load
    _, _, k_hertz = static_contact(model.cg, model.cp, P0)
    contact = 1.0 / (k_hertz + 1j * w * model.cp[ContactConstants.contact_damping] * P0)
    e = np.mean(output_arrays(result.rows)["contact_position"][after])
    rail = (1.0 / (sup[E.vertical_stiffness] + 1j * w * sup[E.vertical_damping] - sup[E.vertical_mass] * w * w)
            + e * e / (sup[E.roll_stiffness] + 1j * w * sup[E.roll_damping] - sup[E.roll_inertia] * w * w))
    wheel = 1.0 / (vehicle.primary_vertical_stiffness + 1j * w * vehicle.primary_vertical_damping
                   - 0.5 * vehicle.wheelset_mass * w * w)
    expected = amplitude / abs(contact + rail + wheel)
    assert swing == pytest.approx(np.full(8, expected), rel=0.02)
    # and the elastic track's answer is not the rigid one's
    rigid = amplitude / abs(1.0 / k_hertz + wheel)
    assert abs(expected - rigid) > 0.2 * rigid


def test_elastic_track_runs_are_reproducible_and_start_on_the_deflected_rails():
    sc = replace(scenario(radius=1000.0, speed_kmh=250.0), track_model="elastic")
    one, two = Simulation(sc), Simulation(sc)
    assert np.array_equal(one.advance(0.3), two.advance(0.3))
    first = output_arrays(Simulation(sc).advance(0.0))
    sink = sc.vehicle.static_wheel_load / Simulation(sc).model.support[ElasticTrack.vertical_stiffness]
    assert np.allclose(first["rails"][0, :, 1], -sink, rtol=0, atol=1e-12)
    assert np.allclose(first["vertical_force"], sc.vehicle.static_wheel_load, rtol=0.02)
    assert math.isfinite(first["wheel_lift"].sum())
