"""`railderail bench --only ros`: the ROS product's figures (group "ros" of railderail_sim.bench).

- publish_rate_hz: WheelsetStates received per wall second by a subscriber, while the simulator node
  runs at `requested_rate_hz` (200 Hz at real time) over R = 1000 m at a constant 290 km/h (about
  20 s, no derailment; the inner wheels unload past the threshold in the transition, which gives
  alerts); the monitor node runs beside it (its missed samples: monitor_missed_samples).
- alert_latency_ms (median; _max): from the receipt of the sample that raised an alert (the state
  or force message whose `sample` the alert names) to the receipt of the alert, both in this
  process: the monitor's processing plus one DDS hop.
- measured_alert_latency_ms (median; _max): the monitor in measured mode (signals:=measured) beside the
  simulator with its shipped sensor set on, at real time, the same run with levels lowered so that it
  alerts (MEASURED_LEVELS): from the receipt of the last sensor message stamped at the alert's instant
  (the sample that completes it, or the later one the monitor waited for) to the receipt of the alert;
  measured_sensor_messages_per_s: the sensor messages received per wall second.
- node_core_ms_per_s / node_sensors_ms_per_s / node_sensor_messages_ms_per_s / node_sensor_serialize_ms_per_s
  (CPU milliseconds per simulated second, no ROS graph): the simulator node's work for the default run (R =
  1000 m, 300 km/h, 200 Hz, the shipped sensor set) as the node does it, one publication period at a time: the
  core's step, the sensors' models (SensorStream.process), their messages (SensorConverter.messages) and the
  messages' CDR (what rclpy's publish serializes); node_sensor_messages_per_s the sensor messages a second.
- mcap_write_mb_per_s: CDR megabytes per second that the recorder's writer (McapRecording: zstd
  chunks, flushed every 0.5 s) stores, from the serialized messages of a real run, no ROS in the
  loop; mcap_read_messages_per_s: what `railderail replay` decodes per second.
The nodes run in their own processes on their own ROS_DOMAIN_ID, discovery on this machine only.
"""
from __future__ import annotations

import os
import re
import signal
import statistics
import struct
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

RATE = 200.0
SPEED_KMH = 290.0


# levels of the measured bench run (290 km/h on R = 1000 m, smooth track): low enough to alert on its
# transition and its curve, so that there is a latency to measure
MEASURED_LEVELS = dict(car_body_lateral=0.3, bogie_peak=1.0, car_body_roll_rate=0.01, car_body_roll=0.005,
                       estimated_running_gear_unloading=0.3, estimated_side_ratio=0.15)


def _spin_run(executor, simulator, monitor, nothing_yet):
    """Spin until the simulator node exits (an error after 300 s, or after 240 s while `nothing_yet()`:
    a cold compile included), 1 s more for the last messages; stop it and the monitor: their stderr."""
    try:
        started = time.monotonic()
        while simulator.poll() is None:
            executor.spin_once(timeout_sec=0.05)
            if nothing_yet() and time.monotonic() - started > 240:
                raise RuntimeError("bench: the simulator node published nothing within 240 s")
            if time.monotonic() - started > 300:
                raise RuntimeError("bench: the simulator node ran for more than 300 s")
        end = time.monotonic() + 1.0
        while time.monotonic() < end:
            executor.spin_once(timeout_sec=0.05)
    finally:
        if simulator.poll() is None:
            simulator.send_signal(signal.SIGINT)
        sim_log = simulator.communicate(timeout=30)[1]
        monitor.send_signal(signal.SIGINT)
        mon_log = monitor.communicate(timeout=30)[1]
    return sim_log, mon_log


