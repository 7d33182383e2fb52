"""The speed supervision (railderail_monitor/supervision) scored by the warning evaluation like every criterion
(docs/warning-evaluation.md, "The speed supervision"), and the derailments it prevents in the closed loop.

Each catalogue run is supervised over its own line: `Line.from_track` of the run's track (its curve; its
defect in the line data, as the last track-recording run found it), surveyed by `railderail_sim.methods.survey`
at the evaluation's setting (`survey_settings`: the run's own car and friction, no wind or fault
cases), the survey's most restrictive profile its targets (`supervision.loop.profile_targets`). The
supervisor sees every output row's front (the leading wheelset) and speed (ground truth: the line data and
the position are taken as true) and the friction the run has; its levels WARNING and INTERVENTION are the
criterion's two "thresholds" (`LEVELS`: the level's code), a row in alarm while the level is at or above it,
scored by `scoring.score` on one channel covering every place (the supervisor watches the train, not a wheel).

`prevented`: a run that derailed is run again in the closed loop (`supervision.loop.Controller` braking it by
`closed_loop.run_closed_loop`, the braking model dry); true when the re-run does not derail. On the test
part the re-run is repeated with what the supervisor cannot see (`VARIANTS`, the sensitivity table).

The surveys are made once per curve shape (or line with a defect) and friction before the runs (`surveys`:
every case of every survey in one parallel pass, each cached by the survey itself), so a run finds its
survey ready.
"""
from __future__ import annotations

from dataclasses import replace
import functools
import math

import numpy as np

from railderail_sim import jsonout

from ..supervision.curves import INTERVENTION, WARNING, SupervisionLimits
from .hazards import PLACES
from .scoring import Samples, score

CRITERION = "speed_supervision"
SIGNALS = "line_data"          # what it reads: the front's position and speed against the line data
# the levels scored, each by its code (supervision.curves): a row is in alarm at a level while the
# supervisor's level is at or above it
LEVELS = {float(WARNING): "warning", float(INTERVENTION): "intervention"}
ADHESION = "dry"               # the braking model of the closed-loop re-runs
# the sensitivity's friction: the survey made this much above the run's friction, at most the top of the
# survey's default range (methods.survey.DEFAULT_FRICTIONS), so that the rail is below every friction surveyed
FRICTION_ABOVE = 0.2
# the odometer error beyond its interval: the odometer reads this share of the distance short (its modelled
# interval is 5 m + 5 %, SUBSET-041 §5.3.1.1)
ODOMETER_SHORT_SHARE = 0.10
VARIANTS = ("defect missing from the line data", "gust above the measured wind", "friction below the survey's range",
            "odometer, its modelled error", "odometer error beyond its interval")


def survey_settings(friction, vehicle_set):
    """The evaluation's survey setting: the run's own car (its entry's `vehicle_set`) at the run's own
    friction; no crosswind, fault or wind-site cases (the scenario's line has no wind site and the
    supervisor is given no fault). The survey's default (four frictions x three parameter sets) would cost
    twelve trials a curve where this costs one (docs/warning-evaluation.md, "The speed supervision")."""
    from railderail_sim.methods.survey import Settings
    return Settings(frictions=(friction,), vehicle_sets=(vehicle_set,), reference_set=vehicle_set,
                    reference_friction=friction,
                    wind_speeds_m_s=(), faults=(), cwc_speeds_kmh=()).validated()


def survey_settings_row():
    """What the evaluation's surveys share, for the report: the car, the frictions, the braking model."""
    return dict(vehicle_sets="the run's own", frictions="the run's own (and, for the sensitivity, "
                f"{FRICTION_ABOVE:g} above it)", wind_and_fault_cases=False, braking_adhesion=ADHESION)


def run_line(entry, seed, with_defect=True):
    """The line a run is supervised over: its own track (no irregularity: the line data knows the geometry)
    with its defect, if it has one and `with_defect`, as a known defect."""
    from railderail_sim.line.data import Defect, Line
    track = replace(entry, irregularity="none", defect=()).scenario(seed).track
    defects = ()
    if entry.defect and with_defect:
        kind, amplitude, length, at, hold = entry.defect
        defects = (Defect(position_m=at, kind=kind, size_m=amplitude, length_m=length, hold_m=hold,
                          source="the catalogue entry's defect"),)
    return Line.from_track(track, entry.name, defects=defects)


