"""Criteria on what a train in service measures (railderail_sim.sensors: accelerometers and gyros on the
bogie frames and the car body, the odometer), each from its source with the standard's filter.

Every criterion is a plain function over arrays (time in s, signal in SI) returning a `Measured`: a value
per sample and the level it is compared with, so that `Measured.alarm_mask` (through the monitor's
`criteria.alarm_intervals`, as `scoring.in_alarm` uses it) gives the channel's alarm state sample by sample,
and the warning evaluation can score it beside the ground-truth criteria.

The filters are EN 14363's (railderail_sim.assessment.filters), applied causally: the analog design is
turned into a digital one by the bilinear transform at the sensor's rate (`causal`), as an on-board unit
must filter (it cannot see the future), prewarped at the band's centre (its gain there is the analog one;
without it a 3-7 Hz band at 200 Hz loses 1 % at 5 Hz).

| criterion                | signal                         | filter          | value                                  | level (sure)                  |
| ------------------------ | ------------------------------ | --------------- | -------------------------------------- | ----------------------------- |
| `bogie_rms`              | bogie-frame lateral acc.       | f0 +- 2 Hz      | sliding r.m.s. over 100 m, 10 m step   | (12 - M_b/5)/2 m/s^2 (C)      |
| `bogie_peak`             | bogie-frame lateral acc.       | f0 +- 2 Hz      | abs. value                             | 12 - M_b/5 m/s^2 (C)          |
| `bids_peak_count`        | bogie-frame lateral acc.       | 4-8 Hz          | consecutive half-wave peaks >= 8 m/s^2 | 6 peaks (A: EP 2166333 "e.g.")|
| `bids_peak_count_china`  | bogie-frame lateral acc.       | 0.5-10 Hz       | consecutive peaks >= 8 m/s^2           | 6 peaks (C)                   |
| `car_body_lateral`       | car-body floor lateral acc.    | 0.4-10 Hz       | abs. value (EN 14363 ydd*)             | 2.5 m/s^2 (C)                 |
| `car_body_lateral_qst`   | car-body floor lateral acc.    | 20 Hz low-pass  | sliding mean over 100 m, 10 m step     | 1.5 m/s^2 (C)                 |
| `car_body_roll`          | air-spring heights             | 20 Hz low-pass  | abs. roll of the car body to its bogie | emergency-spring contact (A)  |
| `car_body_roll_rate`     | car-body gyro, x               | 0.4-10 Hz       | abs. roll rate                         | roll level x roll frequency (A)|

Track distance (the EN 14363 windows are in metres) is the odometer's speed integrated (`odometer_distance`).
"""
from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np
from scipy import signal as sps

from railderail_sim.assessment import en14363, filters
from railderail_sim.ranges import check_range

from ..criteria import alarm_intervals

# UIC 515-5 as stated in EP 2166333 A1 (Bombardier, 2010) [0004]: band about 4-8 Hz, "e.g." N = 6 peaks
# over 8 m/s^2 (A for what the patent states; the UIC leaflet itself not read)
BIDS_BAND_HZ = (4.0, 8.0)
BIDS_LIMIT = 8.0            # m/s^2
BIDS_PEAKS = 6
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


def apply_causal(analog, x, rate_hz, centre_hz):
    """The record x (axis 0 time) through `causal(analog, rate_hz)`, its state settled on the first sample
    (as the sensors' filters start, sensors.measure): a monitor switched on does not see a step."""
    sos = causal(analog, rate_hz, centre_hz)
    x = np.asarray(x, dtype=float)
    zi = sps.sosfilt_zi(sos).reshape((sos.shape[0], 2) + (1,) * (x.ndim - 1)) * x[0]
    return sps.sosfilt(sos, x, axis=0, zi=zi)[0]


def sample_rate(time):
    """The sample rate (Hz) of a record's stamps: the inverse of their median step (lost samples leave gaps)."""
    t = np.asarray(time, dtype=float)
    if len(t) < 2 or not np.all(np.diff(t) > 0):
        raise ValueError(f"sensor time stamps must be at least 2 and strictly increasing, {len(t)} given")
    return 1.0 / float(np.median(np.diff(t)))


def odometer_distance(odometer_time, odometer_speed, at_time):
    """Track distance (m) at `at_time` from the odometer's speed, integrated (trapezoid) from its first
    sample and held constant before it."""
    t = np.asarray(odometer_time, dtype=float)
    v = np.asarray(odometer_speed, dtype=float)
    s = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (v[1:] + v[:-1]))])
    return np.interp(at_time, t, s)


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
        """[(alert, rearm)] of the monitor's Detector fed this value (`criteria.alarm_intervals`)."""
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


