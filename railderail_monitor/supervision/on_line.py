"""The speed supervision in the monitor node: the supervisor fed, every sample, the front's position and the
speed, its level rises published as Alerts of the criterion `speed_supervision` and its intervention as an
emergency brake command (railderail_msgs/BrakeCommand on /railderail/brake_command, which the simulator node
obeys: the loop closed through ROS).

Two modes (`SIGNALS`): ground_truth, each wheelset-states sample's car-body position and speed (the front is
the leading wheelset, the car body's position plus the bogie's and the wheelbase's semi-distances of the car);
odometer, what a train has: the odometer's speed samples (the sensor set's, as the simulator publishes them,
with their modelled error) integrated from a balise (`odometry.Odometry`), and the pessimistic end of the
confidence interval supervised, as `simulate --supervision --odometer` does. The balise is read at the first
odometer sample: the front's position then is the last wheelset-states sample's at or before the instant the
odometer measured (its stamp less its latency), the batch loop's rule; after it the ground truth is not read.

Live inputs (supervisor.LiveRules, by the rules of docs/supervision.md): a measured wind against the
characteristic wind curve of the survey's wind sites (`live_rules`), hunting when the measured monitor's
bogie-instability rules (`HUNTING_CRITERIA`) raise an alert, a friction estimate.

Levels on the Alert message: INDICATION -> SEVERITY_INFO, WARNING -> SEVERITY_WARNING, INTERVENTION ->
SEVERITY_CRITICAL. The Alert's value is the speed (m/s) and its threshold the target's speed limit (m/s); its
message gives the margin (km/h) and the time to the last braking point (s). Every step also gives a
SupervisionStatus row (railderail_sim.ros.interface) for the driver's planning area of the views, and, when
the target to brake for changes (another, or its curves rebuilt by a live input) and once per simulated second
(CURVES_PERIOD_S) otherwise, its braking curves along the line (`braking_curve_rows`, interface.BrakingCurves:
what the node publishes on /railderail/braking_curves and the Rerun planning area draws).
"""
from dataclasses import dataclass, replace
import math

import numpy as np

from railderail_sim.parameters import vehicle_parameters
from railderail_sim.ros.interface import BrakingCurves, SupervisionStatus
from railderail_sim.supervision.braking import BrakingModel

from ..warning.alerts import AlertRecord
from ..warning.limits import SEVERITY_CRITICAL, SEVERITY_INFO, SEVERITY_WARNING
from .curves import INDICATION, INTERVENTION, KMH, LEVELS, WARNING, SupervisionLimits
from .odometry import Odometry
from .supervisor import LiveRules, Supervisor

CRITERION = "speed_supervision"
SEVERITY = {INDICATION: SEVERITY_INFO, WARNING: SEVERITY_WARNING, INTERVENTION: SEVERITY_CRITICAL}
SIGNALS = ("ground_truth", "odometer")
# the measured monitor's criteria (onboard.measured) that see hunting: the bogie frame's instability rules
HUNTING_CRITERIA = ("bogie_rms", "bogie_peak", "bids_peak_count", "bids_peak_count_china")
# m: how far either side of a wind site on straight track its wind is taken to blow (one on a curve covers the
# curve's extent). A modelling choice: no source read gives an anemometer's reach.
WIND_SITE_REACH_M = 1000.0
# s of simulated time: the braking curves are sent again at least this often while their target stays (a
# planning area needs no more: at 300 km/h the front moves 83 m, against the kilometres a curve spans; at every
# sample they would cost each step about 0.4 ms more)
CURVES_PERIOD_S = 1.0
# km/h: a planning area's top is the multiple of this above the highest speed it shows, and one more
SPEED_STEP_KMH = 50.0