def surveyed_line(line):
    """The line its survey is made of: a line with a defect as it is; a curve alone cut to the survey's own run
    of it (Table 2's straights, its arc cut to `simulated_arc_m`, `methods.survey`) and named by its shape, so
    that every run on a curve of that shape shares one survey (the survey's result depends on nothing else);
    None for a line with nothing to survey (straight track)."""
    from railderail_sim.line.data import LineRules, Line
    from railderail_sim.methods.survey import RULES
    from railderail_sim.parameters import TrackParameters
    if line.defects:
        return line
    if not line.curves:
        return None
    (c,) = line.curves
    rules = LineRules()
    track = TrackParameters(straight_in=rules.approach_m, transition_in=c.transition_in_m,
                            curve_length=min(c.arc_m, RULES.simulated_arc_m), transition_out=c.transition_out_m,
                            straight_out=rules.exit_m, radius=c.radius_m, cant_height=c.cant_m, direction=c.direction,
                            rail_spacing=line.rail_spacing)
    return Line.from_track(track, f"curve R {c.radius_m:g} m, cant {c.cant_m * 1e3:g} mm",
                           source="a catalogue run's curve, cut to the survey's run of it")


def placed(survey, line):
    """A survey of `surveyed_line(line)` put on the run's own line: its line data and each curve's extent. A
    safe speed of 0 (a curve or defect whose margins break even at the simulator's slowest speed) stays a stop
    (docs/supervision.md, "A stop")."""
    from railderail_sim.line.file import line_as_dict
    curves = [dict(row, start_m=c.start_m, end_m=c.end_m) for row, c in zip(survey["curves"], line.curves)]
    return dict(survey, line=dict(survey["line"], name=line.name, length_m=line.length_m, file=line_as_dict(line)),
                curves=curves)


def survey_key(line, friction, vehicle_set="hs19"):
    """The key of the survey a line needs at a friction with a car (`surveyed_line`), None where it needs
    none."""
    from railderail_sim.line.file import line_as_dict
    line = surveyed_line(line)
    return None if line is None else jsonout.dumps(dict(line=line_as_dict(line), friction=friction,
                                                         vehicle_set=vehicle_set))


def survey_for(line, friction, vehicle_set, survey_by_key):
    """The survey (its dict) a run on `line` at `friction` with the car `vehicle_set` is supervised over,
    placed on the line; None for a line with nothing to survey."""
    key = survey_key(line, friction, vehicle_set)
    return None if key is None else placed(survey_by_key[key], line)


def survey_case(job, folder):
    """One case of one survey: job (survey key, the survey's case), cached by the survey under `folder` (a
    module-level function for the process pool and Dask); its process time (s; about 0 from the cache)."""
    import json
    import time

    from railderail_sim.methods.survey import run_case
    from railderail_sim.vehicle.simulate import Scenario
    key, item = job
    data = json.loads(key)
    started = time.process_time()
    run_case(item, data["line"], Scenario(), survey_settings(data["friction"], data["vehicle_set"]),
             cache=folder)
    return time.process_time() - started


def friction_above(friction):
    """The friction of the sensitivity's survey (`FRICTION_ABOVE`)."""
    from railderail_sim.methods.survey import DEFAULT_FRICTIONS
    return min(friction + FRICTION_ABOVE, max(DEFAULT_FRICTIONS))


def needed(entries):
    """The survey keys the runs of `entries` need: each run's line at its friction; on the test part, for the
    sensitivity, also without its defect and at the friction above (`FRICTION_ABOVE`)."""
    keys = []
    for entry in entries:
        for _, seed in entry.runs():
            keys.append(survey_key(run_line(entry, seed), entry.friction, entry.vehicle_set))
            if entry.part_of(seed) != "test" or entry.family == "ordinary":
                continue
            if entry.defect:
                keys.append(survey_key(run_line(entry, seed, with_defect=False), entry.friction, entry.vehicle_set))
            above = friction_above(entry.friction)
            if above > entry.friction:
                keys.append(survey_key(run_line(entry, seed), above, entry.vehicle_set))
    return sorted(set(keys) - {None})


