"""The stability study (`railderail limit-cycle --sensitivity --out DIR`, docs/report/stability.md): what sets the
model car's hunting speed.

Each input is moved alone, from the default set (hs19) to the values other public sources give for a
high-speed car of the same family (the stand-in sets of parameters.py, the yaw-damper count of the SF400/SF500
bogie lineage, the S1002 wheel), never to a value chosen for its result. For each case: the nonlinear critical
speed by the ramp-down method (the fold of the subcritical branch, `limit_cycle.ramp_down`) and the linear one
(root locus). The kick's size and shape are varied for both limit-cycle methods. Each vehicle set is run at
1.1 x 300 km/h on straight track with the China high-speed irregularity (TB/T 3352) and assessed by EN 14363's
stability quantity (sum Y r.m.s. against half Prud'homme's limit). Every run is kept in DIR/cache/ under a key of
what it depends on, so a second call rebuilds the report from the cache.
"""
from dataclasses import replace
import hashlib
import json
import os

import numpy as np

from .. import jsonout, plotting
from ..assessment import assess as assessment
from ..assessment import signals
from ..atomic import atomic_write
from ..parameters import VEHICLE_SETS, vehicle_parameters
from ..track import irregularity as ir
from ..vehicle.simulate import Scenario, constant_speed, simulate, straight_track
from . import limit_cycle as lc
from . import root_locus as rl

CACHE_VERSION = 1
GRID = dict(top_kmh=460.0, bottom_kmh=180.0, step_kmh=40.0, tolerance_kmh=5.0)   # the descent, km/h
SERVICE_KMH = 300.0                 # the CRH3's maximum service speed (crh3-suspension.md: 300-350 km/h)
MARGIN = 1.1                        # EN 14363: stable to 1.1 x the maximum speed
IRREGULARITY = "china-hsr"
SEEDS = (0, 1, 2)
HSR_LINE_M = 2000.0

A380_YAW = dict(yaw_damper_knee_velocity=0.004, yaw_damper_damping=2452.5e3, yaw_damper_damping_after_knee=49.95e3,
                yaw_damper_series_stiffness=8.82e6)
ZHAI_YAW = dict(yaw_damper_knee_velocity=0.01, yaw_damper_damping=1320.0e3,
                yaw_damper_damping_after_knee=(25.75e3 - 13.2e3) / 0.19, yaw_damper_series_stiffness=4.0e6)


def _base_yaw():
    v = vehicle_parameters()
    return v.yaw_damper_damping, v.yaw_damper_knee_velocity * v.yaw_damper_damping


