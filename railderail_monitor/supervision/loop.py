"""`railderail simulate --supervision`: the supervisor beside a batch run, and with --closed-loop braking it
(railderail_sim.supervision.closed_loop). The simulate command finds `simulate_supervised` through the
command table's SUPERVISION (railderail_monitor/commands.py), so railderail_sim never imports this package.

Targets: a survey's JSON (`railderail survey LINE.yaml --json`) placed on the run's own curve
(`survey_on_track`: the survey's curve of the run's radius and cant, its safe speed and per-friction limits),
or the scenario's own curve from its entry transition to the end of its exit transition under a given
critical derailment speed (`--critical-speed-kmh`; the survey computes it by the paper's method, `railderail
trial` for one curve), its target speed from `curves.target_limit`: that speed less dV_ebi only, without the
margins a survey's safe speed keeps (docs/supervision.md, "The safe speed").
"""
import json
import math
import time

import numpy as np

from railderail_sim.sensors import config as sensor_config
from railderail_sim.sensors.measure import SensorStream
from railderail_sim.sensors.sensor_set import ODOMETER, SensorSet
from railderail_sim.supervision.braking import BrakingModel
from railderail_sim.supervision.closed_loop import BrakeCommand, run_closed_loop
from railderail_sim.vehicle.layout import WHEELSETS, BodyTable, OutputRow
from railderail_sim.vehicle.simulate import curve_extent, output_arrays

from .curves import INTERVENTION, KMH, SupervisionLimits, Target, target_limit
from .odometry import Odometry
from .supervisor import LiveInputs, Supervisor


def scenario_targets(track, critical_speed, limits):
    """The target of a scenario's curve (transition in to transition out) under its critical derailment speed
    (m/s)."""
    start, end = curve_extent(track)
    return [Target(start, end, target_limit(critical_speed, limits),
                   f"curve R {track.radius:g} m: critical derailment speed {critical_speed / KMH:.1f} km/h "
                   "(given)")]


def survey_on_track(path, track):
    """The survey at `path` for a run of a scenario's own geometry (`track`, a one-curve run such as `simulate`
    and the demo run). A whole survey (with its line) has its own line's positions: its curve of the run's
    radius and cant is moved to the run's curve (its entry transition to the end of its exit transition), as a
    survey of curves only, so that a run with another approach meets it where its curve is (ValueError when
    the survey has no such curve). A survey of curves only is taken as given in the run's positions."""
    try:
        with open(path) as f:
            data = json.load(f)
        curves = data["curves"]
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise ValueError(f"survey {path}: not a survey's JSON with 'curves' ({error})") from None
    if "line" not in data:
        return data
    match = [c for c in curves if c.get("radius_m") == track.radius and c.get("cant_mm") == track.cant_height * 1e3
             and c.get("safe_speed_kmh") is not None]
    if not match:
        raise ValueError(f"survey {path} has no curve of R {track.radius:g} m and {track.cant_height * 1e3:g} mm "
                         f"cant: survey a line with that curve (`railderail survey LINE.yaml --out FILE.json`) "
                         "and give it with --survey")
    start, end = curve_extent(track)
    return dict(source=str(path), curves=[dict(match[0], start_m=start, end_m=end)])


def targets_of_survey(data, path):
    """The targets of a survey's JSON content `data` (read from `path`, which the errors and reasons name). A
    whole survey (`railderail survey --out`, with its line): the most restrictive speed profile along the
    line (railderail_sim.methods.survey_profile.survey_targets: the line speed, the civil limits, each curve's
    permitted and safe speed, each defect's safe speed), a curve's safe-speed piece carrying the curve's
    per-friction limits. A survey of curves only (its `curves`, each with `start_m`, `end_m`,
    `safe_speed_kmh`): one target per curve under its safe speed."""
    try:
        curves = data["curves"]
    except (KeyError, TypeError) as error:
        raise ValueError(f"survey {path}: not a survey's JSON with 'curves' ({error})") from None
    if "line" in data:
        return profile_targets(data, f"survey {path}")
    targets = []
    for i, c in enumerate(curves):
        try:
            targets.append(Target(float(c["start_m"]), float(c["end_m"]), float(c["safe_speed_kmh"]) * KMH,
                                  f"curve {i} of {path}: safe speed {float(c['safe_speed_kmh']):.1f} km/h (survey)",
                                  _by_friction(c)).validated())
        except (KeyError, TypeError, ValueError) as error:
            raise ValueError(f"survey {path}, curve {i}: {error}") from None
    return targets