def surveys(entries, cache=None, workers=None, scheduler=None, progress=True):
    """({survey key: survey dict}, the cases' process time s) of every survey the runs of `entries` need: every
    case of every survey in one parallel pass (processes or Dask, none nested), cached under CACHE/survey (a
    scratch folder without a cache), then each survey put together from its cached cases."""
    import json
    from pathlib import Path
    import tempfile

    from railderail_sim.line.file import line_from_dict
    from railderail_sim.methods.parallel import run_all
    from railderail_sim.methods.survey import COST, cases, survey
    from railderail_sim.methods.survey_cache import case_key
    from railderail_sim.vehicle.simulate import Scenario
    keys = {key: json.loads(key) for key in needed(entries)}
    lines = {key: line_from_dict(data["line"]) for key, data in keys.items()}
    settings = {key: survey_settings(data["friction"], data["vehicle_set"]) for key, data in keys.items()}
    # a case shared by several surveys (a curve's, `case_key`) run once
    jobs = list({case_key(item, data["line"], Scenario(), settings[key]): (key, item)
                 for key, data in keys.items() for item in cases(lines[key], settings[key])}.values())
    with tempfile.TemporaryDirectory() as scratch:
        folder = str(Path(cache or scratch, "survey"))
        cpu = sum(run_all(functools.partial(survey_case, folder=folder), jobs, workers=workers, scheduler=scheduler,
                          progress=progress, desc="surveys", unit="case", cost=[COST[item[0]] for _, item in jobs])
                  if jobs else [])
        return {key: survey(lines[key], settings=settings[key], workers=1, progress=False, cache=folder).as_dict()
                for key in keys}, cpu


def targets(survey):
    """The supervisor's targets of a survey's dict (none without a survey)."""
    from ..supervision.loop import profile_targets
    return [] if survey is None else profile_targets(survey, f"the survey of {survey['line']['name']}")


def supervisor(survey, friction):
    """A fresh supervisor over a survey's targets, the braking model dry, told the run's friction."""
    from railderail_sim.supervision.braking import BrakingModel

    from ..supervision.supervisor import LiveInputs, Supervisor
    s = Supervisor(targets(survey), BrakingModel(adhesion=ADHESION), SupervisionLimits())
    s.inputs(LiveInputs(friction=friction), 0.0)
    return s


def row_levels(sup, arrays, front_offset_m):
    """(n,) int: the supervisor's level at each output row (ground truth: the front and the speed)."""
    t, s, v = (np.asarray(arrays[k], dtype=float).tolist() for k in ("time", "position", "speed"))
    return np.array([sup.step(ti, si + front_offset_m, vi) for ti, si, vi in zip(t, s, v)], dtype=np.int8)


def alarms(levels):
    """{level code: (1, n) bool}: the rows at or above each scored level."""
    return {code: (levels >= code)[None, :] for code in LEVELS}


def scores(levels, arrays, found, window_s, label):
    """The criterion's rows at the window W (as `catalogue_runs.scores` gives the others'): one per level."""
    samples = Samples.of(arrays)
    return [dict(threshold=code, **score(mask, [list(PLACES)], samples, found, window_s, label))
            for code, mask in alarms(levels).items()]


def _short_controller(share):
    """A loop.Controller on ground truth whose front reads short by `share` of the distance run since its first
    row, with the odometer's confidence interval (5 m + 5 %) given beside it: an odometer error beyond its
    interval, which the supervisor cannot know of."""
    from ..supervision.loop import Controller

    class ShortOdometer(Controller):
        origin = None

        def samples(self, sim, rows):
            out = []
            for k, t, front, v, _, _ in super().samples(sim, rows):
                self.origin = front if self.origin is None else self.origin
                run = front - self.origin
                limits = self.supervisor.limits
                error = limits.position_accuracy_m + limits.position_accuracy_share * run
                out.append((k, t, self.origin + (1.0 - share) * run, v, error, 0.0))
            return out
    return ShortOdometer


