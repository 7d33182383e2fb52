"""Virtual on-board sensors (railderail_sim.sensors): closed cases of a car on cant and in steady curving
with the noise off, the noise's statistics against its density and the filter's bandwidth, the bias's
random walk, determinism from the seed, quantisation and range, latency and lost samples, the odometer,
the air springs' load, the sensor file and its refusals."""
from dataclasses import replace
import math

import numpy as np
import pytest
from scipy import signal

from railderail_sim.parameters import GRAVITY as G, TrackParameters
from railderail_sim.sensors import config
from railderail_sim.sensors.instruments import INSTRUMENTS, Instrument
from railderail_sim.sensors.measure import Readings, SensorLog, SensorStream, noise_bandwidth, filter_sections
from railderail_sim.sensors.sensor_set import AIR_SPRING_EFFECTIVE_AREA, MOUNTS, Mount, Odometer, Sampling, SensorSet
from railderail_sim.vehicle.layout import N_BODY, Body, BodyMotion, Dof
from railderail_sim.vehicle.simulate import Scenario, constant_speed, scenario, simulate


def _in_curve(radius, cant, speed_kmh, seconds):
    """The arrays and the sensors' log of a run starting 100 m into the circular curve."""
    track = TrackParameters(radius=radius, cant_height=cant)
    start = track.straight_in + track.transition_in + 100.0
    sc = replace(scenario(radius=radius, speed_kmh=speed_kmh), track=track, speed_table=constant_speed(speed_kmh),
                 start_position=start, end_position=start + speed_kmh / 3.6 * seconds)
    log = SensorLog(config.default_set().quiet())
    result = simulate(sc, observe=log.observe)
    return result.arrays(), log.arrays(), sc


@pytest.fixture(scope="module")
def at_rest_on_cant():
    """30 km/h on a 20 km curve with 150 mm cant (centripetal 0.0035 m/s^2: at rest on the cant to 0.04 % of g)."""
    return _in_curve(20000.0, 0.150, 30.0, 8.0)


def _settled(times, t0):
    return times > t0


def test_a_car_at_rest_on_cant_reads_g_sin_cant_laterally(at_rest_on_cant):
    a, s, _ = at_rest_on_cant
    cant = math.asin(0.150 / 1.5)
    t = s["sensor_bogie_front_frame_time"]
    late = _settled(t, 5.0)

    def roll_to_ground(body):      # the low (left) side down
        return cant - np.interp(t, a["time"], a["body_states"][:, body, Dof.roll])

    # the frame and the car body lean toward the low rail on their springs: g sin of their roll to the ground
    for mount, body in (("bogie_front_frame", Body.front_bogie), ("car_body_centre", Body.car_body)):
        reading, roll = s[f"sensor_{mount}_acceleration"], roll_to_ground(body)
        assert np.mean(-reading[late, 1]) == pytest.approx(np.mean(G * np.sin(roll[late])), rel=0.01)
        assert np.mean(reading[late, 2]) == pytest.approx(np.mean(G * np.cos(roll[late])), rel=1e-3)
    # within a few percent of the cant's own g sin(cant) = 0.981 m/s^2
    assert np.mean(-s["sensor_bogie_front_frame_acceleration"][late, 1]) == pytest.approx(G * math.sin(cant),
                                                                                        rel=0.06)
    # an IEPE axle-box accelerometer is AC coupled: it does not see the cant
    box = s["sensor_axle_box_0_left_acceleration"]
    assert abs(np.mean(box[late, 1])) < 0.02 * G * math.sin(cant)


@pytest.fixture(scope="module")
def steady_curving():
    return _in_curve(1000.0, 0.175, 200.0, 6.0)