def cases():
    """(input, value, vehicle changes, contact changes, source, how sure) of each one-at-a-time case."""
    c0, f0 = _base_yaw()
    v0 = vehicle_parameters()
    doubled = {k: 2.0 * getattr(v0, k) for k in ("yaw_damper_damping", "yaw_damper_damping_after_knee",
                                                 "yaw_damper_series_stiffness")}
    return [
        ("yaw damper law", "A380: 2452.5 kN s/m to 9.8 kN, 49.95 kN s/m after; series 8.82 MN/m", A380_YAW, {},
         "A380", "S"),
        ("yaw damper law", "Zhai: 1320 kN s/m to 13.2 kN, 66 kN s/m after; series 4 MN/m", ZHAI_YAW, {},
         "Zhai", "S"),
        ("yaw dampers per bogie side", "2 (HS19's law twice)", doubled, {},
         "SF400 (ICE 2) bogie: doubled yaw dampers (crh3-suspension.md, table A); not confirmed for CRH3", "S/U"),
        ("yaw damper blow-off force", "9.8 kN (A380's), HS19 damping", dict(yaw_damper_knee_velocity=9.81e3 / c0),
         {}, "A380", "S"),
        ("yaw damper blow-off force", "13.2 kN (Zhai's), HS19 damping", dict(yaw_damper_knee_velocity=13.2e3 / c0),
         {}, "Zhai", "S"),
        ("yaw damper damping", "1320 kN s/m (Zhai's), HS19 blow-off 3 kN",
         dict(yaw_damper_damping=1320.0e3, yaw_damper_knee_velocity=f0 / 1320.0e3), {}, "Zhai", "S"),
        ("yaw damper damping", "2452.5 kN s/m (A380's), HS19 blow-off 3 kN",
         dict(yaw_damper_damping=2452.5e3, yaw_damper_knee_velocity=f0 / 2452.5e3), {}, "A380", "S"),
        ("yaw damper series stiffness", "4 MN/m (Zhai's)", dict(yaw_damper_series_stiffness=4.0e6), {}, "Zhai", "S"),
        ("yaw damper series stiffness", "8.82 MN/m (A380's)", dict(yaw_damper_series_stiffness=8.82e6), {},
         "A380", "S"),
        ("primary longitudinal stiffness", "14.7 MN/m (A380: spring 0.98 + arm node 13.72)",
         dict(primary_longitudinal_stiffness=14.7e6), {}, "A380", "S"),
        ("primary longitudinal stiffness", "10 MN/m (Zhai's)", dict(primary_longitudinal_stiffness=10.0e6), {},
         "Zhai", "S"),
        ("primary lateral stiffness", "6.5 MN/m (A380: spring 0.98 + arm node 5.52)",
         dict(primary_lateral_stiffness=6.5e6), {}, "A380", "S"),
        ("primary lateral stiffness", "5 MN/m (Zhai's)", dict(primary_lateral_stiffness=5.0e6), {}, "Zhai", "S"),
        ("bogie frame yaw inertia", "A380's radius of gyration (2280 kg m^2 at 2280 kg)",
         dict(bogie_frame_yaw_inertia_source=(2280.0, 2280.0)), {}, "A380", "S"),
        ("bogie frame yaw inertia", "Zhai's radius of gyration (3160 kg m^2 at 3000 kg)",
         dict(bogie_frame_yaw_inertia_source=(3160.0, 3000.0)), {}, "Zhai", "S"),
        ("wheel profile (conicity at 3 mm)", "S1002 on UIC60 1:40", {}, dict(wheel_profile="s1002"),
         "EN13674", "V"),
        ("friction", "0.2", {}, dict(friction_coefficient=0.2), "Iwnicki: 0.3 dry; 0.2 a damp rail", "A"),
        ("friction", "0.4", {}, dict(friction_coefficient=0.4), "the report's sensitivity (0.3 -> 0.4)", "A"),
    ]


def kicks():
    """(method, Kick) of the kick study."""
    return ([("bisection", lc.Kick(a)) for a in (0.002, 0.005, 0.010, 0.020)]
            + [("bisection", lc.Kick(0.010, shape="s-kink"))]
            + [("ramp-down", lc.Kick(0.020)), ("ramp-down", lc.Kick(0.010, shape="s-kink"))])


class Cache:
    """Results kept as JSON under DIR/cache/, keyed by a hash of what they depend on."""

    def __init__(self, out):
        self.folder = os.path.join(out, "cache")
        os.makedirs(self.folder, exist_ok=True)

    def get(self, key, compute):
        name = hashlib.sha1(jsonout.dumps(dict(key, version=CACHE_VERSION)).encode()).hexdigest()[:16]
        path = os.path.join(self.folder, name + ".json")
        if os.path.exists(path):
            with open(path) as f:
                return json.load(f)["value"]
        value = jsonout.plain(compute())
        jsonout.write(path, dict(key=key, value=value))
        return value


def _scenario(vehicle_set="hs19", vehicle=None, contact=None):
    sc = Scenario(vehicle=vehicle_parameters(vehicle_set, **(vehicle or {})))
    return replace(sc, contact=replace(sc.contact, **(contact or {})))


