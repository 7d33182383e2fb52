"""Suspension travel limits and faults (vehicle.assemble.FAULTS), checked against statics and stability.

The static checks run the car at 50 km/h on straight track with a fault until it has settled (12 s); each
element's travel is read from the settled state with the core's own kinematics, a stop's force from its law.
"""
import math
from dataclasses import replace

import numpy as np
import pytest

from railderail_sim.cli import main
from railderail_sim.methods import root_locus as rl
from railderail_sim.parameters import GRAVITY, vehicle_parameters
from railderail_sim.vehicle import dynamics as dyn
from railderail_sim.vehicle import integrator as itg
from railderail_sim.vehicle.assemble import FAULT_NAMES, failed_elements
from railderail_sim.vehicle.layout import BOGIES, CAR_BODY, VERTICAL, WHEELSETS, BumpStop, Bushing, Vector
from railderail_sim.vehicle.simulate import Scenario, Simulation, constant_speed, scenario, simulate, straight_track

SETTLE_S = 12.0
FRONT = BOGIES[0]


def settled(*faults):
    """A Simulation of the car on straight track at 50 km/h with `faults`, settled."""
    sim = Simulation(Scenario(track=straight_track(), speed_table=constant_speed(50.0), faults=faults))
    sim.advance(SETTLE_S)
    return sim


def travel(sim, row, point_a, point_b):
    """Displacement (x, y, z) of body b's point from body a's, in body a's axes (as dynamics.suspension)."""
    kin = itg.workspace(sim.model.cg).rhs.kin
    dyn.kinematics(sim.x, sim.model.bodies, sim.model.track, sim.speed_table, kin)
    a, b = int(row[Bushing.body_a]), int(row[Bushing.body_b])
    pa = dyn._point(kin, a, *row[point_a.columns])
    pb = dyn._point(kin, b, *row[point_b.columns])
    return dyn._to_body_axes(kin, a, pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2])


def vertical_stops(sim, body_a, body_b, side):
    """{on the left: row} of the vertical stops between two bodies acting on `side` ("negative"/"positive")."""
    clearance = BumpStop.clearance_negative if side == "negative" else BumpStop.clearance_positive
    return {bool(row[BumpStop.point_a + Vector.y] > 0.0): row for row in sim.model.bump
            if int(row[BumpStop.axis]) == VERTICAL and int(row[BumpStop.body_a]) == body_a
            and int(row[BumpStop.body_b]) == body_b and math.isfinite(row[clearance])}


def stop_force(sim, row):
    """The stop's force (N, magnitude) and its vertical travel (m) in the settled state."""
    d = travel(sim, row, BumpStop.point_a, BumpStop.point_b)[2]
    clear = row[BumpStop.clearance_positive] if d > 0.0 else row[BumpStop.clearance_negative]
    return dyn.bump_force(row, abs(d), clear), d


def test_deflated_air_springs_put_the_car_body_share_on_the_emergency_springs():
    sim = settled("air-spring-deflated@front")
    vp = sim.model.vehicle
    # the car body on two bogies: each carries half its weight, whatever the springs under it
    share = vp.car_body_mass * GRAVITY / 4.0
    sink = vp.air_spring_emergency_clearance + share / vp.air_spring_emergency_stiffness
    emergency = vertical_stops(sim, FRONT, CAR_BODY, "negative")
    assert len(emergency) == 2
    for row in emergency.values():
        force, d = stop_force(sim, row)
        assert force == pytest.approx(share, rel=0.02)
        assert -d == pytest.approx(sink, rel=0.02)
    # the rear air springs keep the load, their emergency springs stay free
    for row in vertical_stops(sim, BOGIES[1], CAR_BODY, "negative").values():
        assert stop_force(sim, row)[0] == 0.0


