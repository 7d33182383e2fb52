"""The monitor node in measured mode (`signals:=measured`): it subscribes to the sensor topics and nothing
else (rclpy's graph API), and the alerts it publishes are MeasuredMonitor's on the same messages; the
sensor messages decode back to the samples they were made from (sensor_messages.SensorDecoder)."""
import numpy as np
import pytest
from rclpy.serialization import deserialize_message, serialize_message

from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.parameters import vehicle_parameters
from railderail_sim.sensors.config import load as load_sensors
from railderail_monitor.onboard import measured as me
from railderail_monitor.onboard.monitor import MeasuredMonitor
from monitor_node import node_of, subscribed  # noqa: F401 (node_of: a fixture)
from test_onboard_measured import LOW, _record

GROUND_TRUTH_TOPICS = {m.STATES, m.FORCES, m.STATUS, m.FINAL_STATUS, m.DERAILMENT, m.ALERTS}


def test_measured_mode_subscribes_to_the_sensor_topics_only(node_of):
    node = node_of("signals:=measured")
    topics = subscribed(node)
    assert topics == set(sm.sensor_topics(load_sensors()))
    assert not topics & GROUND_TRUTH_TOPICS
    published = {t for t, _ in node.get_publisher_names_and_types_by_node(node.get_name(), node.get_namespace())}
    assert m.ONBOARD_ALERTS in published and m.ALERTS not in published


def test_ground_truth_mode_subscribes_to_the_simulator_s_samples(node_of):
    """The wheelset states and contact forces; not the vehicle status, since each sample's message carries the
    curvature that names an alert's rail (issue 43)."""
    topics = subscribed(node_of())
    assert {m.STATES, m.FORCES} <= topics and m.STATUS not in topics


def _messages(record):
    """(stamp, topic, message) of a record's samples as the simulator node publishes them, through CDR."""
    sensors = load_sensors()
    convert = sm.SensorConverter(sensors, 1000.0, vehicle_parameters("hs19").rolling_radius)
    return [(t, topic, deserialize_message(serialize_message(msg), type(msg)))
            for t, topic, msg in convert.messages(me.units_of(record))]


def test_the_decoder_gives_back_the_samples():
    record = _record(1.0)
    decoder = sm.SensorDecoder(load_sensors())
    got = {}
    for _, topic, msg in _messages(record):
        for unit, t, signals in decoder.decode(topic, msg):
            got.setdefault(unit, []).append((t, signals))
    frame = got["bogie_front_frame"]
    assert np.allclose([t for t, _ in frame], record["sensor_bogie_front_frame_time"], rtol=0, atol=1e-9)
    assert np.array_equal([s["acceleration"] for _, s in frame], record["sensor_bogie_front_frame_acceleration"])
    springs = got["air_springs"]
    assert len(springs) == len(record["sensor_air_springs_time"]) and decoder.missed == 0
    # the height travels as a float32 Range
    assert np.allclose([s["deflection"] for _, s in springs], record["sensor_air_springs_deflection"], atol=1e-7)
    assert np.array_equal([s["pressure"] for _, s in springs], record["sensor_air_springs_pressure"])
    assert np.array_equal([float(s["speed"]) for _, s in got["odometer"]], record["sensor_odometer_speed"])


def test_the_node_publishes_the_monitor_s_alerts(node_of):
    vp = vehicle_parameters("hs19")
    node = node_of("signals:=measured", *[f"{k}:={v!r}" for k, v in LOW.items()])
    published = []
    node.publisher.publish = published.append
    decoder = sm.SensorDecoder(load_sensors())
    reference, found = MeasuredMonitor(vp, me.measured_limits(vp, **LOW)), []
    for _, topic, msg in _messages(_record()):
        node.on_sensor(topic, msg)
        for unit, t, signals in decoder.decode(topic, msg):
            found += reference.feed(unit, t, **signals)
    assert len(found) > 10 and len(published) == len(found)
    for msg, alert in zip(published, found):
        assert (msg.sample, msg.criterion, msg.value, msg.header.frame_id) == \
               (alert.sample, alert.criterion, alert.value, alert.place)
        assert m.seconds(msg.header.stamp) == pytest.approx(alert.time_s, abs=1e-9)
        assert msg.message.startswith("measured warning")
    gear = next(msg for msg in published if msg.criterion == "estimated_side_ratio")
    assert gear.wheelset in (0, 2) and gear.wheel_side in ("left", "right")


def test_the_node_publishes_the_estimator_s_values_at_its_stamps(node_of):
    from railderail_monitor.onboard import estimator as est
    vp = vehicle_parameters("hs19")
    node = node_of("signals:=measured")
    published = []
    node.estimate_publisher.publish = published.append
    record = _record(2.0)
    for _, topic, msg in _messages(record):
        node.on_sensor(topic, msg)
    batch = est.estimate(record, vp, me.measured_limits(vp).air_spring_effective_area, rate_hz=200.0)
    # decided as the samples come, so all but the last few of the record's stamps, once each, in order
    assert len(batch["time"]) - 5 < len(published) <= len(batch["time"])
    n = len(published)
    assert np.allclose([m.seconds(msg.header.stamp) for msg in published], batch["time"][:n], rtol=0, atol=1e-9)
    assert {msg.header.frame_id for msg in published} == {"car_body"}
    # the air springs' heights travel as float32 Ranges: 1e-7 m of deflection, a few N of load
    assert np.allclose([msg.wheel_load for msg in published], 0.5 * batch["side_load"][:n], rtol=0, atol=20.0)
    for name in ("unloading", "lateral_force", "derailment_coefficient"):
        got = np.array([getattr(msg, name) for msg in published])
        assert np.allclose(got, batch[name][:n], rtol=1e-6, atol=1e-3 if name != "lateral_force" else 20.0), name


def test_a_decoder_without_the_sensor_set_reads_the_gyro_from_the_message():
    """sensor_msgs/Imu's own marker (angular_velocity_covariance[0] = -1: no reading) says which mounts have
    a gyro, so that a recording of another sensor set decodes without it."""
    convert = sm.SensorConverter(load_sensors(), 200.0, vehicle_parameters("hs19").rolling_radius)
    t, acc = np.array([0.005, 0.010]), np.array([[0.1, -0.2, 9.8]] * 2)
    signals, decoder = {}, sm.SensorDecoder()
    for _, topic, msg in convert.messages({"bogie_front_frame": dict(time=t, acceleration=acc,
                                                                     angular_rate=np.zeros((2, 3))),
                                           "bogie_frame_0": dict(time=t, acceleration=acc)}):
        for unit, _, s in decoder.decode(topic, deserialize_message(serialize_message(msg), type(msg))):
            signals.setdefault(unit, set(s))
    assert signals["bogie_front_frame"] == {"acceleration", "angular_rate"}         # a gyro (shipped set)
    assert signals["bogie_frame_0"] == {"acceleration"}                             # none
    assert decoder.decode("/railderail/alerts", None) is None
    with pytest.raises(ValueError, match="without a sensor set"):
        decoder.topics()


def test_a_wind_and_a_car_file_given_to_the_node_reach_its_estimator(node_of, tmp_path):
    car = tmp_path / "car.yaml"
    car.write_text("base: hs19\ncar_body_mass: 36000\n")
    node = node_of("signals:=measured", f"vehicle_set:={car}", "wind_speed:=25.0", "wind_direction:=-90.0")
    assert node.vehicle.car_body_mass == 36000.0
    wind = next(g for g in node.monitor.groups if g.group is me.GROUPS[0]).processor.wind
    assert (wind.speed, wind.direction) == (25.0, pytest.approx(-np.pi / 2))
