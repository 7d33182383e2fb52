"""The speed supervisor as a stream: every sample the front's position and the speed (and, in the measured
mode, the odometer's confidence interval) against the braking curves to every target ahead; levels
INDICATION, WARNING, INTERVENTION (the emergency brake command) with hysteresis; an alert each time the level
rises; live inputs that move the targets by stated rules (`LiveRules`).

Rules of the live inputs (docs/supervision.md, "The supervisor"):
  friction  a target with per-friction limits takes the lower of the limits at the surveyed frictions on
            either side of the estimate (the end one outside the surveyed range); with no estimate the lowest
  wind      on each wind stretch, the measured wind against the characteristic wind curve (vehicle speed ->
            critical wind, EN 14067-6): the vehicle speed at which the curve's critical wind equals the
            measured wind is a physical limit, whose target speed follows as for a critical derailment speed
            (`curves.target_limit`); a wind below the curve at its top speed restricts nothing, one above it
            at its lowest speed restricts to that speed
  hunting   while the on-board instability rules see hunting, a target from where it was first seen to the
            end of the line under the nonlinear critical speed (again through `curves.target_limit`)
Positions are the front of the train (the leading wheelset); the supervisor compares the pessimistic end of
the odometer's confidence interval (the max safe front, est + error) with every curve, and compensates the
speed's error in the EBI, as ETCS does.
"""
from dataclasses import dataclass, replace
import math

import numpy as np

from .curves import INTERVENTION, KMH, LEVELS, NONE, SupervisionLimits, Target, TargetCurves, target_limit


@dataclass(frozen=True)
class LiveRules:
    """What the live inputs act on: the characteristic wind curve (vehicle speed km/h, critical wind m/s)
    pairs, speeds rising, and the stretches (start m, end m) where it applies; the car's nonlinear critical
    speed (km/h) for the hunting target."""
    cwc: tuple = ()
    wind_stretches: tuple = ()
    nonlinear_critical_speed_kmh: float = math.nan

    def validated(self):
        speeds = [v for v, _ in self.cwc]
        if speeds != sorted(speeds) or len(set(speeds)) != len(speeds):
            raise ValueError(f"characteristic wind curve {self.cwc!r}: its vehicle speeds must rise")
        if self.wind_stretches and not self.cwc:
            raise ValueError("wind stretches need a characteristic wind curve")
        return self


@dataclass(frozen=True)
class LiveInputs:
    """Measured now: the wind speed (m/s; None: no anemometer reading), hunting seen by the on-board rules,
    the friction estimate (None: none)."""
    wind_speed_m_s: float | None = None
    hunting: bool = False
    friction: float | None = None


@dataclass(frozen=True)
class Alert:
    """A rise of the level: when and where (the front, estimated), at which speed, the target that set it,
    the margin (km/h: the target's limit less the speed the train keeps if nothing is done; inside a target
    its limit less the speed), and the time to the last braking point (s, to the EBI at this speed; 0 inside
    a target or past it)."""
    time_s: float
    position_m: float
    speed_kmh: float
    level: str
    reason: str
    limit_kmh: float
    margin_kmh: float
    time_to_intervention_s: float

    def as_dict(self):
        return dict(self.__dict__)


def friction_limit(target, friction):
    """A target's speed limit (m/s) at a friction estimate (None: the lowest over the survey's frictions)."""
    if not target.limits_by_friction:
        return target.speed_limit_m_s
    pairs = sorted(target.limits_by_friction)
    if friction is None:
        return min(v for _, v in pairs)
    below = [v for f, v in pairs if f <= friction] or [pairs[0][1]]
    above = [v for f, v in pairs if f >= friction] or [pairs[-1][1]]
    return min(below[-1], above[0])


def wind_speed_limit(cwc, wind):
    """The vehicle speed (m/s) at which the characteristic wind curve's critical wind equals `wind` (m/s);
    None if the wind is below the curve at its top speed."""
    speeds = np.array([v for v, _ in cwc]) * KMH
    winds = np.array([w for _, w in cwc])
    if wind <= winds[-1]:
        return None
    if wind >= winds[0]:
        return float(speeds[0])
    k = int(np.flatnonzero(winds >= wind)[-1])
    share = (winds[k] - wind) / (winds[k] - winds[k + 1])
    return float(speeds[k] + share * (speeds[k + 1] - speeds[k]))


