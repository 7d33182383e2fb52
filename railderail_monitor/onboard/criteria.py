"""Criteria on what a train in service measures (railderail_sim.sensors: accelerometers and gyros on the
bogie frames and the car body, the odometer), each from its source with the standard's filter.

Every criterion is a plain function over arrays (time in s, signal in SI) returning a `Measured`: a value
per sample and the level it is compared with, so that `Measured.alarm_mask` (through the monitor's
`warning.alarms.alarm_intervals`, as `scoring.in_alarm` uses it) gives the channel's alarm state sample by sample,
and the warning evaluation can score it beside the ground-truth criteria.

The filters are EN 14363's (railderail_sim.assessment.filters), applied causally: the analog design is
turned into a digital one by the bilinear transform at the sensor's rate (`causal`), as an on-board unit
must filter (it cannot see the future), prewarped at the band's centre (its gain there is the analog one;
without it a 3-7 Hz band at 200 Hz loses 1 % at 5 Hz).

| criterion                | signal                         | filter          | value                                  | level (sure)                  |
| ------------------------ | ------------------------------ | --------------- | -------------------------------------- | ----------------------------- |
| `bogie_rms`              | bogie-frame lateral acc.       | f0 +- 2 Hz      | sliding r.m.s. over 100 m, 10 m step   | (12 - M_b/5)/2 m/s^2 (C)      |
| `bogie_peak`             | bogie-frame lateral acc.       | f0 +- 2 Hz      | abs. value                             | 12 - M_b/5 m/s^2 (C)          |
| `bids_peak_count`        | bogie-frame lateral acc.       | 4-8 Hz          | consecutive half-wave peaks >= 8 m/s^2 | more than 6 peaks within      |
|                          |                                |                 | within the last 500 ms                 | 500 ms (A: EP 2166333 "e.g.") |
| `bids_peak_count_china`  | bogie-frame lateral acc.       | 0.5-10 Hz       | consecutive peaks >= 8 m/s^2           | 6 peaks (C)                   |
| `car_body_lateral`       | car-body floor lateral acc.    | 0.4-10 Hz       | abs. value (EN 14363 ydd*)             | 2.5 m/s^2 (C)                 |
| `car_body_lateral_qst`   | car-body floor lateral acc.    | 20 Hz low-pass  | sliding mean over 100 m, 10 m step     | 1.5 m/s^2 (C)                 |
| `car_body_roll`          | air-spring heights             | 20 Hz low-pass  | abs. roll of the car body to its bogie | emergency-spring contact (A)  |
| `car_body_roll_rate`     | car-body gyro, x               | 0.4-10 Hz       | abs. roll rate                         | roll level x roll frequency (A)|
| `car_body_twist`         | air-spring heights, gyro x     | -               | abs. 100 m mean of front minus rear    | 3 sigma of the height sensors'|
|                          |                                |                 | roll to the bogie, gated on cant ramps | offsets (A, derived)          |

Track distance (the EN 14363 windows are in metres) is the odometer's speed integrated, causally (`Odometer`).
"""
from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np
from scipy import signal as sps

from railderail_sim.assessment import en14363, filters
from railderail_sim.ranges import check_range

from ..warning.alarms import alarm_intervals

# UIC 515-5 as stated in EP 2166333 A1 (Bombardier, 2010) [0004]: band about 4-8 Hz, "more than" "e.g." 6
# consecutive peaks over "e.g." 8 m/s^2 within "e.g." 500 ms (A for what the patent states; the UIC leaflet
# itself not read). "More than 6" is a count of 7 reached: the level the monitor's Detector compares with.
BIDS_BAND_HZ = (4.0, 8.0)
BIDS_LIMIT = 8.0            # m/s^2
BIDS_PEAKS = 7
BIDS_WINDOW_S = 0.5
# the Chinese on-board instability alarm (GB/T 5599-2019 / TB/T 3188 / the 2008 EMU test code as recalled,
# C): 0.5-10 Hz (A: CARS study of the existing rule), 6 or more consecutive peaks at or over 8-10 m/s^2
CHINA_BAND_HZ = (0.5, 10.0)
CHINA_LIMIT = 8.0           # m/s^2 (10 for power bogies in some texts)
CHINA_PEAKS = 6
CAR_BODY_CENTRE_HZ = math.sqrt(filters.CAR_BODY_BAND_HZ[0] * filters.CAR_BODY_BAND_HZ[1])