def critical_speeds(sc: Scenario, kick=lc.Kick()):
    """{nonlinear (ramp-down fold), linear (root locus)} critical speeds (km/h) and the downward branch."""
    g = GRID
    speeds, amps, fold = lc.ramp_down(sc, g["top_kmh"], g["bottom_kmh"], g["step_kmh"], g["tolerance_kmh"], kick)
    locus = rl.root_locus(sc, np.linspace(100.0, 600.0, 26))
    return dict(nonlinear_kmh=fold, linear_kmh=locus.linear_critical_speed_kmh, mode=locus.critical_mode,
                frequency_hz=locus.critical_frequency_hz, downward=[speeds.tolist(), amps.tolist()])


def bisection_speed(sc: Scenario, kick):
    res = lc.limit_cycle(sc, np.arange(200.0, 501.0, 50.0), GRID["tolerance_kmh"], amplitude=kick.amplitude_m,
                         length=kick.length_m, shape=kick.shape)
    return dict(nonlinear_kmh=res.nonlinear_critical_speed_kmh)


def hsr_check(vehicle_set, seed, speed_kmh=MARGIN * SERVICE_KMH):
    """EN 14363's stability quantity of one run at speed_kmh on straight track with the China HSR irregularity:
    the largest sum Y r.m.s. of any wheelset (N), its limit (N) and the largest wheelset lateral displacement (m)."""
    track = straight_track().with_line_length(HSR_LINE_M)
    sc = replace(_scenario(vehicle_set), track=track, irregularity=ir.resolve(IRREGULARITY, seed, HSR_LINE_M),
                 speed_table=constant_speed(speed_kmh), output_rate=200.0)
    r = simulate(sc)
    a = assessment.assess(signals.from_arrays(r.arrays(), sc.vehicle))
    rms = [row for row in a.rows if row.quantity == "sum_Y_rms"]
    worst = max(rms, key=lambda row: row.value)
    return dict(status=r.status, sum_y_rms_n=worst.value, limit_n=worst.limit,
                lateral_max_m=float(np.max(np.abs(r.wheelset_lateral))))


def bifurcation(vehicle_set):
    """The ramp-down LimitCycle of a set with both branches, as JSON (160-480 km/h by 20)."""
    res = lc.limit_cycle(_scenario(vehicle_set), np.arange(160.0, 481.0, 20.0), GRID["tolerance_kmh"],
                         method="ramp-down", branches=True)
    return res.as_json()


def limit_cycle_of(j):
    """The LimitCycle of its JSON (for the figure)."""
    def branch(b):
        pts = b["points"]
        return lc.Branch(b["name"], np.array([p["speed_kmh"] for p in pts]),
                         np.array([np.inf if p["amplitude_m"] is None else p["amplitude_m"] for p in pts]),
                         lc.Kick(**b["kick"]))
    v = j["nonlinear_critical_speed_kmh"]
    return lc.LimitCycle(nonlinear_critical_speed_kmh=float("nan") if v is None else v,
                         tolerance_kmh=j["tolerance_kmh"], speeds_kmh=np.array(j["speeds_kmh"]),
                         amplitudes_m=np.array(j["final_amplitude_m"]), excitation_amplitude_m=j["excitation_amplitude_m"],
                         excitation_length_m=j["excitation_length_m"], excitation=j["excitation"], method=j["method"],
                         kick=lc.Kick(**j["kick"]), branches=tuple(branch(b) for b in j["bifurcation"].values()))


def yaw_damper_stroke(vehicle_set, speed_kmh=SERVICE_KMH, window_m=300.0):
    """On the limit cycle after the 10 mm kink at speed_kmh: the front bogie's largest yaw relative to the car body
    (rad) and its yaw dampers' largest stroke velocity (m/s: that yaw's rate, central differences at the output
    rate, times the dampers' semi-spacing), over the last window_m."""
    from ..vehicle.layout import Body, Dof
    sc = lc.excited_scenario(_scenario(vehicle_set), speed_kmh)
    r = simulate(sc)
    states = r.arrays()["body_states"]
    rel = states[:, Body.front_bogie, Dof.yaw] - states[:, Body.car_body, Dof.yaw]
    rate = np.gradient(rel, 1.0 / sc.output_rate)
    sel = r.position >= r.position[-1] - window_m
    return dict(relative_yaw_rad=float(np.max(np.abs(rel[sel]))),
                stroke_velocity_m_s=float(np.max(np.abs(rate[sel]))) * sc.vehicle.yaw_damper_semi_spacing)


