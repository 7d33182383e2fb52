"""`railderail onboard-study --out DIR`: are hunting and a suspension fault seen by the bogie-instability rules
of an on-board unit, at which speed and how early (issue 24 item 6; docs/onboard-criteria.md).

A speed sweep on straight irregular track (the catalogue's `Entry`, so that a case found detectable is a
catalogue line as it stands): the car healthy, with both bogies' yaw dampers failed (its linear critical
speed falls from about 403 to 197 km/h) and with a broken primary spring. Each run carries the shipped
sensor set (noise on, its seed the run's seed); the instability rules of the on-board monitor (`measured`:
the sliding r.m.s. and the peak in the design band f0 +- 2 Hz, the BIDS and the Chinese peak counts, at its
shipped settings) are applied to the lateral acceleration of every frame mount: the frame's centre and the
frame over each wheelset, where EN 14363 places the reading; beside them, the first alert of every other
measured criterion of the whole sensor set. Track distance is the odometer's, as the unit knows it. The
fault is there from the run's start; the monitor sees the record from `sensors.measure.START_UP_S` on
(the suspension's start-up transient, 13-16 m/s^2 in the first 0.1 s, is not a hunting), so a first
alarm's time and distance count from that switch-on, the start of the section (the fault's onset is
START_UP_S earlier). A rule that never alarms is reported with its largest value against its level, not
tuned.
"""
from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np

from railderail_sim.sensors.measure import START_UP_S
from railderail_sim.sensors.sensor_set import ODOMETER

from ..onboard.criteria import hunting_frequency
from ..onboard.measured import FRAMES, alerts, evaluate, measured_limits, sample_rates

SPEEDS_KMH = (250.0, 275.0, 300.0, 325.0, 350.0)
LINE_M = 3000.0             # m of straight track per run: 30 or more hunting cycles at 250-350 km/h
IRREGULARITY = "erri-low"
SEED = 1
RATE_HZ = 200.0             # the simulator's output rate, the sensors' top rate
# the frame mounts, in pairs of one per bogie: the centres, over the leading wheelsets, over the trailing ones
MOUNT_PAIRS = (FRAMES, ("bogie_frame_0", "bogie_frame_2"), ("bogie_frame_1", "bogie_frame_3"))
FRAME_MOUNTS = tuple(m for pair in MOUNT_PAIRS for m in pair)
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
    from .catalogue import Entry
    return Entry(name=f"study-{case.name}-{speed_kmh:g}", family="fault" if case.faults else "ordinary",
                 radius_m=math.inf, speed_kmh=speed_kmh, irregularity=IRREGULARITY, seeds=(SEED,),
                 line_length_m=LINE_M, faults=case.faults)


def frame_rules(signals, mounts, vehicle):
    """{(mount, rule): (Measured, its channel)} of the frame mounts `mounts` (one per bogie, front first):
    `measured.evaluate` of the record with these mounts as the two frames, at the monitor's shipped settings
    (design f0, bands, levels, the sensors' rates)."""
    seen = {k: v for k, v in signals.items() if k.startswith(f"sensor_{ODOMETER}_")}
    rates = sample_rates()
    for frame, mount in zip(FRAMES, mounts):
        for signal in ("time", "acceleration"):
            seen[f"sensor_{frame}_{signal}"] = signals[f"sensor_{mount}_{signal}"]
        rates[frame] = rates[mount]
    found = evaluate(seen, vehicle, rates=rates)
    return {(mount, rule): (found[rule], k) for rule in RULES for k, mount in enumerate(mounts)}


def run_case(item):
    """One run of the sweep (case, speed km/h), simulated with the shipped sensor set (`record`)."""
    from dataclasses import replace

    from railderail_sim.sensors.config import load as load_sensors
    from railderail_sim.sensors.measure import run_signals
    from railderail_sim.vehicle.simulate import run_to_stop

    case, speed_kmh = item
    sc = replace(entry(case, speed_kmh).scenario(SEED), output_rate=RATE_HZ)
    sim, arrays, error = run_to_stop(sc)
    return dict(case=case.name, faults=list(case.faults), speed_kmh=speed_kmh, simulated_s=float(arrays["time"][-1]),
                diverged=error, **record(run_signals(replace(load_sensors(), seed=SEED), sim, arrays), sc.vehicle,
                                         sim.derailment()))


