"""Progressive trial method (Yu 2022, §3.2): critical derailment speed on a curve.

Staircase: the car enters the curve at a safe speed, then on the circular curve repeatedly accelerates by
a step and holds the new speed over a distance (Yu 2022, Fig. 3), until a wheel derails by the
geometric criterion of the paper (the wheel lift hp reaches the flange height and the wheel is off its
rail; see `vehicle.run_end.check_derailment`). The circular curve of the Table 2 line is lengthened
so that the whole staircase fits on it; everything else is the paper's alignment. The critical
derailment speed is the speed at the derailment instant.

Refinement: bisection over constant-speed runs on the paper's line itself (Table 2): the lowest constant
speed whose run derails, to a stated tolerance. It includes the dynamic entry through the transition,
which the staircase (held on the steady curve) does not, so the two need not agree; the report says by
how much. Bisection assumes that every speed above a derailing one derails too (checked at the bracket).
"""
from dataclasses import dataclass, replace

import numpy as np

from ..parameters import TrackParameters
from ..ranges import check_range
from ..vehicle.simulate import (KMH, RADIUS_RANGE, Scenario, constant_speed, simulate,
                                staircase_speed)

SPEED_RANGE_KMH = (60.0, 600.0)


@dataclass(frozen=True)
class Staircase:
    """The speed staircase (km/h, m, m/s^2); modelling choices documented in docs/methods.md."""
    start_kmh: float = 200.0
    step_kmh: float = 5.0
    hold_m: float = 200.0
    acceleration: float = 0.5
    top_kmh: float = 450.0
    lead_in_m: float = 100.0          # into the circular curve before the first acceleration


@dataclass
class TrialResult:
    radius_m: float
    critical_derailment_speed_kmh: float     # nan if no derailment up to the top speed
    last_safe_speed_kmh: float               # last speed held over a whole step without derailment
    derailed_wheelset: int                   # 0..3 from the front, -1 if none
    derailed_side: str                       # inner / outer
    derailment_position_m: float
    mechanism: str
    derailment_time_s: float
    refined_speed_kmh: float = float("nan")  # bisection over constant-speed runs on the Table 2 line
    refined_position_m: float = float("nan")
    refined_section: str = ""
    refined_mechanism: str = ""
    refined_side: str = ""
    refined_wheelset: int = -1
    tolerance_kmh: float = float("nan")
    runs: int = 0

    def as_json(self):
        return {k: v for k, v in self.__dict__.items()}


def trial_track(track: TrackParameters, stair: Staircase):
    """The Table 2 line with its circular curve long enough for the staircase."""
    table = staircase_speed(stair.start_kmh, stair.step_kmh, 0.0, stair.hold_m, stair.acceleration, stair.top_kmh)
    need = stair.lead_in_m + float(table[-1, 0]) + 100.0
    return replace(track, curve_length=max(track.curve_length, need))


def staircase_scenario(sc: Scenario, radius, stair: Staircase):
    check_range("curve radius", radius, *RADIUS_RANGE, "m")
    check_range("staircase start speed", stair.start_kmh, *SPEED_RANGE_KMH, "km/h")
    check_range("staircase top speed", stair.top_kmh, stair.start_kmh, SPEED_RANGE_KMH[1], "km/h")
    track = trial_track(replace(sc.track, radius=radius), stair)
    circle_start = track.straight_in + track.transition_in
    table = staircase_speed(stair.start_kmh, stair.step_kmh, circle_start + stair.lead_in_m, stair.hold_m,
                            stair.acceleration, stair.top_kmh)
    return replace(sc, track=track, speed_table=table, stop_on_derailment=True, output_rate=50.0)


def _last_safe(table, s_event):
    """Highest speed held over a complete hold before the derailment point (km/h)."""
    held = [table[i, 1] for i in range(len(table) - 1)
            if table[i, 1] == table[i + 1, 1] and table[i + 1, 0] <= s_event]
    return max(held) / KMH if held else float("nan")


def constant_run(sc: Scenario, radius, speed_kmh):
    """One run at a constant speed over the scenario's line with its curve of `radius` (the bisection's)."""
    return simulate(replace(sc, track=replace(sc.track, radius=radius), speed_table=constant_speed(speed_kmh),
                            stop_on_derailment=True, output_rate=50.0))


def progressive_trial(sc: Scenario = None, radius=1000.0, stair: Staircase = Staircase(), refine=True,
                      tolerance_kmh=1.0, runs=None):
    """The paper's method on one radius; with `refine`, also the bisection over constant speeds (its runs kept
    in the dict `runs` if given, `bisect_constant_speeds`)."""
    sc = sc or Scenario()
    check_range("bisection tolerance", tolerance_kmh, 0.0, 20.0, "km/h", lo_open=True)
    scs = staircase_scenario(sc, radius, stair)
    r = simulate(scs)
    d = r.derailment
    res = TrialResult(radius_m=radius, critical_derailment_speed_kmh=float("nan"), last_safe_speed_kmh=float("nan"),
                      derailed_wheelset=-1, derailed_side="", derailment_position_m=float("nan"), mechanism="",
                      derailment_time_s=float("nan"), runs=1)
    if d is not None:
        res.critical_derailment_speed_kmh = d["speed_kmh"]
        res.last_safe_speed_kmh = _last_safe(scs.speed_table, d["position_m"])
        res.derailed_wheelset = d["wheelset"]
        res.derailed_side = d["rail_side"]
        res.derailment_position_m = d["position_m"]
        res.mechanism = d["mechanism"]
        res.derailment_time_s = d["time_s"]
    if refine and d is not None:
        bisect_constant_speeds(sc, radius, res, tolerance_kmh, runs)
    return res


def bisect_constant_speeds(sc, radius, res, tolerance_kmh, runs=None):
    """Bisection over constant-speed runs on the scenario's line (the Table 2 line), bracketed around the
    speed `res.critical_derailment_speed_kmh` (the staircase's, or another first guess); fills `res`'s
    refined fields. The runs (Results) are kept by speed (km/h, rounded to 1e-6) in the dict `runs` if given,
    for a caller that reads them (the survey: the derailment at the refined speed)."""
    cache = {} if runs is None else runs
    before = len(cache)

    def run(v):
        v = round(v, 6)
        if v not in cache:
            cache[v] = constant_run(sc, radius, v)
        return cache[v]

    hi = round(res.critical_derailment_speed_kmh)
    while run(hi).derailment is None:
        hi += 10.0
        if hi > SPEED_RANGE_KMH[1]:
            return
    lo = hi - 20.0
    while run(lo).derailment is not None:
        lo -= 20.0
        if lo < SPEED_RANGE_KMH[0]:
            return
    while hi - lo > tolerance_kmh:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if run(mid).derailment is not None else (mid, hi)
    d = run(hi).derailment
    res.refined_speed_kmh = hi
    res.refined_position_m = d["position_m"]
    sec_ends = np.cumsum([sc.track.straight_in, sc.track.transition_in, sc.track.curve_length,
                          sc.track.transition_out])
    k = int(np.searchsorted(sec_ends, d["position_m"]))
    res.refined_section = ("straight", "transition", "curve", "transition", "straight")[min(k, 4)]
    res.refined_mechanism = d["mechanism"]
    res.refined_side = d["rail_side"]
    res.refined_wheelset = d["wheelset"]
    res.tolerance_kmh = tolerance_kmh
    res.runs += len(cache) - before