def trial(vehicle_set):
    """The paper's progressive trial on R = TRIAL_RADIUS for a set: the staircase's and the refined (constant-speed
    bisection) critical derailment speeds, km/h."""
    from .progressive_trial import progressive_trial
    res = progressive_trial(_scenario(vehicle_set), radius=TRIAL_RADIUS)
    return dict(staircase_kmh=res.critical_derailment_speed_kmh, refined_kmh=res.refined_speed_kmh)


def study(out, progress=None):
    """Run (or read from the cache) every case; write stability.json, stability.md and stability.png to `out`."""
    os.makedirs(out, exist_ok=True)
    cache = Cache(out)
    say = progress or (lambda message: None)
    base = cache.get(dict(case="base", grid=GRID), lambda: critical_speeds(_scenario()))
    say(f"base: {_kmh(base['nonlinear_kmh'])} / {_kmh(base['linear_kmh'])} km/h")
    rows = []
    for name, value, vehicle, contact, source, sure in cases():
        r = cache.get(dict(case=name, vehicle=vehicle, contact=contact, grid=GRID),
                      lambda: critical_speeds(_scenario(vehicle=vehicle, contact=contact)))
        rows.append(dict(input=name, value=value, source=source, sure=sure, **r))
        say(f"{name}, {value}: {_kmh(r['nonlinear_kmh'])} / {_kmh(r['linear_kmh'])} km/h")
    kick_rows = []
    for method, kick in kicks():
        key = dict(case="kick", method=method, kick=kick.as_json(), grid=GRID)
        if method == "bisection":
            r = cache.get(key, lambda: bisection_speed(_scenario(), kick))
        else:
            r = cache.get(key, lambda: critical_speeds(_scenario(), kick))
        kick_rows.append(dict(method=method, kick=kick.as_json(), nonlinear_kmh=r["nonlinear_kmh"]))
        say(f"kick {method} {kick}: {_kmh(r['nonlinear_kmh'])} km/h")
    sets = {}
    for vs in VEHICLE_SETS:
        speeds = cache.get(dict(case="set", vehicle_set=vs, grid=GRID), lambda: critical_speeds(_scenario(vs)))
        runs = [cache.get(dict(case="hsr", vehicle_set=vs, seed=s, speed_kmh=MARGIN * SERVICE_KMH,
                               line_m=HSR_LINE_M), lambda: hsr_check(vs, s)) for s in SEEDS]
        sets[vs] = dict(speeds, hsr=runs)
        say(f"set {vs}: {_kmh(speeds['nonlinear_kmh'])} / {_kmh(speeds['linear_kmh'])} km/h; sum Y rms "
            f"{max(r['sum_y_rms_n'] for r in runs) / 1e3:.1f} kN")
    for vs in ("hs19", DECIDED):
        j = cache.get(dict(case="bifurcation", vehicle_set=vs, grid=GRID), lambda: bifurcation(vs))
        plotting.limit_cycle_figure(limit_cycle_of(j), os.path.join(out, f"stability-bifurcation-{vs}.png"),
                                    lc.THRESHOLD_M, sets[vs]["linear_kmh"])
        say(f"bifurcation diagram of {vs}: fold {_kmh(j['nonlinear_critical_speed_kmh'])} km/h")
    stroke = cache.get(dict(case="stroke", vehicle_set="hs19", speed_kmh=SERVICE_KMH),
                       lambda: yaw_damper_stroke("hs19"))
    trials = {vs: cache.get(dict(case="trial", vehicle_set=vs, radius_m=TRIAL_RADIUS), lambda: trial(vs))
              for vs in ("hs19", DECIDED)}
    data = dict(grid=GRID, service_speed_kmh=SERVICE_KMH, margin=MARGIN, irregularity=IRREGULARITY, seeds=SEEDS,
                base=base, cases=rows, kicks=kick_rows, sets=sets, stroke_hs19=stroke,
                trials=trials)
    jsonout.write(os.path.join(out, "stability.json"), data)
    plotting.stability_figure(base, rows, os.path.join(out, "stability.png"), MARGIN * SERVICE_KMH)
    with atomic_write(os.path.join(out, "stability.md")) as f:
        f.write(markdown(data))
    return dict(base=dict(nonlinear_kmh=base["nonlinear_kmh"], linear_kmh=base["linear_kmh"]),
                cases=[dict(input=r["input"], value=r["value"], nonlinear_kmh=r["nonlinear_kmh"],
                            linear_kmh=r["linear_kmh"]) for r in rows])


