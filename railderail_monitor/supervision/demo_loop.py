"""The closed loop's part of `railderail demo --closed-loop` (docs/supervision.md, "The loop closed through
ROS"): the survey the monitor supervises, placed on the run's own geometry, the same run without the
supervisor in the batch core, and the lines that set the two side by side."""
from importlib.resources import files

from railderail_sim import jsonout

# the survey the closed loop supervises by default: `railderail survey` of the Table 2 line
SHIPPED_SURVEY = files("railderail_sim") / "config" / "lines" / "table2-survey.json"


def _scenario(sim_params):
    from railderail_sim.ros.node import PARAMETERS, build_scenario
    return build_scenario({**{spec.name: spec.default for spec in PARAMETERS}, **sim_params})


def closed_loop_survey(path, sim_params, out):
    """The survey the closed loop's monitor supervises, placed on the run's own geometry
    (`loop.survey_on_track`), written to the run folder (a catalogue scenario's line is supervised from its
    own geometry). ValueError when the survey has no curve of the run's radius and cant."""
    from .loop import survey_on_track
    placed = out / "survey.json"
    jsonout.write(placed, survey_on_track(path, _scenario(sim_params).track))
    return str(placed)


def open_loop_run(sim_params):
    """The closed loop's run without the supervisor: the simulator node's scenario in the batch core (no ROS):
    {status, derailment (or None)}."""
    from railderail_sim.vehicle.simulate import simulate

    result = simulate(_scenario(sim_params))
    return dict(status=result.status, derailment=result.derailment)


def closed_loop_summary(brakes, derailment, open_loop):
    """Lines: the run with the supervisor in the loop against the same run without it."""
    lines = ["speed supervision, closed loop:"]
    for b in brakes:
        lines.append(f"  emergency brake at t = {b['time_s']:.2f} s, s = {b['track_position_m']:.0f} m, "
                     f"{b['speed_kmh']:.1f} km/h, down to {b['release_speed_kmh']:.1f} km/h ({b['reason']})")
    if not brakes:
        lines.append("  no brake command")
    lines.append("  with the supervisor:    " + ("DERAILED" if derailment else "no derailment: the run ended at the "
                                                 "end of the line"))
    od = open_loop["derailment"]
    lines.append("  without the supervisor: " + (f"derails at t = {od['time_s']:.2f} s, s = {od['position_m']:.0f} m, "
                                                  f"{od['speed_kmh']:.1f} km/h (the batch core, no ROS)"
                                                  if od else f"no derailment ({open_loop['status']})"))
    return "\n".join(lines)