def test_a_broken_primary_spring_puts_its_load_on_the_primary_stop():
    sim = settled("primary-spring-broken@0-left")
    vp = sim.model.vehicle
    box_load = (0.5 * vp.car_body_mass + vp.bogie_frame_mass) * GRAVITY / 4.0
    force, d = stop_force(sim, vertical_stops(sim, FRONT, WHEELSETS[0], "positive")[True])
    assert d > vp.primary_stop_clearance                      # the frame corner came down onto the stop
    # it takes over a good part of the box's load (how much, the frame's warp against the three other
    # springs, the anti-roll bar and the guidance decide); the other stops of the bogie stay free
    assert box_load / 3.0 < force < box_load
    others = [vertical_stops(sim, FRONT, WHEELSETS[0], "positive")[False],
              *vertical_stops(sim, FRONT, WHEELSETS[1], "positive").values()]
    assert [stop_force(sim, row)[0] for row in others] == [0.0, 0.0, 0.0]
    # statics: the front bogie's boxes (three springs and the stop) still carry its share of the car
    springs = 0.0
    for row in sim.model.bush:
        if int(row[Bushing.body_a]) == FRONT and int(row[Bushing.body_b]) in WHEELSETS[:2]:
            dz = travel(sim, row, Bushing.point_a, Bushing.point_b)[2]
            springs -= row[Bushing.preload + Vector.z] - row[Bushing.stiffness + Vector.z] * dz
    assert springs + force == pytest.approx(4.0 * box_load, rel=0.02)


def test_failed_yaw_dampers_lower_the_linear_critical_speed():
    speeds = np.linspace(100.0, 600.0, 26)
    healthy = rl.root_locus(Scenario(), speeds).linear_critical_speed_kmh
    failed = rl.root_locus(Scenario(faults=("yaw-dampers-failed@both",)), speeds).linear_critical_speed_kmh
    assert math.isfinite(healthy) and math.isfinite(failed)
    assert failed < 0.8 * healthy


@pytest.mark.parametrize("faults, message", [
    (("wheel-lost@front",), r"fault 'wheel-lost@front' is unknown; .* yaw-dampers-failed, lateral-damper-failed, "
                            r"air-spring-deflated, primary-spring-broken"),
    (("air-spring-deflated@middle",), r"location 'middle' is not one of front-left, front-right, front, rear-left, "
                                      r"rear-right, rear"),
    (("primary-spring-broken@4-left",), r"location '4-left' is not one of 0-left, 0-right, 1-left"),
    ("yaw-dampers-failed@front", r"must be a sequence of fault names"),
    (("yaw-dampers-failed@both", "yaw-dampers-failed@both"), r"yaw-dampers-failed@both given more than once"),
])
def test_unknown_faults_are_refused_with_the_accepted_ones(faults, message):
    with pytest.raises(ValueError, match=message):
        Scenario(faults=faults).validated()


def test_an_unknown_fault_on_the_command_line_is_one_line_and_status_2(capsys):
    assert main(["simulate", "--fault", "yaw-dampers-failed@middle"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "front, rear, both" in err


def test_every_fault_name_takes_out_elements():
    assert all(failed_elements((name,)) for name in FAULT_NAMES)


def test_stops_not_engaged_leave_the_run_bit_identical():
    """Up to 260 m at 300 km/h on R 1000 m the lateral stops are engaged and the vertical ones not yet: the
    run with the vertical stops is the run without them, bit for bit."""
    sc = replace(scenario(radius=1000.0, speed_kmh=300.0), end_position=260.0)
    free = dict(primary_stop_clearance=math.inf, air_spring_emergency_clearance=math.inf,
                air_spring_extension_clearance=math.inf)
    with_stops = simulate(sc)
    without = simulate(replace(sc, vehicle=vehicle_parameters(**free)))
    assert np.array_equal(with_stops.rows, without.rows)


def test_the_simulator_node_takes_faults_as_a_string_array():
    from railderail_sim.ros.node import PARAMETERS
    (spec,) = [spec for spec in PARAMETERS if spec.name == "faults"]
    assert spec.checked(None) == []                   # [] in a parameter file: rcl leaves it unset
    assert spec.checked(["yaw-dampers-failed@both", "air-spring-deflated@rear"]) == \
        ["yaw-dampers-failed@both", "air-spring-deflated@rear"]
    with pytest.raises(ValueError, match=r"faults: 'yaw-dampers-failed@middle' is not one of yaw-dampers-failed@front"):
        spec.checked(["yaw-dampers-failed@middle"])
    with pytest.raises(ValueError, match="is not a list of strings"):
        spec.checked("yaw-dampers-failed@both")