def closed_loop_derails(sc, survey, friction, odometer=None, short_share=0.0, seed=0, checkpoints=None):
    """True when the run `sc` derails with the supervisor over `survey` braking it (the braking model dry);
    `odometer` (a sensors Odometer) supervises the measured mode, `short_share` an odometer reading short;
    `checkpoints` the open run's (`run_closed_loop`: its approach not simulated again)."""
    from railderail_sim.supervision.braking import BrakingModel
    from railderail_sim.supervision.closed_loop import run_closed_loop

    from ..supervision.loop import Controller
    # in the measured mode the friction is not known: the survey's lowest
    sup = supervisor(survey, None if odometer is not None else friction)
    controller = (_short_controller(short_share) if short_share else Controller)(sup, odometer, seed=seed)
    run = run_closed_loop(sc, controller, BrakingModel(adhesion=ADHESION), checkpoints=checkpoints)
    return run.result.derailment is not None


def supervision_of_run(entry, seed, sc, sim, arrays, found, rules, beyond, survey_by_key, checkpoints=None):
    """{windows: {W: [the criterion's rows]}, rows_at: {level name: rows at or above it}, prevented, sensitivity}
    of one run (`catalogue_runs.run_one`): the supervisor beside it, and, if it derailed, the closed-loop
    re-run (and on the test part its variants), each going on from the run's `checkpoints` if given."""
    from .hazards import windows
    from railderail_sim.vehicle.layout import WHEELSETS, BodyTable
    front = float(sim.model.bodies[WHEELSETS[0], BodyTable.station])
    survey = survey_for(run_line(entry, seed), entry.friction, entry.vehicle_set, survey_by_key)
    levels = row_levels(supervisor(survey, entry.friction), arrays, front)
    out = dict(windows={str(w): scores(levels, arrays, found, w, windows(arrays["time"], found, w, beyond)[1])
                        for w in rules.windows_s},
               rows_at={name: int(np.sum(levels >= code)) for code, name in LEVELS.items()},
               prevented=None, sensitivity=None)
    if sim.derailment() is None:
        return out
    out["prevented"] = not closed_loop_derails(sc, survey, entry.friction, checkpoints=checkpoints)
    # the variants take information away from the supervisor: asked only of what it prevents as shipped
    if entry.part_of(seed) == "test" and out["prevented"]:
        out["sensitivity"] = sensitivity_of_run(entry, seed, sc, survey, survey_by_key, out["prevented"],
                                                checkpoints)
    return out


def sensitivity_of_run(entry, seed, sc, survey, survey_by_key, prevented, checkpoints=None):
    """{variant: prevented (bool) or None where it does not apply} of a derailed test-part run (`VARIANTS`)."""
    from railderail_sim.sensors import config as sensor_config
    out = dict.fromkeys(VARIANTS)
    if entry.defect:
        bare = survey_for(run_line(entry, seed, with_defect=False), entry.friction, entry.vehicle_set, survey_by_key)
        out[VARIANTS[0]] = not closed_loop_derails(sc, bare, entry.friction, checkpoints=checkpoints)
    if entry.gust != "none":
        # the scenario's line has no wind site: the supervisor is given no wind at all (not even the mean), so
        # the gust's run is supervised as it was (its curve alone)
        out[VARIANTS[1]] = prevented
    above = friction_above(entry.friction)
    if above > entry.friction:
        out[VARIANTS[2]] = not closed_loop_derails(
            sc, survey_for(run_line(entry, seed), above, entry.vehicle_set, survey_by_key), above,
            checkpoints=checkpoints)
    shipped = sensor_config.load(None)
    out[VARIANTS[3]] = not closed_loop_derails(sc, survey, entry.friction, odometer=shipped.odometer,
                                               seed=shipped.seed, checkpoints=checkpoints)
    out[VARIANTS[4]] = not closed_loop_derails(sc, survey, entry.friction, short_share=ODOMETER_SHORT_SHARE,
                                               checkpoints=checkpoints)
    return out