def _by_friction(curve):
    return tuple((float(f), float(v) * KMH) for f, v in (curve.get("safe_speed_by_friction_kmh") or {}).items())


def profile_targets(data, where):
    """The targets of a whole survey's dict (`railderail survey --json`, with its line): its most restrictive
    profile, a curve's safe-speed piece carrying the curve's per-friction limits; `where` names the survey in
    an error."""
    from railderail_sim.methods.survey_profile import survey_targets as profile
    try:
        pieces = profile(data)
    except (KeyError, TypeError, ValueError) as error:
        raise ValueError(f"{where}: {error}") from None
    targets = []
    for a, b, v, why in pieces:
        curve = next((c for c in data["curves"] if c["start_m"] <= a and b <= c["end_m"]
                      and c.get("safe_speed_kmh") is not None and abs(c["safe_speed_kmh"] * KMH - v) < 1e-9), None)
        targets.append(Target(a, b, v, why, () if curve is None else _by_friction(curve)).validated())
    return targets


class Controller:
    """The supervisor fed a run's rows; a BrakeCommand when it first intervenes for a brake not yet commanded
    (at the true place and speed of the row it decided on). Ground truth: the front (the leading wheelset) and
    the speed of every output row. Measured (`odometer`, a railderail_sim.sensors Odometer): the odometer's
    speed samples only, the position integrated from a balise at the first sample (`odometry.Odometry`), the
    pessimistic end of its confidence interval supervised. `step_s`: the supervisor's own time."""

    def __init__(self, supervisor, odometer=None, seed=0):
        self.supervisor = supervisor
        self.odometer, self.seed = odometer, seed
        self.stream = self.odometry = None
        self.issued = False
        self.step_s = 0.0
        self.steps = 0
        self.lowest_speed = math.inf

    def samples(self, sim, rows):
        """(row index, time, front m, speed m/s, position error m, speed error m/s) of each sample the
        supervisor sees in these rows."""
        station = float(sim.model.bodies[WHEELSETS[0], BodyTable.station])
        truth = rows[:, [OutputRow.time, OutputRow.position, OutputRow.speed]].tolist()
        if self.odometer is None:
            return [(k, t, s + station, v, 0.0, 0.0) for k, (t, s, v) in enumerate(truth)]
        if self.stream is None:
            sensors = SensorSet(seed=self.seed, odometer=self.odometer)
            self.stream = SensorStream(sensors.validated(sim.scenario.output_rate), sim.scenario)
        odo = self.stream.process(output_arrays(rows)).get(ODOMETER, dict(time=[], speed=[]))
        out = []
        for t, v in zip(np.asarray(odo["time"]).tolist(), np.asarray(odo["speed"]).tolist()):
            k = int(np.searchsorted(rows[:, OutputRow.time], t - self.odometer.sampling.latency_s + 1e-9)) - 1
            if self.odometry is None:
                self.odometry = Odometry(self.supervisor.limits, truth[k][1] + station, t, v)
            else:
                self.odometry.update(t, v)
            o = self.odometry
            out.append((k, t, o.position, v, o.position_error, o.speed_error))
        return out

    def __call__(self, sim, rows):
        command = None
        start = time.perf_counter()
        for k, t, front, v, position_error, speed_error in self.samples(sim, rows):
            level = self.supervisor.step(t, front, v, position_error, speed_error)
            if level == INTERVENTION and not self.issued and command is None:
                row = rows[k]
                command = BrakeCommand(float(row[OutputRow.time]), float(row[OutputRow.position]),
                                       float(row[OutputRow.speed]), self.supervisor.release_speed)
            self.issued = self.supervisor.release_speed is not None
            self.steps += 1
        self.step_s += time.perf_counter() - start
        self.lowest_speed = min(self.lowest_speed, float(np.min(rows[:, OutputRow.speed], initial=math.inf)))
        return command


