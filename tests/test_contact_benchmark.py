"""The Manchester contact benchmark, case A-2.2, against CONTACT's own reference output.

The reference (tests/data/mbench_a22_contact.json) is CONTACT's published result file for the case, with
Kalker's exact steady-rolling theory on a 0.2 mm grid: nothing in it comes from this code. CONTACT
prescribes each wheel's vertical force and the wheelset's pitch rate, as `contact_case` does with
`wheel_loads_kn` and `pitch_rate_rad_s`; the roll that CONTACT's input prescribes is the one this code
must find from the two loads. CONTACT's track axes have y to the right and z down: the wheelset shifts
and yaws toward the right rail, which here is a negative shift and yaw.
"""
import json
import math
from pathlib import Path

import pytest

from railderail_sim.methods.contact_case import contact_case
from railderail_sim.methods.wheel_rail_pair import build_pair

REFERENCE = json.loads((Path(__file__).parent / "data" / "mbench_a22_contact.json").read_text())
COLUMNS = REFERENCE["columns"]
# Shifts away from the jumps of the right wheel's contact (0-0.5 mm and 5-6 mm, where the two codes' contact
# searches may pick different points of a near two-point contact); the tread and the flange both in.
SHIFTS_MM = (1.0, 3.0, 4.5, 6.5, 8.0, 10.0)


def reference(side, y_mm):
    row = next(r for r in REFERENCE[side] if r[0] == y_mm)
    return dict(zip(COLUMNS, row))


@pytest.fixture(scope="module")
def a22():
    pair = build_pair("s1002", "uic60-mbench", gauge_mm=1435.0, inclination="1/40", back_to_back_mm=1360.0,
                      radius_m=0.46, friction=0.3, youngs_gpa=2.0 * 82.0 * (1.0 + 0.28), poisson=0.28,
                      model="hertz")
    cases = {}
    for y in SHIFTS_MM:
        left = reference("left", y)
        cases[y] = contact_case(pair, lateral_mm=-y, yaw_mrad=-left["yaw_ws_rad"] * 1e3, wheel_loads_kn=(10, 10),
                                speed_kmh=2.0 * 3.6, pitch_rate_rad_s=-left["vpitch_ws_rad_s"])
    return cases


def on_rail_in_contact_axes(case, side):
    """The wheel's force on its rail in CONTACT's axes (x forward, y right, z down)."""
    fx, fy, fz = case.wheels[0 if side == "left" else 1].force_on_rail_N
    return fx, -fy, -fz


@pytest.mark.parametrize("y", SHIFTS_MM)
def test_each_wheel_carries_its_prescribed_load(a22, y):
    for side in ("left", "right"):
        assert on_rail_in_contact_axes(a22[y], side)[2] == pytest.approx(10e3, rel=1e-9)


@pytest.mark.parametrize("y", SHIFTS_MM)
def test_the_wheel_loads_give_the_benchmark_roll(a22, y):
    """The roll that shares the two 10 kN loads is the roll CONTACT's input prescribes (from the rigid
    contact geometry of the same profiles), within 0.02 mrad; the flanging cases roll 4-11 mrad."""
    roll_ref = reference("left", y)["roll_ws_rad"]
    # CONTACT's roll is about its x axis with y right, z down: a right wheel rising is a negative roll in
    # both frames (the rotation and the axes mirror together).
    assert a22[y].pose.roll_rad == pytest.approx(roll_ref, abs=2e-5)


@pytest.mark.parametrize("y", SHIFTS_MM)
def test_the_lateral_forces_agree_with_contact_within_5_percent(a22, y):
    for side in ("left", "right"):
        fy = on_rail_in_contact_axes(a22[y], side)[1]
        assert fy == pytest.approx(reference(side, y)["fy_N"], rel=0.05), side


@pytest.mark.parametrize("y", SHIFTS_MM)
def test_the_longitudinal_forces_agree_with_contact_within_25_percent(a22, y):
    """Shen-Hedrick-Elkins on a Hertz ellipse against the exact theory: within 14 % on the tread, within 25 %
    on the flange, where the large spin (about 0.6 1/m here) takes from Fx what the simplified law keeps
    (docs/contact-report.md, the benchmark's section, has the whole table)."""
    for side in ("left", "right"):
        fx = on_rail_in_contact_axes(a22[y], side)[0]
        ref = reference(side, y)["fx_N"]
        assert math.copysign(1.0, fx) == math.copysign(1.0, ref), side
        assert fx == pytest.approx(ref, rel=0.25), side