def causal(analog, rate_hz, centre_hz):
    """Second-order sections of the digital filter made from an AnalogFilter by the bilinear transform at
    rate_hz, prewarped at centre_hz: the transform at fs' = w / (2 tan(w / 2 fs)), w = 2 pi centre_hz, maps
    that frequency onto itself."""
    check_range("sample rate", rate_hz, 2.0 * centre_hz, math.inf, "Hz", lo_open=True)
    w = 2.0 * math.pi * centre_hz
    z, p, k = sps.tf2zpk(analog.b, analog.a)
    zd, pd, kd = sps.bilinear_zpk(z, p, k, w / (2.0 * math.tan(w / (2.0 * rate_hz))))
    return sps.zpk2sos(zd, pd, kd)


SHORT_CHUNK = 16       # samples up to which SosFilter runs its own loop instead of scipy's


class SosFilter:
    """A digital filter's second-order sections over a signal fed in chunks (axis 0 time), its state carried
    (scipy.signal.sosfilt's zi) and settled on the first sample (as the sensors' filters start,
    sensors.measure: a monitor switched on does not see a step): the same output whatever the chunks."""

    def __init__(self, sos):
        self.sos = np.asarray(sos, dtype=float)
        self.sections = self.sos.tolist()
        self.zi = None              # the state as scipy holds it (sections, 2, ...) or, between short chunks,
        self.state = None           # as Python floats [section][0 or 1][channel]

    def __call__(self, x):
        x = np.asarray(x, dtype=float)
        if not len(x):
            return x.copy()
        if self.zi is None and self.state is None:
            self.zi = sps.sosfilt_zi(self.sos).reshape((self.sos.shape[0], 2) + (1,) * (x.ndim - 1)) * x[0]
        if len(x) > SHORT_CHUNK:
            if self.zi is None:
                self.zi = np.array(self.state).reshape((self.sos.shape[0], 2) + x.shape[1:])
                self.state = None
            y, self.zi = sps.sosfilt(self.sos, x, axis=0, zi=self.zi)
            return y
        return self._short(x)

    def _short(self, x):
        """sosfilt's recursion (scipy/signal/_sosfilt.pyx) in Python floats, the same operations in the same
        order (so the same numbers), without its call's overhead, which dominates for a sample or two."""
        if self.state is None:
            self.state = self.zi.reshape(self.sos.shape[0], 2, -1).tolist()
            self.zi = None
        state = self.state
        rows = x.reshape(len(x), -1).tolist()
        for row in rows:
            for c, value in enumerate(row):
                for z, (b0, b1, b2, _, a1, a2) in zip(state, self.sections):
                    y = b0 * value + z[0][c]
                    z[0][c] = b1 * value - a1 * y + z[1][c]
                    z[1][c] = b2 * value - a2 * y
                    value = y
                row[c] = value
        return np.array(rows).reshape(x.shape)


class CausalFilter(SosFilter):
    """`causal(analog, rate_hz, centre_hz)` as a SosFilter."""

    def __init__(self, analog, rate_hz, centre_hz):
        super().__init__(causal(analog, rate_hz, centre_hz))


def apply_causal(analog, x, rate_hz, centre_hz):
    """The record x (axis 0 time) through `CausalFilter`."""
    return CausalFilter(analog, rate_hz, centre_hz)(x)


def sample_rate(time):
    """The sample rate (Hz) of a record's stamps: the inverse of their median step (lost samples leave gaps)."""
    t = np.asarray(time, dtype=float)
    if len(t) < 2 or not np.all(np.diff(t) > 0):
        raise ValueError(f"sensor time stamps must be at least 2 and strictly increasing, {len(t)} given")
    return 1.0 / float(np.median(np.diff(t)))


