"""The on-board sensors through ROS 2: the simulator node publishes each mount's sensor_msgs/Imu (frame_id the
mount, covariances from the noise model), the air springs' FluidPressure and Range, the odometer's
TwistWithCovarianceStamped, at the sensors' rates; the recorder writes them to a rosbag2 MCAP bag that rosbags
(which shares no code with ours) decodes, every one of them although its process was held still for a while;
the messages carry, bit for bit, what `railderail simulate --sensors` stores for the same scenario and seed."""
import signal
import sys
import time
from dataclasses import replace

import numpy as np
import pytest
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from conftest import STARTUP_S
from railderail_sim.cli import main
from railderail_sim.parameters import GRAVITY
from railderail_sim.parameters import vehicle_parameters
from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.sensors.config import load
from railderail_sim.sensors.measure import noise_variance
from railderail_sim.sensors.sensor_set import AIR_SPRING_EFFECTIVE_AREA, AIR_SPRINGS

PY = sys.executable
SIMULATOR = [PY, "-m", "railderail_sim.ros.node", "--ros-args", "-p", "speed_mode:=constant", "-p", "speed_kmh:=310.0",
             "-p", "radius:=1000.0", "-p", "real_time_factor:=0.0", "-p", "wait_for_subscribers:=1",
             "-p", "sensors:=shipped", "-p", "sensor_seed:=4"]


def stamp_ns(message):
    return message.header.stamp.sec * 1_000_000_000 + message.header.stamp.nanosec


def assert_as_simulate(messages, sensors, npz):
    """The decoded messages of every sensor topic equal `simulate --sensors`'s arrays bit for bit: the stamps
    (integer ns, as the messages carry them) and every value; a height through its Range's float32."""
    stored = np.load(npz)
    for mount in sensors.mounts:
        imu = messages[f"{m.SENSORS_NS}/{mount.name}/imu"]
        key = f"sensor_{mount.name}"
        assert np.array_equal([stamp_ns(x) for x in imu], np.round(stored[f"{key}_time"] * 1e9)), mount.name
        acc = [(x.linear_acceleration.x, x.linear_acceleration.y, x.linear_acceleration.z) for x in imu]
        assert np.array_equal(acc, stored[f"{key}_acceleration"]), mount.name
        if mount.gyro is not None:             # an accelerometer alone (the frame over a wheelset) has no rate
            rate = [(x.angular_velocity.x, x.angular_velocity.y, x.angular_velocity.z) for x in imu]
            assert np.array_equal(rate, stored[f"{key}_angular_rate"]), mount.name
        else:
            assert f"{key}_angular_rate" not in stored and all(x.angular_velocity_covariance[0] == -1.0 for x in imu)
    for j, spring in enumerate(AIR_SPRINGS):
        pressure = messages[f"{m.SENSORS_NS}/{spring}/pressure"]
        height = messages[f"{m.SENSORS_NS}/{spring}/height"]
        for series in (pressure, height):
            assert np.array_equal([stamp_ns(x) for x in series], np.round(stored["sensor_air_springs_time"] * 1e9))
        assert np.array_equal([x.fluid_pressure for x in pressure], stored["sensor_air_springs_pressure"][:, j])
        assert np.array_equal([x.range for x in height], np.float32(sensors.air_springs.height_m
                                                                    - stored["sensor_air_springs_deflection"][:, j]))
    odometer = messages[f"{m.SENSORS_NS}/odometer"]
    assert np.array_equal([stamp_ns(x) for x in odometer], np.round(stored["sensor_odometer_time"] * 1e9))
    assert np.array_equal([x.twist.twist.linear.x for x in odometer], stored["sensor_odometer_speed"])
    # the speed's variance: the pulse count's rounding and the wheel radius's error, relative to the speed
    o = sensors.odometer
    step = 2.0 * np.pi * 0.46 / o.pulses_per_revolution * o.sampling.sample_rate_hz
    v = stored["sensor_odometer_speed"]
    assert [x.twist.covariance[0] for x in odometer] == pytest.approx(step ** 2 / 12.0 + (o.radius_error * v) ** 2)