def _isolated_env():
    env = dict(os.environ, ROS_DOMAIN_ID=str(150 + os.getpid() % 80), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    os.environ.update({k: env[k] for k in ("ROS_DOMAIN_ID", "ROS_AUTOMATIC_DISCOVERY_RANGE")})
    return env


def _measured_figures():
    import rclpy
    from rclpy.signals import SignalHandlerOptions

    from railderail_sim.ros import interface as m
    from railderail_sim.ros import sensor_messages as sm
    from railderail_sim.sensors.config import load as load_sensors

    env = _isolated_env()
    py = sys.executable
    monitor = subprocess.Popen([py, "-m", "railderail_monitor.node", "--ros-args", "-p", "signals:=measured"]
                               + [a for k, v in MEASURED_LEVELS.items() for a in ("-p", f"{k}:={v!r}")],
                               env=env, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True,
                               start_new_session=True)
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node("railderail_bench_measured", context=context)
    # the events executor, as the monitor's: this node takes every sensor message too, and at the
    # single-threaded executor's cost it would take a core from the two it measures
    executor = m.events_executor(context)
    executor.add_node(node)
    last_of_stamp, alerts, count = {}, [], [0]
    clock = time.perf_counter

    def on_sensor(data):
        # raw: the stamp is the first field after the CDR header (int32 sec, uint32 nanosec)
        sec, nanosec = struct.unpack_from("<iI", data, 4)
        last_of_stamp[sec * 1_000_000_000 + nanosec] = clock()
        count[0] += 1

    for topic, (_, cls, _, qos) in sm.sensor_topics(load_sensors()).items():
        node.create_subscription(cls, topic, on_sensor, qos, raw=True)
    node.create_subscription(m.Alert, m.ONBOARD_ALERTS, lambda msg: alerts.append(
        (clock(), msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)), m.ALERT_QOS)
    m.count_as_subscriber(node)
    odometer = f"{m.SENSORS_NS}/odometer"
    up = time.monotonic() + 120.0
    while node.count_subscribers(odometer) < 2:         # this node's and the monitor's: it is up
        if time.monotonic() > up or monitor.poll() is not None:
            raise RuntimeError("bench: the measured-mode monitor did not subscribe to the sensors")
        executor.spin_once(timeout_sec=0.1)
    simulator = subprocess.Popen(
        [py, "-m", "railderail_sim.ros.node", "--ros-args", "-p", "speed_mode:=constant", "-p", f"speed_kmh:={SPEED_KMH}",
         "-p", f"publish_rate:={RATE}", "-p", "real_time_factor:=1.0", "-p", "wait_for_subscribers:=1",
         "-p", "sensors:=shipped"], env=env, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True,
        start_new_session=True)
    try:
        _, mon_log = _spin_run(executor, simulator, monitor, lambda: not last_of_stamp)
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)
    latencies = [(t - last_of_stamp[stamp]) * 1e3 for t, stamp in alerts if stamp in last_of_stamp]
    received = sorted(last_of_stamp.values())
    processed = re.search(r"processed (\d+) sensor messages", mon_log)
    return dict(measured_alerts=len(alerts),
                measured_alert_latency_ms=round(statistics.median(latencies), 3) if latencies else float("nan"),
                measured_alert_latency_ms_max=round(max(latencies), 3) if latencies else float("nan"),
                measured_sensor_messages_per_s=round(count[0] / (received[-1] - received[0]), 1)
                if len(received) > 1 else 0.0,
                measured_monitor_processed=int(processed.group(1)) if processed else -1,
                measured_sensor_messages_received=count[0])


