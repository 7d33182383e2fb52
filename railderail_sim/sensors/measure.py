"""The sensors' signals from a run's output rows, chunk by chunk (`SensorStream`) or whole (`SensorLog`).

The ideal signals come from the output rows: each mount's specific force and angular rate in its body's
axes (`vehicle.motion.points_motion`), each air spring's deflection and elastic force from the bodies'
positions (the core's own kinematics, `vehicle.dynamics.kinematics`), the odometer's pulses from the
distance run. Each instrument's model (instruments.py: its scale factor and the mount's misalignment, its
element saturating before its filters) is applied
at the output rate, then the samples are taken at the mount's rate (every k-th row, k = output rate / sample
rate, counted from the run's first row), clipped and quantised, stamped with the physical instant plus the latency, and some dropped.

Determinism: every mount (and the air springs, the odometer) draws from its own PCG64 generators seeded by
`SeedSequence(seed, spawn_key=(crc32 of its name,))`, spawned into the white noise with the bias's random
walk, the constant bias and the lost samples; the draws, the filters (scipy.signal.sosfilt's sections,
compiled in chain.py, their state carried) and the walk's running sum are the same whatever the chunks, so a
run gives the same signals bit for bit from the same seed, processed at once or row by row (the simulator
node)."""
from dataclasses import dataclass
import zlib

import numpy as np
from scipy import signal

from ..vehicle.assemble import air_springs, local_point
from ..vehicle.dynamics import K_COLS
from ..vehicle.layout import CAR_BODY, N_BODY, N_STATE
from ..vehicle.motion import points_motion_into
from ..vehicle.simulate import output_arrays
from .chain import instrument_chain
from .sensor_set import ODOMETER, SensorSet, misaligned_axes, mount_point
from .springs import spring_rise

AXES = 3


def generators(seed, name):
    """The (white noise and random walk, constant bias, lost samples) generators of a named sensor unit."""
    children = np.random.SeedSequence(seed, spawn_key=(zlib.crc32(name.encode()),)).spawn(3)
    return tuple(np.random.Generator(np.random.PCG64(child)) for child in children)


def filter_sections(inst, sampling, output_rate):
    """The second-order sections (scipy.signal) of an instrument's AC coupling and anti-alias low-pass at the
    output rate."""
    sos = [signal.butter(inst.anti_alias_order, inst.anti_alias_ratio * sampling.sample_rate_hz, fs=output_rate,
                         output="sos")]
    if inst.high_pass_hz > 0.0:
        sos.insert(0, signal.butter(1, inst.high_pass_hz, btype="highpass", fs=output_rate, output="sos"))
    return np.vstack(sos)


def noise_bandwidth(sos, output_rate, points=1 << 16):
    """Equivalent noise bandwidth (Hz) of a filter at the output rate: the integral of |H|^2 over 0..fs/2."""
    _, h = signal.sosfreqz(sos, worN=points, fs=output_rate)
    return float(np.mean(np.abs(h) ** 2) * output_rate / 2.0)


def noise_variance(inst, sampling, output_rate):
    """Variance of a reading about the truth (unit^2), as a sensor_msgs covariance states it: the white noise
    through the filters, the constant bias and the quantisation (the bias's random walk, growing with time,
    left out)."""
    white = inst.noise_density ** 2 * noise_bandwidth(filter_sections(inst, sampling, output_rate), output_rate)
    return white + inst.bias ** 2 + inst.resolution ** 2 / 12.0


class _Unit:
    """A sensor unit's channels: its columns of the channel matrix (a slice), sampling and generators."""

    def __init__(self, name, columns, sampling, seed, output_rate):
        self.name, self.columns, self.sampling = name, columns, sampling
        self.every = sampling.decimation(output_rate)
        self.noise, self.bias, self.lost = generators(seed, name)


