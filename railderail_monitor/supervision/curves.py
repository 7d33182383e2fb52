"""The supervision's constants and the braking curves to one target, as ETCS derives them (ERA SUBSET-026
§3.13.9.3): the emergency brake deceleration curve (EBD) ends at the target at V_target + dV_ebi(V_target);
the emergency brake intervention (EBI) is the EBD moved back by the distance run during the brake build-up;
the service brake intervention (SBI) T_bs before it; the warning T_warning and the permitted speed T_driver
before the SBI; the indication T_indication before the permitted speed. Inside a target the ceiling speed
is supervised with the margins dV_warning, dV_sbi and dV_ebi. Each curve is a location by speed:
`TargetCurves.locations(v)`; the train at s and v is beyond a curve when s >= its location at v.

Sureness: A read in the primary text, B several secondary sources agree (here: two open implementations
of SUBSET-026, OSRD's and an open ETCS on-board, and the reference sheet), C one source or recalled.
"""
from dataclasses import dataclass, field, fields
import math

import numpy as np

from railderail_sim.ranges import check_range
from railderail_sim.supervision.margin import SafetyMargin

EBI_MARGIN = SafetyMargin()

KMH = 1.0 / 3.6
NONE, INDICATION, WARNING, INTERVENTION = 0, 1, 2, 3
LEVELS = ("none", "indication", "warning", "intervention")
# the curves of a target a planning area draws (TargetCurves.along), the emergency brake's first
CURVES = ("ebd", "ebi", "sbi", "warning", "permitted", "indication")
# a planning area's samples: from the front to the target's start (closer together towards it: the curves bend
# there), then over the target; the speeds each curve's locations are taken at, besides those where it bends
# (inverted by interpolation between them: 60 over 255-450 km/h give the curve's speed within 0.01 km/h,
# tests/test_supervision_views.py)
APPROACH_SAMPLES, TARGET_SAMPLES, CURVE_SPEEDS = 100, 20, 60
SAMPLES = APPROACH_SAMPLES + 1 + TARGET_SAMPLES          # along() gives this many
# m of a target without an end (the hunting target runs to the end of the line) drawn past its start or the front
OPEN_END_M = 2000.0


def _c(value, unit, meaning, source, sure):
    return field(default=value, metadata=dict(unit=unit, meaning=meaning, source=source, sure=sure))


@dataclass(frozen=True)
class SupervisionLimits:
    """Every constant of the supervisor, with unit, meaning, source and how sure."""
    t_warning_s: float = _c(2.0, "s", "the warning curve ahead of the SBI", "SUBSET-026 Appendix A.3.1 (T_warning)",
                            "A")
    t_driver_s: float = _c(4.0, "s", "the permitted speed curve ahead of the SBI",
                           "SUBSET-026 Appendix A.3.1 (T_driver)", "A")
    indication_min_s: float = _c(5.0, "s", "T_indication = max(indication_share T_bs, this) + T_driver",
                                 "SUBSET-026 §3.13.9.3.6 as two open implementations have it", "B")
    indication_share: float = _c(0.8, "-", "share of the service brake build-up in T_indication",
                                 "SUBSET-026 §3.13.9.3.6 as two open implementations have it", "B")
    dv_warning_kmh: tuple = _c((4.0, 5.0, 110.0, 140.0), "km/h",
                               "ceiling warning margin: dV_warning_min, _max, V_warning_min, _max (linear between)",
                               "SUBSET-026 Appendix A.3.1", "A")
    dv_sbi_kmh: tuple = _c((5.5, 10.0, 110.0, 210.0), "km/h", "ceiling SBI margin: dV_sbi_min, _max, V_sbi_min, _max",
                           "SUBSET-026 Appendix A.3.1", "A")
    dv_ebi_kmh: tuple = _c(EBI_MARGIN.kmh(), "km/h", "ceiling EBI margin and the EBD's foot above a "
                           "target: dV_ebi_min, _max, V_ebi_min, _max", "SUBSET-026 Appendix A.3.1; the foot "
                           "§3.13.8.3.1", "A (values), B (foot)")
    speed_accuracy_kmh: tuple = _c((2.0, 12.0, 30.0, 500.0), "km/h",
                                   "odometer speed accuracy V_ura: at and below the third value the first, at and "
                                   "above the fourth the second, linear between", "SUBSET-041 §5.3.1.2 as OSRD "
                                   "has it", "B")
    position_accuracy_m: float = _c(5.0, "m", "odometer position accuracy: this plus position_accuracy_share of "
                                    "the distance since the last balise", "SUBSET-041 §5.3.1.1 (recalled)", "C")
    position_accuracy_share: float = _c(0.05, "-", "odometer position accuracy per metre since the last balise",
                                        "SUBSET-041 §5.3.1.1 (recalled)", "C")
    hysteresis_kmh: float = _c(2.0, "km/h", "a level is left only once the train is this far below its curve "
                               "(so that it does not flicker on a noisy speed)", "a modelling choice (ETCS leaves a "
                               "status when the speed is below the permitted speed)", "-")

    def validated(self):
        for name in ("t_warning_s", "t_driver_s", "indication_min_s", "indication_share", "position_accuracy_m",
                     "position_accuracy_share", "hysteresis_kmh"):
            check_range(name, getattr(self, name), 0.0, 100.0)
        for name in ("dv_warning_kmh", "dv_sbi_kmh", "dv_ebi_kmh", "speed_accuracy_kmh"):
            lo, hi, v_lo, v_hi = getattr(self, name)
            if not (0.0 <= lo <= hi and 0.0 <= v_lo < v_hi):
                raise ValueError(f"{name} {getattr(self, name)!r} must be (margin low <= high, speed low < high)")
        return self

    def table(self):
        """Rows (name, value, unit, meaning, source, sure) for the docs."""
        return [(f.name, getattr(self, f.name), *(f.metadata[k] for k in ("unit", "meaning", "source", "sure")))
                for f in fields(self)]


