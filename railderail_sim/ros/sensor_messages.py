"""The on-board sensors' ROS 2 messages (docs/onboard.md): the topics of a sensor set, its samples -> messages
(`SensorConverter`), and messages -> samples (`SensorDecoder`) or -> the `sensor_<unit>_<signal>` arrays of
`railderail simulate --sensors` (`SensorRecord`, built on the decoder, so that a message is read one way).

With the simulator's `sensors` on, each sensor is published at its own rate with the samples' QoS (reliable),
stamped with the physical instant plus its latency, header.frame_id the mount's or the air spring's name
(`sensor_topics`):

| topic                                          | type                                      |
| ---------------------------------------------- | ----------------------------------------- |
| /railderail/sensors/<mount>/imu                | sensor_msgs/Imu (no orientation: its      |
|                                                | covariance[0] = -1; a mount without gyro  |
|                                                | the same for the angular velocity)        |
| /railderail/sensors/<air_spring>/pressure      | sensor_msgs/FluidPressure (Pa, the proxy) |
| /railderail/sensors/<air_spring>/height        | sensor_msgs/Range (m, height sensor: the  |
|                                                | spring's height less its deflection)      |
| /railderail/sensors/odometer                   | geometry_msgs/TwistWithCovarianceStamped  |
|                                                | (linear.x the forward speed, m/s)         |

The decoding follows the messages' own conventions (an angular velocity whose covariance[0] is -1 is absent, as
sensor_msgs/Imu defines it), so a recording of another sensor set, or of a user's own IMUs on these topics,
decodes without the set that made it.
"""
from __future__ import annotations

import math

import numpy as np
from geometry_msgs.msg import TwistWithCovarianceStamped
from sensor_msgs.msg import FluidPressure, Imu, Range

from railderail_sim.sensors.sensor_set import AIR_SPRING_HEIGHT, AIR_SPRINGS, ODOMETER, reading_covariance

from .interface import SENSOR, SENSOR_SUBSCRIBER, SENSORS_NS, seconds, stamp, stamp_ns


def sensor_topics(sensors):
    """{topic: (ROS type name, message class, publisher QoS, subscriber QoS)} of a sensor set
    (`sensors.sensor_set.SensorSet`)."""
    topics = {f"{SENSORS_NS}/{mount.name}/imu": ("sensor_msgs/msg/Imu", Imu) for mount in sensors.mounts}
    if sensors.air_springs is not None:
        for spring in AIR_SPRINGS:
            topics[f"{SENSORS_NS}/{spring}/pressure"] = ("sensor_msgs/msg/FluidPressure", FluidPressure)
            topics[f"{SENSORS_NS}/{spring}/height"] = ("sensor_msgs/msg/Range", Range)
    if sensors.odometer is not None:
        topics[f"{SENSORS_NS}/{ODOMETER}"] = ("geometry_msgs/msg/TwistWithCovarianceStamped", TwistWithCovarianceStamped)
    return {topic: (type_name, cls, SENSOR, SENSOR_SUBSCRIBER) for topic, (type_name, cls) in topics.items()}