class SensorStream:
    """The sensor set's measurements of a run, fed with its output arrays chunk by chunk (`process`).

    `scenario` is the run's (its vehicle, faults and output rate); `model` and `speed_table` (the
    Simulation's) are needed for the air springs only."""

    def __init__(self, sensors: SensorSet, scenario, model=None, speed_table=None):
        self.fs = float(scenario.output_rate)
        self.sensors = sensors.validated(self.fs)
        vp = scenario.vehicle
        self.units, insts = [], []
        places = [mount_point(m.name, vp) for m in sensors.mounts]
        self.mount_bodies = np.array([int(b) for b, _ in places], dtype=int)
        self.mount_points = np.array([np.add(p, m.offset) for (_, p), m in zip(places, sensors.mounts)]).reshape(-1, 3)
        column, self.force_at, self.rate_at = 0, [], []
        for m in sensors.mounts:
            parts = [m.accelerometer] + ([m.gyro] if m.gyro is not None else [])
            self.force_at.append(column)
            self.rate_at.append(column + AXES if m.gyro is not None else -1)
            self.units.append(_Unit(m.name, slice(column, column + AXES * len(parts)), m.sampling, sensors.seed,
                                    self.fs))
            insts += [inst for inst in parts for _ in range(AXES)]
            column += AXES * len(parts)
        # each mount's columns of the channel matrix: its acceleration's, its angular rate's (-1: no gyro)
        self.force_at, self.rate_at = np.array(self.force_at, dtype=np.int64), np.array(self.rate_at, dtype=np.int64)
        self.springs = None
        if sensors.air_springs is not None:
            if model is None or speed_table is None:
                raise ValueError("the air springs' sensors need the run's model and speed table")
            a = sensors.air_springs
            self.springs = air_springs(vp, scenario.faults)
            self.model, self.speed_table = model, np.ascontiguousarray(speed_table, dtype=np.float64)
            self.spring_local = np.array([[local_point(model.bodies, s.bogie, s.point) for s in self.springs],
                                          [local_point(model.bodies, CAR_BODY, s.point) for s in self.springs]])
            self.spring_bogies = np.array([s.bogie for s in self.springs], dtype=np.int64)
            self.spring_stiffness = np.array([s.vertical_stiffness for s in self.springs])
            self.spring_preload = np.array([s.preload for s in self.springs])
            self.spring_scratch = np.zeros(N_STATE), np.zeros((N_BODY, K_COLS))    # the state, the kinematics
            n = len(self.springs)
            self.deflection_at, self.pressure_at = slice(column, column + n), slice(column + n, column + 2 * n)
            self.units.append(_Unit("air_springs", slice(column, column + 2 * n), a.sampling, sensors.seed, self.fs))
            insts += [a.deflection] * n + [a.pressure] * n
            column += 2 * n
        self.instruments, self.channels = insts, column
        self.white = np.array([i.noise_density * np.sqrt(self.fs / 2.0) for i in insts])
        self.walk_step = np.array([i.bias_random_walk / np.sqrt(self.fs) for i in insts])
        self.low = np.array([i.range_low for i in insts])
        self.high = np.array([i.range_high for i in insts])
        self.lsb = np.array([i.resolution for i in insts])
        self.codes = np.array([2.0 ** i.bits - 1.0 for i in insts])
        self.constant_bias = np.zeros(column)
        for u in self.units:
            width = u.columns.stop - u.columns.start
            self.constant_bias[u.columns] = u.bias.standard_normal(width) * [i.bias for i in insts[u.columns]]
        # the sensing errors, drawn after the constant bias from the same generator (so a set without them
        # gives the signals it gave before they existed): each axis's scale factor, a mount's misalignment
        self.sensing = []       # (columns, matrix: the readings of the columns' ideal values)
        for u, m in zip(self.units, sensors.mounts + (None,)):
            width = u.columns.stop - u.columns.start
            angles = u.bias.standard_normal(AXES) * (0.0 if m is None else m.misalignment_rad)
            scale = 1.0 + u.bias.standard_normal(width) * np.array([i.scale_factor_error for i in insts[u.columns]])
            if np.any(angles) or np.any(scale != 1.0):
                turn = np.eye(width) if m is None else np.kron(np.eye(width // AXES), misaligned_axes(*angles))
                self.sensing.append((np.arange(u.columns.start, u.columns.stop), scale[:, None] * turn))
        self.walk = np.zeros(column)
        # the filters: each channel's sections, padded to the longest cascade, and their steady state per unit
        # input (the states start settled on the first row)
        designs, design = {}, []
        for u in self.units:
            for c in range(u.columns.start, u.columns.stop):
                key = (insts[c], u.sampling.sample_rate_hz)
                if key not in designs:
                    designs[key] = filter_sections(insts[c], u.sampling, self.fs)
                design.append(designs[key])
        depth = max((len(sos) for sos in design), default=0)
        self.sos = np.zeros((column, depth, 6))
        self.settled = np.zeros((column, depth, 2))
        self.sections = np.zeros(column, dtype=np.int64)
        for c, sos in enumerate(design):
            self.sos[c, :len(sos)], self.settled[c, :len(sos)] = sos, signal.sosfilt_zi(sos)
            self.sections[c] = len(sos)
        self.filter_state, self.settle = np.zeros_like(self.settled), True
        # each channel's unit (its first channel and width: where its draws are), each unit's signals' channels
        self.first = np.zeros(column, dtype=np.int64)
        self.width = np.zeros(column, dtype=np.int64)
        for u in self.units:
            self.first[u.columns], self.width[u.columns] = u.columns.start, u.columns.stop - u.columns.start
        self.signals = [(u, (u.every, u.sampling.latency_s), self.unit_signals(u)) for u in self.units]
        self.draws = self.blocks = None     # the draws' buffer and each unit's block of it, for a chunk's rows
        # what the draws depend on: the seed, and each unit's name and channels
        self.draw_units = (sensors.seed, tuple((u.name, u.columns.start, u.columns.stop) for u in self.units))
        self.odometer = sensors.odometer
        if self.odometer is not None:
            o = self.odometer
            self.odometer_unit = _Unit(ODOMETER, slice(0, 0), o.sampling, sensors.seed, self.fs)
            circumference = 2.0 * np.pi * vp.rolling_radius / o.pulses_per_revolution
            scale = 1.0 + o.radius_error * self.odometer_unit.bias.standard_normal()
            self.pulse_nominal, self.pulse_true = circumference, circumference * scale
            self.last_count = None
        self.row = 0

    @staticmethod
    def unit_signals(u):
        """((signal name, its columns (a slice)), ...) of a unit."""
        start, stop = u.columns.start, u.columns.stop
        if u.name == "air_springs":
            half = (start + stop) // 2
            return ("deflection", slice(start, half)), ("pressure", slice(half, stop))
        gyro = (("angular_rate", slice(start + AXES, stop)),) if stop - start > AXES else ()
        return (("acceleration", slice(start, start + AXES)),) + gyro

    # --- the ideal signals ----------------------------------------------------------------------

    def ideal(self, a):
        """(n, channels) ideal readings of the output arrays `a` (vehicle.simulate.output_arrays)."""
        y = np.empty((len(a["time"]), self.channels))
        if len(self.sensors.mounts):
            points_motion_into(a, self.mount_bodies, self.mount_points, self.force_at, self.rate_at, y)
        if self.springs is not None:
            deflection, force = self.spring_states(a)
            y[:, self.deflection_at] = deflection
            y[:, self.pressure_at] = force / self.sensors.air_springs.effective_area_m2
        return y

    def spring_states(self, a):
        """(deflection (n, 4) m, compression +, elastic force (n, 4) N) of the air springs: the car body's
        point of each spring against its frame's, in the frame's axes, from the core's kinematics."""
        n = len(a["time"])
        rise = np.zeros((n, len(self.springs)))
        spring_rise(np.ascontiguousarray(np.reshape(a["body_states"], (n, -1))), np.ascontiguousarray(a["position"]),
                    self.model.bodies, self.model.track, self.speed_table, self.spring_bogies, self.spring_local,
                    *self.spring_scratch, rise)
        return -rise, self.spring_preload - self.spring_stiffness * rise

    # --- the sensor models ----------------------------------------------------------------------

    def process(self, a, shared=None):
        """The new samples of the output arrays `a` of the next rows: {unit name: {signal: array}}, the
        mounts' `time` (s), `acceleration` (m, 3) m/s^2 and `angular_rate` (m, 3) rad/s; the air springs'
        `time`, `deflection` (m, 4) m and `pressure` (m, 4) Pa; the odometer's `time` and `speed` (m/s).
        `shared`: the `Readings` of these rows when already known (a set's variants over a whole run share
        them: the ideal readings depend on the mounts' places only, the noise draws on the units and the seed,
        not on the instruments nor the rates); a stream given them has not drawn, so takes no further chunk."""
        n = len(a["time"])
        out = {}
        if n == 0:
            return out
        if shared is not None and (self.row or shared.units != self.draw_units or shared.draws.size != 2 * n * self.channels):
            raise ValueError(f"shared readings are for a whole run's {len(shared.ideal)} rows from row 0 and the units "
                             f"{shared.units}; this stream is at row {self.row}, {n} rows, units {self.draw_units}")
        y = self.ideal(a) if shared is None else np.array(shared.ideal, dtype=np.float64)
        for cols, sensed in self.sensing:
            y[:, cols] = y[:, cols] @ sensed.T
        draws = self.noise_draws(n) if shared is None else shared.draws
        # the sensing element saturates before the filters in the chain (a reading beyond the range does not
        # come back within it through the anti-alias filter, as clipping only after it would let it)
        instrument_chain(y, self.constant_bias, draws, self.first, self.width, self.white, self.walk_step,
                         self.walk, self.low, self.high, self.sos, self.sections, self.settled, self.filter_state,
                         self.settle, self.lsb, self.codes)
        self.settle = False
        taken = {}      # the units' samples: views of the readings, the rows of their phase
        for u, key, signals in self.signals:
            if key not in taken:
                take = slice((-self.row) % u.every, n, u.every)
                taken[key] = a["time"][take] + u.sampling.latency_s, y[take]
            time, samples = self.kept(u, *taken[key])
            got = out[u.name] = {"time": time}
            for name, cols in signals:
                got[name] = samples[:, cols]
        if self.odometer is not None:
            out[ODOMETER] = self.odometer_samples(a)
        self.row += n
        return out

    def noise_draws(self, n):
        """The standard normal draws of n rows (`instrument_chain`'s `draws`): unit after unit, each unit's
        block from its own generator in one call."""
        if self.draws is None or len(self.draws) != 2 * n * self.channels:
            self.draws = np.empty(2 * n * self.channels)
            self.blocks = [self.draws[2 * n * u.columns.start:2 * n * u.columns.stop].reshape(n, -1)
                           for u in self.units]
        for u, block in zip(self.units, self.blocks):
            u.noise.standard_normal(out=block)      # each unit from its own generator
        return self.draws

    @staticmethod
    def kept(unit, *taken):
        """The samples of a unit that are not lost (each with its chance `dropout`, from the unit's own
        generator: a unit that loses none draws nothing, which changes none of its signals)."""
        if unit.sampling.dropout == 0.0:
            return taken
        kept = unit.lost.random(len(taken[0])) >= unit.sampling.dropout
        return tuple(x[kept] for x in taken)

    def odometer_samples(self, a):
        """The odometer's speed: the pulses counted since its last sample times the nominal pulse length,
        over the sample period (its first sample one period after the run's start)."""
        u, o = self.odometer_unit, self.odometer
        if self.last_count is None:
            self.last_count = np.floor(a["position"][0] / self.pulse_true)
        first = (-self.row) % u.every
        take = np.arange(u.every if self.row + first == 0 else first, len(a["time"]), u.every)
        counts = np.floor(a["position"][take] / self.pulse_true)
        previous = np.concatenate([[self.last_count], counts[:-1]])
        speed = (counts - previous) * self.pulse_nominal * o.sampling.sample_rate_hz
        if len(take):
            self.last_count = counts[-1]
        time, speed = self.kept(u, a["time"][take] + o.sampling.latency_s, speed)
        return dict(time=time, speed=speed)


def named(samples):
    """{`sensor_<unit>_<signal>`: array} of `SensorStream.process`'s {unit: {signal: array}}
    (docs/output-format.md)."""
    return {f"sensor_{unit}_{name}": values for unit, signals in samples.items() for name, values in signals.items()}


# s: a simulated run's start-up, which no sensor on a train in service sees: the suspension taking up the
# rails' offsets at the first row (13-16 m/s^2 on the bogie frames in the first 0.1 s on erri-low track,
# docs/onboard-criteria.md); a monitor fed a simulated run is switched on after it (`after`)
START_UP_S = 1.0


def after(signals, start_s):
    """`sensor_<unit>_<signal>` arrays from start_s on: every unit's samples stamped at or after it."""
    out = {}
    for unit in (k[len("sensor_"):-len("_time")] for k in signals if k.endswith("_time")):
        # a unit's stamps rise with the rows: its samples from start_s on are a tail (a view, no copy)
        first = int(np.searchsorted(signals[f"sensor_{unit}_time"], start_s, "left"))
        out.update({k: np.asarray(v)[first:] for k, v in signals.items() if k.startswith(f"sensor_{unit}_")})
    return out


def run_signals(sensors: SensorSet, sim, arrays, shared=None):
    """The `sensor_<unit>_<signal>` arrays of a whole run already simulated: a Simulation (its scenario,
    model and speed table) and its output arrays; any sensor set over the same arrays, no re-simulation.
    `shared`: the run's `shared_readings` of a set with the same mounts, units and seed, when already known."""
    return named(SensorStream(sensors, sim.scenario, sim.model, sim.speed_table).process(arrays, shared))


@dataclass(frozen=True)
class Readings:
    """What the variants of a sensor set (its instruments' scales, its rates) over one whole run share
    (`run_signals`' `shared`): the ideal readings (n, channels) of its mounts and air springs, and its noise
    draws (`SensorStream.noise_draws`) with the seed and units they were drawn for (`SensorStream.draw_units`).
    Each variant drawing them anew drew the same numbers: a third of the catalogue's sensor variants' time."""
    ideal: np.ndarray
    draws: np.ndarray
    units: tuple


def shared_readings(sensors: SensorSet, sim, arrays):
    """The `Readings` of a set over a whole run."""
    stream = SensorStream(sensors, sim.scenario, sim.model, sim.speed_table)
    return Readings(stream.ideal(arrays), stream.noise_draws(len(arrays["time"])), stream.draw_units)


class SensorLog:
    """A whole run's sensor signals: `observe(sim, rows)` after each chunk of `vehicle.simulate.simulate`,
    then `arrays()`: `sensor_<unit>_<signal>` arrays for the output file (docs/output-format.md)."""

    def __init__(self, sensors: SensorSet):
        self.sensors, self.stream, self.parts = sensors, None, {}

    def observe(self, sim, rows):
        if self.stream is None:
            self.stream = SensorStream(self.sensors, sim.scenario, sim.model, sim.speed_table)
        for name, values in named(self.stream.process(output_arrays(rows))).items():
            self.parts.setdefault(name, []).append(values)

    def arrays(self):
        return {name: np.concatenate(parts) for name, parts in self.parts.items()}