def test_steady_curving_reads_the_uncompensated_acceleration(steady_curving):
    a, s, sc = steady_curving
    v = 200.0 / 3.6
    theta = sc.track.cant_angle
    uncompensated = sc.track.uncompensated_acceleration(v)
    late = _settled(s["sensor_car_body_centre_time"], 3.0)
    # the frame and the car body roll outward on their springs by phi (to the track): they read
    # a_nc cos(phi) + (g cos(theta) + v^2/R sin(theta)) sin(phi)
    normal = G * math.cos(theta) + v * v / 1000.0 * math.sin(theta)
    for mount, body in (("bogie_rear_frame", Body.rear_bogie), ("car_body_centre", Body.car_body)):
        roll = np.interp(s[f"sensor_{mount}_time"], a["time"], a["body_states"][:, body, Dof.roll])
        expected = uncompensated * np.cos(roll) + normal * np.sin(roll)
        assert np.mean(s[f"sensor_{mount}_acceleration"][late, 1]) == pytest.approx(np.mean(expected[late]), rel=5e-3)
    # the frame's roll is small: within 5 % of the uncompensated acceleration itself
    assert np.mean(s["sensor_bogie_rear_frame_acceleration"][late, 1]) == pytest.approx(uncompensated, rel=0.05)
    # the gyros read the turning of the track, v / R about the vertical: v / R cos(theta - phi) about the body's
    # z axis (the track plane rolled by -theta, the body by phi to it)
    assert np.mean(s["sensor_car_body_centre_angular_rate"][late, 2]) == pytest.approx(
        np.mean(v / 1000.0 * np.cos(theta - roll[late])), rel=1e-3)
    # the air springs carry the car body's weight and its centripetal force along the track normal
    springs = _settled(s["sensor_air_springs_time"], 3.0)
    load = np.sum(s["sensor_air_springs_pressure"][springs], axis=1) * AIR_SPRING_EFFECTIVE_AREA
    assert np.mean(load) == pytest.approx(sc.vehicle.car_body_mass * normal, rel=0.01)
    # the outer (right) springs are compressed more than the inner ones
    deflection = np.mean(s["sensor_air_springs_deflection"][springs], axis=0)
    assert deflection[1] > deflection[0] and deflection[3] > deflection[2]
    # the odometer counts 2 pi r0 / 200 per pulse: 0.52 km/h per pulse in 0.1 s
    speed = s["sensor_odometer_speed"]
    assert np.all(np.abs(speed - v) <= 2.0 * math.pi * sc.vehicle.rolling_radius / 200 * 10.0 + 1e-9)
    assert np.mean(speed) == pytest.approx(v, rel=2e-3)


# --- synthetic motion: the sensor models alone ------------------------------------------------------

def _synthetic(n, rate, lateral=None, position=None):
    """Output arrays of a car body at rest (specific force +g up) with an optional lateral specific force."""
    motion = np.zeros((n, N_BODY, BodyMotion.size()))
    motion[:, :, BodyMotion.specific_force + 2] = G
    if lateral is not None:
        motion[:, Body.car_body, BodyMotion.specific_force + 1] = lateral
    t = np.arange(n) / rate
    return dict(time=t, position=np.zeros(n) if position is None else position, body_motion=motion,
                body_states=np.zeros((n, N_BODY, 5)))


def _one_mount(inst, gyro=None, rate=200.0, seed=0, **sampling):
    return SensorSet(seed=seed, mounts=(Mount(name="car_body_centre", accelerometer=inst, gyro=gyro,
                                              sampling=Sampling(rate, **sampling)),),
                     instruments={inst.name: inst})


NOISY = Instrument(name="noisy", quantity="acceleration", unit="m/s^2", noise_density=1.0e-3)