def test_wheel_loads_refuse_a_wheelset_load_or_a_roll_beside_them():
    pair = build_pair("s1002", "uic60-mbench", model="hertz")
    with pytest.raises(ValueError, match="not both"):
        contact_case(pair, wheel_loads_kn=(10, 10), load_kn=20)
    with pytest.raises(ValueError, match="roll follows"):
        contact_case(pair, wheel_loads_kn=(10, 10), roll_mrad=0.1)
    with pytest.raises(ValueError, match=r"right wheel load --wheel-loads-kn -1 kN .*\(0, 500\] kN"):
        contact_case(pair, wheel_loads_kn=(10, -1))
    with pytest.raises(ValueError, match="two loads"):
        contact_case(pair, wheel_loads_kn=(10, 10, 10))


def test_a_pitch_rate_far_from_rolling_or_beside_free_spin_is_refused():
    pair = build_pair("s1002", "uic60-mbench", model="hertz")
    with pytest.raises(ValueError, match=r"pitch rate --pitch-rate-rad-s 1 rad/s .*v / r0"):
        contact_case(pair, speed_kmh=7.2, pitch_rate_rad_s=1.0)
    with pytest.raises(ValueError, match="spin free"):
        contact_case(pair, speed_kmh=7.2, pitch_rate_rad_s=4.35, spin="free")


def test_unequal_wheel_loads_are_carried_and_roll_the_wheelset():
    """30 kN on the left and 10 kN on the right on a centred wheelset: each carried, and the wheelset rolls
    toward the loaded wheel (its left side down: a negative roll lifts the right wheel)."""
    pair = build_pair("s1002", "uic60-mbench", model="hertz")
    case = contact_case(pair, wheel_loads_kn=(30, 10), speed_kmh=7.2)
    assert -case.wheels[0].force_on_rail_N[2] == pytest.approx(30e3, rel=1e-9)
    assert -case.wheels[1].force_on_rail_N[2] == pytest.approx(10e3, rel=1e-9)
    assert case.pose.roll_rad < 0.0


@pytest.mark.parametrize("y", (3.0, 8.0, 10.0))
def test_the_exact_rolling_theory_gives_contact_s_longitudinal_forces_within_3_percent(y):
    """The same cases with `--contact exact`: each patch (its Hertz normal force, the load shared by the
    simplified laws) solved by Kalker's exact steady rolling theory. Its longitudinal force is CONTACT's within
    3 % on the tread and on the flange, where Shen-Hedrick-Elkins is 15-23 % low; FASTSIM lies between."""
    pair = build_pair("s1002", "uic60-mbench", gauge_mm=1435.0, inclination="1/40", back_to_back_mm=1360.0,
                      radius_m=0.46, friction=0.3, youngs_gpa=2.0 * 82.0 * (1.0 + 0.28), poisson=0.28,
                      model="exact")
    left = reference("left", y)
    case = contact_case(pair, lateral_mm=-y, yaw_mrad=-left["yaw_ws_rad"] * 1e3, wheel_loads_kn=(10, 10),
                        speed_kmh=2.0 * 3.6, pitch_rate_rad_s=-left["vpitch_ws_rad_s"])
    for k, side in enumerate(("left", "right")):
        wheel = case.wheels[k]
        exact = sum(-p.exact_rolling.creep_force.longitudinal_N for p in wheel.patches)
        assert exact == pytest.approx(reference(side, y)["fx_N"], rel=0.03), side
        # the wheel's totals are the exact model's, the shared-load law's beside them
        assert wheel.creep_forces == "exact rolling"
        assert on_rail_in_contact_axes(case, side)[0] == pytest.approx(exact, rel=1e-12), side
        assert wheel.longitudinal_force_on_rail_N == pytest.approx(exact, rel=1e-12), side
        assert -wheel.laws["she"].force_on_rail_N[2] == pytest.approx(10e3, rel=1e-9), side
    if y == 8.0:        # the flanging right wheel: the figure of issue 26 (SHE -1692 N, CONTACT -2070 N)
        assert on_rail_in_contact_axes(case, "right")[0] == pytest.approx(reference("right", y)["fx_N"], rel=0.01)
        assert case.wheels[1].laws["she"].force_on_rail_N[0] == pytest.approx(-1692.0, abs=5.0)