def record(signals, vehicle, event=None):
    """What the monitor, switched on at START_UP_S, makes of a run's sensor signals: the derailment (if any,
    its time from the switch-on); per frame mount and rule its largest value, its level and its first alarm
    (time s and odometer distance m from the switch-on); the first alert of every measured criterion of the
    whole sensor set (`measured.alerts`); the Welch peak f0 of each frame mount's record."""
    from railderail_sim.sensors.measure import after
    signals = after(signals, START_UP_S)
    limits = measured_limits(vehicle)
    out = dict(derailment=None if event is None else dict(
                   {k: event[k] for k in ("car_body_position_m", "wheelset", "wheel_side", "mechanism")},
                   time_s=event["time_s"] - START_UP_S),
               f0_record_hz={}, rules={rule: {} for rule in RULES})
    for pair in MOUNT_PAIRS:
        for (mount, rule), (m, k) in frame_rules(signals, pair, vehicle).items():
            first = next((a for a, _ in m.channel_intervals(None, limits.rearm_fraction, limits.rearm_m)[k]), None)
            out["rules"][rule][mount] = dict(
                peak=float(np.nanmax(m.value[:, k])), level=m.level, unit=m.unit,
                first_alarm=None if first is None else dict(time_s=float(m.time[first] - START_UP_S),
                                                            distance_m=float(m.position[first])))
        for mount in pair:
            out["f0_record_hz"][mount] = hunting_frequency(signals[f"sensor_{mount}_time"],
                                                           signals[f"sensor_{mount}_acceleration"][:, 1])
    firsts = {}
    for a in alerts(evaluate(signals, vehicle, limits), limits):
        firsts.setdefault(a.criterion, dict(time_s=a.time_s - START_UP_S, distance_m=a.track_position, place=a.place))
    out["measured_first_alerts"] = firsts
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
    return summary(run_all(run_case, items, workers=workers, progress=progress, desc="onboard-study", unit="run"),
                   cases)


def summary(runs, cases):
    """The study's JSON object of its runs (`run_case`) over `cases`."""
    first_speed = {case.name: {rule: min((r["speed_kmh"] for r in runs if r["case"] == case.name
                                          and earliest(r, rule) is not None), default=None) for rule in RULES}
                   for case in cases}
    from railderail_sim.parameters import VehicleParameters
    limits = measured_limits(VehicleParameters())
    return dict(settings=dict(track="straight", line_m=LINE_M, irregularity=IRREGULARITY, seed=SEED,
                              switch_on_s=START_UP_S,
                              output_rate_hz=RATE_HZ, sensors="the shipped set (railderail_sim/config/sensors.yaml), "
                              "noise on, seed = the run's seed", frame_mounts=list(FRAME_MOUNTS),
                              hunting_frequency_hz=limits.hunting_frequency,
                              limits={rule: getattr(limits, rule) for rule in RULES},
                              peak_limits=dict(bids_peak_count=limits.bids_peak_limit,
                                               bids_peak_count_china=limits.china_peak_limit),
                              bids_window_s=limits.bids_window),
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
             f"{st['switch_on_s']:g} s on (the fault is there from the start), track distance from the odometer; the "
             f"monitor's design f0 {st['hunting_frequency_hz']:.2f} Hz (band f0 +- 2 Hz). Levels: sliding r.m.s. "
             f"{st['limits']['bogie_rms']:.2f} m/s^2, peak {st['limits']['bogie_peak']:.2f} m/s^2, "
             f"{st['limits']['bids_peak_count']:g} consecutive peaks at or over "
             f"{st['peak_limits']['bids_peak_count']:g} m/s^2 within {st['bids_window_s']:g} s (4-8 Hz, UIC 515-5) and "
             f"{st['limits']['bids_peak_count_china']:g} at or over {st['peak_limits']['bids_peak_count_china']:g} "
             "m/s^2 (0.5-10 Hz, the Chinese form). A cell gives the earliest alarm over the mounts (time and "
             "distance from the switch-on, the mount), or, where the rule never alarmed, its largest value against "
             "its level (the mount nearest to it). f0 of the record: the Welch peak of the frame centres' readings "
             "(1.5-12 Hz), where the motion really is.", "",
             "| case | speed (km/h) | derailed (s after the switch-on) | f0 of the record (Hz, front/rear) | "
             + " | ".join(RULES) + " | other measured criteria's first alert (s) |",
             "|---|---|---|---|" + "---|" * len(RULES) + "---|"]
    for r in result["runs"]:
        d = r["derailment"]
        derailed = "-" if d is None else f"{d['mechanism'].replace('_', ' ')} at {d['time_s']:.1f} s"
        f0 = "/".join(f"{r['f0_record_hz'][m]:.2f}" for m in FRAMES)
        others = ", ".join(f"{c} {a['time_s']:.1f} ({a['place']})" for c, a in r["measured_first_alerts"].items()
                           if c not in RULES) or "-"
        lines.append(f"| {r['case']} | {r['speed_kmh']:g} | {derailed} | {f0} | "
                     + " | ".join(_cell(r, rule) for rule in RULES) + f" | {others} |")
    lines += ["", "Lowest speed of the sweep at which each rule alarmed:", "",
              "| case | " + " | ".join(RULES) + " |", "|---|" + "---|" * len(RULES)]
    for case, by_rule in result["first_speed_kmh"].items():
        lines.append(f"| {case} | " + " | ".join("never" if v is None else f"{v:g} km/h" for v in by_rule.values()) + " |")
    return "\n".join(lines)