def test_the_noise_rms_is_the_noise_density_times_the_root_of_the_filters_noise_bandwidth():
    sc = replace(Scenario(), output_rate=1000.0)
    gyro = replace(INSTRUMENTS["adis16470"], bias=0.0, bias_random_walk=0.0, bits=0)
    stream = SensorStream(_one_mount(NOISY, gyro), sc)
    out = stream.process(_synthetic(200000, 1000.0))["car_body_centre"]
    # a 4th-order Butterworth at 50 Hz, far below the 500 Hz Nyquist: (pi / 8) / sin(pi / 8) times 50 Hz
    bandwidth = 50.0 * (math.pi / 8.0) / math.sin(math.pi / 8.0)
    assert noise_bandwidth(filter_sections(NOISY, Sampling(200.0), 1000.0), 1000.0) == pytest.approx(bandwidth, rel=2e-3)
    noise = out["acceleration"] - [0.0, 0.0, G]
    # 40000 nearly independent samples: the r.m.s. to 1 % (3 sigma 1.1 %)
    assert np.sqrt(np.mean(noise ** 2, axis=0)) == pytest.approx([1e-3 * math.sqrt(bandwidth)] * 3, rel=0.02)
    assert np.abs(np.mean(noise, axis=0)).max() < 4.0 * 1e-3 * math.sqrt(bandwidth) / math.sqrt(40000.0 / 2.0)
    # the gyro's, 2nd order: (pi / 4) / sin(pi / 4)
    rate_bandwidth = 50.0 * (math.pi / 4.0) / math.sin(math.pi / 4.0)
    assert np.sqrt(np.mean(out["angular_rate"] ** 2, axis=0)) == pytest.approx(
        [gyro.noise_density * math.sqrt(rate_bandwidth)] * 3, rel=0.02)


def test_the_bias_is_constant_from_the_seed_and_its_random_walk_grows_with_the_root_of_time():
    sc = replace(Scenario(), output_rate=200.0)
    walking = Instrument(name="walking", quantity="acceleration", unit="m/s^2", bias=0.01, bias_random_walk=0.002)
    ends, starts = [], []
    for seed in range(300):
        out = SensorStream(_one_mount(walking, seed=seed), sc).process(_synthetic(2001, 200.0))["car_body_centre"]
        starts.append(out["acceleration"][0, :2])
        ends.append(out["acceleration"][-1, :2] - out["acceleration"][0, :2])
    # 600 draws each: the standard deviations to 3 sigma = 9 %
    assert np.std(starts) == pytest.approx(0.01, rel=0.09)
    assert np.std(ends) == pytest.approx(0.002 * math.sqrt(10.0), rel=0.09)


def test_the_same_seed_gives_the_same_signals_bit_for_bit_whatever_the_chunks():
    sc = replace(Scenario(), output_rate=200.0)
    t = np.arange(3001) / 200.0
    arrays = _synthetic(3001, 200.0, lateral=0.5 * np.sin(2 * math.pi * 1.3 * t), position=55.0 * t)
    # unquantised, so that no rounding of the last bit is hidden by the resolution
    accelerometer = replace(INSTRUMENTS["adxl355"], bits=0, bias_random_walk=0.01)
    sensors = replace(_one_mount(accelerometer, INSTRUMENTS["adis16470"], rate=100.0, seed=7, dropout=0.05),
                      odometer=Odometer(sampling=Sampling(10.0, dropout=0.05)))
    whole = SensorStream(sensors, sc).process(arrays)
    chunked = SensorStream(sensors, sc)
    parts = [chunked.process({k: v[i:i + 7] for k, v in arrays.items()}) for i in range(0, 3001, 7)]
    for unit, signals in whole.items():
        for name, values in signals.items():
            again = np.concatenate([p[unit][name] for p in parts])
            assert again.tobytes() == values.tobytes(), (unit, name)
    other = SensorStream(replace(sensors, seed=8), sc).process(arrays)
    assert not np.array_equal(other["car_body_centre"]["acceleration"][:100],
                              whole["car_body_centre"]["acceleration"][:100])