def planning_top_kmh(setup):
    """The top speed (km/h) of a planning area of what a supervision supervises (`OnLineSupervision.setup()`'s
    dict): the highest target, permitted or critical derailment speed rounded up to SPEED_STEP_KMH, and one step
    more; the braking curves are drawn up to it."""
    speeds = [t["speed_kmh"] for t in setup["targets"]] + [p["speed_kmh"] for p in setup["permitted"]]
    speeds += [c[k] for c in setup["curves"] for k in ("critical_derailment_speed_kmh", "permitted_speed_kmh")
               if c.get(k) is not None]
    return SPEED_STEP_KMH * (math.floor(max(speeds) / SPEED_STEP_KMH) + 2)


def braking_curve_rows(curves, front, speed, top_kmh):
    """The BrakingCurves rows (a float array, fields x samples) of a target's braking curves
    (curves.TargetCurves.along) from the front (m) on, up to top_kmh, and the train's speed (m/s) at the
    front: what the monitor node publishes and the Rerun planning area draws."""
    positions, speeds = curves.along(front, top_kmh * KMH)
    rows = np.full((BrakingCurves.size(), positions.size), math.nan)
    rows[BrakingCurves.position_m] = positions
    rows[BrakingCurves.speed_kmh, 0] = speed / KMH
    for name, v in speeds.items():
        rows[BrakingCurves[f"{name}_kmh"]] = v / KMH
    return rows


def alert_text(alert):
    """One line for people of a supervisor's Alert (supervisor.Alert)."""
    return (f"{alert.level}: speed supervision {alert.speed_kmh:.1f} km/h against {alert.limit_kmh:.1f} km/h, margin "
            f"{alert.margin_kmh:+.1f} km/h, {alert.time_to_intervention_s:.1f} s to the last braking point "
            f"({alert.reason})")


def live_rules(survey, nonlinear_critical_speed_kmh=math.nan):
    """The live inputs' rules of a survey's JSON content: the characteristic wind curve, at each vehicle speed
    the lowest over the wind sites (one measured wind stands for the line, so the most exposed site's curve
    rules; a point whose search reached no unloading, null, is left out: that site restricts nothing there);
    each site's stretch the extent of the survey's curve it stands on, else WIND_SITE_REACH_M either side;
    the car's nonlinear critical speed (km/h) for the hunting target."""
    sites = survey.get("wind_sites") or []
    cwc, stretches = (), ()
    if sites:
        speeds = sites[0]["curve"]["speed_kmh"]
        if any(site["curve"]["speed_kmh"] != speeds for site in sites):
            raise ValueError("survey: its wind sites' characteristic wind curves are at different vehicle speeds")
        lowest = [min((w for w in (site["curve"]["wind_speed_m_s"][k] for site in sites) if w is not None),
                      default=None) for k in range(len(speeds))]
        cwc = tuple((float(v), float(w)) for v, w in zip(speeds, lowest) if w is not None)
        if cwc:
            stretches = tuple(_stretch(survey["curves"], float(site["position_m"])) for site in sites)
    return LiveRules(cwc, stretches, nonlinear_critical_speed_kmh).validated()


def _stretch(curves, x):
    curve = next((c for c in curves if c["start_m"] <= x <= c["end_m"]), None)
    if curve is not None:
        return float(curve["start_m"]), float(curve["end_m"])
    return max(0.0, x - WIND_SITE_REACH_M), x + WIND_SITE_REACH_M


@dataclass(frozen=True)
class Step:
    """What one supervised sample gives: its time (s), the car body's position (m) and the speed (m/s) as
    supervised (the odometer's estimates in that mode), the alerts (AlertRecords), the release speed of a brake
    to command (m/s) or None, the SupervisionStatus row, and the BrakingCurves rows to send (`braking_curve_rows`;
    no samples once no target is ahead) or None."""
    time_s: float
    position_m: float
    speed_m_s: float
    alerts: list
    brake: float | None
    status: object
    curves: object = None