class Odometer:
    """Track distance from the odometer's samples, fed in chunks (`add`): `position(at)` at times at or
    after the samples' start of what is kept (`forget` drops those no later time needs). The distance at its
    sample k is 0 at the first and grows by each step's starting speed times its duration; at a time t it is
    that at the last sample k at or before t plus v_k (t - t_k), 0 before the first (causal: no later sample
    is used). Continuous and non-decreasing (speeds >= 0); it lags the true distance by at most the change of
    speed over a sample period times the period."""

    def __init__(self):
        self.t, self.v, self.s = np.zeros(0), np.zeros(0), np.zeros(0)
        self.started = False
        self.last_query = None          # (time, samples kept, position) of the last single stamp asked

    def add(self, time, speed):
        t, v = np.asarray(time, dtype=float), np.asarray(speed, dtype=float)
        if not len(t):
            return
        if self.started:
            steps = np.concatenate([self.v[-1:], v[:-1]]) * np.diff(np.concatenate([self.t[-1:], t]))
            s = np.cumsum(np.concatenate([self.s[-1:], steps]))[1:]
        else:
            s = np.cumsum(np.concatenate([[0.0], v[:-1] * np.diff(t)]))
            self.started = True
        self.t, self.v, self.s = (np.concatenate([self.t, t]), np.concatenate([self.v, v]),
                                  np.concatenate([self.s, s]))

    def position(self, at_time):
        at = np.asarray(at_time, dtype=float)
        if at.size == 1 and len(self.t):          # one stamp: the same operations without array calls
            x = at.item()
            if self.last_query is not None and self.last_query[0] == x and self.last_query[1] == len(self.t):
                return np.full(at.shape, self.last_query[2])     # the units of one instant ask alike
            k = int(self.t.searchsorted(x, "right")) - 1
            value = float(self.s[k]) + float(self.v[k]) * (x - float(self.t[k])) if k >= 0 else 0.0
            self.last_query = (x, len(self.t), value)
            return np.full(at.shape, value)
        k = np.searchsorted(self.t, at, "right") - 1
        kk = np.maximum(k, 0)
        if not len(self.t):
            return np.zeros(at.shape)
        return np.where(k >= 0, self.s[kk] + self.v[kk] * (at - self.t[kk]), 0.0)

    def speed(self, at_time):
        """The speed (m/s) of the last sample at or before each time, 0 before the first."""
        k = np.searchsorted(self.t, np.asarray(at_time, dtype=float), "right") - 1
        return np.where(k >= 0, self.v[np.maximum(k, 0)], 0.0) if len(self.t) else np.zeros(np.shape(at_time))

    def forget(self, before):
        """Drop the samples no time at or after `before` needs (all but the last at or before it)."""
        keep = max(int(np.searchsorted(self.t, before, "right")) - 1, 0)
        self.t, self.v, self.s = self.t[keep:], self.v[keep:], self.s[keep:]
        self.last_query = None


def odometer_distance(odometer_time, odometer_speed, at_time):
    """Track distance (m) at each of `at_time` from a whole record of the odometer (`Odometer`)."""
    odometer = Odometer()
    odometer.add(odometer_time, odometer_speed)
    return odometer.position(at_time)


@dataclass(frozen=True)
class Measured:
    """A criterion's value per sample (n,) and its level, in SI (`unit`), with its source and how sure.
    From `measured.evaluate`: value (n, k), one column per place (`places`: the mount or running-gear side),
    on the criterion's own `time` (n,) s, with the track `position` (n,) m the odometer gives there."""
    criterion: str
    value: np.ndarray
    level: float
    unit: str
    source: str
    sure: str
    debounce: float = 0.0     # m of track the value must stay at or above the level before the alarm
    time: np.ndarray = None
    position: np.ndarray = None
    places: tuple = ()

    def alarm_intervals(self, position, rearm_fraction=0.9, rearm_m=50.0):
        """[(alert, rearm)] of the monitor's Detector fed this value (`warning.alarms.alarm_intervals`)."""
        return alarm_intervals(self.value, position, self.level, self.debounce, rearm_fraction, rearm_m)

    def channel_intervals(self, position=None, rearm_fraction=0.9, rearm_m=50.0):
        """[[(alert, rearm)] of each column] (one list for a value (n,)), each column its own channel."""
        position = self.position if position is None else position
        columns = self.value.T if np.ndim(self.value) == 2 else [self.value]
        return [alarm_intervals(v, position, self.level, self.debounce, rearm_fraction, rearm_m) for v in columns]

    def alarm_mask(self, position=None, rearm_fraction=0.9, rearm_m=50.0):
        """(n,) bool: a channel is in alarm (as `scoring.in_alarm`)."""
        mask = np.zeros(len(self.value), dtype=bool)
        for intervals in self.channel_intervals(position, rearm_fraction, rearm_m):
            for a, b in intervals:
                mask[a:b] = True
        return mask

    def first_alarm(self, position, rearm_fraction=0.9, rearm_m=50.0):
        """The sample of the first alert, or None."""
        found = self.alarm_intervals(position, rearm_fraction, rearm_m)
        return found[0][0] if found else None