def test_a_variant_over_its_set_s_shared_readings_reads_what_it_draws_alone():
    """The warning evaluation's sensor variants share the run's ideal readings and noise draws: a variant with
    other noise and bias scales and another rate reads, bit for bit, what its own stream draws; readings
    drawn for another seed or another length are refused, as is a stream that has already taken rows."""
    sc = replace(Scenario(), output_rate=200.0)
    t = np.arange(2001) / 200.0
    arrays = _synthetic(2001, 200.0, lateral=0.5 * np.sin(2 * math.pi * 1.3 * t), position=55.0 * t)
    accelerometer = replace(INSTRUMENTS["adxl355"], bits=0, bias_random_walk=0.01)
    gyro = INSTRUMENTS["adis16470"]
    sensors = replace(_one_mount(accelerometer, gyro, seed=7), instruments={i.name: i for i in (accelerometer, gyro)})
    stream = SensorStream(sensors, sc)
    shared = Readings(stream.ideal(arrays), stream.noise_draws(2001), stream.draw_units)
    variant = sensors.scaled(3.0, 0.5).resampled(100.0)
    alone = SensorStream(variant, sc).process(arrays)
    over_shared = SensorStream(variant, sc).process(arrays, shared)
    for name, values in alone["car_body_centre"].items():
        assert over_shared["car_body_centre"][name].tobytes() == values.tobytes(), name
    other_seed = SensorStream(replace(sensors, seed=8), sc)
    with pytest.raises(ValueError, match="units"):
        other_seed.process(arrays, shared)
    with pytest.raises(ValueError, match="rows"):
        SensorStream(sensors, sc).process({k: v[:2000] for k, v in arrays.items()}, shared)
    started = SensorStream(sensors, sc)
    started.process({k: v[:10] for k, v in arrays.items()})
    with pytest.raises(ValueError, match="at row 10"):
        started.process(arrays, shared)


def test_readings_are_clipped_to_the_range_and_quantised_to_the_resolution():
    coarse = Instrument(name="coarse", quantity="acceleration", unit="m/s^2", range_low=-2 * G, range_high=2 * G,
                        bits=8)
    lsb = 4 * G / 256
    n = 4001
    ramp = np.linspace(-30.0, 30.0, n)          # 3 m/s^2 per second: the low-pass lags it by 9 ms, 0.03 m/s^2
    out = SensorStream(_one_mount(coarse), replace(Scenario(), output_rate=200.0)).process(
        _synthetic(n, 200.0, lateral=ramp))["car_body_centre"]["acceleration"][:, 1]
    codes = (out + 2 * G) / lsb
    assert np.allclose(codes, np.round(codes), atol=1e-9)
    assert out.min() == pytest.approx(-2 * G) and out.max() == pytest.approx(2 * G - lsb)
    inside = np.abs(ramp) < 2 * G - lsb
    assert np.all(np.abs(out[inside] - ramp[inside]) <= lsb / 2 + 0.03)
    assert np.all(out[ramp > 2 * G] == out.max()) and np.all(out[ramp < -2 * G] == out.min())


def test_latency_shifts_the_stamps_and_dropouts_lose_their_share_of_samples():
    sensors = _one_mount(INSTRUMENTS["adxl355"], rate=100.0, latency_s=0.015, dropout=0.2)
    out = SensorStream(sensors, replace(Scenario(), output_rate=200.0)).process(_synthetic(20001, 200.0))
    stamps = out["car_body_centre"]["time"]
    assert np.allclose(np.round((stamps - 0.015) * 100.0), (stamps - 0.015) * 100.0, atol=1e-6)
    # 10001 samples, 20 % lost: 2000 +- 3 x 40
    assert 10001 - len(stamps) == pytest.approx(2000, abs=120)