class SensorConverter:
    """Messages of the sensors' samples (`sensors.measure.SensorStream.process`), with covariances from the
    noise model (`sensors.measure.noise_variance`: the filtered white noise, the bias and the quantisation)
    and, where the set has them, the scale-factor errors and the mounts' misalignment at each reading
    (`sensor_set.reading_covariance`; the pressure's scale factor likewise)."""

    def __init__(self, sensors, output_rate=None, rolling_radius=None):
        """Without the simulator's `output_rate` (Hz) the noise model is not known (a logger's data,
        recording.import_imu): every covariance is 0, which sensor_msgs reads as unknown."""
        self.sensors, self.springs, self.odometer = sensors, AIR_SPRINGS, ODOMETER
        if output_rate is None:
            noise_variance = lambda inst, sampling, rate: 0.0
        else:
            # here, not at the top: the noise model imports the numba core, which a decoding node (the
            # monitor, the recorder, the viewer) must not load
            from railderail_sim.sensors.measure import noise_variance
        self.imu_covariance, self.imu_variance = {}, {}
        for mount in sensors.mounts:
            acc = noise_variance(mount.accelerometer, mount.sampling, output_rate)
            gyro = -1.0 if mount.gyro is None else noise_variance(mount.gyro, mount.sampling, output_rate)
            self.imu_covariance[mount.name] = (np.diag([acc] * 3).ravel(),
                                               np.diag([gyro] * 3).ravel() if gyro >= 0 else
                                               np.array([-1.0] + [0.0] * 8))
            self.imu_variance[mount.name] = (acc, gyro)
        if sensors.air_springs is not None:
            a = sensors.air_springs
            self.pressure_variance = noise_variance(a.pressure, a.sampling, output_rate)
            self.height_range = (a.height_m - a.deflection.range_high, a.height_m - a.deflection.range_low)
        if sensors.odometer is not None:
            o = sensors.odometer
            # the count's rounding, uniform over one pulse in the period: (its speed)^2 / 12
            step = (0.0 if output_rate is None else
                    2.0 * math.pi * rolling_radius / o.pulses_per_revolution * o.sampling.sample_rate_hz)
            self.speed_variance = step * step / 12.0
            # 1 sigma, relative: the speed read off by as much
            self.radius_error = 0.0 if output_rate is None else o.radius_error

    @staticmethod
    def sensed_covariance(mount, inst, variance, readings, constant):
        """(n, 9) covariances of a mount's n readings by one of its instruments: `constant` for each where the
        instrument has no scale-factor error and the mount no misalignment."""
        if inst.scale_factor_error == 0.0 and mount.misalignment_rad == 0.0:
            return np.broadcast_to(constant, (len(readings), 9))
        return reading_covariance(variance, inst.scale_factor_error, mount.misalignment_rad, readings)

    def arrays_messages(self, arrays):
        """`messages` of a run's `sensor_<unit>_<signal>` arrays (`sensors.measure.SensorLog.arrays()`, the
        output file of `simulate --sensors`)."""
        units = [mount.name for mount in self.sensors.mounts] + ["air_springs", self.odometer]
        return self.messages({unit: {name[len(f"sensor_{unit}_"):]: values for name, values in arrays.items()
                                     if name.startswith(f"sensor_{unit}_")} for unit in units})

    def messages(self, samples):
        """(stamp s, topic, message) of every sample of one `process` output."""
        out = []
        for mount in self.sensors.mounts:
            s = samples.get(mount.name)
            if s is None:
                continue
            (acc_cov, gyro_cov), (acc_var, gyro_var), n = (self.imu_covariance[mount.name],
                                                            self.imu_variance[mount.name], len(s["time"]))
            acc_cov = self.sensed_covariance(mount, mount.accelerometer, acc_var, s["acceleration"], acc_cov)
            gyro_cov = (np.broadcast_to(gyro_cov, (n, 9)) if mount.gyro is None else
                        self.sensed_covariance(mount, mount.gyro, gyro_var, s["angular_rate"], gyro_cov))
            topic = f"{SENSORS_NS}/{mount.name}/imu"
            for k, t in enumerate(s["time"]):
                m = stamp(Imu(), t)
                m.header.frame_id = mount.name
                m.orientation_covariance[0] = -1.0
                a = s["acceleration"][k]
                m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z = (float(v) for v in a)
                m.linear_acceleration_covariance = acc_cov[k]
                if "angular_rate" in s:
                    w = s["angular_rate"][k]
                    m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z = (float(v) for v in w)
                m.angular_velocity_covariance = gyro_cov[k]
                out.append((t, topic, m))
        springs = samples.get("air_springs")
        if springs is not None:
            a = self.sensors.air_springs
            for k, t in enumerate(springs["time"]):
                for j, name in enumerate(self.springs):
                    p = stamp(FluidPressure(), t)
                    p.header.frame_id = name
                    p.fluid_pressure = float(springs["pressure"][k, j])
                    p.variance = self.pressure_variance + (a.pressure.scale_factor_error * p.fluid_pressure) ** 2
                    h = stamp(Range(), t)
                    h.header.frame_id = name
                    h.radiation_type = Range.ULTRASOUND
                    h.min_range, h.max_range = self.height_range
                    h.range = float(a.height_m - springs["deflection"][k, j])
                    out += [(t, f"{SENSORS_NS}/{name}/pressure", p), (t, f"{SENSORS_NS}/{name}/height", h)]
        odometer = samples.get(self.odometer)
        if odometer is not None:
            for k, t in enumerate(odometer["time"]):
                m = stamp(TwistWithCovarianceStamped(), t)
                m.header.frame_id = self.odometer
                m.twist.twist.linear.x = float(odometer["speed"][k])
                # the count's rounding and the wheel radius's error (a relative error of the speed read)
                m.twist.covariance[0] = self.speed_variance + (self.radius_error * m.twist.twist.linear.x) ** 2
                out.append((t, f"{SENSORS_NS}/{self.odometer}", m))
        out.sort(key=lambda item: item[0])
        return out


