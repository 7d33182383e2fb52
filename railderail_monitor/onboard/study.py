"""`railderail onboard-study --out DIR`: are hunting and a suspension fault seen by the bogie-instability rules
of an on-board unit, at which speed and how early (issue 24 item 6; docs/onboard-criteria.md).

A speed sweep on straight irregular track (the catalogue's `Entry`, so that a case found detectable is a
catalogue line as it stands): the car healthy, with both bogies' yaw dampers failed (its linear critical
speed falls from about 403 to 197 km/h) and with a broken primary spring. Each run carries the shipped
sensor set (noise on, its seed the run's seed); the instability rules (`criteria.bogie_rms`, `bogie_peak`,
`peak_count`, `china_peak_count`) are applied to the lateral acceleration of every frame mount: the frame's
centre and the frame over each wheelset, where EN 14363 places the reading. Track distance is the odometer's
(`criteria.odometer_distance`), as the unit knows it. The fault is there from the run's start; the rules
see the record from `SETTLE_S` on (the suspension's start-up transient, 13-16 m/s^2 in the first 0.1 s,
is not a hunting), so a first alarm's time and distance count from that switch-on, the start of the
section. A rule that never alarms is reported with its largest value against its level, not tuned.
"""
from __future__ import annotations

from dataclasses import dataclass
import math
from pathlib import Path

import numpy as np

from .criteria import (bogie_limits, bogie_peak, bogie_rms, china_peak_count, hunting_frequency, odometer_distance,
                       peak_count)

SPEEDS_KMH = (250.0, 275.0, 300.0, 325.0, 350.0)
LINE_M = 3000.0             # m of straight track per run: 30 or more hunting cycles at 250-350 km/h
IRREGULARITY = "erri-low"
SEED = 1
SETTLE_S = 1.0              # s: the rules switched on after the start-up transient
RATE_HZ = 200.0             # the simulator's output rate, the sensors' top rate
FRAME_MOUNTS = ("bogie_front_frame", "bogie_rear_frame", "bogie_frame_0", "bogie_frame_1", "bogie_frame_2",
                "bogie_frame_3")
RULES = ("bogie_rms", "bogie_peak", "bids_peak_count", "bids_peak_count_china")


@dataclass(frozen=True)
class Case:
    name: str
    faults: tuple
    meaning: str


CASES = (Case("healthy", (), "no fault (linear critical speed about 403 km/h)"),
         Case("yaw-dampers-failed", ("yaw-dampers-failed@both",),
              "both bogies' yaw dampers failed (linear critical speed about 197 km/h)"),
         Case("primary-spring-broken", ("primary-spring-broken@0-left",),
              "wheelset 0's left primary spring broken"))


def entry(case, speed_kmh):
    """The catalogue entry of one run of the sweep."""
    from ..catalogue import Entry
    return Entry(name=f"study-{case.name}-{speed_kmh:g}", family="fault" if case.faults else "ordinary",
                 radius_m=math.inf, speed_kmh=speed_kmh, irregularity=IRREGULARITY, seeds=(SEED,),
                 line_length_m=LINE_M, faults=case.faults)


def frame_rules(time, lateral, position, bogie_mass, f0_hz):
    """{rule: Measured} of one frame mount's lateral acceleration."""
    return {"bogie_rms": bogie_rms(time, lateral, position, bogie_mass, f0_hz),
            "bogie_peak": bogie_peak(time, lateral, bogie_mass, f0_hz),
            "bids_peak_count": peak_count(time, lateral),
            "bids_peak_count_china": china_peak_count(time, lateral)}


def run_case(item):
    """One run of the sweep (case, speed km/h): the derailment if any, and per frame mount and rule its
    largest value, its level and its first alarm (time s and distance m from the switch-on, speed km/h)."""
    from dataclasses import replace

    from railderail_sim.sensors.config import load as load_sensors
    from railderail_sim.sensors.measure import run_signals
    from railderail_sim.vehicle.simulate import run_to_stop

    case, speed_kmh = item
    sc = replace(entry(case, speed_kmh).scenario(SEED), output_rate=RATE_HZ)
    sim, arrays, error = run_to_stop(sc)
    signals = run_signals(replace(load_sensors(), seed=SEED), sim, arrays)
    vp = sc.vehicle
    bogie_mass = vp.bogie_frame_mass + 2.0 * vp.wheelset_mass
    event = sim.derailment()
    out = dict(case=case.name, faults=list(case.faults), speed_kmh=speed_kmh, simulated_s=float(arrays["time"][-1]),
               diverged=error, derailment=None if event is None else {
                   k: event[k] for k in ("time_s", "car_body_position_m", "wheelset", "wheel_side", "mechanism")},
               f0_hz={}, rules={rule: {} for rule in RULES})
    for mount in FRAME_MOUNTS:
        t = signals[f"sensor_{mount}_time"]
        keep = t >= SETTLE_S
        t, lateral = t[keep], signals[f"sensor_{mount}_acceleration"][keep, 1]
        s = odometer_distance(signals["sensor_odometer_time"], signals["sensor_odometer_speed"], t)
        s = s - s[0]
        f0 = hunting_frequency(t, lateral)
        out["f0_hz"][mount] = f0
        for rule, measured in frame_rules(t, lateral, s, bogie_mass, f0).items():
            first = measured.first_alarm(s)
            out["rules"][rule][mount] = dict(
                peak=float(np.nanmax(measured.value)), level=measured.level, unit=measured.unit,
                first_alarm=None if first is None else dict(time_s=float(t[first] - t[0]), distance_m=float(s[first]),
                                                            speed_kmh=speed_kmh))
    return out