def test_the_frame_over_each_wheelset_reads_the_frame_s_yaw_acceleration_times_half_the_wheelbase():
    """EN 14363 reads the bogie frame over each wheelset: a frame turning at yaw acceleration alpha reads
    +-a alpha laterally there (a the half wheelbase, + over the leading wheelset) and -alpha b_p forward
    (over the left axle box, b_p to the left of the centre line), nothing at its centre."""
    from railderail_sim.parameters import VehicleParameters
    vp = VehicleParameters()
    alpha = {Body.front_bogie: 0.8, Body.rear_bogie: -1.7}              # rad/s^2
    a = _synthetic(400, 200.0)
    for body, value in alpha.items():
        a["body_motion"][:, body, BodyMotion.angular_acceleration + 2] = value
    frames = [m for m in config.default_set().quiet().mounts if "frame" in m.name]
    assert [m.name for m in frames] == ["bogie_front_frame", "bogie_rear_frame"] + [f"bogie_frame_{w}" for w in range(4)]
    sensors = SensorSet(mounts=tuple(frames), instruments=config.default_set().quiet().instruments)
    out = SensorStream(sensors, replace(Scenario(), output_rate=200.0)).process(a)
    for name, body, x in (("bogie_frame_0", Body.front_bogie, 1.0), ("bogie_frame_1", Body.front_bogie, -1.0),
                          ("bogie_frame_2", Body.rear_bogie, 1.0), ("bogie_frame_3", Body.rear_bogie, -1.0),
                          ("bogie_front_frame", Body.front_bogie, 0.0), ("bogie_rear_frame", Body.rear_bogie, 0.0)):
        reading = out[name]["acceleration"]
        lsb = frames[0].accelerometer.resolution
        assert np.allclose(reading[:, 1], x * vp.wheelbase_semi * alpha[body], atol=lsb), name
        forward = 0.0 if x == 0.0 else -alpha[body] * vp.primary_semi_spacing
        assert np.allclose(reading[:, 0], forward, atol=lsb), name
        assert np.allclose(reading[:, 2], G, atol=lsb), name
    assert "angular_rate" not in out["bogie_frame_0"] and "angular_rate" in out["bogie_front_frame"]


def test_the_shipped_sensor_file_is_the_default_set_written_out():
    assert config.SHIPPED.read_text() == config.file_text(config.default_set())
    assert config.load() == config.default_set()
    assert [m.name for m in config.default_set().mounts] == list(MOUNTS)


@pytest.mark.parametrize("text, message", [
    ("mounts: {car_roof: {accelerometer: adxl355, sample_rate_hz: 100}}",
     "mount 'car_roof' is unknown; the mounts are car_body_front"),
    ("instruments: {adxl355: {noise_density: -1e-4}}\nmounts: {car_body_front: {accelerometer: adxl355, "
     "sample_rate_hz: 100}}",
     "instrument adxl355 noise_density -0.0001 m/s^2/sqrt(Hz) is outside the accepted range [0, 1e+09]"),
    ("mounts: {car_body_front: {accelerometer: adxl355, sample_rate_hz: 400}}",
     "mount car_body_front sample_rate_hz 400 Hz is outside the accepted range (0, 200] Hz (the top is the "
     "simulator's output rate)"),
    ("mounts: {car_body_front: {accelerometer: adxl355, sample_rate_hz: 150}}",
     "sample_rate_hz 150 Hz does not divide the simulator's output rate 200 Hz"),
    ("mounts: {car_body_front: {accelerometer: adis16470, sample_rate_hz: 100}}",
     "instrument 'adis16470' measures angular_rate, not acceleration"),
    ("odometer: {sample_rate_hz: 10, dropout: 1.5}", "odometer dropout 1.5 is outside the accepted range [0, 1)"),
])
def test_a_bad_sensor_file_is_refused_with_one_line_naming_the_value(tmp_path, text, message):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(ValueError) as error:
        config.load(path, output_rate=200.0)
    assert message in str(error.value) and "\n" not in str(error.value)


def test_simulate_stores_each_mounts_signals_in_the_output_file(tmp_path):
    import json
    from railderail_sim.cli import main
    sensors = tmp_path / "two.yaml"
    sensors.write_text("seed: 5\nmounts:\n  car_body_front: {accelerometer: adxl355, gyro: adis16470, "
                       "sample_rate_hz: 100}\n  axle_box_3_right: {accelerometer: iepe_axle_box, gyro: none, "
                       "sample_rate_hz: 200, latency_s: 0.0}\nodometer: {sample_rate_hz: 20}\n")
    out = tmp_path / "run.npz"
    assert main(["simulate", "--sensors", str(sensors), "--sensor-seed", "9", "--out", str(out)]) in (0, None)
    d = np.load(out)
    meta = json.loads(str(d["metadata"]))["sensors"]
    assert meta["seed"] == 9 and meta["mounts"] == ["car_body_front", "axle_box_3_right"] and meta["odometer"]
    n = len(d["time"])
    front = d["sensor_car_body_front_time"]
    assert len(front) == (n + 1) // 2 and np.allclose(np.diff(front), 0.01)
    assert front[0] == pytest.approx(0.002)
    assert d["sensor_car_body_front_acceleration"].shape == (len(front), 3)
    assert d["sensor_car_body_front_angular_rate"].shape == (len(front), 3)
    # at the start, on straight level track, the car body reads +g up (its bias within 4 sigma)
    assert d["sensor_car_body_front_acceleration"][0, 2] == pytest.approx(G, abs=4 * INSTRUMENTS["adxl355"].bias)
    assert "sensor_axle_box_3_right_angular_rate" not in d.files
    assert np.array_equal(d["sensor_axle_box_3_right_time"], d["time"])
    assert d["sensor_odometer_speed"].mean() == pytest.approx(300.0 / 3.6, rel=0.02)