class TrailingWindow:
    """At each sample, the mean of values**power over the last completed window of `window_m` m of track,
    the windows every `step_m` m from the first sample's position (EN 14363's sliding windows, as
    en14363.sliding integrates them: the trapezoid over the track, interpolated at the window's ends, as a
    monitor sees them: each known once the train has run its whole length); NaN before the first is complete.
    Fed (position, values) in chunks (positions strictly increasing), it keeps the samples the windows still
    to come need and gives the same numbers whatever the chunks: the running integral is one sequential sum,
    each window end interpolated between the same two samples."""

    def __init__(self, window_m, step_m, power):
        self.window, self.step, self.power = float(window_m), float(step_m), power
        self.s, self.integral = [], []      # the kept samples' positions and running integrals (floats)
        self.v = None                       # the last value**power
        self.lo, self.k, self.mean = None, 0, math.nan

    def __call__(self, position, values):
        s, v = np.asarray(position, dtype=float), np.asarray(values, dtype=float) ** self.power
        n = len(s)
        if not n:
            return np.full(0, np.nan)
        if self.lo is None:
            self.lo = s[0] + 0.5 * self.window
        if n > SHORT_CHUNK:
            if self.s:
                steps = 0.5 * np.diff(np.concatenate([[self.s[-1]], s])) * (v + np.concatenate([[self.v], v[:-1]]))
                integral = np.cumsum(np.concatenate([[self.integral[-1]], steps]))[1:]
            else:
                integral = np.cumsum(np.concatenate([[0.0], 0.5 * np.diff(s) * (v[1:] + v[:-1])]))
            self.s += s.tolist()
            self.integral += integral.tolist()
        else:           # the same operations in Python floats: a sample at a time costs no array calls
            for si, vi in zip(s.tolist(), v.tolist()):
                self.integral.append(self.integral[-1] + 0.5 * (si - self.s[-1]) * (vi + self.v) if self.s else 0.0)
                self.s.append(si)
                self.v = vi
        self.v = float(v[-1])
        last = self.s[-1]
        if not self.lo + self.step * self.k + 0.5 * self.window <= last:
            return np.full(n, self.mean)         # no window completed in this chunk
        hs, hi = np.array(self.s), np.array(self.integral)
        # the windows completed: k from self.k while their end is at or before the last sample
        k = self.k + np.arange(max(int(math.floor((last - 0.5 * self.window - self.lo) / self.step + 1e-9))
                                   + 1 - self.k, 0))
        centres = self.lo + self.step * k
        ends = centres + 0.5 * self.window
        k, centres, ends = k[ends <= last], centres[ends <= last], ends[ends <= last]
        means = (np.interp(ends, hs, hi) - np.interp(centres - 0.5 * self.window, hs, hi)) / self.window
        out = np.concatenate([[self.mean], means])[np.searchsorted(np.concatenate([[-math.inf], ends]), s, "right") - 1]
        if len(k):
            self.k, self.mean = int(k[-1]) + 1, float(means[-1])
        # keep from the last sample at or before the next window's start
        keep = max(int(np.searchsorted(hs, self.lo + self.step * self.k - 0.5 * self.window, "right")) - 1, 0)
        del self.s[:keep], self.integral[:keep]
        return out


