"""The car of the on-board monitor from a file its user writes (railderail_monitor.onboard.car)."""
from pathlib import Path

import pytest

from railderail_sim.parameters import vehicle_parameters
from railderail_monitor.onboard import measured as me
from railderail_monitor.onboard.car import load_car

EXAMPLE = Path(__file__).resolve().parents[1] / "railderail_monitor" / "config" / "car-example.yaml"


def test_the_shipped_example_is_the_shipped_car_and_a_built_in_name_is_its_set():
    assert load_car(str(EXAMPLE)) == vehicle_parameters("hs19")
    assert load_car("a380") == vehicle_parameters("a380")


def test_a_users_car_changes_what_the_monitor_estimates(tmp_path):
    path = tmp_path / "my-car.yaml"
    path.write_text("base: hs19\ncar_body_mass: 40000\nair_spring_semi_spacing: 1.0\n")
    car = load_car(str(path))
    assert (car.car_body_mass, car.air_spring_semi_spacing) == (40000.0, 1.0)
    assert car.car_body_yaw_inertia == pytest.approx(vehicle_parameters("hs19").car_body_yaw_inertia * 40 / 32)
    # its levels follow: the roll at the emergency spring over the springs' semi-spacing, the twist's 3 sigma
    assert me.measured_limits(car).car_body_roll == pytest.approx(0.035 / 1.0)
    assert me.measured_limits(car).car_body_twist == pytest.approx(3 * 0.5e-3 / 1.0)


@pytest.mark.parametrize("text, message", [
    ("base: hs19\ncar_mass: 1\n", "unknown key.s. car_mass; the keys are base, car_body_mass"),
    ("base: velaro\n", "base 'velaro' is unknown"),
    ("car_body_mass: -5\n", r"car_body_mass -5 kg is outside the accepted range \(0, 200000\]"),
    ("car_body_mass: heavy\n", "car_body_mass 'heavy' must be a number in kg"),
])
def test_a_bad_car_file_is_refused_with_a_sentence(tmp_path, text, message):
    path = tmp_path / "car.yaml"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        load_car(str(path))
    with pytest.raises(ValueError, match="neither a built-in set"):
        load_car(str(tmp_path / "missing.yaml"))