class OnLineSupervision:
    """The supervisor over a survey's targets (`survey` its JSON content, read from `source`) for one car, in
    a mode of SIGNALS (odometer: `odometer` the sensor set's instrument, whose latency dates its samples).
    `on_states` per wheelset-states sample and `on_odometer` per odometer sample give [Step]."""

    def __init__(self, survey, source, vehicle_set="hs19", adhesion="dry", signals="ground_truth", odometer=None,
                 nonlinear_critical_speed_kmh=math.nan, limits=SupervisionLimits()):
        if signals not in SIGNALS:
            raise ValueError(f"supervision signals {signals!r} is not one of {', '.join(SIGNALS)}")
        if signals == "odometer" and odometer is None:
            raise ValueError("the odometer mode of the speed supervision needs a sensor set with an odometer")
        from .loop import targets_of_survey         # the batch loop's modules load the core: only when supervising

        self.survey, self.source, self.signals, self.vehicle_set = survey, str(source), signals, vehicle_set
        self.supervisor = Supervisor(targets_of_survey(survey, self.source), BrakingModel(adhesion=adhesion), limits,
                                     live_rules(survey, nonlinear_critical_speed_kmh))
        v = vehicle_parameters(vehicle_set)
        self.front_offset = v.bogie_semi_distance + v.wheelbase_semi
        self.latency = odometer.sampling.latency_s if odometer is not None else 0.0
        self.odometry = None
        self.truth = []             # (time, car-body position) of the states samples until the balise is read
        self.pending = []           # the odometer's (time, speed) samples waiting for the balise
        self.sample, self.front = -1, math.nan
        self.commanded = False
        self.top_kmh = planning_top_kmh(self.setup())
        self.curves_sent = (None, -math.inf)      # the target's curves last sent (None: none) and when

    # --- the samples -----------------------------------------------------------------------------
    def on_states(self, t, sample, position, speed):
        """A wheelset-states sample: its time (s), index, car-body position (m) and speed (m/s)."""
        self.sample = sample
        if self.signals == "ground_truth":
            return [self._step(t, position + self.front_offset, speed)]
        if self.odometry is None:
            self.truth.append((t, position))
            return self._drain()
        return []

    def on_odometer(self, t, speed):
        """An odometer sample: its stamp (s) and measured speed (m/s); nothing in the ground-truth mode."""
        if self.signals != "odometer":
            return []
        self.pending.append((t, speed))
        return self._drain()

    def _drain(self):
        if self.odometry is None and not self._balise():
            return []
        steps = []
        for t, v in self.pending:
            if self.odometry is None:
                self.odometry = Odometry(self.supervisor.limits, self.balise_m, t, v)
            else:
                self.odometry.update(t, v)
            o = self.odometry
            steps.append(self._step(t, o.position, v, o.position_error, o.speed_error))
        self.pending.clear()
        return steps

    def _balise(self):
        """Read the balise at the first odometer sample once a states sample after the instant it measured has
        come (so that the last one at or before it is known); a lost one before it: the first after it."""
        if not self.pending:
            return False
        measured = self.pending[0][0] - self.latency + 1e-9
        if not any(t > measured for t, _ in self.truth):
            return False
        before = [(t, s) for t, s in self.truth if t <= measured]
        _, position = max(before) if before else min(self.truth)
        self.balise_m = position + self.front_offset
        self.truth.clear()
        return True

    def _step(self, t, front, v, position_error=0.0, speed_error=0.0):
        sup = self.supervisor
        before = len(sup.alerts)
        level = sup.step(t, front, v, position_error, speed_error)
        self.front = front
        position = front - self.front_offset
        records = [AlertRecord(t, self.sample, CRITERION, SEVERITY[LEVELS.index(a.level)], v, a.limit_kmh * KMH, 0,
                               "", "", position, v, alert_text(a))
                   for a in sup.alerts[before:]]
        brake = sup.release_speed if level == INTERVENTION and not self.commanded else None
        self.commanded = sup.release_speed is not None
        status, first = self.status(t, front, position_error, v, speed_error, level)
        return Step(t, position, v, records, brake, status, self._curves(t, first, front, v))

    def _curves(self, t, first, front, v):
        """The braking curves to send at this sample (braking_curve_rows) or None: when the target to brake for
        is another (or its curves were rebuilt), CURVES_PERIOD_S after the last, and once no samples when none is."""
        shown, when = self.curves_sent
        if first is shown and (first is None or t - when < CURVES_PERIOD_S - 1e-9):
            return None
        self.curves_sent = (first, t)
        if first is None:
            return np.empty((BrakingCurves.size(), 0))
        return braking_curve_rows(first, front, v, self.top_kmh)

    def status(self, t, front, position_error, v, speed_error, level):
        """The SupervisionStatus row at one sample (the front estimated, its error, the speed, its error, the
        level) and the target's curves (curves.TargetCurves, or None): the target the train must brake for first,
        or, with none, the lowest in force."""
        ahead = front + position_error
        curves = self.supervisor.curves
        in_force = [c for c in curves if c.target.start_m <= ahead < c.target.end_m]
        limit = min((c.v_target for c in in_force), default=math.nan)
        first, time = None, math.inf
        for c in curves:
            if ahead >= c.target.end_m or v <= c.v_target:
                continue
            to_ebi = 0.0 if ahead >= c.target.start_m else max(c.ebi(v, speed_error) - ahead, 0.0) / v
            if to_ebi < time or (to_ebi == time and c.v_target < first.v_target):
                first, time = c, to_ebi
        if first is None and in_force:
            first = min(in_force, key=lambda c: c.v_target)
        target = ((first.target.start_m, first.target.end_m, first.v_target / KMH, (first.v_target - v) / KMH)
                  if first is not None else (math.nan,) * 4)
        return SupervisionStatus.pack(time_s=t, front_m=front, position_error_m=position_error, speed_kmh=v / KMH,
                                      level=level, limit_kmh=limit / KMH, target_start_m=target[0],
                                      target_end_m=target[1], target_speed_kmh=target[2], margin_kmh=target[3],
                                      time_to_intervention_s=time, braking=float(self.commanded)), first

    # --- the live inputs -------------------------------------------------------------------------
    def inputs(self, **given):
        """New live inputs (supervisor.LiveInputs' fields: wind_speed_m_s, hunting, friction; None: not
        measured), seen at the front's last position (the line's start before the first sample)."""
        self.supervisor.inputs(replace(self.supervisor.live, **given), self.front if math.isfinite(self.front)
                               else 0.0)
        self.top_kmh = planning_top_kmh(self.setup())

    def on_onboard_alert(self, criterion):
        """A measured monitor's alert of `criterion`: True if it is a hunting alert that starts the hunting target
        (the rule's target runs from where hunting was first seen to the end of the line: it stays)."""
        if criterion not in HUNTING_CRITERIA or self.supervisor.live.hunting:
            return False
        self.inputs(hunting=True)
        return True

    def reason(self):
        """The reason of the last alert (the target that set the level)."""
        return self.supervisor.alerts[-1].reason if self.supervisor.alerts else ""

    def setup(self):
        """What it supervises, for the views (a JSON-able dict): the mode, the braking model's adhesion, the car,
        the targets now (m, km/h: the live inputs' included), the survey's curves (extent, critical derailment,
        safe and permitted speeds, km/h) and the civil profile where the survey has its line, the live inputs."""
        sup = self.supervisor
        civil = []
        if "line" in self.survey:
            from railderail_sim.methods.survey_profile import permitted_profile
            civil = [dict(start_m=a, end_m=b, speed_kmh=v / KMH) for a, b, v in permitted_profile(self.survey)]
        return dict(
            source=self.source, signals=self.signals, adhesion=sup.braking.adhesion, vehicle_set=self.vehicle_set,
            front_offset_m=self.front_offset,
            targets=[dict(start_m=c.target.start_m, end_m=c.target.end_m, speed_kmh=c.v_target / KMH,
                          reason=c.target.reason) for c in sup.curves],
            curves=[{k: c.get(k) for k in ("start_m", "end_m", "radius_m", "critical_derailment_speed_kmh",
                                           "safe_speed_kmh", "permitted_speed_kmh")} for c in self.survey["curves"]],
            permitted=civil,
            live=dict(wind_speed_m_s=sup.live.wind_speed_m_s, friction=sup.live.friction, hunting=sup.live.hunting,
                      hunting_from_m=sup.hunting_from))