class Supervisor:
    """The streaming supervisor over fixed `targets` (curves.Target), a braking model (railderail_sim's
    BrakingModel), the constants and the live rules. `step(...)` per sample; `alerts` the level rises so far."""

    def __init__(self, targets, braking, limits=SupervisionLimits(), rules=LiveRules()):
        self.base = [t.validated() for t in targets]
        self.braking = braking.validated()
        self.limits = limits.validated()
        self.rules = rules.validated()
        self.level = NONE
        self.alerts = []
        self.release_speed = None           # m/s while the emergency brake is commanded
        self.live = LiveInputs()
        self.hunting_from = None
        self._curves = self._build()

    def _build(self):
        targets = [replace(t, speed_limit_m_s=friction_limit(t, self.live.friction)) for t in self.base]
        if self.live.wind_speed_m_s is not None and self.rules.cwc:
            v = wind_speed_limit(self.rules.cwc, self.live.wind_speed_m_s)
            if v is not None:
                targets += [Target(a, b, target_limit(v, self.limits),
                                   f"wind {self.live.wind_speed_m_s:g} m/s: characteristic wind curve's speed "
                                   f"{v / KMH:.0f} km/h") for a, b in self.rules.wind_stretches]
        if self.hunting_from is not None and math.isfinite(self.rules.nonlinear_critical_speed_kmh):
            vn = self.rules.nonlinear_critical_speed_kmh * KMH
            targets.append(Target(self.hunting_from, math.inf, target_limit(vn, self.limits),
                                  f"hunting: nonlinear critical speed {vn / KMH:.0f} km/h"))
        return [TargetCurves(t.validated(), self.braking, self.limits) for t in targets]

    @property
    def curves(self):
        """The braking curves (curves.TargetCurves) of the targets now, the live inputs' included."""
        return self._curves

    def inputs(self, live, front_m):
        """New live inputs (LiveInputs), seen with the front at front_m (m): the targets they move are rebuilt."""
        if live == self.live:
            return
        hunting_from = self.hunting_from
        if live.hunting and hunting_from is None:
            hunting_from = front_m
        elif not live.hunting:
            hunting_from = None
        self.live, self.hunting_from = live, hunting_from
        self._curves = self._build()

    def behind_intervention(self, front_m, speed_m_s):
        """The reasons of the targets ahead whose EBI at this speed (m/s) lies at or behind the front (m): a
        train there is already inside its braking distance to them."""
        return [c.target.reason for c in self._curves if c.target.start_m > front_m and speed_m_s > c.v_target
                and c.ebi(speed_m_s) <= front_m]

    def step(self, time_s, front_m, speed_m_s, position_error_m=0.0, speed_error_m_s=0.0):
        """The level (curves.NONE..INTERVENTION) at one sample: the estimated front (m), the estimated speed
        (m/s) and the odometer's errors (the max safe front is front_m + position_error_m)."""
        front = front_m + position_error_m
        up, worst = NONE, None
        for c in self._curves:
            lv = c.level(front, speed_m_s, speed_error_m_s)
            if lv > up or (lv == up and worst is not None and lv > NONE and c.v_target < worst.v_target):
                up, worst = lv, c
        if self.release_speed is not None and speed_m_s > self.release_speed:
            level = INTERVENTION
        else:
            self.release_speed = None
            level = up
            if up < self.level:
                # leave a level only as far as the train is clear of the curves by the hysteresis
                h = self.limits.hysteresis_kmh * KMH
                down = max((c.level(front, speed_m_s + h, speed_error_m_s) for c in self._curves), default=NONE)
                level = max(up, min(self.level, down))
        if level > self.level and worst is not None:
            self.alerts.append(self._alert(time_s, front_m, speed_m_s, level, worst, front, speed_error_m_s))
            if level == INTERVENTION:
                self.release_speed = worst.v_target
        self.level = level
        return level

    def _alert(self, time_s, front_m, v, level, c, front, speed_error):
        inside = front >= c.target.start_m
        ebi = c.ebi(v, speed_error)
        return Alert(time_s=time_s, position_m=front_m, speed_kmh=v / KMH, level=LEVELS[level], reason=c.target.reason,
                     limit_kmh=c.v_target / KMH, margin_kmh=(c.v_target - v) / KMH,
                     time_to_intervention_s=0.0 if inside else max(ebi - front, 0.0) / v)