def earliest(run, rule):
    """(mount, first alarm) of the rule's earliest alarm over the frame mounts, or None."""
    found = [(a["first_alarm"]["time_s"], mount, a["first_alarm"]) for mount, a in run["rules"][rule].items()
             if a["first_alarm"] is not None]
    return min(found)[1:] if found else None


def study(workers=None, progress=True, speeds=SPEEDS_KMH, cases=CASES):
    """The sweep's JSON object: settings, runs, and per case and rule the lowest speed at which it alarmed."""
    from railderail_sim.methods.parallel import run_all
    items = [(case, v) for case in cases for v in speeds]
    runs = run_all(run_case, items, workers=workers, progress=progress, desc="onboard-study", unit="run")
    first_speed = {case.name: {rule: next((r["speed_kmh"] for r in runs if r["case"] == case.name
                                           and earliest(r, rule) is not None), None) for rule in RULES}
                   for case in cases}
    from railderail_sim.parameters import VehicleParameters
    vp = VehicleParameters()
    peak_limit, rms_limit = bogie_limits(vp.bogie_frame_mass + 2.0 * vp.wheelset_mass)
    return dict(settings=dict(track="straight", line_m=LINE_M, irregularity=IRREGULARITY, seed=SEED, settle_s=SETTLE_S,
                              output_rate_hz=RATE_HZ, sensors="the shipped set (railderail_sim/config/sensors.yaml), "
                              "noise on, seed = the run's seed", frame_mounts=list(FRAME_MOUNTS),
                              f0="the Welch peak of each mount's record in 1.5-12 Hz (criteria.hunting_frequency)",
                              limits=dict(bogie_rms=rms_limit, bogie_peak=peak_limit, bids_peak_count=6,
                                          bids_peak_count_china=6)),
                cases=[dict(name=c.name, faults=list(c.faults), meaning=c.meaning) for c in cases],
                runs=runs, first_speed_kmh=first_speed)


def _cell(run, rule):
    hit = earliest(run, rule)
    if hit is not None:
        mount, first = hit
        return f"**{first['time_s']:.1f} s, {first['distance_m']:.0f} m** ({mount})"
    top = max(run["rules"][rule].items(), key=lambda kv: kv[1]["peak"] / kv[1]["level"])
    return f"no: {top[1]['peak']:.2f} of {top[1]['level']:.3g} ({top[0]})"


def markdown(result):
    """The study as Markdown (docs/report/onboard-study.md)."""
    st = result["settings"]
    lines = ["## Hunting and faults seen by the instability rules (`railderail onboard-study`)", "",
             f"Straight track, {st['irregularity']} irregularity (seed {st['seed']}), {st['line_m']:.0f} m per run at a "
             f"constant speed; {st['sensors']}; the rules on every frame mount ({', '.join(st['frame_mounts'])}) from "
             f"{st['settle_s']:g} s on, track distance from the odometer; f0: {st['f0']}. Limits: sliding r.m.s. "
             f"{st['limits']['bogie_rms']:.2f} m/s^2, peak {st['limits']['bogie_peak']:.2f} m/s^2, 6 consecutive peaks "
             "at or over 8 m/s^2 (4-8 Hz, UIC 515-5; 0.5-10 Hz, the Chinese form). A cell gives the earliest alarm "
             "over the mounts (time and distance from the switch-on, the mount), or the largest value against its "
             "level where the rule never alarmed.", "",
             "| case | speed (km/h) | derailed | f0 (Hz, frame centres) | " + " | ".join(RULES) + " |",
             "|---|---|---|---|" + "---|" * len(RULES)]
    for r in result["runs"]:
        d = r["derailment"]
        derailed = "-" if d is None else f"{d['mechanism'].replace('_', ' ')} at {d['time_s']:.1f} s"
        f0 = "/".join(f"{r['f0_hz'][m]:.2f}" for m in FRAME_MOUNTS[:2])
        lines.append(f"| {r['case']} | {r['speed_kmh']:g} | {derailed} | {f0} | "
                     + " | ".join(_cell(r, rule) for rule in RULES) + " |")
    lines += ["", "Lowest speed of the sweep at which each rule alarmed:", "",
              "| case | " + " | ".join(RULES) + " |", "|---|" + "---|" * len(RULES)]
    for case, by_rule in result["first_speed_kmh"].items():
        lines.append(f"| {case} | " + " | ".join("never" if v is None else f"{v:g} km/h" for v in by_rule.values()) + " |")
    return "\n".join(lines)


def write(result, out):
    """OUT/onboard-study.json and OUT/onboard-study.md."""
    from railderail_sim import jsonout
    from railderail_sim.atomic import atomic_write
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    jsonout.write(out / "onboard-study.json", result)
    with atomic_write(out / "onboard-study.md") as handle:
        handle.write(markdown(result) + "\n")
    return out / "onboard-study.md"


def command(parser):
    parser.add_argument("--out", metavar="DIR", default=None, help="write DIR/onboard-study.json and .md")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: the cores)")
    parser.add_argument("--json", action="store_true", help="print the JSON object instead of the table")

    def run(args):
        import sys

        from railderail_sim import jsonout
        from railderail_sim.ranges import check_range
        if args.workers is not None:
            check_range("--workers", args.workers, 1, 256)
        result = study(workers=args.workers, progress=not args.json)
        if args.out:
            print(f"wrote {write(result, args.out)}", file=sys.stderr)
        print(jsonout.dumps(result, indent=1) if args.json else markdown(result))
        return 0
    return run