def ramp(spec_kmh, v):
    """A SUBSET-026 speed margin (m/s) at speed v (m/s): spec (low, high, V_low, V_high) in km/h."""
    lo, hi, v_lo, v_hi = spec_kmh
    kmh = v / KMH
    if kmh <= v_lo:
        return lo * KMH
    if kmh >= v_hi:
        return hi * KMH
    return (lo + (hi - lo) * (kmh - v_lo) / (v_hi - v_lo)) * KMH


def target_limit(critical_speed, limits):
    """The target speed (m/s) under a physical limit (m/s, e.g. a critical derailment speed): the highest V
    whose emergency-brake margin still stays under it, V + dV_ebi(V) = critical_speed (ETCS sizes its EBI
    above the permitted speed by dV_ebi, and its EBD reaches a target at V_target + dV_ebi); the survey's safe
    speed is the same (railderail_sim.supervision.margin)."""
    return SafetyMargin.from_kmh(limits.dv_ebi_kmh).safe_speed(critical_speed)


@dataclass(frozen=True)
class Target:
    """A speed target: from start_m to end_m (the front of the train) the speed may not exceed
    speed_limit_m_s; `reason` says why. `limits_by_friction`: (friction, speed limit m/s) pairs where the
    survey gives one per friction (`supervisor.friction_limit` picks)."""
    start_m: float
    end_m: float
    speed_limit_m_s: float
    reason: str
    limits_by_friction: tuple = ()

    def validated(self):
        if not (self.start_m < self.end_m):
            raise ValueError(f"target {self.reason!r}: start {self.start_m:g} m is not before its end {self.end_m:g} m")
        # 0: a stop before the target (ETCS's end of authority), where the survey found no speed that keeps the
        # margins
        check_range(f"target {self.reason!r} speed limit", self.speed_limit_m_s / KMH, 0.0, 1000.0, "km/h")
        return self


