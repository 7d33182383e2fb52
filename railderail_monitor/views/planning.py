"""The speed supervision's tab of the Rerun views: a driver's planning area and the supervision's state over
time, drawn from the monitor's topics (the views compute no supervision of their own): /railderail/supervision
(what it supervises: the targets, the survey's curves, the civil profile, the braking model) and
/railderail/supervision_status (each supervised sample: interface.SupervisionStatus).

Entities (timeline `sim_time`):
  planning/grid, planning/permitted, planning/targets, planning/critical    the area's speed grid and
                  kilometre posts; the civil permitted speed; the targets supervised (the safe speeds, the live
                  inputs' included, drawn again when they move); each curve's critical derailment speed
  planning/braking     the braking curves to the target the train must brake for, from the front on: the EBD
                  (the emergency brake deceleration curve), the EBI (the emergency brake's intervention, the last
                  braking point at each speed) and the permitted speed curve (the driver's, T_driver ahead of the
                  service brake intervention), without the odometer's speed error; drawn again when the target
                  changes and every CURVES_PERIOD_S, as the monitor node sends them on /railderail/braking_curves
                  (supervision.on_line.braking_curve_rows, one function for both)
  planning/train, planning/front    the train's speed along the line so far and where its front is now, with
                  its margin and time to the last braking point
  supervision/speed_kmh/{speed,limit,target}, supervision/margin_kmh, supervision/time_to_intervention_s,
  supervision/level     the same over time
The area is a 2-D view with its own axes (a Rerun 2-D view has none, and its y axis points down): x the front's
position, X_SCALE units a metre; y the speed, minus one unit a km/h (faster is higher).
"""
from __future__ import annotations

import json
import math

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from railderail_sim.ros import interface as m
from railderail_sim.supervision.braking import BrakingModel

from ..supervision.curves import KMH, LEVELS, SupervisionLimits, Target, TargetCurves
from ..supervision.on_line import CURVES_PERIOD_S, SPEED_STEP_KMH, braking_curve_rows, planning_top_kmh
from .plots import plot

X_SCALE = 0.1               # units of the area per metre of track, against one per km/h: 1 km is 100 units
# the grid's speed lines are SPEED_STEP_KMH apart (on_line's, which sets the area's top); the braking curves'
# colours are the Foxglove tab's too
COLOURS = dict(grid=(90, 90, 90), permitted=(170, 170, 170), targets=(255, 127, 14), critical=(214, 39, 40),
               ebd=(140, 86, 75), ebi=(148, 103, 189), sbi=(227, 119, 194), warning=(255, 187, 120),
               driver=(188, 189, 34), indication=(23, 190, 207), train=(31, 119, 180))
# the braking curves drawn: (BrakingCurves row, colour, label)
BRAKING = (("ebd_kmh", "ebd", "EBD"), ("ebi_kmh", "ebi", "EBI"), ("permitted_kmh", "driver", "permitted (driver)"))
SERIES = (("speed", (31, 119, 180)), ("limit", (170, 170, 170)), ("target", (255, 127, 14)))


def planning_view(name="supervision"):
    """The tab: the planning area above the supervision's speed, margin, time to the last braking point and
    level over time (the views' time series, `plots.plot`)."""
    area = rrb.Spatial2DView(origin="/planning", name="planning area: speed (km/h, up) along the line (the front, km)")
    return rrb.Vertical(
        area,
        rrb.Horizontal(plot("/supervision/speed_kmh", "speed, limit in force and target speed (km/h)"),
                       plot("/supervision/margin_kmh", "margin to the target (km/h)"),
                       plot("/supervision/time_to_intervention_s", "time to the last braking point (s)"),
                       plot("/supervision/level", "level: 1 indication, 2 warning, 3 intervention")),
        row_shares=[3, 2], name=name)


def _point(x_m, v_kmh):
    return [x_m * X_SCALE, -v_kmh]


def profile_strip(pieces, end_m):
    """A step line [(x, y)] through pieces (start m, end m, km/h) in order; an open end (null) drawn to end_m."""
    points = []
    for a, b, v in pieces:
        b = end_m if b is None or not math.isfinite(b) else b
        points += [_point(a, v), _point(b, v)]
    return points


def curve_strips(positions, speeds_kmh):
    """A curve's samples as the area's strips [[(x, y)]], broken where it has no speed (NaN: above the area)."""
    strips, strip = [], []
    for x, v in zip(positions, speeds_kmh):
        if math.isfinite(v):
            strip.append(_point(x, v))
        elif strip:
            strips.append(strip)
            strip = []
    return strips + ([strip] if strip else [])