@pytest.mark.timeout(700)
def test_the_simulator_publishes_the_sensors_on_standard_messages_that_rosbags_decodes(spawn, read_until, tmp_path):
    folder = tmp_path / "bag"
    recorder = spawn([PY, "-m", "railderail_monitor.recording.recorder", "--bag-dir", str(folder)])
    read_until(recorder, "recording", timeout=STARTUP_S)
    simulator = spawn(SIMULATOR)
    # the recorder's process held still for 3 s mid-run, as on a busy machine a process waits for a core (the run,
    # published as fast as possible, ends meanwhile): with best-effort topics the transport lost about a tenth of
    # what was sent meanwhile; reliable ones send it again, on the writer's heartbeats, while the simulator waits
    # for the acknowledgements (5 s of waiting lost a topic's tail in 4 of 6 tries, 30 s none in 6). Stopped at once
    # after the run, the recorder still writes what its queues hold (test_run_node.py)
    read_until(simulator, "starting the run", timeout=300)
    time.sleep(0.5)
    recorder.send_signal(signal.SIGSTOP)
    time.sleep(3.0)
    recorder.send_signal(signal.SIGCONT)
    assert simulator.wait(timeout=400) == 0, simulator.stderr.read()
    assert "did not acknowledge" not in simulator.stderr.read()
    recorder.send_signal(signal.SIGINT)
    assert recorder.wait(timeout=30) == 0

    sensors = load()
    topics = sm.sensor_topics(sensors)
    messages = {}
    with AnyReader([folder], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as reader:
        for connection, _, raw in reader.messages():
            if connection.topic in topics:
                messages.setdefault(connection.topic, []).append(reader.deserialize(raw, connection.msgtype))
    assert set(messages) == set(topics)
    front = messages[f"{m.SENSORS_NS}/car_body_front/imu"]
    stamps = np.array([x.header.stamp.sec + 1e-9 * x.header.stamp.nanosec for x in front])
    # 200 Hz, 2 ms of latency, none lost; the run derails about 5 s after the start
    assert len(front) > 800 and np.allclose(np.diff(stamps), 0.005) and stamps[0] == pytest.approx(0.002)
    first = front[0]
    assert first.header.frame_id == "car_body_front" and first.orientation_covariance[0] == -1.0
    mount = sensors.mounts[0]
    assert first.linear_acceleration_covariance[0] == pytest.approx(noise_variance(mount.accelerometer, mount.sampling,
                                                                                   200.0))
    assert first.angular_velocity_covariance[8] == pytest.approx(noise_variance(mount.gyro, mount.sampling, 200.0))
    assert first.linear_acceleration.z == pytest.approx(GRAVITY, abs=0.1)
    pressure = messages[f"{m.SENSORS_NS}/air_spring_front_left/pressure"]
    load_per_spring = vehicle_parameters().car_body_mass * GRAVITY / 4.0
    assert pressure[0].fluid_pressure == pytest.approx(load_per_spring / AIR_SPRING_EFFECTIVE_AREA, rel=0.01)
    assert len(pressure) == pytest.approx(len(front) / 4, abs=2)
    height = messages[f"{m.SENSORS_NS}/air_spring_rear_right/height"][0]
    assert height.range == pytest.approx(sensors.air_springs.height_m, abs=2e-3)
    speed = [x.twist.twist.linear.x for x in messages[f"{m.SENSORS_NS}/odometer"]]
    assert np.mean(speed) == pytest.approx(310.0 / 3.6, rel=0.02)

    # the same scenario and seed through the command line: the same signals, bit for bit, every sample of the
    # run (the last rows' too, stamped after the run's end by their latency)
    npz = tmp_path / "run.npz"
    assert main(["simulate", "--radius", "1000", "--speed-kmh", "310", "--rate", "200", "--sensors",
                 "--sensor-seed", "4", "--out", str(npz)]) == 0
    assert_as_simulate(messages, replace(sensors, seed=4), npz)