def trailing_window(position, values, window_m, step_m, power):
    """`TrailingWindow` over a whole record."""
    return TrailingWindow(window_m, step_m, power)(position, values)


def bogie_limits(bogie_mass):
    """(peak, r.m.s.) limits of the bogie frame's lateral acceleration (m/s^2) for a bogie of bogie_mass kg
    with its wheelsets: 12 - M_b/5 and half of it, M_b in t (EN 14363:2005 / UIC 515 / UIC 518, C)."""
    check_range("bogie mass", bogie_mass, 0.0, 60e3, "kg", lo_open=True)
    rms = en14363.bogie_rms_limit(bogie_mass)
    return 2.0 * rms, rms


def hunting_frequency(time, frame_lateral):
    """f0 (Hz): the peak of the Welch spectrum of the frame's lateral acceleration in EN 14363's search
    band (en14363.INSTABILITY_BAND_HZ), for a record whose instability frequency is not known beforehand."""
    f0 = en14363.spectral_peak(frame_lateral, sample_rate(time))
    if f0 is None:
        raise ValueError(f"a record of {len(time)} samples is too short for a spectrum in "
                         f"{en14363.INSTABILITY_BAND_HZ[0]:g}-{en14363.INSTABILITY_BAND_HZ[1]:g} Hz")
    return f0


def bogie_rms(time, frame_lateral, position, bogie_mass, f0_hz, rate_hz=None, window_m=en14363.RMS_WINDOW_M,
              step_m=en14363.RMS_STEP_M):
    """EN 14363's instability rule on the bogie frame (simplified method): the lateral acceleration band-passed
    f0 +- 2 Hz (filters.stability_band_pass), its sliding r.m.s. over 100 m every 10 m (en14363.RMS_WINDOW_M,
    RMS_STEP_M), against (12 - M_b/5)/2 m/s^2. Processing B (GENSYS course page), limit and window C.
    rate_hz: the sensor's sample rate (default: from the stamps, `sample_rate`)."""
    value = BogieRms(rate_hz or sample_rate(time), f0_hz, window_m, step_m)(frame_lateral, position)
    return Measured("bogie_rms", value, bogie_limits(bogie_mass)[1], "m/s^2",
                    "EN 14363:2005 / UIC 518 simplified method: (12 - M_b/5)/2, sliding r.m.s. 100 m, f0 +- 2 Hz", "C")


def bogie_peak(time, frame_lateral, bogie_mass, f0_hz, rate_hz=None):
    """The peak form of the same rule (UIC 515 / UIC 518): |band-passed frame acceleration| against
    12 - M_b/5 m/s^2 (C)."""
    value = BogiePeak(rate_hz or sample_rate(time), f0_hz)(frame_lateral, None)
    return Measured("bogie_peak", value, bogie_limits(bogie_mass)[0], "m/s^2",
                    "UIC 515 / UIC 518 / EN 14363:2005: 12 - M_b/5 (recalled)", "C")


class PeakCounter:
    """The number of consecutive half-wave peaks of a signal at or over `limit` in magnitude, known at each
    sample: a half-wave runs between sign changes, its peak is its largest |x|; the count rises at the sample
    where |x| first reaches the limit within a half-wave, falls to 0 at the start of the half-wave after one
    that never reached it, and holds between. With `window` (samples), only the run's peaks reached within
    the last `window` samples count (UIC 515-5's "within a set time"). Fed in chunks, the current half-wave
    and the run's peak samples carried over. A loop per sample: the on-board monitor feeds it a message's few
    samples at a time, where numpy's per-call cost (running sums over the chunk: 47-90 us a call against
    2 us) outweighs what whole runs would gain (4.5 times over 100 000 samples)."""

    def __init__(self, limit, window=None):
        self.limit, self.run, self.reached, self.negative = float(limit), 0, False, None
        self.window, self.n, self.peaks = window, 0, []      # the samples at which the run's peaks were reached

    def __call__(self, x):
        count = []
        for value in np.asarray(x, dtype=float).tolist():
            negative = math.copysign(1.0, value) < 0.0          # np.signbit: a sign change at -0.0 too
            if negative != self.negative:                      # a new half-wave
                if not self.reached:
                    self.run = 0
                    self.peaks.clear()
                self.reached, self.negative = False, negative
            if not self.reached and abs(value) >= self.limit:
                self.run += 1
                self.reached = True
                self.peaks.append(self.n)
            if self.window is None:
                count.append(self.run)
            else:
                while self.peaks and self.peaks[0] <= self.n - self.window:
                    del self.peaks[0]
                count.append(len(self.peaks))
            self.n += 1
        return np.array(count, dtype=float)