def test_the_element_saturates_before_the_anti_alias_filter():
    """A 30 ms pulse of 6 g into a +-2 g accelerometer: the element saturates at 2 g and the filter smooths
    that, so the reading is the filtered 2 g pulse, not the filtered 6 g pulse clipped afterwards (which would
    read 2 g for longer, understating the saturation)."""
    inst = Instrument(name="fine", quantity="acceleration", unit="m/s^2", range_low=-2 * G, range_high=2 * G,
                      anti_alias_ratio=0.25, anti_alias_order=4)
    n = 2001
    lateral = np.where((np.arange(n) >= 1000) & (np.arange(n) < 1006), 6 * G, 0.0)      # 6 rows at 200 Hz
    out = SensorStream(_one_mount(inst), replace(Scenario(), output_rate=200.0)).process(
        _synthetic(n, 200.0, lateral=lateral))["car_body_centre"]["acceleration"][:, 1]
    sos = signal.butter(4, 0.25 * 200.0, fs=200.0, output="sos")
    saturated = signal.sosfilt(sos, np.clip(lateral, -2 * G, 2 * G))
    assert np.allclose(out, np.clip(saturated, -2 * G, 2 * G), atol=1e-9)
    assert np.sum(out >= 2 * G - 1e-9) < np.sum(np.clip(signal.sosfilt(sos, lateral), -2 * G, 2 * G) >= 2 * G - 1e-9)


# --- the sensing errors: scale factor and mounting misalignment (issue 42, item 7) ----------------------

def _turning(n, rate, lateral):
    """A car body at rest on its springs but for a lateral specific force, turning at 0.2 rad/s about z."""
    a = _synthetic(n, rate, lateral=lateral)
    a["body_motion"][:, Body.car_body, BodyMotion.angular_velocity + 2] = 0.2
    return a


def test_a_misaligned_mount_reads_its_turned_axes_with_the_stated_spread_and_covariance():
    """A mount turned by a small angle theta (1-sigma 0.02 rad about each axis) reads g x theta sideways at rest:
    over 300 seeds its lateral and forward readings spread by g sigma, its vertical by nothing to first order,
    and the Imu covariance states that spread; its gyro is turned with it (both the same rotation)."""
    from railderail_sim.ros import sensor_messages as sm
    sigma = 0.02
    ideal = replace(INSTRUMENTS["adxl355"], noise_density=0.0, bias=0.0, bias_random_walk=0.0, bits=0)
    gyro = replace(INSTRUMENTS["adis16470"], noise_density=0.0, bias=0.0, bias_random_walk=0.0, bits=0)
    sc = replace(Scenario(), output_rate=200.0)
    readings, rates = [], []
    for seed in range(300):
        sensors = _one_mount(ideal, gyro, seed=seed)
        sensors = replace(sensors, mounts=(replace(sensors.mounts[0], misalignment_rad=sigma),))
        out = SensorStream(sensors, sc).process(_turning(401, 200.0, 0.0))["car_body_centre"]
        readings.append(out["acceleration"][-1])
        rates.append(out["angular_rate"][-1])
    readings, rates = np.array(readings), np.array(rates)
    # a rotation keeps the magnitude; the gyro's z (the turning) goes where the accelerometer's z (gravity) went
    assert np.allclose(np.linalg.norm(readings, axis=1), G, rtol=1e-9)
    assert np.allclose(rates / 0.2, readings / G, atol=1e-9)
    # 300 draws: the standard deviation to 3 sigma = 12 %
    assert np.std(readings[:, :2], axis=0) == pytest.approx([G * sigma] * 2, rel=0.12)
    assert np.std(readings[:, 2]) < 0.05 * G * sigma
    covariance = sm.SensorConverter(sensors, 200.0, 0.46).sensed_covariance(
        sensors.mounts[0], ideal, 0.0, np.array([[0.0, 0.0, G]]), None)[0].reshape(3, 3)
    assert np.allclose(np.diag(covariance), [(G * sigma) ** 2] * 2 + [0.0])


