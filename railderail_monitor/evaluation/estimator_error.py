"""`railderail onboard-study --estimator-error`: the on-board estimator's error (onboard.estimator) per side
and per scenario kind, with the estimator's model of the car off by what a real car's is, beside
(docs/onboard-criteria.md; issue 42 item 2).

Each kind is one short run with the shipped sensor set (or a sensor file's: `--sensors`; noise on, seed 1): steady curving on smooth and on
irregular track, straight irregular track healthy and hunting, and a steady crosswind and the CEN gust on
straight track (the estimator told the wind, `estimator.GivenWind` from the wind the car meets, and not).
The error is the estimate less the simulator's wheel forces at the estimate's stamps, after the run's
first second (its start-up), per place (never pooled over sides whose errors have opposite signs): bias,
r.m.s. and the 95th percentile of its magnitude. The model mismatches (the estimator's model changed, the
simulated car not): the car body's mass (the payload) +-10 %, the air springs' effective area +-5 %, and the
heights of the car body's lateral force and the frame's centre of gravity (secondary_height,
bogie_frame_cog_height) +-5 cm, each alone; their bias is shown beside the nominal's.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
import math
from pathlib import Path

import numpy as np

SEED = 1
SETTLE_S = 1.0
# the estimator's model of the car, off by these (the simulated car unchanged)
MISMATCHES = (("payload -10 %", dict(car_body_mass=0.9)), ("payload +10 %", dict(car_body_mass=1.1)),
              ("area -5 %", dict(area=0.95)), ("area +5 %", dict(area=1.05)),
              ("heights -5 cm", dict(heights=-0.05)), ("heights +5 cm", dict(heights=0.05)))


@dataclass(frozen=True)
class Kind:
    name: str
    meaning: str
    radius_m: float = math.inf
    cant_mm: float = 0.0
    speed_kmh: float = 250.0
    irregularity: str = "none"
    faults: tuple = ()
    wind_speed_m_s: float = 0.0
    gust: str = "none"


KINDS = (Kind("steady-curving", "R 1000 m, 175 mm, 220 km/h, smooth", 1000.0, 175.0, 220.0),
         Kind("curving-irregular", "the same on erri-low track", 1000.0, 175.0, 220.0, "erri-low"),
         Kind("straight-irregular", "straight, erri-low, 250 km/h", speed_kmh=250.0, irregularity="erri-low"),
         Kind("hunting", "the same, both bogies' yaw dampers failed", speed_kmh=250.0, irregularity="erri-low",
              faults=("yaw-dampers-failed@both",)),
         Kind("steady-wind", "straight, smooth, 300 km/h, 30 m/s from the left", speed_kmh=300.0,
              wind_speed_m_s=30.0),
         Kind("gust", "straight, smooth, 300 km/h, CEN gust peaking at 30 m/s from the left", speed_kmh=300.0,
              wind_speed_m_s=30.0, gust="chinese-hat"))


def scenario(kind: Kind, seconds):
    """The run of a kind: `seconds` at its speed, in the circular curve from 100 m into it, or on straight
    track from 100 m (a gust peaking 2/3 of the way, the run starting late enough for the gust's ramp)."""
    from railderail_sim.loads.wind import Wind
    from railderail_sim.parameters import TrackParameters
    from railderail_sim.track.irregularity import resolve
    from railderail_sim.vehicle.simulate import constant_speed, scenario as base, straight_track

    straight = math.isinf(kind.radius_m)
    track = straight_track() if straight else TrackParameters(radius=kind.radius_m, cant_height=kind.cant_mm / 1e3)
    length = kind.speed_kmh / 3.6 * seconds
    start = 100.0 if straight else track.straight_in + track.transition_in + 100.0
    if kind.gust != "none":     # the peak at least 600 m along the line (loads.wind: the ramp and the hat)
        start = max(start, 650.0 - 2.0 * length / 3.0)
    track = track.with_line_length(max(track.line_length, start + length + 200.0))
    wind = None
    if kind.wind_speed_m_s > 0.0:
        wind = Wind(speed=kind.wind_speed_m_s, direction_deg=90.0, gust=kind.gust,
                    peak_position=start + 2.0 * length / 3.0 if kind.gust != "none" else math.nan)
    sc = replace(base(radius=1000.0 if straight else kind.radius_m, speed_kmh=kind.speed_kmh), track=track,
                 speed_table=constant_speed(kind.speed_kmh), start_position=start, end_position=start + length,
                 wind=wind, faults=kind.faults)
    if kind.irregularity != "none":
        sc = replace(sc, irregularity=resolve(kind.irregularity, SEED, track.line_length))
    return sc.validated()


def model(vehicle, area, change):
    """(the estimator's vehicle parameters, its air spring area) off by one MISMATCHES change."""
    if "car_body_mass" in change:
        return replace(vehicle, car_body_mass=vehicle.car_body_mass * change["car_body_mass"]), area
    if "area" in change:
        return vehicle, area * change["area"]
    dh = change["heights"]
    return replace(vehicle, secondary_height=vehicle.secondary_height + dh,
                   bogie_frame_cog_height=vehicle.bogie_frame_cog_height + dh), area


def run_kind(item):
    """One kind's errors: nominal (and told the wind, if it blows) and under each mismatch."""
    from railderail_sim.sensors.config import load as load_sensors
    from railderail_sim.sensors.measure import SensorLog
    from railderail_sim.sensors.sensor_set import AIR_SPRING_EFFECTIVE_AREA
    from railderail_sim.vehicle.simulate import simulate

    from ..onboard import estimator as est

    kind, seconds, sensors = item
    sc = scenario(kind, seconds)
    log = SensorLog(replace(load_sensors(sensors), seed=SEED))
    result = simulate(sc, observe=log.observe)
    a = {**result.arrays(), **log.arrays()}
    vp, area = sc.vehicle, AIR_SPRING_EFFECTIVE_AREA
    variants = {"nominal": dict(wind=None)}
    if kind.wind_speed_m_s > 0.0:
        # the wind the car meets, as an anemometer on it reads it (the simulator's wind speed at the car body)
        from railderail_sim.loads.layout import AeroLoad
        variants["told the wind"] = dict(wind=est.GivenWind(a["time"], a["aerodynamics"][:, AeroLoad.wind_speed],
                                                            math.pi / 2))
    out = dict(kind=kind.name, meaning=kind.meaning, seconds=seconds, derailed=result.derailment is not None)
    out["errors"] = {name: est.estimator_error(a, vp, area, SETTLE_S, v["wind"]) for name, v in variants.items()}
    wind = variants.get("told the wind", variants["nominal"])["wind"]
    out["mismatch"] = {name: est.estimator_error(a, *model(vp, area, change), SETTLE_S, wind, truth_vehicle=vp)
                       for name, change in MISMATCHES}
    tru = est.truth(a, vp)
    settled = tru["time"] >= tru["time"][0] + SETTLE_S
    out["truth_range"] = {q: {p: [float(np.min(c)), float(np.max(c))] for p, c in zip(est.PLACES[q], tru[q][settled].T)}
                          for q in est.PLACES}
    return out


def study(seconds=6.0, workers=None, progress=True, kinds=KINDS, sensors=None):
    """`sensors`: a sensor file (None: the shipped set; config/sensors-realistic.yaml its realistic errors)."""
    from railderail_sim.methods.parallel import run_all
    runs = run_all(run_kind, [(k, seconds, sensors) for k in kinds], workers=workers, progress=progress,
                   desc="estimator-error", unit="run")
    named = "the shipped set" if sensors is None else f"the sensor file {Path(sensors).name}"
    return dict(settings=dict(seed=SEED, settle_s=SETTLE_S, seconds=seconds, sensors=f"{named}, noise on",
                              mismatches=[m for m, _ in MISMATCHES]), runs=runs)


# quantity: (heading, scale to the table's unit, format)
SHOWN = {"unloading": ("unloading", 1.0, "{:.3f}"), "lateral_force": ("Y (kN)", 1e-3, "{:.1f}"),
         "derailment_coefficient": ("side ratio", 1.0, "{:.3f}")}


def markdown(result):
    st = result["settings"]
    lines = ["## The estimator's error per side and scenario kind (`railderail onboard-study --estimator-error`)", "",
             f"One run per kind, {st['seconds']:g} s, {st['sensors']}, seed {st['seed']}; the error is the estimate "
             f"less the wheel forces' truth at the estimate's stamps after {st['settle_s']:g} s, per place: bias / "
             "r.m.s. / 95th percentile of its magnitude. Beside it, the bias with the estimator's model of the car "
             "off by each mismatch alone (the simulated car unchanged), where a wind blows with the estimator told "
             "it. The side ratio's error is unbounded where a side's load nears zero (its truth range says so).", "",
             "| kind | estimator | quantity | place | truth min..max | bias / r.m.s. / p95 | "
             + " | ".join(f"bias, {m}" for m in st["mismatches"]) + " |",
             "|---|---|---|---|---|---|" + "---|" * len(st["mismatches"])]
    for r in result["runs"]:
        for variant, errors in r["errors"].items():
            for q, (head, scale, fmt) in SHOWN.items():
                for place, e in errors[q].items():
                    lo, hi = r["truth_range"][q][place]
                    nominal = " / ".join(fmt.format(e[k] * scale) for k in ("bias", "rms", "p95"))
                    mism = (" | ".join(fmt.format(r["mismatch"][m][q][place]["bias"] * scale) for m in st["mismatches"])
                            if variant == list(r["errors"])[-1] else " | ".join("" for _ in st["mismatches"]))
                    lines.append(f"| {r['kind']} | {variant} | {head} | {place} | {fmt.format(lo * scale)}.."
                                 f"{fmt.format(hi * scale)} | {nominal} | {mism} |")
    lines += ["", "Kinds: " + "; ".join(f"{r['kind']}: {r['meaning']}" for r in result["runs"]) + "."]
    return "\n".join(lines)


def write(result, out):
    """OUT/estimator-error.json and OUT/estimator-error.md."""
    from railderail_sim import jsonout
    return jsonout.write_report(out, "estimator-error", result, markdown(result))
