"""`railderail import-imu` (recording.import_imu): a logger's CSV into the recording the measured-mode monitor
replays. The shipped example's recording carries its readings (read here by name from the CSV, apart from
the importer), its replay gives the on-board criteria's alerts over those readings, other units of measure
and the direction of running give the same recording, and a bad log is refused with one line."""
import io
import json
import math

import numpy as np
import pytest

from railderail_sim.cli import main
from railderail_sim.parameters import GRAVITY
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.sensors.config import load as load_sensors
from railderail_monitor.onboard import measured as me
from railderail_monitor.onboard.car import load_car
from railderail_monitor.recording import import_imu as ii
from railderail_monitor.recording.replay import measured_key, read_recording


def _columns(path):
    """{column: values} of a CSV, by numpy, NaN where empty."""
    return _table(path.read_text())


def _table(text):
    rows = [line for line in text.splitlines() if not line.startswith("#")]
    table = np.genfromtxt(io.StringIO("\n".join(rows)), delimiter=",", names=True)
    return {name: table[name] for name in table.dtype.names}


def _decoded(mcap, height_m=0.2):
    record = sm.SensorRecord(height_m=height_m)
    for topic, _, _, _, msg in read_recording(mcap).messages:
        record.add(topic, msg)
    return record.arrays()


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    out = tmp_path_factory.mktemp("example") / "ride.mcap"
    assert main(["import-imu", str(ii.EXAMPLE), str(out)]) == 0
    return out, out.with_name("ride.sensors.yaml")


def test_the_example_s_recording_carries_its_readings(example):
    out, sensors = example
    csv, got = _columns(ii.EXAMPLE), _decoded(out)
    for unit, signals in (("car_body_centre", ("acc", "gyro")), ("bogie_rear_frame", ("acc",))):
        rows = ~np.isnan(csv[f"{unit}_acc_x_m_s2"])
        assert np.allclose(got[f"sensor_{unit}_time"], csv["time_s"][rows], rtol=0, atol=1e-9)
        for signal, key in (("acc", "acceleration"), ("gyro", "angular_rate")):
            expected = (np.stack([csv[f"{unit}_{signal}_{a}_{'m_s2' if signal == 'acc' else 'rad_s'}"][rows]
                                  for a in "xyz"], axis=1) if signal in signals else None)
            assert (f"sensor_{unit}_{key}" in got) == (expected is not None)
            if expected is not None:
                assert np.array_equal(got[f"sensor_{unit}_{key}"], expected)
    springs = ~np.isnan(csv["air_spring_rear_right_height_m"])
    # the height travels as a float32 Range
    assert np.allclose(got["sensor_air_springs_deflection"][:, 3], 0.2 - csv["air_spring_rear_right_height_m"][springs],
                       rtol=0, atol=1e-7)
    assert np.array_equal(got["sensor_air_springs_pressure"][:, 0], csv["air_spring_front_left_pressure_pa"][springs])
    assert np.array_equal(got["sensor_odometer_speed"], csv["odometer_speed_m_s"][~np.isnan(csv["odometer_speed_m_s"])])
    # and written back as a log (csv_text, which wrote the example from a run's arrays): the same table
    again = _table(ii.csv_text(got))
    assert list(again) == list(csv)
    for name, values in csv.items():
        assert np.array_equal(np.isnan(again[name]), np.isnan(values)), name
        assert np.allclose(again[name], values, rtol=1e-6, atol=1e-7, equal_nan=True), name
    # the sensor file names the log's mounts at the log's rates
    rates = me.sample_rates(load_sensors(sensors))
    assert rates == {"car_body_front": 100.0, "car_body_centre": 100.0, "car_body_rear": 100.0,
                     "bogie_front_frame": 100.0, "bogie_rear_frame": 100.0, "air_springs": 25.0, "odometer": 10.0}


def test_the_example_replays_to_the_criteria_s_alerts_over_its_readings(example, capsys):
    out, sensors = example
    capsys.readouterr()
    assert main(["replay", str(out), "--signals", "measured", "--sensors", str(sensors), "--no-publish", "--json"]) == 0
    replayed = json.loads(capsys.readouterr().out)["alerts"]
    assert replayed, "the example's hunting car must raise measured alerts"
    # the batch definition of the criteria over the readings the recording carries
    car = load_car("hs19")
    limits = me.measured_limits(car)
    found = me.evaluate(_decoded(out), car, limits, me.sample_rates(load_sensors(sensors)))
    assert sorted(map(measured_key, replayed)) == sorted(map(measured_key, me.alerts(found, limits)))