class TargetCurves:
    """The braking curves to one target, precomputed for the braking model (emergency bands, T_be, T_bs)."""

    def __init__(self, target, braking, limits):
        self.target = target
        self.v_target = target.speed_limit_m_s
        self.v_foot = self.v_target + ramp(limits.dv_ebi_kmh, self.v_target)
        self.ceiling = (self.v_target + ramp(limits.dv_warning_kmh, self.v_target),
                        self.v_target + ramp(limits.dv_sbi_kmh, self.v_target), self.v_foot)
        self.t_be, self.t_bs = braking.buildup_s, braking.service_buildup_s
        self.t_warning, self.t_driver = limits.t_warning_s, limits.t_driver_s
        self.t_indication = max(limits.indication_share * self.t_bs, limits.indication_min_s) + limits.t_driver_s
        # the EBD's distance to the target from the band edges up: (edge, distance from it to the foot, a)
        self.pieces = []
        d, lo = 0.0, self.v_foot
        for top in braking.edges() + [math.inf]:
            if top <= lo:
                continue
            a = braking.deceleration(lo + 1e-9)
            self.pieces.append((lo, d, a))
            if math.isfinite(top):
                d += (top * top - lo * lo) / (2.0 * a)
            lo = top
        self.pieces.reverse()               # searched from the top band down
        # the warning and the indication behind the EBI, in seconds at the train's speed
        self.warning_back = self.t_bs + self.t_warning
        self.indication_back = self.t_bs + self.t_driver + self.t_indication
        self._last = (math.nan, math.nan, math.nan)

    def ebd(self, v):
        """Location (m) of the EBD at speed v (m/s): where braking at full emergency deceleration from v
        reaches the target at its foot speed."""
        if v <= self.v_foot:
            return self.target.start_m
        for lo, d, a in self.pieces:
            if v > lo:
                return self.target.start_m - d - (v * v - lo * lo) / (2.0 * a)
        return self.target.start_m

    def ebi(self, v, speed_error=0.0):
        """The EBI's location (m) at the estimated speed v (m/s), the speed measurement's error (V_ura, m/s)
        compensated as ETCS does (V_delta0). The last one is kept: a train at constant speed asks again."""
        last_v, last_error, location = self._last
        if v == last_v and speed_error == last_error:
            return location
        v_bec = max(v + speed_error, self.v_target)
        location = self.ebd(v_bec) - v_bec * self.t_be
        self._last = (v, speed_error, location)
        return location

    def locations(self, v, speed_error=0.0):
        """(indication, permitted, warning, SBI, EBI) locations (m) at the estimated speed v (m/s)."""
        ebi = self.ebi(v, speed_error)
        sbi = ebi - v * self.t_bs
        permitted = sbi - v * self.t_driver
        return permitted - v * self.t_indication, permitted, sbi - v * self.t_warning, sbi, ebi

    def along(self, front, top):
        """The curves (CURVES) as a planning area draws them, from the front (m) to the target's end (an open
        one's OPEN_END_M past its start or the front): the positions (m) and each curve's speed there (m/s,
        {name: array}), NaN above `top` (m/s). Before the target a curve's speed at a position is the highest
        at which a train there is not beyond it (its locations inverted, no speed error; the target's speed, or
        the EBD's foot, where the curve has reached it); from the target's start its ceiling (permitted and
        indication the target's speed). The target's start comes twice, the approach's end and the target's
        start, so that the step is drawn upright."""
        start, end = self.target.start_m, self.target.end_m
        u = np.linspace(0.0, 1.0, APPROACH_SAMPLES + 1)
        before = front < start
        approach = start - (start - front) * (1.0 - u) ** 2 if before else np.full(u.size, front)
        approach[0] = front                 # the train's own place, not a rounding of it
        inside = np.linspace(max(start, front), min(end, max(start, front) + OPEN_END_M), TARGET_SAMPLES)
        warning, sbi, ebi = self.ceiling
        ceilings = dict(ebd=self.v_foot, ebi=ebi, sbi=sbi, warning=warning, permitted=self.v_target,
                        indication=self.v_target)
        speeds = {}
        for name, located in self._located(top).items():
            if before and located is not None:
                low, v, x = located          # x rising, v falling
                head = np.interp(approach, x, v, left=math.nan, right=low)
            else:
                head = np.full(approach.size, ceilings[name] if not before else math.nan)
            speeds[name] = np.concatenate([head, np.full(inside.size, ceilings[name])])
            speeds[name][speeds[name] > top] = math.nan
        return np.concatenate([approach, inside]), speeds

    def _located(self, top):
        """{curve: (its lowest speed, speeds falling, its locations rising)} over CURVE_SPEEDS speeds from top
        (m/s) down to its lowest (the EBD's foot, the others' the target's speed); None where top is not above."""
        out = dict.fromkeys(CURVES)
        if top > self.v_foot:
            v = self._speeds(top, self.v_foot)
            out["ebd"] = (self.v_foot, v, np.array([self.ebd(s) for s in v]))
        if top > self.v_target:
            v = self._speeds(top, self.v_target)
            # locations() gives (indication, permitted, warning, SBI, EBI): CURVES' others reversed
            x = np.array([self.locations(s) for s in v])
            out.update({name: (self.v_target, v, x[:, 5 - k]) for k, name in enumerate(CURVES) if k})
        return out

    def _speeds(self, top, low):
        """CURVE_SPEEDS speeds (m/s) falling from top to low, and the ones where the curves bend (the EBD's foot,
        the edges of the deceleration's bands), so that between two the curves are smooth."""
        bends = [v for v in (self.v_foot, *(lo for lo, _, _ in self.pieces)) if low < v < top]
        return np.unique(np.concatenate([np.linspace(top, low, CURVE_SPEEDS), bends]))[::-1]

    def level(self, front, v, speed_error=0.0):
        """The supervision level (NONE..INTERVENTION) of a train whose front is at `front` (m) at speed v (m/s)."""
        if front >= self.target.end_m:
            return NONE
        if front >= self.target.start_m:
            warning, _, ebi = self.ceiling
            return (INTERVENTION if v > ebi else WARNING if v > warning else INDICATION if v > self.v_target
                    else NONE)
        if v <= self.v_target:
            return NONE
        ebi = self.ebi(v, speed_error)
        return (INTERVENTION if front >= ebi else WARNING if front >= ebi - v * self.warning_back
                else INDICATION if front >= ebi - v * self.indication_back else NONE)