def trailing_window(position, values, window_m, step_m, power):
    """At each sample, the mean of values**power over the last completed window of `window_m` m of track,
    the windows every `step_m` m (en14363.sliding: EN 14363's sliding windows as a monitor sees them, each
    known once the train has run its whole length); NaN before the first is complete."""
    s = np.asarray(position, dtype=float)
    centres, means = en14363.sliding(s, np.asarray(values, dtype=float), window_m, step_m, -math.inf, math.inf,
                                     power)
    out = np.full(len(s), np.nan)
    if len(centres):
        k = np.searchsorted(centres + 0.5 * window_m, s, "right") - 1
        out[k >= 0] = means[k[k >= 0]]
    return out


def bogie_limits(bogie_mass):
    """(peak, r.m.s.) limits of the bogie frame's lateral acceleration (m/s^2) for a bogie of bogie_mass kg
    with its wheelsets: 12 - M_b/5 and half of it, M_b in t (EN 14363:2005 / UIC 515 / UIC 518, C)."""
    check_range("bogie mass", bogie_mass, 0.0, 60e3, "kg", lo_open=True)
    rms = en14363.bogie_rms_limit(bogie_mass)
    return 2.0 * rms, rms


def hunting_frequency(time, frame_lateral):
    """f0 (Hz): the peak of the Welch spectrum of the frame's lateral acceleration in EN 14363's search
    band (en14363.INSTABILITY_BAND_HZ), for a record whose instability frequency is not known beforehand."""
    rate = sample_rate(time)
    x = np.asarray(frame_lateral, dtype=float)
    f, p = sps.welch(x - x.mean(), fs=rate, nperseg=min(len(x), int(round(4.0 * rate))))
    band = (f >= en14363.INSTABILITY_BAND_HZ[0]) & (f <= en14363.INSTABILITY_BAND_HZ[1])
    return float(f[band][np.argmax(p[band])])


def bogie_rms(time, frame_lateral, position, bogie_mass, f0_hz, rate_hz=None, window_m=en14363.RMS_WINDOW_M,
              step_m=en14363.RMS_STEP_M):
    """EN 14363's instability rule on the bogie frame (simplified method): the lateral acceleration band-passed
    f0 +- 2 Hz (filters.stability_band_pass), its sliding r.m.s. over 100 m every 10 m (en14363.RMS_WINDOW_M,
    RMS_STEP_M), against (12 - M_b/5)/2 m/s^2. Processing B (GENSYS course page), limit and window C.
    rate_hz: the sensor's sample rate (default: from the stamps, `sample_rate`)."""
    rate = rate_hz or sample_rate(time)
    band = apply_causal(filters.stability_band_pass(f0_hz), frame_lateral, rate, f0_hz)
    mean_square = trailing_window(position, band, window_m, step_m, 2)
    return Measured("bogie_rms", np.sqrt(mean_square), bogie_limits(bogie_mass)[1], "m/s^2",
                    "EN 14363:2005 / UIC 518 simplified method: (12 - M_b/5)/2, sliding r.m.s. 100 m, f0 +- 2 Hz", "C")


def bogie_peak(time, frame_lateral, bogie_mass, f0_hz, rate_hz=None):
    """The peak form of the same rule (UIC 515 / UIC 518): |band-passed frame acceleration| against
    12 - M_b/5 m/s^2 (C)."""
    band = apply_causal(filters.stability_band_pass(f0_hz), frame_lateral, rate_hz or sample_rate(time), f0_hz)
    return Measured("bogie_peak", np.abs(band), bogie_limits(bogie_mass)[0], "m/s^2",
                    "UIC 515 / UIC 518 / EN 14363:2005: 12 - M_b/5 (recalled)", "C")


