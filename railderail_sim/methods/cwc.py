"""Characteristic wind curves (EN 14067-6): for each vehicle speed, the gust peak wind speed at which the
most unloaded running gear reaches the wheel-unloading limit.

A run is the car at constant speed through the CEN extreme gust (`loads.wind`), on straight track or on a
curve whose radius gives the uncompensated lateral acceleration a_q at that speed (on Table 2's cant; the
wind from the inside of the curve, toward its outside, where it adds to the centrifugal force). Its
unloading is the largest over the run of

    dQ/Q0 = 1 - mean(Q of the windward wheels of a bogie) / Q0

over both bogies (the running gear's mean of EN 14067-6), with Q0 the static wheel load, low-pass filtered
at UNLOADING_FILTER_HZ (the standard's filter as quoted in secondary sources, not read in the standard:
an assumption; above the nonlinear critical speed the gust sets the car hunting, and the flange impacts'
wheel-load peaks are not the unloading the criterion means), and 1 once a wheel derails. Since the
unloading need not rise steadily with the wind (the gust's passage can meet the car's own modes), the
characteristic wind speed is the lowest one that reaches the limit: the gust's peak is raised from 0 in
steps of SCAN_STEP until the limit is reached, then that step is bisected until the bracket is narrower
than the tolerance; its midpoint is the result. Runs go in parallel over the speeds (`parallel.run_all`).
"""
from dataclasses import dataclass, replace
import functools
import math

import numpy as np

from ..loads.wind import WIND_SPEED_RANGE, Wind
from ..parameters import RUNNING_GEAR_UNLOADING_FILTER_HZ, RUNNING_GEAR_UNLOADING_LIMIT, TrackParameters
from ..ranges import check_range
from ..vehicle.layout import running_gear_sides
from ..vehicle.simulate import KMH, RADIUS_RANGE, Scenario, constant_speed, curve_middle, simulate, straight_track
from .parallel import run_all

UNLOADING_LIMIT = RUNNING_GEAR_UNLOADING_LIMIT
UNLOADING_FILTER_HZ = RUNNING_GEAR_UNLOADING_FILTER_HZ   # 4th-order Butterworth, forward and back
SCAN_STEP = 2.5                           # m/s: the upward scan of the gust's peak before the bisection
DEFAULT_SPEEDS_KMH = (200.0, 220.0, 240.0, 260.0, 280.0, 300.0, 320.0, 340.0, 360.0)
AQ_RANGE = (0.0, 1.5)                     # m/s^2 of uncompensated lateral acceleration
AFTER_PEAK = 4.0                          # the run ends this many gust decay lengths past the peak


@dataclass(frozen=True)
class CwcCase:
    """One curve of the CWC figure: straight track (a_q None) or a curve at a_q (m/s^2)."""
    uncompensated_acceleration: float = None

    @property
    def label(self):
        a = self.uncompensated_acceleration
        return "straight track" if a is None else f"curve, a_q = {a:g} m/s^2"


def cwc_track(case: CwcCase, speed, base: TrackParameters):
    """The track of a case at speed v (m/s): straight without cant, or Table 2's line with the radius of a_q."""
    if case.uncompensated_acceleration is None:
        return straight_track(rail_profile=base.rail_profile)
    radius = base.radius_at_uncompensated_acceleration(speed, case.uncompensated_acceleration)
    check_range(f"radius of a_q = {case.uncompensated_acceleration:g} m/s^2 at {speed / KMH:.0f} km/h", radius,
                *RADIUS_RANGE, "m")
    return replace(base, radius=radius)


def gust_scenario(base: Scenario, case: CwcCase, speed_kmh, wind_speed):
    """The run of one gust peak: constant speed, the wind from the inside of the curve (from the left on
    straight track) at right angles to it, the gust at the middle of the curve (of the line)."""
    v = speed_kmh * KMH
    track = cwc_track(case, v, base.track)
    peak = curve_middle(track)
    direction = 90.0 * track.direction              # the inside of a left curve is on the left
    return replace(base, track=track, speed_table=constant_speed(speed_kmh),
                   wind=Wind(speed=wind_speed, direction_deg=direction, gust="chinese-hat", peak_position=peak),
                   end_position=peak + AFTER_PEAK * base.aerodynamics.gust_length_scale, output_rate=100.0)