def test_the_scale_factor_error_multiplies_each_axis_with_the_stated_spread_and_covariance():
    from railderail_sim.sensors.sensor_set import reading_covariance
    sigma = 0.03
    inst = replace(INSTRUMENTS["adxl355"], noise_density=0.0, bias=0.0, bias_random_walk=0.0, bits=0,
                   scale_factor_error=sigma)
    sc = replace(Scenario(), output_rate=200.0)
    ratios = np.array([SensorStream(_one_mount(inst, seed=seed), sc).process(
        _synthetic(401, 200.0, lateral=1.5))["car_body_centre"]["acceleration"][-1] / [1.0, 1.5, G]
        for seed in range(300)])
    assert np.allclose(ratios[:, 0], 0.0)                    # nothing forward: 0 times any scale
    assert np.std(ratios[:, 1:], axis=0) == pytest.approx([sigma] * 2, rel=0.12)
    assert np.mean(ratios[:, 1:], axis=0) == pytest.approx([1.0] * 2, abs=3 * sigma / math.sqrt(300))
    # the axes' factors are drawn apart
    assert abs(np.corrcoef(ratios[:, 1], ratios[:, 2])[0, 1]) < 0.2
    covariance = reading_covariance(1e-6, sigma, 0.0, [[0.0, 1.5, G]])[0]
    assert np.allclose(covariance, np.diag([1e-6, 1e-6 + (1.5 * sigma) ** 2, 1e-6 + (G * sigma) ** 2]).ravel())


def test_the_sensing_errors_change_no_other_draw_and_the_shipped_set_has_none():
    """The scale factors and the misalignment are drawn after the constant bias: a set with them reads the
    same noise and bias (its difference from the set without them is the sensing error alone, here a pure
    scale on a noise-free-by-design constant lateral signal); the shipped set has none, the realistic file
    has them."""
    sc = replace(Scenario(), output_rate=200.0)
    plain = replace(INSTRUMENTS["adxl355"], bits=0)
    scaled = replace(plain, scale_factor_error=0.05)
    arrays = _synthetic(801, 200.0, lateral=1.5)
    a = SensorStream(_one_mount(plain, seed=3), sc).process(arrays)["car_body_centre"]["acceleration"]
    b = SensorStream(_one_mount(scaled, seed=3), sc).process(arrays)["car_body_centre"]["acceleration"]
    difference = b - a
    # a constant offset per axis: the scale's part of the constant signal, the noise identical
    assert np.allclose(difference, difference[-1], atol=1e-12)
    assert np.all(np.abs(difference[-1, 1:]) > 0.0) and difference[-1, 0] == 0.0
    shipped = config.default_set()
    assert all(i.scale_factor_error == 0.0 for i in shipped.instruments.values())
    assert all(m.misalignment_rad == 0.0 for m in shipped.mounts)
    assert SensorStream(replace(shipped, air_springs=None), sc).sensing == []
    realistic = config.load(config.REALISTIC_FILE)
    assert realistic == config.realistic_set()
    assert config.REALISTIC_FILE.read_text() == config.file_text(realistic)
    assert all(m.misalignment_rad > 0.0 for m in realistic.mounts)
    assert realistic.instruments["adxl355"].scale_factor_error > 0.0