def _kmh(v, none="no limit cycle"):
    return none if v is None or not np.isfinite(v) else f"{v:.0f}"


def _fold(v):
    """A fold speed of the study's descent: its lowest step still holding a cycle means that speed or below."""
    return f"<= {v:.0f}" if v is not None and v <= GRID["bottom_kmh"] else _kmh(v)


def _linear(v):
    return _kmh(v, "stable to 600")


def _mode(r):
    return f" ({r['mode']}, {r['frequency_hz']:.1f} Hz)" if r["mode"] else ""


def markdown(d):
    """The report section (docs/report/stability.md): the findings, then the tables."""
    g = d["grid"]
    b = d["base"]
    lines = findings(d).splitlines() + [
        "", "## One input at a time", "",
        f"Nonlinear critical speed: the ramp-down method (`railderail limit-cycle --method ramp-down`), a 10 mm, 20 m "
        f"kink at {g['top_kmh']:.0f} km/h, then steps of {g['step_kmh']:.0f} km/h held {lc.HOLD_M:.0f} m each down to "
        f"{g['bottom_kmh']:.0f} km/h, refined by {g['tolerance_kmh']:.0f} km/h steps: the lowest speed holding a limit "
        "cycle ('<=': still one at the lowest step; 'no limit cycle': none at the top speed). Linear: the root locus (26 speeds 100-600 km/h), the mode "
        "that crosses.", "",
        "| input | value | source (sure) | nonlinear km/h | linear km/h (mode) |", "|---|---|---|---|---|",
        f"| default (hs19) | HS19 throughout | HS19 (S) | {_fold(b['nonlinear_kmh'])} | {_linear(b['linear_kmh'])}{_mode(b)} |"]
    for r in d["cases"]:
        lines.append(f"| {r['input']} | {r['value']} | {r['source']} ({r['sure']}) | {_fold(r['nonlinear_kmh'])} | "
                     f"{_linear(r['linear_kmh'])}{_mode(r)} |")
    lines += ["", "![one input at a time](stability.png)", "",
              "## Bifurcation diagrams", "",
              "Both branches (`railderail limit-cycle --method ramp-down --plot`): the final amplitude after a 0.5 mm "
              "kink at each speed (upward) and the amplitude held at each step of the descent from 480 km/h after a "
              "10 mm kink (downward).", "",
              "![hs19](stability-bifurcation-hs19.png)", "", f"![{DECIDED}](stability-bifurcation-{DECIDED}.png)", "",
              "## The kick", "", "| method | kick | nonlinear km/h |", "|---|---|---|"]
    for r in d["kicks"]:
        k = r["kick"]
        lines.append(f"| {r['method']} | {k['shape']} {k['amplitude_m'] * 1e3:g} mm over {k['length_m']:g} m | "
                     f"{_kmh(r['nonlinear_kmh'])} |")
    limit = d["margin"] * d["service_speed_kmh"]
    lines += ["", "## The vehicle sets", "",
              f"Straight track at {limit:.0f} km/h ({d['margin']:g} x {d['service_speed_kmh']:.0f}) with the "
              f"{d['irregularity']} irregularity (seeds {', '.join(map(str, d['seeds']))}, {HSR_LINE_M:.0f} m): "
              "EN 14363's sum Y r.m.s. (the largest of any wheelset) against its limit, and the largest wheelset "
              "lateral displacement.", "",
              "| set | nonlinear km/h | linear km/h | sum Y r.m.s. kN (limit) | lateral max mm |",
              "|---|---|---|---|---|"]
    for name, s in d["sets"].items():
        rms = max(r["sum_y_rms_n"] for r in s["hsr"])
        lat = max(r["lateral_max_m"] for r in s["hsr"])
        lines.append(f"| {name} | {_fold(s['nonlinear_kmh'])} | {_linear(s['linear_kmh'])} | {rms / 1e3:.1f} "
                     f"({s['hsr'][0]['limit_n'] / 1e3:.1f}) | {lat * 1e3:.2f} |")
    return "\n".join(lines) + "\n"