def _rewritten(path, rename, change):
    """The CSV at `path` with its header's names through `rename` and each column's values through
    `change(name, values)` (the new name)."""
    lines = [line for line in path.read_text().splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    cells = [line.split(",") for line in lines[1:]]
    new = [rename(name) for name in header]
    for k, name in enumerate(new):
        for row in cells:
            if row[k]:
                row[k] = repr(change(name, float(row[k])))
    return "\n".join([",".join(new)] + [",".join(row) for row in cells]) + "\n"


def test_other_units_and_the_car_running_reversed_give_the_same_recording(example, tmp_path):
    """The example written as a logger on the car turned end for end would log it (every name front <-> rear,
    left <-> right, x and y of each reading negated) and in g, deg/s, mm, kPa and km/h: imported with
    --running reversed it is the example's recording."""
    swap = {"front": "rear", "rear": "front", "left": "right", "right": "left"}
    units = {"m_s2": ("g", 1.0 / GRAVITY), "rad_s": ("deg_s", 180.0 / math.pi), "height_m": ("height_mm", 1e3),
             "pressure_pa": ("pressure_kpa", 1e-3), "speed_m_s": ("speed_kmh", 3.6)}

    def rename(name):
        for si, (other, _) in units.items():
            if name.endswith("_" + si):
                name = name[:-len(si)] + other
        return "_".join(swap.get(part, part) for part in name.split("_"))

    def change(name, value):
        scale = next((s for si, (other, s) in units.items() if name.endswith("_" + other)), 1.0)
        turned = -1.0 if any(f"_{axis}_" in name for axis in ("acc_x", "acc_y", "gyro_x", "gyro_y")) else 1.0
        return value * scale * turned

    log = tmp_path / "reversed.csv"
    log.write_text(_rewritten(ii.EXAMPLE, rename, change))
    out = tmp_path / "reversed.mcap"
    assert main(["import-imu", str(log), str(out), "--running", "reversed"]) == 0
    original, again = _decoded(example[0]), _decoded(out)
    assert set(again) == set(original)
    for key, values in original.items():
        assert np.allclose(again[key], values, rtol=1e-12, atol=1e-7), key
    # forward, the same log is another car: its front frame reads the example's rear frame turned
    assert main(["import-imu", str(log), str(tmp_path / "forward.mcap")]) == 0
    forward = _decoded(tmp_path / "forward.mcap")
    assert np.allclose(forward["sensor_bogie_front_frame_acceleration"][:, :2],
                       -original["sensor_bogie_rear_frame_acceleration"][:, :2], rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("text, args, message", [
    ("time_s,car_roof_acc_x_m_s2\n0,1\n", (), "column 'car_roof_acc_x_m_s2' is not one the import reads"),
    ("time_s,car_body_front_acc_x_m_s2,car_body_front_acc_y_m_s2\n0,1,2\n",
     (), "car_body_front acc: no column for axis z"),
    ("time_s,odometer_speed_kmh,car_body_front_acc_x_g,car_body_front_acc_y_g,car_body_front_acc_z_g\n"
     "0,100,0,0,1\n0.01,100,0,,1\n", (), "IMU log LOG, data row 2: car_body_front has some cells filled and "
     "car_body_front_acc_y_g empty"),
    ("time_s,odometer_speed_m_s\n0.1,50\n0.1,50\n", (), "odometer's time_s 0.1 is not after its previous sample's"),
    ("time_s,bogie_frame_1_acc_x_g,bogie_frame_1_acc_y_g,bogie_frame_1_acc_z_g\n0,0,0,1\n0.01,0,0,1\n",
     ("--running", "reversed"), "mount bogie_frame_1 is over wheelset 1's left axle box"),
    ("time_s,odometer_speed_m_s\n0,x\n0.1,50\n", (), "column odometer_speed_m_s: 'x' is not a number"),
])
def test_a_bad_log_is_refused_with_one_line(tmp_path, capsys, text, args, message):
    log = tmp_path / "log.csv"
    log.write_text(text)
    assert main(["import-imu", str(log), str(tmp_path / "out.mcap"), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert message.replace("LOG", str(log)) in err and "\n" not in err
    assert not (tmp_path / "out.mcap").exists()