def running_gear_unloading(result, windward_side, window):
    """The largest dQ/Q0 of a run over both bogies while the car-body centre is within `window` (m, m) (1 if
    a wheel derailed)."""
    if result.derailment is not None:
        return 1.0
    from scipy.signal import butter, sosfiltfilt
    inside = (result.position >= window[0]) & (result.position <= window[1])
    q0 = result.scenario.vehicle.static_wheel_load
    low_pass = butter(4, UNLOADING_FILTER_HZ, fs=result.scenario.output_rate, output="sos")
    gears = running_gear_sides(result.wheel("vertical_force"))[:, windward_side::2]   # the windward side of each
    windward = sosfiltfilt(low_pass, gears, axis=0)
    return float(np.max(1.0 - windward[inside] / q0))


def unloading(base: Scenario, case: CwcCase, speed_kmh, wind_speed):
    """dQ/Q0 of the most unloaded running gear while the gust passes (its peak +- AFTER_PEAK decay lengths)."""
    sc = gust_scenario(base, case, speed_kmh, wind_speed)
    peak, reach = sc.wind.peak_position, AFTER_PEAK * base.aerodynamics.gust_length_scale
    return running_gear_unloading(simulate(sc), 0 if sc.wind.direction_deg > 0 else 1, (peak - reach, peak + reach))


def characteristic_wind_speed(speed_kmh, base: Scenario, case: CwcCase, tolerance=0.25,
                              top=WIND_SPEED_RANGE[1]):
    """(wind speed m/s, or NaN if the limit is not reached up to `top`; [(u, dQ/Q0) of each run]) at one speed."""
    tried = []

    def exceeds(u):
        value = unloading(base, case, speed_kmh, u)
        tried.append((u, value))
        return value >= UNLOADING_LIMIT

    if exceeds(0.0):
        return 0.0, tried
    lo = 0.0
    while True:
        hi = min(lo + SCAN_STEP, top)
        if exceeds(hi):
            break
        if hi >= top:
            return math.nan, tried
        lo = hi
    while hi - lo > tolerance:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if exceeds(mid) else (mid, hi)
    return 0.5 * (lo + hi), tried


def _point(item, base, tolerance):
    case, speed_kmh = item
    u, tried = characteristic_wind_speed(speed_kmh, base, case, tolerance)
    return dict(case=case.label, uncompensated_acceleration_m_s2=case.uncompensated_acceleration,
                speed_kmh=speed_kmh, wind_speed_m_s=u, runs=len(tried),
                tried=[dict(wind_speed_m_s=w, unloading=q) for w, q in tried])


@dataclass
class CwcResult:
    points: list

    def curves(self):
        """{case label: (speeds km/h, wind speeds m/s)}."""
        out = {}
        for p in self.points:
            speeds, winds = out.setdefault(p["case"], ([], []))
            speeds.append(p["speed_kmh"])
            winds.append(p["wind_speed_m_s"])
        return out

    def as_dict(self):
        return dict(limit=UNLOADING_LIMIT, criterion="dQ/Q0 of the most unloaded running gear",
                    curves=[dict(case=k, speed_kmh=s, wind_speed_m_s=w) for k, (s, w) in self.curves().items()],
                    points=self.points)


def cwc(base: Scenario = None, speeds_kmh=DEFAULT_SPEEDS_KMH, accelerations=(None, 1.0), tolerance=0.25,
        workers=None, scheduler=None, progress=True):
    """The characteristic wind curves of `base` (its vehicle, contact and track model) for each a_q in
    `accelerations` (None: straight track)."""
    base = base or Scenario()
    check_range("bisection tolerance", tolerance, 0.01, 5.0, "m/s")
    for a in accelerations:
        if a is not None:
            check_range("uncompensated acceleration", a, *AQ_RANGE, "m/s^2")
    if not speeds_kmh or not accelerations:
        raise ValueError("the characteristic wind curves need at least one vehicle speed and one case")
    if len(set(speeds_kmh)) != len(speeds_kmh) or len(set(accelerations)) != len(accelerations):
        raise ValueError(f"vehicle speeds {list(speeds_kmh)} and cases {list(accelerations)} must not repeat")
    items = [(CwcCase(a), float(v)) for a in accelerations for v in speeds_kmh]
    for case, v in items:                           # every track checked before any run starts
        check_range("vehicle speed", v, 60.0, 400.0, "km/h")
        cwc_track(case, v * KMH, base.track)
    return CwcResult(run_all(functools.partial(_point, base=base, tolerance=tolerance), items, workers=workers,
                             scheduler=scheduler, progress=progress, desc="cwc", unit="speed"))