def consecutive_peaks(x, limit, window=None):
    """(n,) `PeakCounter` over a whole record."""
    return PeakCounter(limit, window)(x)


def peak_count(time, frame_lateral, band_hz=BIDS_BAND_HZ, limit=BIDS_LIMIT, peaks=BIDS_PEAKS,
               name="bids_peak_count", source="UIC 515-5 as stated in EP 2166333 A1 [0004] (e.g. values)", sure="A",
               rate_hz=None, window_s=BIDS_WINDOW_S):
    """The peak-count rule of on-board bogie instability detection: the frame's lateral acceleration band-passed
    `band_hz` (Butterworth, 2 poles at each edge), alarm when `peaks` consecutive half-wave peaks reach `limit`
    m/s^2 within the last `window_s` (None: in a row, however long). Defaults: UIC 515-5 (EP 2166333);
    `china_peak_count` for the Chinese form."""
    check_range("number of peaks", peaks, 1, 1000)
    value = PeakCount(rate_hz or sample_rate(time), band_hz, limit, window_s)(frame_lateral, None)
    return Measured(name, value, float(peaks), "peaks", source, sure)


CHINA_SOURCE = ("GB/T 5599-2019 / TB/T 3188 / 2008 EMU test code (clause not read); band and 8 m/s^2 from a "
                "CARS study")


def china_peak_count(time, frame_lateral, limit=CHINA_LIMIT, band_hz=CHINA_BAND_HZ, peaks=CHINA_PEAKS, rate_hz=None):
    """The Chinese on-board form: 0.5-10 Hz, 6 consecutive peaks at or over 8 m/s^2 (10 for power bogies)."""
    return peak_count(time, frame_lateral, band_hz, limit, peaks, "bids_peak_count_china", CHINA_SOURCE, "C",
                      rate_hz, None)


def car_body_lateral(time, floor_lateral, debounce_m=0.0, rate_hz=None):
    """EN 14363's ydd*: the car-body floor's lateral acceleration over a bogie band-passed 0.4-10 Hz, its
    magnitude against 2.5 m/s^2 (passenger coaches and MUs, C; the standard takes the 99.85 % percentile of
    a section, a monitor each sample)."""
    value = CarBodyLateral(rate_hz or sample_rate(time))(floor_lateral, None)
    lim = en14363.LIMITS["ydd_car_body"]
    return Measured("car_body_lateral", value, lim.value, lim.unit, lim.source, lim.sure, debounce_m)


def car_body_lateral_qst(time, floor_lateral, position, rate_hz=None, window_m=en14363.MIN_SECTION_M,
                         step_m=en14363.RMS_STEP_M):
    """EN 14363's ydd*_qst: the floor's lateral acceleration low-passed 20 Hz, its mean over the last 100 m
    (en14363.MIN_SECTION_M, the shortest curve section) every 10 m, its magnitude against 1.5 m/s^2 (C)."""
    value = CarBodyLateralQst(rate_hz or sample_rate(time), window_m, step_m)(floor_lateral, position)
    lim = en14363.LIMITS["ydd_qst"]
    return Measured("car_body_lateral_qst", value, lim.value, lim.unit, lim.source, lim.sure)


def air_spring_roll(deflection, air_spring_semi_spacing):
    """(n, 2) the car body's roll (rad, + right-handed about x forward: the left side up) to the front and the
    rear bogie from the air springs' compressions (n, 4) [front left, front right, rear left, rear right]."""
    d = np.asarray(deflection, dtype=float)
    return np.stack([(d[:, 1] - d[:, 0]), (d[:, 3] - d[:, 2])], axis=1) / (2.0 * air_spring_semi_spacing)