DECIDED = "hs19-a380yaw"            # the set the findings adopt (parameters.py)
TRIAL_RADIUS = 1000.0               # m: the radius whose critical derailment speed shows what the choice moves


def _row(d, name, value_start):
    return next(r for r in d["cases"] if r["input"] == name and r["value"].startswith(value_start))


def findings(d):
    """The findings, their numbers read from the study's data `d`."""
    b, sets = d["base"], d["sets"]
    nl = {(r["input"], r["value"].split(" ")[0]): _fold(r["nonlinear_kmh"]) for r in d["cases"]}
    kicks = {(r["method"], r["kick"]["shape"], r["kick"]["amplitude_m"]): _kmh(r["nonlinear_kmh"])
             for r in d["kicks"]}
    doubled = _row(d, "yaw dampers per bogie side", "2")
    s1002 = _row(d, "wheel profile (conicity at 3 mm)", "S1002")
    new = sets[DECIDED]
    rms = {k: max(r["sum_y_rms_n"] for r in v["hsr"]) / 1e3 for k, v in sets.items()}
    limit = new["hsr"][0]["limit_n"] / 1e3
    required = d["margin"] * d["service_speed_kmh"]
    t0, t1 = d["trials"]["hs19"], d["trials"][DECIDED]
    st, v0 = d["stroke_hs19"], vehicle_parameters()
    v = st["stroke_velocity_m_s"]
    knee_force = v0.yaw_damper_damping * v0.yaw_damper_knee_velocity
    f_cycle = (knee_force + v0.yaw_damper_damping_after_knee * (v - v0.yaw_damper_knee_velocity)) / 1e3
    f_linear = v0.yaw_damper_damping * v / 1e3
    return f"""# What sets the model car's hunting speed (issue 41)

Generated by `railderail limit-cycle --sensitivity --out DIR` (railderail_sim/methods/stability.py) from the
runs it keeps in DIR/cache; every number is in stability.json. Speeds in km/h. The paper's CRH3 hunts near 320
km/h, the real one runs at 300-350 and EN 14363 asks stability to 1.1 x the maximum speed, here
{required:.0f} km/h.

## Findings

1. **Not the method.** The default set's limit cycle is a flange-contact cycle of about 8.7 mm and its
   bifurcation is strongly subcritical: a 0.5 mm kick grows only at the linear critical speed
   ({_linear(b["linear_kmh"])}), while a large cycle, once started, lives down to the fold. The ramp-down method
   (the fold: the lowest speed holding a limit cycle) gives {_kmh(b["nonlinear_kmh"])}, and
   {kicks[("ramp-down", "kink", 0.02)]} after a 20 mm kink or {kicks[("ramp-down", "s-kink", 0.01)]} after a 10 mm
   S-kink. The bisection on a fixed kink gives {kicks[("bisection", "kink", 0.01)]} for 10 mm,
   {kicks[("bisection", "kink", 0.02)]} for 20 mm and {kicks[("bisection", "s-kink", 0.01)]} for a 10 mm S-kink, but
   {kicks[("bisection", "kink", 0.005)]} for 5 mm and {kicks[("bisection", "kink", 0.002)]} for 2 mm: a small kick
   does not reach the large cycle near the fold, which is why the bisection's answer depends on the kick and the
   ramp-down's does not. The 234 km/h of report.json is the fold, not an artefact of the kick.
2. **The yaw damper's blow-off force sets it.** HS19's yaw damper (one per bogie side) gives 300 kN s/m up to
   0.01 m/s, that is 3 kN, then 20 kN s/m. On its flange-contact cycle at {d["service_speed_kmh"]:.0f} the front
   bogie yaws {st["relative_yaw_rad"] * 1e3:.1f} mrad against the car body and the yaw dampers stroke at up to
   {v:.2f} m/s, {v / v0.yaw_damper_knee_velocity:.0f} times the knee velocity: they push with about
   {f_cycle:.0f} kN where their first stage would give {f_linear:.0f} kN. The damper resists the large cycle with
   little more than its blow-off force while it damps small motions fully (the linear critical speed is high). Raising the blow-off force alone to the
   CRH380A file's 9.8 kN moves the fold to {nl[("yaw damper blow-off force", "9.8")]}, to Zhai's 13.2 kN to
   {nl[("yaw damper blow-off force", "13.2")]}. Raising the damping below the knee alone (blow-off kept at 3 kN)
   leaves it at {nl[("yaw damper damping", "1320")]} / {nl[("yaw damper damping", "2452.5")]} (and removes the
   linear instability below 600); the series stiffness (4 or 8.82 MN/m) gives
   {nl[("yaw damper series stiffness", "4")]} / {nl[("yaw damper series stiffness", "8.82")]}.
3. **The other inputs, within the public sets' values, move it less**: the primary longitudinal stiffness
   (14.7 or 10 MN/m against HS19's 85) {nl[("primary longitudinal stiffness", "14.7")]} /
   {nl[("primary longitudinal stiffness", "10")]}, the largest after the yaw damper; the primary lateral
   stiffness {nl[("primary lateral stiffness", "6.5")]} / {nl[("primary lateral stiffness", "5")]}; the bogie
   frame's yaw inertia {nl[("bogie frame yaw inertia", "A380's")]} / {nl[("bogie frame yaw inertia", "Zhai's")]};
   friction 0.2 / 0.4 {nl[("friction", "0.2")]} / {nl[("friction", "0.4")]}. The S1002 wheel on UIC60 1:40
   (equivalent conicity 0.018 at 3 mm with the 1353 mm back-to-back, against 0.116 for LM; `railderail
   contact-geometry --wheel s1002`) lowers it to {_fold(s1002["nonlinear_kmh"])} with a linear critical speed of
   {_linear(s1002["linear_kmh"])}{_mode(s1002)}: a pair that flat near the centre and steep beyond 3 mm is no
   stand-in for the CRH3's S1002CN on CHN60, whose coordinates are not public (docs/profiles.md); measured
   values in the literature are LMA on CHN60 about 0.04 (nominal), none found for S1002CN.
4. **Whole sourced yaw-damper laws.** With the CRH380A file's law (A380: 2452.5 kN s/m to 9.8 kN, then
   49.95 kN s/m; series 8.82 MN/m) the fold is {nl[("yaw damper law", "A380:")]} and no mode crosses below 600;
   with Zhai's (13.2 kN at 0.01 m/s; series 4 MN/m) {nl[("yaw damper law", "Zhai:")]}, linear
   {_linear(_row(d, "yaw damper law", "Zhai")["linear_kmh"])}. Two HS19 dampers per side (the SF400 lineage's
   doubled yaw dampers, not confirmed for CRH3) go unstable already at {_linear(doubled["linear_kmh"])}
   {_mode(doubled)}, a low-frequency mode: HS19's law doubled is no sourced law, and the count cannot be
   settled without the CRH3's own damper data.
5. **Decision.** The sets with a sourced yaw damper of 9.8-13.2 kN blow-off are stable beyond {required:.0f}:
   on straight track at {required:.0f} with the China HSR irregularity the largest sum Y r.m.s. (EN 14363,
   limit {limit:.1f} kN) is {rms["hs19"]:.1f} kN for hs19 (hunting in flange contact, at the limit), {rms["a380"]:.1f} for a380,
   {rms["zhai"]:.1f} for zhai and {rms[DECIDED]:.1f} for {DECIDED}. `--vehicle-set {DECIDED}` is hs19 with the
   CRH380A file's yaw damper law taken whole (one source per subsystem, as the other elements of hs19 follow;
   that file is a 380 km/h Chinese EMU's and already gives hs19's damper height). Its fold is
   {_kmh(new["nonlinear_kmh"])} and its linear critical speed {_linear(new["linear_kmh"])}; its critical derailment
   speed at R {TRIAL_RADIUS:.0f} m is {t1["refined_kmh"]:.1f} refined ({t1["staircase_kmh"]:.1f} by the staircase)
   against hs19's {t0["refined_kmh"]:.1f} ({t0["staircase_kmh"]:.1f}): the derailment speeds, which agree with the paper within 1 %, do not move. It is not the
   default: its yaw damper is no more the CRH3's than HS19's is (both [S], neither source is clearly better),
   and the choice between the two laws is what moves the hunting speed from {_kmh(b["nonlinear_kmh"])} to
   {_kmh(new["nonlinear_kmh"])}; the paper's 320 lies between and no value here was chosen for it.
6. **What the model car can and cannot represent.** It represents the mechanism (a subcritical hunting
   bifurcation whose fold the yaw damper's saturation sets, a flange-contact limit cycle) and the derailment
   speeds. It cannot represent the CRH3's own hunting speed: no public source gives the CRH3's yaw dampers
   (count, blow-off, series stiffness), its primary guidance stiffness or its S1002CN/CHN60 contact
   geometry, and within the public sets' values the fold ranges from
   {_fold(min(float(r["nonlinear_kmh"]) for r in d["cases"] if r["nonlinear_kmh"] is not None))} to
   {_fold(max(float(r["nonlinear_kmh"]) for r in d["cases"] if r["nonlinear_kmh"] is not None))}.
   Runs at line speed (250-350 km/h) should take `--vehicle-set {DECIDED}` (hs19-a380yaw.md); false-alarm figures
   on hs19 hold below its fold over EN 14363's margin ({_kmh(b["nonlinear_kmh"])} / {MARGIN:g}).

Sources: HS19 = Math. Probl. Eng. 2019, art. 7163732, Table 2; A380 = the public CRH380A parameter file
Par_Vehicle_CRH380A_v6; Zhai = the "high-speed passenger car" preset of Zhai's Vehicle-Track Coupled Dynamics
as republished in public code (all three as transcribed in /work/shared/reference/crh3-suspension.md, [S]);
SF400 doubled yaw dampers: ice-fansite.com, ICE 2 bogie types ([S], CRH3 [U]); LMA/CHN60 conicity: Zhang,
Chi et al., J. Mech. Eng. 2025, 61(24) 180-189, abstract ([S]); S1002CN on CRH3, CHN60 1:40: Ye, Huang, Zhang,
Rail. Eng. Sci. 30 (2022) 96-116 ([V]); EN 14363 sum Y r.m.s. limit (10 + 2 Q0 / 3) / 2 kN as in
railderail_sim/assessment/en14363.py.
"""