class SensorDecoder:
    """The samples of sensor messages (`SensorConverter`'s, or another source's on the same topics), as
    `sensors.measure.SensorStream.process` gives them: `decode(topic, message)` returns [(unit, stamp s,
    {signal: values})], or None for a topic that is not a sensor's. A mount's acceleration, and its angular_rate
    unless the message marks it absent; the air springs' four deflections (the spring's height less the Range)
    and pressures once all eight messages of a stamp are in; the odometer's speed. `missed` counts the air
    springs' stamps given up incomplete (a later stamp completed first: a message was lost, e.g. a reader's queue
    overflowed).
    `sensors` (a `sensors.sensor_set.SensorSet`) gives the topics to subscribe to and the springs' height; without
    it, any mount decodes and the height is the shipped one (`height_m` to say another)."""

    def __init__(self, sensors=None, height_m=None):
        self.sensors = sensors
        self.spring_height = (float(height_m) if height_m is not None else
                              sensors.air_springs.height_m if sensors is not None and sensors.air_springs is not None
                              else AIR_SPRING_HEIGHT)
        self.pending = {}               # stamp (ns) -> [[deflection, pressure] of each spring]
        self.missed = 0

    def topics(self):
        """The sensor set's topics, in `sensor_topics`' order."""
        if self.sensors is None:
            raise ValueError("a SensorDecoder made without a sensor set decodes any sensor topic but has no list "
                             "of them: give it the set (sensors.config.load) to subscribe by")
        return list(sensor_topics(self.sensors))

    def decode(self, topic, message):
        if not topic.startswith(SENSORS_NS + "/"):
            return None
        name, _, kind = topic[len(SENSORS_NS) + 1:].partition("/")
        t = seconds(message.header.stamp)
        if kind == "imu":
            a = message.linear_acceleration
            signals = {"acceleration": np.array([a.x, a.y, a.z])}
            if message.angular_velocity_covariance[0] != -1.0:
                w = message.angular_velocity
                signals["angular_rate"] = np.array([w.x, w.y, w.z])
            return [(name, t, signals)]
        if name == ODOMETER and not kind:
            return [(ODOMETER, t, {"speed": np.array(message.twist.twist.linear.x)})]
        if name not in AIR_SPRINGS or kind not in ("height", "pressure"):
            return None
        j = AIR_SPRINGS.index(name)
        ns = stamp_ns(message.header.stamp)
        values = self.pending.setdefault(ns, [[None, None] for _ in AIR_SPRINGS])
        if kind == "height":
            values[j][0] = self.spring_height - message.range
        else:
            values[j][1] = message.fluid_pressure
        if any(v is None for pair in values for v in pair):
            return []
        for older in [k for k in self.pending if k < ns]:
            del self.pending[older]
            self.missed += 1
        del self.pending[ns]
        d, p = np.array(values).T
        return [("air_springs", t, {"deflection": d, "pressure": p})]


class SensorRecord:
    """The sensor topics' messages (decoded: rclpy's or a reader's, attribute access) back into the
    `sensor_<unit>_<signal>` arrays of `railderail simulate --sensors` (docs/output-format.md), the inverse of
    SensorConverter: `add(topic, message)` for each, then `arrays()` (times in s from the stamps) or
    `stamps_ns()` (the stamps as the messages carry them, integer ns), each unit's samples in stamp order.
    The samples are `SensorDecoder`'s (`height_m` the air springs' height, default the shipped one). Each call
    of `arrays` converts only what came since the last (a live viewer asks for the whole record every
    simulated second)."""

    def __init__(self, height_m=None):
        self.decoder = SensorDecoder(height_m=height_m)
        self.pending = {}      # unit -> {"stamp" | signal: [values since the last conversion]}
        self.blocks = {}       # unit -> {"stamp" | signal: array, in stamp order}
        self.messages = 0

    def add(self, topic, message):
        """Keep a sensor topic's message; False (and nothing kept) for any other topic."""
        samples = self.decoder.decode(topic, message)
        if samples is None:
            return False
        ns = stamp_ns(message.header.stamp)
        for unit, _, signals in samples:
            pending = self.pending.setdefault(unit, {})
            pending.setdefault("stamp", []).append(ns)
            for name, value in signals.items():
                pending.setdefault(name, []).append(value)
        self.messages += 1
        return True

    def _converted(self):
        """{unit: {"stamp" | signal: array}} of everything so far, in stamp order (a stable sort: samples of
        one stamp in their order of arrival)."""
        for unit, pending in self.pending.items():
            blocks = self.blocks.setdefault(unit, {})
            stamps = np.concatenate([blocks.get("stamp", np.zeros(0, dtype=np.int64)),
                                     np.asarray(pending.pop("stamp"), dtype=np.int64)])
            order = np.argsort(stamps, kind="stable")
            blocks["stamp"] = stamps[order]
            for name in set(pending) | set(blocks) - {"stamp"}:
                # a signal every sample has (a mount without gyro has no angular rate; one that comes and goes
                # is dropped)
                new = np.asarray(pending.get(name, ()), dtype=float)
                old = blocks.get(name, np.zeros((0,) + new.shape[1:]))
                blocks[name] = None if old is None or len(old) + len(new) != len(order) else (
                    np.concatenate([old, new.reshape((-1,) + old.shape[1:])])[order])
        self.pending = {}
        return {unit: {k: v for k, v in blocks.items() if v is not None} for unit, blocks in self.blocks.items()}

    def stamps_ns(self):
        """{unit: (m,) int64 stamps}, the units of `arrays`."""
        return {unit: signals["stamp"] for unit, signals in self._converted().items()}

    def arrays(self):
        """{sensor_<unit>_<signal>: array} of the messages so far."""
        out = {}
        for unit, signals in self._converted().items():
            out[f"sensor_{unit}_time"] = signals["stamp"] / 1e9
            out.update({f"sensor_{unit}_{name}": v for name, v in signals.items() if name != "stamp"})
        return out