def consecutive_peaks(x, limit):
    """(n,) the number of consecutive half-wave peaks of x at or over `limit` in magnitude, known at each
    sample: a half-wave runs between sign changes, its peak is its largest |x|; the count rises at the sample
    where |x| first reaches the limit within a half-wave, falls to 0 at the end of a half-wave that never
    reached it, and holds between."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    count = np.zeros(n)
    sign_change = np.flatnonzero(np.signbit(x[1:]) != np.signbit(x[:-1])) + 1
    starts = np.concatenate([[0], sign_change])
    ends = np.concatenate([sign_change, [n]])
    run = 0
    for a, b in zip(starts, ends):
        over = np.flatnonzero(np.abs(x[a:b]) >= limit)
        if len(over):
            count[a:a + over[0]] = run
            run += 1
            count[a + over[0]:b] = run
        else:
            count[a:b] = run
            run = 0                        # from the next half-wave's first sample on
    return count


def peak_count(time, frame_lateral, band_hz=BIDS_BAND_HZ, limit=BIDS_LIMIT, peaks=BIDS_PEAKS,
               name="bids_peak_count", source="UIC 515-5 as stated in EP 2166333 A1 [0004] (e.g. values)", sure="A",
               rate_hz=None):
    """The peak-count rule of on-board bogie instability detection: the frame's lateral acceleration band-passed
    `band_hz` (Butterworth, 2 poles at each edge), alarm when `peaks` consecutive half-wave peaks reach `limit`
    m/s^2. Defaults: UIC 515-5 (EP 2166333); `china_peak_count` for the Chinese form."""
    check_range("peak limit", limit, 0.0, 1000.0, "m/s^2", lo_open=True)
    check_range("number of peaks", peaks, 1, 1000)
    band = apply_causal(filters.butterworth(f"{band_hz[0]:g}-{band_hz[1]:g} Hz band-pass", 2, band_hz, "bandpass"),
                        frame_lateral, rate_hz or sample_rate(time), math.sqrt(band_hz[0] * band_hz[1]))
    return Measured(name, consecutive_peaks(band, limit), float(peaks), "peaks", source, sure)


CHINA_SOURCE = ("GB/T 5599-2019 / TB/T 3188 / 2008 EMU test code (clause not read); band and 8 m/s^2 from a "
                "CARS study")


def china_peak_count(time, frame_lateral, limit=CHINA_LIMIT, band_hz=CHINA_BAND_HZ, peaks=CHINA_PEAKS, rate_hz=None):
    """The Chinese on-board form: 0.5-10 Hz, 6 consecutive peaks at or over 8 m/s^2 (10 for power bogies)."""
    return peak_count(time, frame_lateral, band_hz, limit, peaks, "bids_peak_count_china", CHINA_SOURCE, "C",
                      rate_hz)


def car_body_lateral(time, floor_lateral, debounce_m=0.0, rate_hz=None):
    """EN 14363's ydd*: the car-body floor's lateral acceleration over a bogie band-passed 0.4-10 Hz, its
    magnitude against 2.5 m/s^2 (passenger coaches and MUs, C; the standard takes the 99.85 % percentile of
    a section, a monitor each sample)."""
    band = apply_causal(filters.car_body_band_pass(), floor_lateral, rate_hz or sample_rate(time), CAR_BODY_CENTRE_HZ)
    lim = en14363.LIMITS["ydd_car_body"]
    return Measured("car_body_lateral", np.abs(band), lim.value, lim.unit, lim.source, lim.sure, debounce_m)


def car_body_lateral_qst(time, floor_lateral, position, rate_hz=None, window_m=en14363.MIN_SECTION_M,
                         step_m=en14363.RMS_STEP_M):
    """EN 14363's ydd*_qst: the floor's lateral acceleration low-passed 20 Hz, its mean over the last 100 m
    (en14363.MIN_SECTION_M, the shortest curve section) every 10 m, its magnitude against 1.5 m/s^2 (C)."""
    low = apply_causal(filters.force_low_pass(), floor_lateral, rate_hz or sample_rate(time), filters.FORCE_LOW_PASS_HZ)
    mean = trailing_window(position, low, window_m, step_m, 1)
    lim = en14363.LIMITS["ydd_qst"]
    return Measured("car_body_lateral_qst", np.abs(mean), lim.value, lim.unit, lim.source, lim.sure)


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
    roll = air_spring_roll(deflection, vehicle.air_spring_semi_spacing)
    rate = rate_hz or sample_rate(time)
    low = apply_causal(filters.force_low_pass(), roll, rate, min(filters.FORCE_LOW_PASS_HZ, 0.4 * rate))
    return Measured("car_body_roll", np.max(np.abs(low), axis=1), roll_level(vehicle), "rad",
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
    band = apply_causal(filters.car_body_band_pass(), roll_rate, rate_hz or sample_rate(time), CAR_BODY_CENTRE_HZ)
    level = 2.0 * math.pi * car_body_roll_frequency(vehicle) * roll_level(vehicle)
    return Measured("car_body_roll_rate", np.abs(band), level, "rad/s",
                    "roll level x 2 pi x the car body's roll frequency (derived)", "A")