def prevented_by_family(runs):
    """Per family: the derailments (without the loop) and those the closed loop prevented, with the share's
    interval (Clopper-Pearson 95 %)."""
    from .scoring import share_interval
    out = {}
    for r in runs:
        if r["supervision"]["prevented"] is None:
            continue
        row = out.setdefault(r["family"], dict(derailments=0, prevented=0))
        row["derailments"] += 1
        row["prevented"] += bool(r["supervision"]["prevented"])
    for row in out.values():
        row["prevented_ci95"] = share_interval(row["prevented"], row["derailments"])
    return out


def sensitivity_table(test_runs):
    """Per variant (`VARIANTS`) over the test part's derailments it applies to among those the supervisor
    prevented as shipped (a variant is not re-run where the shipped supervisor did not prevent): how many,
    how many the supervisor prevented as shipped, and how many it still prevents."""
    out = []
    for variant in VARIANTS:
        mine = [r for r in test_runs if r["supervision"]["sensitivity"] is not None
                and r["supervision"]["sensitivity"][variant] is not None]
        out.append(dict(variant=variant, derailments=len(mine),
                        prevented_as_shipped=sum(bool(r["supervision"]["prevented"]) for r in mine),
                        still_prevented=sum(bool(r["supervision"]["sensitivity"][variant]) for r in mine)))
    return out


def interventions_in_ordinary_running(runs, window_s):
    """The intervention level's false alarms over normal running (episodes, per 1000 km and per hour, with the
    exposure), and the ordinary family's runs with any intervention."""
    from .scoring import rate_per_1000_km
    w = str(window_s)
    km = sum(r["windows"][w]["normal_km"] for r in runs)
    hours = sum(r["windows"][w]["normal_h"] for r in runs)
    rows = [next(x for x in r["supervision"]["windows"][w] if x["threshold"] == float(INTERVENTION)) for r in runs]
    episodes = sum(x["false_episodes"] for x in rows)
    rate, ci = rate_per_1000_km(episodes, km)
    ordinary = [r for r in runs if r["family"] == "ordinary"]
    return dict(episodes=episodes, per_1000_km=rate, per_1000_km_ci95=ci,
                per_hour=episodes / hours if hours > 0 else math.nan, normal_km=km, normal_h=hours,
                ordinary_runs=len(ordinary),
                ordinary_runs_with_intervention=sum(r["supervision"]["rows_at"]["intervention"] > 0 for r in ordinary))


def held_out_goal(test_runs, window_s, rules):
    """The held-out goal on the test part: every over-speed derailment usefully warned (at WARNING) and
    prevented, no intervention in ordinary running; {met, and each part with the runs that miss it}."""
    from .hazards import hazard_cure
    from .scoring import is_useful
    w = str(window_s)
    missed_warning, missed_prevention, overspeed = [], [], 0
    for r in test_runs:
        if r["family"] != "overspeed" or not r["derailed"]:
            continue
        overspeed += 1
        row = next(x for x in r["supervision"]["windows"][w] if x["threshold"] == float(WARNING))
        name = f"{r['scenario']} seed {r['seed']}"
        cures = [hazard_cure(rules, h, r["line"])["speed_kmh"] for h in r["hazards"]]
        if not any(h["kind"] == "derailment" and is_useful(warning, rules, cure)
                   for h, warning, cure in zip(r["hazards"], row["warnings"], cures)):
            missed_warning.append(name)
        if not r["supervision"]["prevented"]:
            missed_prevention.append(name)
    ordinary = interventions_in_ordinary_running([r for r in test_runs if r["family"] == "ordinary"], window_s)
    met = (overspeed > 0 and not missed_warning and not missed_prevention
           and ordinary["ordinary_runs_with_intervention"] == 0 and ordinary["episodes"] == 0)
    return dict(met=met, overspeed_derailments=overspeed, not_usefully_warned=missed_warning,
                not_prevented=missed_prevention, ordinary_interventions=ordinary)
