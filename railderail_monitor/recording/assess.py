"""`railderail assess RUN.npz | RECORDING.mcap`: EN 14363's running-behaviour quantities and the ride
comfort of a run (railderail_sim.assessment), as a markdown table, `--json` or a figure (`--plot`);
`--study DIR` writes the report section (railderail_sim.assessment.study).

The command lives here because a recording is read here (replay.read_recording): railderail_sim reads the
`.npz` of `railderail simulate --out`, and never imports this package. From a recording it takes the
recorded ContactForces (each wheel's Q toward its rail's field side and P) and VehicleStatus (section,
curvature) topics, paired by sample; the recorded topics carry no accelerations, so the car-body,
bogie-frame and comfort quantities of a recording are listed as not assessed.
"""
from __future__ import annotations

import argparse
from pathlib import Path
import sys

import numpy as np

from railderail_sim import jsonout, plotting
from railderail_sim.parameters import VEHICLE_SETS, vehicle_parameters
from railderail_sim.ros.interface import FORCES, STATUS, seconds


def recording_signals(path, vehicle_set="hs19", allow_truncated=False):
    """assessment.signals.RunSignals of a railderail MCAP (ValueError naming what it lacks)."""
    from railderail_sim.assessment import signals

    from .replay import read_recording

    recording = read_recording(path, allow_truncated=allow_truncated, decode=lambda topic: topic in (FORCES, STATUS))
    forces, status = {}, {}
    for topic, _, _, _, msg in recording.messages:
        if msg is None:
            continue
        if topic == FORCES:
            forces[msg.sample] = msg
        elif topic == STATUS:
            status[msg.sample] = msg
    samples = sorted(set(forces) & set(status))
    if len(samples) < 3:
        raise ValueError(f"{path} has {len(forces)} {FORCES} and {len(status)} {STATUS} messages with "
                         f"{len(samples)} samples in common: the assessment needs both for every sample "
                         "(the wheels' forces and the track section)")
    f = [forces[k] for k in samples]
    s = [status[k] for k in samples]
    vp = vehicle_parameters(vehicle_set)
    ws, bg = signals.stations(vp)
    note = (f"{path} carries no accelerations (no recorded topic holds the car body's or the bogie frames'): "
            "ydd_car_body, zdd_car_body, ydd_qst, ydd_bogie_rms, N_MV, Wz_lateral, Wz_vertical")
    return signals.RunSignals(
        time=np.array([seconds(m.header.stamp) for m in f]), position=np.array([m.track_position for m in f]),
        speed=np.array([m.speed for m in f]), section=np.array([m.section for m in s], dtype=int),
        curvature=np.array([m.curvature for m in s]),
        uncompensated_acceleration=np.array([m.uncompensated_lateral_acceleration for m in s]),
        lateral_force=signals.track_axes_lateral(np.array([m.lateral_force for m in f])),
        vertical_force=np.array([m.vertical_force for m in f]), wheelset_stations=ws, bogie_stations=bg,
        static_wheel_load=vp.static_wheel_load, bogie_mass=vp.bogie_frame_mass + 2.0 * vp.wheelset_mass,
        source=str(path), notes=[note]).validated()


def run_signals(path, vehicle_set=None, allow_truncated=False):
    """The signals of a `.npz` run or an `.mcap` recording."""
    from railderail_sim.assessment import signals

    suffix = Path(path).suffix.lower()
    if suffix == ".npz":
        return signals.from_npz(path, vehicle_set)
    if suffix == ".mcap":
        return recording_signals(path, vehicle_set or "hs19", allow_truncated)
    raise ValueError(f"{path}: assess reads a run (.npz, `railderail simulate --out`) or a recording (.mcap), "
                     f"not {suffix or 'a file without an extension'}")


def command(parser: argparse.ArgumentParser):
    parser.add_argument("file", nargs="?", metavar="RUN.npz|RECORDING.mcap",
                        help="a run of `railderail simulate --out` or a recording of `railderail demo`/`record`")
    parser.add_argument("--json", action="store_true", help="print one JSON object (docs/assessment.md)")
    parser.add_argument("--plot", metavar="FILE.png", help="each quantity's share of its limit per section "
                        "(.png, .pdf or .svg)")
    parser.add_argument("--vehicle-set", default=None, choices=VEHICLE_SETS,
                        help="the vehicle's parameter set (static wheel load, bogie mass); default: the run's own "
                             "(a recording: hs19)")
    parser.add_argument("--from-m", type=float, default=None, metavar="S",
                        help="assess from this car-body position on (m; leaves out a run's start-up)")
    parser.add_argument("--allow-truncated", action="store_true",
                        help="assess the readable part of a truncated recording instead of refusing it")
    parser.add_argument("--study", metavar="DIR",
                        help="instead of a file: the report study (the CRH3 at its permitted speeds over track "
                             "qualities and radii) written to DIR (docs/report/assessment.md)")

    def run(args):
        from railderail_sim.assessment import assess

        plot = plotting.checked_path(args.plot) if args.plot is not None else None
        if args.study is not None:
            if args.file is not None:
                raise ValueError("give either a file to assess or --study DIR, not both")
            from railderail_sim.assessment import study
            out = study.write_study(args.study, progress=lambda text: print(text, file=sys.stderr, flush=True))
            print(f"wrote {out}")
            return 0
        if args.file is None:
            raise ValueError("no file given: assess RUN.npz or RECORDING.mcap (or --study DIR)")
        sig = run_signals(args.file, args.vehicle_set, args.allow_truncated)
        result = assess.assess(sig if args.from_m is None else sig.after(args.from_m))
        if plot is not None:
            plotting.assessment_figure(result, plot)
        if args.json:
            print(jsonout.dumps(result.as_dict(), indent=1))
        else:
            print(result.markdown())
        return 0
    return run