def roll_level(vehicle):
    """The car body's roll (rad) to its bogie at which the air spring on the low side reaches its emergency
    spring: its clearance over the springs' semi-spacing (A: the clearance is an assumption, parameters.py)."""
    return vehicle.air_spring_emergency_clearance / vehicle.air_spring_semi_spacing


def car_body_roll(time, deflection, vehicle, rate_hz=None):
    """The car body's roll to its bogies (the larger of the two), low-passed 20 Hz, against the roll at which
    an air spring reaches its emergency spring (`roll_level`, A): beyond it the car body rolls on the stiff
    stop and the roll no longer tells the load it carries."""
    value = CarBodyRoll(rate_hz or sample_rate(time), vehicle)(deflection, None)
    return Measured("car_body_roll", value, roll_level(vehicle), "rad",
                    "air spring at its emergency spring: clearance / semi-spacing (parameters.py, A)", "A")


def car_body_roll_frequency(vehicle):
    """The car body's roll frequency (Hz) on its air springs and anti-roll bars, the body as a rigid mass on
    the secondary (the lower sway mode neglected): sqrt(k_roll / I_roll) / 2 pi, k_roll = 2 bogies x (2 k_z
    b_s^2 + k_bar)."""
    k = 2.0 * (2.0 * vehicle.secondary_vertical_stiffness * vehicle.air_spring_semi_spacing ** 2
               + vehicle.anti_roll_stiffness)
    return math.sqrt(k / vehicle.car_body_roll_inertia) / (2.0 * math.pi)


def car_body_roll_rate(time, roll_rate, vehicle, rate_hz=None):
    """The car body's roll rate (the gyro's x, rad/s) band-passed 0.4-10 Hz (the car-body band: no steady
    part, no bias), against a roll oscillation at the body's roll frequency reaching `roll_level` (derived, A)."""
    value = CarBodyRollRate(rate_hz or sample_rate(time))(roll_rate, None)
    level = 2.0 * math.pi * car_body_roll_frequency(vehicle) * roll_level(vehicle)
    return Measured("car_body_roll_rate", value, level, "rad/s",
                    "roll level x 2 pi x the car body's roll frequency (derived)", "A")


# --- each criterion's value over a channel fed in chunks: (signal, position) -> value, the same whatever the
# chunks (the monitor's stream and the batch functions above run these) --------------------------------------

class BogieRms:
    """`bogie_rms`' value: the frame's lateral acceleration in f0 +- 2 Hz, its trailing r.m.s."""

    def __init__(self, rate_hz, f0_hz, window_m=en14363.RMS_WINDOW_M, step_m=en14363.RMS_STEP_M):
        self.band = CausalFilter(filters.stability_band_pass(f0_hz), rate_hz, f0_hz)
        self.window = TrailingWindow(window_m, step_m, 2)

    def __call__(self, x, position):
        return np.sqrt(self.window(position, self.band(x)))


class BogiePeak:
    """`bogie_peak`'s value: |the frame's lateral acceleration in f0 +- 2 Hz|."""

    def __init__(self, rate_hz, f0_hz):
        self.band = CausalFilter(filters.stability_band_pass(f0_hz), rate_hz, f0_hz)

    def __call__(self, x, position):
        return np.abs(self.band(x))


class PeakCount:
    """The peak-count rules' value: consecutive half-wave peaks of the band-passed signal over `limit`, within
    the last `window_s` if given."""

    def __init__(self, rate_hz, band_hz, limit, window_s=None):
        check_range("peak limit", limit, 0.0, 1000.0, "m/s^2", lo_open=True)
        self.band = CausalFilter(filters.butterworth(f"{band_hz[0]:g}-{band_hz[1]:g} Hz band-pass", 2, band_hz,
                                                     "bandpass"), rate_hz, math.sqrt(band_hz[0] * band_hz[1]))
        self.peaks = PeakCounter(limit, None if window_s is None else round(window_s * rate_hz))

    def __call__(self, x, position):
        return self.peaks(self.band(x))


