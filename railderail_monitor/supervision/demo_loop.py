"""The closed loop's part of `railderail demo --closed-loop` (docs/supervision.md, "The loop closed through
ROS"): the survey the monitor supervises, placed on the run's own geometry, the same run without the
supervisor in the batch core, and the lines that set the two side by side."""
from importlib.resources import files
import json
from pathlib import Path

from railderail_sim import jsonout

# the survey the closed loop supervises by default: `railderail survey` of the Table 2 line
SHIPPED_SURVEY = files("railderail_sim") / "config" / "lines" / "table2-survey.json"


def _scenario(sim_params):
    from railderail_sim.ros.node import PARAMETERS, build_scenario
    return build_scenario({**{spec.name: spec.default for spec in PARAMETERS}, **sim_params})


def closed_loop_survey(path, sim_params, out):
    """The survey the closed loop's monitor supervises: the curve of the survey at `path` with the radius and
    cant of the run's curve, placed on the run's own geometry (its approach), written to the run folder (a
    catalogue scenario's line is supervised from its own geometry). ValueError when the survey has no such
    curve."""
    try:
        curves = json.loads(Path(path).read_text())["curves"]
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise ValueError(f"survey {path}: not a survey's JSON with 'curves' ({error})") from None
    track = _scenario(sim_params).track
    match = [c for c in curves if c.get("radius_m") == track.radius and c.get("cant_mm") == track.cant_height * 1e3
             and c.get("safe_speed_kmh") is not None]
    if not match:
        raise ValueError(f"survey {path} has no curve of R {track.radius:g} m and {track.cant_height * 1e3:g} mm "
                         f"cant: survey a line with that curve (`railderail survey LINE.yaml --out FILE.json`) "
                         "and give it with --survey")
    curve = dict(match[0], start_m=track.straight_in,
                 end_m=track.straight_in + track.transition_in + track.curve_length + track.transition_out)
    placed = out / "survey.json"
    jsonout.write(placed, dict(source=str(path), curves=[curve]))
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