class PlanningArea:
    """The tab's entities, fed the supervision's messages: `on_setup` (std_msgs/String), `on_status`
    (Float64MultiArray). `append(entity, t, value)` buffers a time series point (RunViewer's); the area is
    drawn at most every `period` s of simulated time."""

    def __init__(self, rec, append, period):
        self.rec, self.append, self.period = rec, append, period
        self.setup = self.braking = None
        self.limits = SupervisionLimits()
        self.seen = False              # a status has come: the tab is shown
        self.time = 0.0
        self.drawn = -math.inf
        self.trace = []
        self.target = None             # (start, end, speed) of the braking curves drawn
        self.curves, self.curves_drawn = None, -math.inf     # their BrakingCurves rows, and when

    def on_setup(self, msg):
        """What the supervision supervises (again when a live input moved its targets): the area's lines from
        the last status's time on."""
        self.setup = json.loads(msg.data)
        self.braking = BrakingModel(adhesion=self.setup["adhesion"]).validated()
        self.target = None
        s = self.setup
        ends = [x for t in s["targets"] for x in (t["start_m"], t["end_m"]) if x is not None]
        ends += [c["end_m"] for c in s["curves"]]
        self.end_m = max(ends)
        self.top_kmh = planning_top_kmh(s)
        self.rec.set_time("sim_time", duration=self.time)
        self._grid()
        permitted = ([(p["start_m"], p["end_m"], p["speed_kmh"]) for p in s["permitted"]] or
                     [(c["start_m"], c["end_m"], c["permitted_speed_kmh"]) for c in s["curves"]
                      if c.get("permitted_speed_kmh") is not None])
        self._strips("permitted", [profile_strip(permitted, self.end_m)] if permitted else [], "permitted speed (civil)")
        self._strips("targets", [profile_strip([(t["start_m"], t["end_m"], t["speed_kmh"]) for t in s["targets"]],
                                               self.end_m)], "targets supervised (safe speeds)")
        critical = [c for c in s["curves"] if c.get("critical_derailment_speed_kmh") is not None]
        self.rec.log("/planning/critical", rr.LineStrips2D(
            [profile_strip([(c["start_m"], c["end_m"], c["critical_derailment_speed_kmh"])], self.end_m)
             for c in critical], colors=[COLOURS["critical"]], radii=rr.Radius.ui_points(2.0),
            labels=[f"critical derailment speed {c['critical_derailment_speed_kmh']:.0f} km/h" for c in critical]))

    def _strips(self, name, strips, label):
        self.rec.log(f"/planning/{name}", rr.LineStrips2D(strips, colors=[COLOURS[name]], labels=[label] * len(strips),
                                                          radii=rr.Radius.ui_points(2.0)))

    def _grid(self):
        speeds = np.arange(0.0, self.top_kmh + 1.0, SPEED_STEP_KMH)
        km_step = max(1.0, 10.0 ** math.floor(math.log10(max(self.end_m / 1000.0, 1.0))))
        posts = np.arange(0.0, self.end_m / 1000.0 + km_step, km_step)
        strips = [[_point(0.0, v), _point(posts[-1] * 1000.0, v)] for v in speeds]
        strips += [[_point(k * 1000.0, 0.0), _point(k * 1000.0, self.top_kmh)] for k in posts]
        labels = [f"{v:.0f} km/h" for v in speeds] + [f"km {k:g}" for k in posts]
        self.rec.log("/planning/grid", rr.LineStrips2D(strips, colors=[COLOURS["grid"]], labels=labels,
                                                       radii=rr.Radius.ui_points(0.5)))

    def on_status(self, msg):
        d = m.supervision_status_dict(msg)
        t = self.time = d["time_s"]
        first, self.seen = not self.seen, True
        if first:
            for name, colour in SERIES:
                self.rec.log(f"/supervision/speed_kmh/{name}", rr.SeriesLines(names=[name], colors=[colour]),
                             static=True)
        for name, key in (("speed_kmh/speed", "speed_kmh"), ("speed_kmh/limit", "limit_kmh"),
                          ("speed_kmh/target", "target_speed_kmh"), ("margin_kmh", "margin_kmh"),
                          ("time_to_intervention_s", "time_to_intervention_s"), ("level", "level")):
            if math.isfinite(d[key]):
                self.append(f"/supervision/{name}", t, d[key])
        self.trace.append(_point(d["front_m"], d["speed_kmh"]))
        if t - self.drawn >= self.period - 1e-9:
            self.drawn = t
            self._draw(d)
        return first

    def _draw(self, d):
        self.rec.set_time("sim_time", duration=d["time_s"])
        self.rec.log("/planning/train", rr.LineStrips2D([self.trace], colors=[COLOURS["train"]],
                                                        radii=rr.Radius.ui_points(2.5), labels=["train"]))
        left = d["time_to_intervention_s"]
        text = (f"{d['speed_kmh']:.0f} km/h, {LEVELS[int(d['level'])]}"
                + (f", margin {d['margin_kmh']:+.1f} km/h" if math.isfinite(d["margin_kmh"]) else "")
                + (f", {left:.1f} s to the last braking point" if math.isfinite(left) else ""))
        self.rec.log("/planning/front", rr.Points2D([self.trace[-1]], colors=[COLOURS["train"]], labels=[text],
                                                    radii=rr.Radius.ui_points(5.0)))
        target = (d["target_start_m"], d["target_end_m"], d["target_speed_kmh"])
        if self.braking is None:
            return
        if not math.isfinite(target[0]):
            if self.curves is not None:         # no target ahead any more: no curves, as the node sends none
                self.curves = self.target = None
                self.rec.log("/planning/braking", rr.Clear(recursive=False))
        elif target != self.target or d["time_s"] - self.curves_drawn >= CURVES_PERIOD_S - 1e-9:
            self.target, self.curves_drawn = target, d["time_s"]
            self._braking_curves(d, *target)

    def _braking_curves(self, d, start, end, speed_kmh):
        curves = TargetCurves(Target(start, end, speed_kmh * KMH, "").validated(), self.braking, self.limits)
        self.curves = rows = braking_curve_rows(curves, d["front_m"], d["speed_kmh"] * KMH, self.top_kmh)
        strips, colours, labels = [], [], []
        for row, colour, label in BRAKING:
            drawn = curve_strips(rows[m.BrakingCurves.position_m], rows[m.BrakingCurves[row]])
            strips += drawn
            colours += [COLOURS[colour]] * len(drawn)
            labels += [f"{label} to {speed_kmh:.0f} km/h at {start / 1000:.2f} km"] * len(drawn)
        self.rec.log("/planning/braking", rr.LineStrips2D(strips, colors=colours, labels=labels,
                                                          radii=rr.Radius.ui_points(1.5)))