class CarBodyLateral:
    """`car_body_lateral`'s value: |the floor's lateral acceleration in 0.4-10 Hz|."""

    def __init__(self, rate_hz):
        self.band = CausalFilter(filters.car_body_band_pass(), rate_hz, CAR_BODY_CENTRE_HZ)

    def __call__(self, x, position):
        return np.abs(self.band(x))


class CarBodyLateralQst:
    """`car_body_lateral_qst`'s value: |the trailing mean of the floor's 20 Hz low-passed lateral acceleration|."""

    def __init__(self, rate_hz, window_m=en14363.MIN_SECTION_M, step_m=en14363.RMS_STEP_M):
        self.low = CausalFilter(filters.force_low_pass(), rate_hz, filters.FORCE_LOW_PASS_HZ)
        self.window = TrailingWindow(window_m, step_m, 1)

    def __call__(self, x, position):
        return np.abs(self.window(position, self.low(x)))


class CarBodyRoll:
    """`car_body_roll`'s value: the larger roll to a bogie from the air springs' deflections (n, 4), low-passed."""

    def __init__(self, rate_hz, vehicle):
        self.semi_spacing = vehicle.air_spring_semi_spacing
        self.low = CausalFilter(filters.force_low_pass(), rate_hz, min(filters.FORCE_LOW_PASS_HZ, 0.4 * rate_hz))

    def __call__(self, deflection, position):
        low = self.low(air_spring_roll(np.reshape(deflection, (-1, 4)), self.semi_spacing))
        return np.max(np.abs(low), axis=1)


class CarBodyRollRate:
    """`car_body_roll_rate`'s value: |the gyro's roll rate in 0.4-10 Hz|."""

    def __init__(self, rate_hz):
        self.band = CausalFilter(filters.car_body_band_pass(), rate_hz, CAR_BODY_CENTRE_HZ)

    def __call__(self, x, position):
        return np.abs(self.band(x))


# --- the twist of the car body's two bogies, front minus rear: a broken or sagging primary spring ----------

def twist_level(vehicle, height_bias):
    """rad: three standard deviations of what the four height sensors' offsets (each `height_bias` m, one
    standard deviation) make of the twist ((d_FR - d_FL) - (d_RR - d_RL)) / 2 b_s: sqrt(4) height_bias / 2 b_s.
    Below it a twist may be a sensor's calibration; at 3 sigma the offsets reach it once in 370 cars."""
    return 3.0 * height_bias / vehicle.air_spring_semi_spacing


class CarBodyTwist:
    """`car_body_twist`'s value: |the trailing mean over window_m of the car body's roll to its front bogie
    minus that to its rear bogie| (rad, from the air springs' heights), NaN where the same window says a cant
    ramp: on a ramp the track rolls at omega = v dphi/ds and the two bogies, 2 l apart, differ in roll by
    omega 2 l / v; the car body rolls with the track, so the window's mean of the gyro's roll rate times
    2 l / v (2 l times the body's roll change over the window, over its length) is the ramp's share of the
    twist, and over half the level the window is not judged. Fed (deflection (n, 4), roll rate (n,), position
    (n,), speed (n,)) in chunks at the gyro's rate, the deflection held at its stamps."""

    def __init__(self, rate_hz, vehicle, level, window_m, step_m):
        self.vehicle, self.gate = vehicle, 0.5 * level
        self.twist = TrailingWindow(window_m, step_m, 1)
        self.ramp = TrailingWindow(window_m, step_m, 1)

    def __call__(self, deflection, roll_rate, position, speed):
        roll = air_spring_roll(np.reshape(deflection, (-1, 4)), self.vehicle.air_spring_semi_spacing)
        twist = np.abs(self.twist(position, roll[:, 0] - roll[:, 1]))
        # m/s: below a walking pace the ramp's share is not told from a stop's roll (and not divided by zero)
        ramp = np.abs(self.ramp(position, np.asarray(roll_rate) * 2.0 * self.vehicle.bogie_semi_distance
                                / np.maximum(speed, 1.0)))
        return np.where(ramp > self.gate, np.nan, twist)
