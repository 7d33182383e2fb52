"""The car the on-board monitor estimates: a built-in parameter set, or a file its user writes of its own
car's masses, heights and spacings (`load_car`; the example railderail_monitor/config/car-example.yaml, the
shipped car's values).

The file: `base:` a built-in set (railderail_sim.parameters.VEHICLE_SETS) whose values stand for those not
given, then any of CAR_FIELDS in SI (each a number); the car body's inertias scale with its mass as the
built-in sets' do. Everything else of the set (profiles, suspension dampers) the monitor does not read.
"""
from __future__ import annotations

from pathlib import Path

from railderail_sim.parameters import VEHICLE_SETS, vehicle_parameters
from railderail_sim.ranges import check_range

# the values the estimator and the measured levels read, with their unit and the largest value accepted
CAR_FIELDS = {
    "car_body_mass": ("kg", 200e3), "bogie_frame_mass": ("kg", 20e3), "wheelset_mass": ("kg", 5e3),
    "air_spring_semi_spacing": ("m", 2.0), "bogie_semi_distance": ("m", 20.0), "wheelbase_semi": ("m", 3.0),
    "secondary_height": ("m", 2.0), "bogie_frame_cog_height": ("m", 2.0), "rolling_radius": ("m", 1.0),
    "anti_roll_stiffness": ("N m/rad", 1e8), "secondary_vertical_stiffness": ("N/m", 1e8),
    "air_spring_emergency_stiffness": ("N/m", 1e9), "air_spring_emergency_clearance": ("m", 0.2),
}


def load_car(spec="hs19"):
    """VehicleParameters of a built-in set's name or of a car file's path (ValueError naming a bad key or
    value and what is accepted)."""
    if spec in VEHICLE_SETS:
        return vehicle_parameters(spec)
    path = Path(spec)
    if not path.is_file():
        raise ValueError(f"car {spec!r} is neither a built-in set ({', '.join(VEHICLE_SETS)}) nor a file")
    import yaml
    data = yaml.safe_load(path.read_text()) or {}
    if not isinstance(data, dict):
        raise ValueError(f"{path}: a car file is a mapping of base and {', '.join(CAR_FIELDS)}")
    base = data.pop("base", "hs19")
    if base not in VEHICLE_SETS:
        raise ValueError(f"{path}: base {base!r} is unknown; choose one of {', '.join(VEHICLE_SETS)}")
    unknown = sorted(set(data) - set(CAR_FIELDS))
    if unknown:
        raise ValueError(f"{path}: unknown key(s) {', '.join(unknown)}; the keys are base, {', '.join(CAR_FIELDS)}")
    values = {}
    for name, value in data.items():
        unit, top = CAR_FIELDS[name]
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{path}: {name} {value!r} must be a number in {unit}")
        values[name] = check_range(f"{path.name}: {name}", float(value), 0.0, top, unit, lo_open=True)
    return vehicle_parameters(base, **values)