def write(result, out):
    """OUT/onboard-study.json and OUT/onboard-study.md."""
    from railderail_sim import jsonout
    return jsonout.write_report(out, "onboard-study", result, markdown(result))


def command(parser):
    parser.add_argument("--out", metavar="DIR", default=None, help="write DIR/onboard-study.json and .md")
    parser.add_argument("--speeds", default=",".join(f"{v:g}" for v in SPEEDS_KMH), metavar="KMH,...",
                        help="the sweep's speeds in km/h (default %(default)s)")
    parser.add_argument("--cases", default=",".join(c.name for c in CASES), metavar="NAME,...",
                        help="the cases (default %(default)s)")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: the cores)")
    parser.add_argument("--json", action="store_true", help="print the JSON object instead of the table")
    parser.add_argument("--estimator-error", action="store_true",
                        help="instead of the sweep: the estimator's error per side and scenario kind, with a model "
                             "mismatch beside (DIR/estimator-error.md and .json with --out)")
    parser.add_argument("--seconds", type=float, default=6.0,
                        help="--estimator-error: each run's length in s (default %(default)s)")
    parser.add_argument("--sensors", metavar="FILE.yaml", default=None,
                        help="--estimator-error: the sensor set (default the shipped one; "
                        "railderail_sim/config/sensors-realistic.yaml adds scale-factor errors and misalignment)")

    def run(args):
        import sys

        from railderail_sim import jsonout
        from railderail_sim.cli.methods import _floats
        from railderail_sim.ranges import check_range
        from railderail_sim.vehicle.simulate import SPEED_RANGE_KMH
        speeds = _floats(args.speeds, "--speeds")
        for v in speeds:
            check_range("--speeds", v, *SPEED_RANGE_KMH, "km/h")
        names = {c.name: c for c in CASES}
        bad = [c for c in args.cases.split(",") if c not in names]
        if bad:
            raise ValueError(f"--cases: unknown case(s) {', '.join(bad)}; the cases are {', '.join(names)}")
        if args.workers is not None:
            check_range("--workers", args.workers, 1, 256)
        if args.sensors is not None and not args.estimator_error:
            raise ValueError(f"--sensors {args.sensors}: only with --estimator-error (the sweep uses the shipped set)")
        if args.estimator_error:
            from railderail_sim.sensors.config import load as load_sensors

            from . import estimator_error as ee
            check_range("--seconds", args.seconds, 1.5, 600.0, "s")
            if args.sensors is not None:
                load_sensors(args.sensors, output_rate=RATE_HZ)      # a bad file refused before the runs
            result = ee.study(args.seconds, workers=args.workers, progress=not args.json, sensors=args.sensors)
            if args.out:
                print(f"wrote {ee.write(result, args.out)}", file=sys.stderr)
            print(jsonout.dumps(result, indent=1) if args.json else ee.markdown(result))
            return 0
        result = study(workers=args.workers, progress=not args.json, speeds=speeds,
                       cases=[names[c] for c in args.cases.split(",")])
        if args.out:
            print(f"wrote {write(result, args.out)}", file=sys.stderr)
        print(jsonout.dumps(result, indent=1) if args.json else markdown(result))
        return 0
    return run