def watching(controller):
    """The controller of an open loop: it sees every row, its commands are not applied."""
    def watch(sim, rows):
        controller(sim, rows)
    return watch


def simulate_supervised(args, sc):
    """The run of `railderail simulate --supervision` (open loop: alerts only; --closed-loop: braked) as
    (JSON object, human text)."""
    limits = SupervisionLimits()
    braking = BrakingModel(adhesion=args.adhesion).validated()
    if args.supervision:
        targets = targets_of_survey(survey_on_track(args.supervision, sc.track), args.supervision)
    elif args.critical_speed_kmh is not None:
        targets = scenario_targets(sc.track, args.critical_speed_kmh * KMH, limits)
    else:
        raise ValueError("--supervision needs a survey's JSON file or --critical-speed-kmh for the scenario's curve")
    supervisor = Supervisor(targets, braking, limits)
    shipped = sensor_config.load(None)
    controller = Controller(supervisor, shipped.odometer if args.odometer else None,
                            seed=shipped.seed if args.sensor_seed is None else args.sensor_seed)
    front = sc.start_position + sc.vehicle.bogie_semi_distance + sc.vehicle.wheelbase_semi
    if not args.odometer:
        # on ground truth the friction is known: it picks a survey's per-friction limits
        supervisor.inputs(LiveInputs(friction=sc.contact.friction_coefficient), front)
    inside = supervisor.behind_intervention(front, float(np.interp(sc.start_position, *sc.speed_table.T)))
    run = run_closed_loop(sc, controller if args.closed_loop else watching(controller), braking)
    result, commands = run.result, run.commands
    out = dict(status=result.status, derailment=result.derailment, closed_loop=bool(args.closed_loop),
               signals="odometer" if args.odometer else "ground_truth",
               brake_commands=[dict(time_s=c.time_s, position_m=c.position_m, speed_kmh=c.speed_m_s / KMH,
                                    release_speed_kmh=c.release_speed_m_s / KMH) for c in commands],
               lowest_speed_kmh=controller.lowest_speed / KMH, stopped_at_m=run.stopped_at_m,
               started_inside_braking_distance=inside,
               alerts=[a.as_dict() for a in supervisor.alerts],
               targets=[dict(start_m=t.start_m, end_m=t.end_m, speed_limit_kmh=t.speed_limit_m_s / KMH,
                             reason=t.reason) for t in targets],
               supervisor_step_us=1e6 * controller.step_s / max(controller.steps, 1))
    lines = [f"status                       {result.status}"]
    if result.derailment:
        d = result.derailment
        lines.append(f"derailment                   t = {d['time_s']:.2f} s at {d['position_m']:.1f} m, "
                     f"{d['speed_kmh']:.1f} km/h, wheelset {d['wheelset']} ({d['mechanism']})")
    for t in targets:
        lines.append(f"target                       {t.start_m:.0f}-{t.end_m:.0f} m at {t.speed_limit_m_s / KMH:.1f} "
                     f"km/h: {t.reason}")
    for reason in inside:
        lines.append(f"starts inside its braking distance to: {reason}; it intervenes at once")
    for a in supervisor.alerts:
        lines.append(f"{a.level:12s} t = {a.time_s:6.2f} s  front {a.position_m:8.1f} m  {a.speed_kmh:6.1f} km/h  "
                     f"margin {a.margin_kmh:+6.1f} km/h  to EBI {a.time_to_intervention_s:5.1f} s")
    for c in commands:
        lines.append(f"emergency brake              t = {c.time_s:.2f} s at {c.position_m:.1f} m, "
                     f"{c.speed_m_s / KMH:.1f} km/h, held down to {c.release_speed_m_s / KMH:.1f} km/h")
    lines.append(f"lowest speed                 {controller.lowest_speed / KMH:.1f} km/h")
    if run.stopped_at_m is not None:
        lines.append(f"stopped at                   {run.stopped_at_m:.1f} m (the car body; braked to a stop: the run "
                     "ends there)")
    return out, "\n".join(lines)