def _ros_figures():
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.signals import SignalHandlerOptions

    from railderail_sim.ros import interface as m

    env = _isolated_env()
    py = sys.executable
    monitor = subprocess.Popen([py, "-m", "railderail_monitor.node"], env=env, stderr=subprocess.PIPE,
                               stdout=subprocess.DEVNULL, text=True, start_new_session=True)
    context = rclpy.Context()
    rclpy.init(context=context, signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node("railderail_bench", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    received = {"states": {}, "forces": {}}
    alerts = []
    clock = time.perf_counter
    def sample_of(data):
        """The `sample` field of a raw WheelsetStates/ContactForces: after the header's stamp and frame_id."""
        (n,) = struct.unpack_from("<I", data, 12)
        return struct.unpack_from("<I", data, 4 + ((8 + 4 + n + 3) & ~3))[0]

    # raw subscriptions (no deserialization): this process should take as little CPU as possible
    node.create_subscription(m.WheelsetStates, m.STATES,
                             lambda data: received["states"].setdefault(sample_of(data), clock()),
                             m.SENSOR_SUBSCRIBER, raw=True)
    node.create_subscription(m.ContactForces, m.FORCES,
                             lambda data: received["forces"].setdefault(sample_of(data), clock()),
                             m.SENSOR_SUBSCRIBER, raw=True)
    node.create_subscription(m.Alert, m.ALERTS, lambda msg: alerts.append((clock(), msg.sample, msg.criterion)),
                             m.ALERT_QOS)
    simulator = subprocess.Popen(
        [py, "-m", "railderail_sim.ros.node", "--ros-args", "-p", "speed_mode:=constant", "-p", f"speed_kmh:={SPEED_KMH}",
         "-p", f"publish_rate:={RATE}", "-p", "real_time_factor:=1.0", "-p", "wait_for_subscribers:=2"],
        env=env, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True, start_new_session=True)
    try:
        sim_log, mon_log = _spin_run(executor, simulator, monitor, lambda: not received["states"])
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)
    states = sorted(received["states"].values())
    rate = (len(states) - 1) / (states[-1] - states[0]) if len(states) > 1 else 0.0
    latencies = []
    for t_alert, sample, criterion in alerts:
        kind = "states" if criterion in ("attack_angle", "wheel_lift") else "forces"
        if sample in received[kind]:
            latencies.append((t_alert - received[kind][sample]) * 1e3)
    missed = re.search(r"\((\d+) missed\) and \d+ contact forces \((\d+) missed\)", mon_log)
    published = re.search(r"published (\d+) samples at ([\d.]+) samples/s", sim_log)
    return dict(requested_rate_hz=RATE, publish_rate_hz=round(rate, 2),
                simulator_reported_rate_hz=float(published.group(2)) if published else float("nan"),
                samples_published=int(published.group(1)) if published else 0,
                samples_received=len(states),
                monitor_missed_samples=int(missed.group(1)) + int(missed.group(2)) if missed else -1,
                alerts=len(alerts),
                alert_latency_ms=round(statistics.median(latencies), 3) if latencies else float("nan"),
                alert_latency_ms_max=round(max(latencies), 3) if latencies else float("nan"))


def _mcap_figures(seconds=2.0):
    from rclpy.serialization import serialize_message

    from railderail_sim.vehicle.simulate import Simulation, output_arrays, scenario

    from railderail_sim.ros import interface as m
    from ..recording.recorder import McapRecording
    from ..recording.replay import read_recording

    sim = Simulation(replace(scenario(radius=1000.0, speed_kmh=300.0), output_rate=RATE))
    rows = sim.advance(1.0)
    a = output_arrays(rows)
    c = m.RowConverter()
    payloads = [(topic, serialize_message(make(a, i, i))) for i in range(len(rows))
                for topic, make in ((m.STATES, c.states), (m.FORCES, c.forces), (m.STATUS, c.status))]
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bench.mcap"
        written = 0
        t0 = time.perf_counter()
        with McapRecording(path) as rec:
            for topic in (m.STATES, m.FORCES, m.STATUS):
                rec.add_topic(topic, m.TOPICS[topic][0])
            while time.perf_counter() - t0 < seconds:
                for topic, data in payloads:
                    rec.write(topic, data)
                    written += len(data)
        dt = time.perf_counter() - t0
        size = path.stat().st_size
        t1 = time.perf_counter()
        n = len(read_recording(path).messages)
        read_dt = time.perf_counter() - t1
    return dict(mcap_write_mb_per_s=round(written / dt / 1e6, 2), mcap_file_mb_per_s=round(size / dt / 1e6, 2),
                mcap_messages_per_s=round(written / dt / (sum(len(d) for _, d in payloads) / len(payloads))),
                mcap_read_messages_per_s=round(n / read_dt))


def _node_sensor_figures(seconds=2.0):
    from rclpy.serialization import serialize_message

    from railderail_sim.ros import sensor_messages as sm
    from railderail_sim.sensors.config import load as load_sensors
    from railderail_sim.sensors.measure import SensorStream
    from railderail_sim.vehicle.simulate import Simulation, output_arrays, scenario

    sc = replace(scenario(radius=1000.0, speed_kmh=300.0), output_rate=RATE)
    sim = Simulation(sc)
    sim.advance(1.0)                    # compiled, and past the start
    sensors = load_sensors()
    stream = SensorStream(sensors, sc, sim.model, sim.speed_table)
    convert = sm.SensorConverter(sensors, RATE, sc.vehicle.rolling_radius)
    spent = dict(core=0.0, sensors=0.0, messages=0.0, serialize=0.0)
    count = 0
    clock = time.process_time
    for _ in range(int(round(seconds * RATE))):
        t0 = clock()
        a = output_arrays(sim.advance(1.0 / RATE))
        t1 = clock()
        samples = stream.process(a)
        t2 = clock()
        messages = convert.messages(samples)
        t3 = clock()
        for _, _, message in messages:
            serialize_message(message)
        t4 = clock()
        for part, dt in zip(spent, (t1 - t0, t2 - t1, t3 - t2, t4 - t3)):
            spent[part] += dt
        count += len(messages)
    names = dict(core="node_core_ms_per_s", sensors="node_sensors_ms_per_s",
                 messages="node_sensor_messages_ms_per_s", serialize="node_sensor_serialize_ms_per_s")
    return {names[part]: round(1e3 * dt / seconds, 1) for part, dt in spent.items()} | dict(
        node_sensor_messages_per_s=count / seconds)


def run():
    figures = _node_sensor_figures()
    figures.update(_ros_figures())
    figures.update(_measured_figures())
    figures.update(_mcap_figures())
    return figures


if __name__ == "__main__":
    from railderail_sim import jsonout
    print(jsonout.dumps(run(), indent=1))
