"""`railderail report`: every method run on the model and put beside every number Yu et al. (2022) state.

The report is a Markdown file with PNG figures in one directory. Nothing in the model is adjusted to the
paper: the paper's numbers are only printed beside ours, with the difference and its likely reason.
`quick` runs a reduced set (fewer speeds, three radii, no sensitivity) for smoke tests. `vehicle_set` runs it
all on another suspension set (docs/report/hs19-a380yaw/ is the report of `hs19-a380yaw`).
"""
from dataclasses import replace
import math
import os
import time

import numpy as np

from .. import jsonout, plotting
from ..atomic import atomic_write
from ..parameters import ContactParameters, TrackParameters, vehicle_parameters
from ..contact.layout import WheelPatch
from ..vehicle.layout import Body, Dof
from ..vehicle.simulate import Scenario, constant_speed, simulate
from . import limit_cycle as lc
from . import root_locus as rl
from . import sweep as sw
from .contact_patch import wheel_patch_details
from .progressive_trial import Staircase
from .wheel_rail_pair import build_pair

# Every number Yu et al. 2022 state (section in brackets)
PAPER = {
    "linear_critical_speed_kmh": 380.0,                   # §3.1 root locus "about 380 km/h"
    "nonlinear_critical_speed_kmh": 320.0,                # §3.1 limit cycle "less than 320 km/h"
    "critical_derailment_speed_kmh": {800.0: 255.0, 1000.0: 285.0, 1200.0: 313.0, 1400.0: 341.0,
                                      1600.0: 365.0, 1800.0: 383.0},   # §3.3.2
    "increase_800_1000_kmh": 30.0,                        # §3.2
    "increase_1600_1800_kmh": 20.0,                       # §3.2
    "front_attack_angle_peak_rad": 0.065,                 # §5.2 group A
    "front_attack_angle_group_b_rad": 0.06,               # §5.2 group B at the nonlinear critical speed
    "lateral_force_at_derailment_kn": 60.0,               # §5.3 "more than 60 kN"
    "vertical_force_group_b_kn": (125.0, 130.0),          # §5.3
    "vertical_force_other_kn": 135.0,                     # §5.3 "can exceed 135 kN"
    "max_derailment_coefficient": 0.8,                    # §5.3/§6 "less than 0.8"
    "tread_patch_mm": (11.0, 11.0),                       # §4.2 Fig. 7a
    "flange_root_patch_mm": (17.4, 7.8),                  # §4.2 Fig. 7c
}


def _pct(ours, theirs):
    return f"{100.0 * (ours - theirs) / theirs:+.0f} %" if ours == ours else "-"


def _critical(speed_kmh, none):
    """A critical speed in km/h, or `none` (what the method found instead) when it found none (NaN)."""
    return f"{speed_kmh:.0f} km/h" if speed_kmh == speed_kmh else none


def process_runs(results, vehicle):
    """Constant-speed run of `vehicle` at each radius's refined critical derailment speed over the Table 2 line."""
    runs = {}
    for d in results:
        v = d.get("refined_speed_kmh")
        if v is None or v != v:
            v = d["critical_derailment_speed_kmh"]
        if v is None or v != v:
            continue
        sc = Scenario(vehicle=vehicle, track=TrackParameters(radius=d["radius_m"]), speed_table=constant_speed(v),
                      output_rate=200.0)
        runs[d["radius_m"]] = simulate(sc)
    return runs


def _process_figures(runs, out):
    """The derailment process against position (Yu 2022, Figs. 8-15); returns the figure names."""
    if not runs:
        return []
    inner = {r: (0 if run.scenario.track.direction > 0 else 1) for r, run in runs.items()}
    specs = [
        ("process_lift_inner.png", "wheel lift, inner wheel of the front wheelset (mm)",
         lambda run, i: run.wheel("wheel_lift")[:, i] * 1e3),
        ("process_lift_outer.png", "wheel lift, outer wheel of the front wheelset (mm)",
         lambda run, i: run.wheel("wheel_lift")[:, 1 - i] * 1e3),
        ("process_attack_front.png", "attack angle, front wheelset (rad)", lambda run, i: run.attack_angle[:, 0]),
        ("process_attack_rear.png", "attack angle, rear wheelset of the front bogie (rad)",
         lambda run, i: run.attack_angle[:, 1]),
        ("process_lateral_force.png", "lateral force Y, outer wheel of the front wheelset (kN)",
         lambda run, i: run.wheel("lateral_force")[:, 1 - i] / 1e3),
        ("process_vertical_force.png", "vertical force Q, outer wheel of the front wheelset (kN)",
         lambda run, i: run.wheel("vertical_force")[:, 1 - i] / 1e3),
        ("process_derailment_coefficient.png", "derailment quotient Y/Q, outer wheel, front wheelset",
         lambda run, i: run.wheel("derailment_coefficient")[:, 1 - i]),
    ]
    names = []
    for name, label, get in specs:
        series = [(run.position, get(run, inner[radius]), f"R {radius:.0f} m, {run.speed[0] * 3.6:.0f} km/h")
                  for radius, run in sorted(runs.items())]
        plotting.position_figure(os.path.join(out, name), series, label, markers=(200.0, 400.0, 1400.0, 1600.0))
        names.append((name, label))
    return names


def sliding_mean(values, position, window=2.0):
    """Mean over the preceding `window` metres of track (EN 14363 evaluates Y/Q as a 2 m sliding mean)."""
    c = np.concatenate(([0.0], np.cumsum(values)))
    start = np.searchsorted(position, position - window)
    n = np.arange(1, len(values) + 1) - start
    return (c[1:] - c[start]) / np.maximum(n, 1)


def _process_numbers(runs):
    """The derailment process per radius: front wheelset, outer wheel unless said otherwise, SI."""
    rows = {}
    for radius, run in sorted(runs.items()):
        i = 0 if run.scenario.track.direction > 0 else 1
        o = 1 - i
        qp = run.wheel("derailment_coefficient")[:, o]
        rows[radius] = dict(
            speed_kmh=run.speed[0] * 3.6, status=run.status,
            max_front_attack_rad=float(np.max(np.abs(run.attack_angle[:, 0]))),
            max_rear_attack_rad=float(np.max(np.abs(run.attack_angle[:, 1]))),
            max_lift_inner_m=float(np.max(run.wheel("wheel_lift")[:, i])),
            max_lift_outer_m=float(np.max(run.wheel("wheel_lift")[:, o])),
            lateral_force_at_end_n=float(run.wheel("lateral_force")[-1, o]),
            vertical_force_at_end_n=float(run.wheel("vertical_force")[-1, o]),
            max_lateral_force_n=float(np.max(run.wheel("lateral_force")[:, o])),
            max_vertical_force_n=float(np.max(run.wheel("vertical_force")[:, o])),
            max_derailment_coefficient=float(np.max(qp)),
            max_derailment_coefficient_2m=float(np.max(sliding_mean(qp, run.position))),
            derailment=run.derailment)
    return rows


def _main_patch(run, wheel):
    """(n, WheelPatch) the most loaded patch of a wheel at each sample."""
    p = run.patches(wheel)
    return p[np.arange(len(p)), np.argmax(p[:, :, WheelPatch.normal_force], axis=1)]


def _patch_sizes(runs):
    """Outer wheel of the front wheelset: the largest Hertz patch while on the tread (contact angle below
    0.1 rad, straight track) and at the flange root (first contact with an angle above 0.5 rad)."""
    out = {}
    for radius, run in sorted(runs.items()):
        i = 0 if run.scenario.track.direction > 0 else 1
        o = 1 - i
        main = WheelPatch.split(_main_patch(run, o))
        tread = (np.abs(main["contact_angle"]) < 0.1) & (run.position < 180.0)
        root = np.nonzero(main["contact_angle"] > 0.5)[0]
        out[radius] = dict(
            tread_length_m=float(np.median(main["length"][tread])) if tread.any() else float("nan"),
            tread_width_m=float(np.median(main["width"][tread])) if tread.any() else float("nan"),
            root_length_m=float(main["length"][root[0]]) if len(root) else float("nan"),
            root_width_m=float(main["width"][root[0]]) if len(root) else float("nan"),
            root_position_m=float(run.position[root[0]]) if len(root) else float("nan"))
    return out


PHASES = ("a: straight track", "b: transition", "c: first flange-root contact", "d: circular curve",
          "e: two-point contact", "f: derailment")


def _phase_rows(run):
    """Row indices of the phases of Yu 2022 Fig. 7 for the outer wheel of the front wheelset (-1: none)."""
    o = 1 if run.scenario.track.direction > 0 else 0
    main = _main_patch(run, o)
    pos = run.position
    first = lambda mask: int(np.argmax(mask)) if mask.any() else -1  # noqa: E731
    curve_start = run.scenario.track.straight_in + run.scenario.track.transition_in
    steady = 0.5 * (curve_start + min(pos[-1], curve_start + run.scenario.track.curve_length))
    tr = run.scenario.track
    return [first(pos >= 0.6 * tr.straight_in), first(pos >= tr.straight_in + 0.25 * tr.transition_in),
            first(main[:, WheelPatch.contact_angle] > 0.5), first(pos >= steady), first(run.wheel("contact_count")[:, o] >= 2),
            len(pos) - 1]


def _patch_phases(run, out):
    """Contact patch of the outer wheel, front wheelset, at the phases of Yu 2022 Fig. 7: Hertz ellipse,
    discrete Kik-Piotrowski outline and the exact half-space pressure (contact/halfspace.py)."""
    sc = run.scenario
    pair = build_pair(sc.contact.wheel_profile, sc.track.rail_profile, model="halfspace",
                      friction=sc.contact.friction_coefficient)
    right = sc.track.direction > 0                  # the outer wheel of a left curve is the right one
    side = "right" if right else "left"
    rows, panels = [], []
    bodies = run.arrays()["body_states"]
    for label, i in zip(PHASES, _phase_rows(run)):
        if i < 0:
            panels.append((None, None, f"{label}: not reached"))
            continue
        front = bodies[i, Body.wheelset_0]
        y, z, phi, psi = run.wheelset_lateral[i, 0], front[Dof.vertical], front[Dof.roll], front[Dof.yaw]
        pose = (-y, z, -phi, -psi) if right else (y, z, phi, psi)
        v = run.speed[i]
        details = wheel_patch_details(pair, pose, v, v / sc.vehicle.rolling_radius, grid=48)
        if not details:
            panels.append((None, None, f"{label}: no contact"))
            continue
        d = max(details, key=lambda p: p.normal_force_N)
        panels.append((d, side, f"{label}, s = {run.position[i]:.0f} m\n{len(details)} patch(es), angle "
                                f"{math.degrees(d.contact_angle_rad):.0f} deg, N {d.normal_force_N / 1e3:.0f} kN"))
        rows.append(dict(phase=label, position_m=float(run.position[i]), patches=len(details),
                         contact_angle_rad=d.contact_angle_rad, normal_force_n=d.normal_force_N,
                         hertz_mm=(2e3 * d.hertz_a_m, 2e3 * d.hertz_b_m),
                         discrete_mm=(1e3 * d.discrete.length_m, 1e3 * d.discrete.width_m),
                         halfspace_mm=(1e3 * d.halfspace.length_m, 1e3 * d.halfspace.width_m)))
    plotting.patch_figure(os.path.join(out, "patch_phases.png"), panels, 2, 3)
    return rows


SUSPENSION_SETS = ("hs19", "a380", "zhai")     # the whole public sets the sensitivity puts beside the report's


def sensitivity_variants(vehicle_set):
    """[(label, change)] of the sensitivity table on `vehicle_set`: the reference, one uncertain value changed at
    a time, each other whole public suspension set; every change names the set it starts from."""
    base = vehicle_parameters(vehicle_set)
    variants = [
        (f"reference ({vehicle_set}, LM, Hertz, mu 0.3)", {}),
        ("car-body CoG height 1.52 -> 1.71 m (CRH6 value)", dict(vehicle=dict(car_body_cog_height=1.712))),
        ("car-body CoG height 1.52 -> 1.35 m", dict(vehicle=dict(car_body_cog_height=1.35))),
        ("anti-roll bar 1.0 -> 2.5 MN m/rad", dict(vehicle=dict(anti_roll_stiffness=2.5e6))),
        ("air-spring vertical 0.2 -> 0.35 MN/m (Velaro E)", dict(vehicle=dict(secondary_vertical_stiffness=0.35e6))),
        ("bump-stop clearance 20 -> 30 mm", dict(vehicle=dict(bump_stop_clearance=0.030,
                                                             bump_stop_travel=tuple(t + 0.010 for t in base.bump_stop_travel)))),
        *[(f"suspension set {name}", dict(vehicle_set=name)) for name in SUSPENSION_SETS if name != vehicle_set],
        ("wheel S1002 instead of LM", dict(contact=dict(wheel_profile="s1002"))),
        ("friction 0.3 -> 0.4", dict(contact=dict(friction_coefficient=0.4))),
        ("discrete (Kik-Piotrowski) normal contact", dict(contact=dict(normal_model="discrete"))),
        ("exact online contact search instead of the contact table", dict(contact=dict(contact_geometry="online"))),
        ("creep law FASTSIM instead of Shen-Hedrick-Elkins", dict(contact=dict(creep_model="fastsim"))),
        ("creep law Polach instead of Shen-Hedrick-Elkins", dict(contact=dict(creep_model="polach"))),
    ]
    return [(label, dict(dict(vehicle_set=vehicle_set), **change)) for label, change in variants]


def _sensitivity(radius, stair, workers, vehicle_set):
    """Critical derailment speed (staircase) at one radius of `vehicle_set` when one uncertain value changes at a
    time, or the suspension is another whole public set."""
    variants = sensitivity_variants(vehicle_set)
    from concurrent.futures import ProcessPoolExecutor
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(_variant_trial, radius, stair, change) for _, change in variants]
        speeds = [f.result() for f in futures]
    return [(label, v) for (label, _), v in zip(variants, speeds)]


def _variant_trial(radius, stair, change):
    """Critical derailment speed of one variant: the bisection over constant speeds (1 km/h), which
    resolves finer than the staircase's 5 km/h steps."""
    from .progressive_trial import progressive_trial
    veh = vehicle_parameters(change["vehicle_set"], **change.get("vehicle", {}))
    sc = Scenario(vehicle=veh, contact=replace(ContactParameters(), **change.get("contact", {})))
    r = progressive_trial(sc, radius, stair, refine=True, tolerance_kmh=1.0)
    return r.refined_speed_kmh if r.refined_speed_kmh == r.refined_speed_kmh else r.critical_derailment_speed_kmh


def nadal_of(sc):
    """Nadal's limit at the profile pair's largest contact angle and the scenario's friction."""
    from ..contact import conicity
    from ..contact.nadal import nadal_limit
    from ..vehicle.assemble import contact_geometry
    exact = replace(sc.contact, contact_geometry="online")          # rigid contact needs no contact table
    angle, _ = conicity.max_contact_angle(contact_geometry(exact, sc.track, sc.vehicle.rolling_radius))
    return angle, nadal_limit(angle, sc.contact.friction_coefficient)


def _below(non, lin, cycle_top_kmh, locus_top_kmh):
    """The sentence on the nonlinear critical speed against the linear one (NaN: none found up to the top speed of
    the limit-cycle scan or of the root locus)."""
    if non != non:
        return f"No limit cycle after the kink up to {cycle_top_kmh:.0f} km/h."
    if lin != lin:
        return (f"Nonlinear below linear: yes ({non:.0f} km/h; the centred running stays damped to {locus_top_kmh:.0f} "
                "km/h): a kicked car hunts on a limit cycle where the centred running is stable, the bifurcation is "
                "subcritical.")
    return (f"Nonlinear below linear: {'yes' if non <= lin else 'no'} ({non:.0f} <= {lin:.0f} km/h): the bifurcation "
            "is subcritical, a kicked car hunts on a flange-contact limit cycle well below the speed where the centred "
            "running loses its damping.")


def _discussion(locus, cyc, results, numbers, phases, sens, sets, nadal):
    """Where the model and the paper differ, by how much, and the likely reason."""
    out = ["## Where we differ from Yu 2022, and why", ""]
    lin = locus.linear_critical_speed_kmh
    lin_text = _critical(lin, f"none (stable to {locus.speeds_kmh.max():.0f} km/h)")
    line = (f"* **Linear critical speed** {lin_text} against about 380 km/h ({_pct(lin, 380.0)}). It rests on "
            "the primary guidance stiffness and the yaw dampers, which no public source gives for the CRH3. ")
    if sets:
        line += "With the documented suspension sets it is " + ", ".join(
            f"{k}: {'stable to 800 km/h' if v != v else f'{v:.0f} km/h'}" for k, v in sets.items()) + ". "
    out.append(line + "The conicity of the reconstructed LM (0.11 at the centre) enters too.")
    non = cyc.nonlinear_critical_speed_kmh
    non_text = _critical(non, f"none (no limit cycle to {cyc.speeds_kmh.max(initial=0.0):.0f} km/h)")
    out.append(f"* **Nonlinear critical speed** {non_text}; the paper says below 320 km/h and close to it. "
               "The bifurcation is subcritical, so the value depends on the size of the kick (here a 10 mm, 20 m "
               "kink; the paper's excitation is not given) and on the same stand-in suspension.")
    d = [(r["radius_m"], r.get("refined_speed_kmh"), PAPER["critical_derailment_speed_kmh"].get(r["radius_m"]))
         for r in results]
    d = [(r, v, p) for r, v, p in d if v == v and p]
    if d:
        diffs = [100.0 * (v - p) / p for _, v, p in d]
        how = sorted({f"{r.get('refined_mechanism')} of the {r.get('refined_side')} wheel of wheelset "
                      f"{r.get('refined_wheelset')}" for r in results if r.get("refined_mechanism")})
        cog = next((v for label, v in sens if "1.71" in label), None) if sens else None
        ref = sens[0][1] if sens else None
        out.append(f"* **Critical derailment speed** {min(diffs):+.0f} to {max(diffs):+.0f} % from the paper over the "
                   f"radii, with the same growth with radius. How this model derails: {'; '.join(how)} (wheelsets "
                   "numbered 0-3 from the front; wheel unloading of the inner wheel is the start of overturning outward; the paper: wheel lift grows 'until the train "
                   "turns over'). The overturning limit rests on the car-body centre-of-gravity height, a stand-in "
                   "(1.52 m, CRH380A)"
                   + (f": at 1.71 m the R = 1000 m speed drops from {ref:.0f} to {cog:.0f} km/h." if cog else "."))
    if numbers:
        att = max(n["max_front_attack_rad"] for n in numbers.values())
        out.append(f"* **Attack angle** of the front wheelset at most {att:.4f} rad against about 0.065 rad. A wheelset "
                   "guided by its primary suspension in a curve of 800 m or more reaches a few milliradians (the bogie's "
                   "geometric angle is about a/R, 1.25 mrad at 1000 m, plus its yaw in the flangeway); 0.065 rad (3.7 deg) "
                   "would need the wheelset to turn far beyond its guidance. We cannot tell what the paper's curve shows "
                   "(another definition, or another unit); in this model the 0.06 rad warning does not fire before "
                   "derailment (see the warning-quality results).")
        qp2 = max(n["max_derailment_coefficient_2m"] for n in numbers.values())
        angle, limit = nadal
        verdict = "below" if qp2 < limit else "above"
        out.append(f"* **Derailment coefficient**: largest 2 m mean {qp2:.2f} on the outer wheels, {verdict} Nadal's "
                   f"limit ({limit:.2f} at {math.degrees(angle):.1f} deg, mu 0.3); the paper found Y/Q (its Q/P) below "
                   "0.8 and concluded that Y/Q does not announce this derailment. Raw 200 Hz peaks during flange "
                   "impacts are higher; EN 14363 evaluates the 2 m mean.")
    if phases:
        root = next((r for r in phases if r["phase"].startswith("c")), None)
        tread = next((r for r in phases if r["phase"].startswith("a")), None)
        if root and tread:
            out.append(f"* **Contact patch**: at the first flange-root contact {root['halfspace_mm'][0]:.1f} x "
                       f"{root['halfspace_mm'][1]:.1f} mm (half-space; Hertz {root['hertz_mm'][0]:.1f} x "
                       f"{root['hertz_mm'][1]:.1f}) against 17.4 x 7.8 mm; on the tread {tread['halfspace_mm'][0]:.1f} x "
                       f"{tread['halfspace_mm'][1]:.1f} mm against about 11 x 11 mm. The centred reconstructed LM touches "
                       "UIC60 on its R80 shoulder, which gives a narrow patch; the paper's LM file may touch nearer the "
                       "crown (S1002 centred gives about 11 x 11 mm, docs/contact-report.md).")
    return out + [""]


def _parameter_table(sc):
    rows = ["## Parameters of this run", "", f"Vehicle set `{sc.vehicle.name}` (V verified, S stand-in vehicle, A assumption; "
            "sources in railderail_sim/parameters.py).", "", "| parameter | value | unit | source | sure | note |",
            "|---|---|---|---|---|---|"]
    for name, value, unit, source, sure, note in sc.vehicle.describe():
        v = ", ".join(f"{x:g}" for x in value) if isinstance(value, tuple) else f"{value:g}"
        rows.append(f"| {name} | {v} | {unit} | {source} | {sure} | {note} |")
    return rows + [""]


def headline_cases(quick, vehicle_set):
    """The trials of the report's sweep: the paper's six radii (three when `quick`) on `vehicle_set`."""
    return sw.cases(radii=(800.0, 1200.0, 1800.0) if quick else sw.PAPER_RADII, vehicle_sets=(vehicle_set,))


def write_report(out="report", quick=False, workers=None, vehicle_set="hs19", sensitivity=True):
    """Run everything on the suspension set `vehicle_set` and write out/report.md with its figures (without the
    sensitivity table when `sensitivity` is false); returns the path of report.md."""
    sc = Scenario(vehicle=vehicle_parameters(vehicle_set))
    os.makedirs(out, exist_ok=True)
    t0 = time.time()
    workers = workers or os.cpu_count() or 1
    lines = ["# railderail report: critical derailment speed of the CRH3 model beside Yu et al. (2022)"
             + ("" if vehicle_set == "hs19" else f", suspension set {vehicle_set}"), ""]
    timing = {}

    # --- root locus
    t = time.time()
    locus = rl.root_locus(sc, np.linspace(100.0, 600.0, 26 if quick else 101))
    plotting.root_locus_figure(locus, os.path.join(out, "root_locus.png"))
    timing["root_locus_s"] = time.time() - t
    # --- limit cycle
    t = time.time()
    cyc = lc.limit_cycle(sc, np.arange(200.0, 601.0, 100.0 if quick else 50.0), 10.0 if quick else 1.0)
    plotting.limit_cycle_figure(cyc, os.path.join(out, "limit_cycle.png"), lc.THRESHOLD_M,
                                locus.linear_critical_speed_kmh)
    timing["limit_cycle_s"] = time.time() - t
    # --- progressive trial sweep
    t = time.time()
    stair = Staircase()
    results = sw.sweep(headline_cases(quick, vehicle_set), sc, stair, refine=True,
                       tolerance_kmh=5.0 if quick else 1.0, workers=workers, progress=False)
    plotting.critical_speed_figure(results, os.path.join(out, "critical_speed_vs_radius.png"))
    timing["sweep_s"] = time.time() - t
    # --- derailment process
    t = time.time()
    runs = process_runs(results, sc.vehicle)
    figs = _process_figures(runs, out)
    numbers = _process_numbers(runs)
    patches = _patch_sizes(runs)
    phase_radius = 1000.0 if 1000.0 in runs else min(runs) if runs else None
    phases = _patch_phases(runs[phase_radius], out) if phase_radius else []
    timing["process_s"] = time.time() - t
    sens = _sensitivity(1000.0, stair, workers, vehicle_set) if sensitivity and not quick else []

    lin = locus.linear_critical_speed_kmh
    non = cyc.nonlinear_critical_speed_kmh
    lines += [
        f"Model: CRH3 car (Yu 2022 Table 1 masses and dimensions), suspension set `{vehicle_set}` "
        "(docs/vehicle-model.md),",
        "LM wheel (reconstructed, docs/profiles.md) on UIC60 at 1:40, Hertz normal contact with Shen-Hedrick-Elkins",
        "creep, friction 0.3, ideal rigid track of Table 2. Nothing was tuned to the paper. The same trial"
        + ("" if vehicle_set == "hs19" else " of hs19, beside this folder,") + " on",
        "irregular and elastic track: real-track.md (`railderail real-track`); under crosswind, and the",
        "characteristic wind curves: cwc.md (`railderail cwc`); with suspension faults: faults.md; the warning",
        "criteria over a catalogue of scenarios (which warns, how early, how often falsely): warnings-catalogue.md.",
        "",
        "## Critical speeds on straight track",
        "",
        "| quantity | this model | Yu 2022 | difference |",
        "|---|---|---|---|",
        "| linear critical speed (root locus) | "
        + (f"{lin:.0f} km/h ({locus.critical_mode}, {locus.critical_frequency_hz:.1f} Hz) " if lin == lin else
           f"none: stable to {locus.speeds_kmh.max():.0f} km/h ")
        + f"| about {PAPER['linear_critical_speed_kmh']:.0f} km/h | {_pct(lin, PAPER['linear_critical_speed_kmh'])} |",
        "| nonlinear critical speed (limit cycle, 10 mm kink) | "
        f"{_critical(non, f'none: no limit cycle to {cyc.speeds_kmh.max(initial=0.0):.0f} km/h')} "
        f"| below {PAPER['nonlinear_critical_speed_kmh']:.0f} km/h "
        f"| {_pct(non, PAPER['nonlinear_critical_speed_kmh'])} |",
        "",
        _below(non, lin, cyc.speeds_kmh.max(initial=0.0), locus.speeds_kmh.max()),
        "",
        "![root locus](root_locus.png)", "", "![limit cycle](limit_cycle.png)", "",
        "## Critical derailment speed against radius (progressive trial)", "",
        "| radius (m) | staircase (km/h) | constant speed, Table 2 line (km/h) | Yu 2022 (km/h) | difference | wheel | mechanism | where |",
        "|---|---|---|---|---|---|---|---|",
    ]
    by_r = {d["radius_m"]: d for d in results}
    for d in results:
        paper = PAPER["critical_derailment_speed_kmh"].get(d["radius_m"])
        v = d["critical_derailment_speed_kmh"]
        rv = d.get("refined_speed_kmh", float("nan"))
        refined = bool(d.get("refined_mechanism"))
        wheelset, side = (d["refined_wheelset"], d["refined_side"]) if refined else (d["derailed_wheelset"],
                                                                                   d["derailed_side"])
        lines.append(f"| {d['radius_m']:.0f} | {v:.1f} | {rv:.1f} | {paper:.0f} | {_pct(rv if rv == rv else v, paper)} | "
                     f"ws {wheelset} {side} "
                     f"| {d.get('refined_mechanism') or d['mechanism']} | {d.get('refined_section', '')} "
                     f"{d.get('refined_position_m', float('nan')):.0f} m |")
    if 800.0 in by_r and 1000.0 in by_r:
        inc = by_r[1000.0]["refined_speed_kmh"] - by_r[800.0]["refined_speed_kmh"]
        lines.append(f"\nIncrease from R 800 to 1000 m: {inc:+.0f} km/h (Yu 2022: +{PAPER['increase_800_1000_kmh']:.0f}).")
    if 1600.0 in by_r and 1800.0 in by_r:
        inc = by_r[1800.0]["refined_speed_kmh"] - by_r[1600.0]["refined_speed_kmh"]
        lines.append(f"Increase from R 1600 to 1800 m: {inc:+.0f} km/h (Yu 2022: +{PAPER['increase_1600_1800_kmh']:.0f}).")
    lines += ["", "![critical speed vs radius](critical_speed_vs_radius.png)", "",
              "## Derailment process at the critical derailment speed", "",
              "Front wheelset; forces and Y/Q of its outer wheel (EN 14363's notation: Y lateral, Q vertical; the "
              "paper writes Q and P); Y/Q raw (200 Hz) and as the 2 m sliding mean of EN 14363.", "",
              "| radius (m) | speed (km/h) | max attack angle front / rear (rad) | max lift inner / outer (mm) | "
              "Y, Q at derailment (kN) | max Y, Q (kN) | max Y/Q raw / 2 m |",
              "|---|---|---|---|---|---|---|"]
    for radius, n in numbers.items():
        lines.append(f"| {radius:.0f} | {n['speed_kmh']:.1f} | {n['max_front_attack_rad']:.4f} / {n['max_rear_attack_rad']:.4f} | "
                     f"{n['max_lift_inner_m'] * 1e3:.1f} / {n['max_lift_outer_m'] * 1e3:.1f} | "
                     f"{n['lateral_force_at_end_n'] / 1e3:.0f}, {n['vertical_force_at_end_n'] / 1e3:.0f} | "
                     f"{n['max_lateral_force_n'] / 1e3:.0f}, {n['max_vertical_force_n'] / 1e3:.0f} | "
                     f"{n['max_derailment_coefficient']:.2f} / {n['max_derailment_coefficient_2m']:.2f} |")
    if numbers:
        att = max(n["max_front_attack_rad"] for n in numbers.values())
        qend = [n["lateral_force_at_end_n"] / 1e3 for n in numbers.values()]
        pend = [n["vertical_force_at_end_n"] / 1e3 for n in numbers.values()]
        qp = max(n["max_derailment_coefficient"] for n in numbers.values())
        qp2 = max(n["max_derailment_coefficient_2m"] for n in numbers.values())
        lines += ["", "| quantity | this model | Yu 2022 |", "|---|---|---|",
                  f"| front-wheelset attack-angle peak | {att:.4f} rad | about {PAPER['front_attack_angle_peak_rad']} rad |",
                  f"| lateral force at derailment (outer wheel) | {min(qend):.0f}-{max(qend):.0f} kN | more than "
                  f"{PAPER['lateral_force_at_derailment_kn']:.0f} kN |",
                  f"| vertical force at derailment (outer wheel) | {min(pend):.0f}-{max(pend):.0f} kN | 125-130 kN "
                  "(group B), over 135 kN (others) |",
                  f"| maximum derailment coefficient | {qp2:.2f} (2 m mean), {qp:.2f} (raw peak) | below "
                  f"{PAPER['max_derailment_coefficient']} |"]
    lines.append("")
    for name, label in figs:
        lines += [f"![{label}]({name})", ""]
    lines += ["## Contact patch (outer wheel, front wheelset)", "",
              "| radius (m) | tread patch length x width (mm) | first flange-root patch (mm) | at (m) |", "|---|---|---|---|"]
    for radius, p in patches.items():
        lines.append(f"| {radius:.0f} | {p['tread_length_m'] * 1e3:.1f} x {p['tread_width_m'] * 1e3:.1f} | "
                     f"{p['root_length_m'] * 1e3:.1f} x {p['root_width_m'] * 1e3:.1f} | {p['root_position_m']:.0f} |")
    lines += [f"\nYu 2022 (discrete contact): about {PAPER['tread_patch_mm'][0]:.0f} x {PAPER['tread_patch_mm'][1]:.0f} mm "
              f"on the tread, {PAPER['flange_root_patch_mm'][0]} x {PAPER['flange_root_patch_mm'][1]} mm at the flange root.", ""]
    if phases:
        lines += [f"### Patch at the phases of Yu 2022 Fig. 7 (R = {phase_radius:.0f} m, outer wheel, front wheelset)", "",
                  "| phase | position (m) | patches | contact angle (deg) | N (kN) | Hertz (mm) | Kik-Piotrowski (mm) | half-space (mm) |",
                  "|---|---|---|---|---|---|---|---|"]
        for r in phases:
            lines.append(f"| {r['phase']} | {r['position_m']:.0f} | {r['patches']} | {math.degrees(r['contact_angle_rad']):.0f} | "
                         f"{r['normal_force_n'] / 1e3:.0f} | {r['hertz_mm'][0]:.1f} x {r['hertz_mm'][1]:.1f} | "
                         f"{r['discrete_mm'][0]:.1f} x {r['discrete_mm'][1]:.1f} | {r['halfspace_mm'][0]:.1f} x {r['halfspace_mm'][1]:.1f} |")
        lines += ["", "Length x width (rolling direction x lateral). The half-space solution is the reference (Boussinesq "
                  "influence coefficients, docs/contact-models.md).", "", "![patch phases](patch_phases.png)", ""]
    if sens:
        ref = sens[0][1]
        lines += ["## Sensitivity of the critical derailment speed (R = 1000 m, constant speed, bisection to 1 km/h)", "",
                  "| change | critical derailment speed (km/h) | change (km/h) |", "|---|---|---|"]
        for label, v in sens:
            lines.append(f"| {label} | {v:.1f} | {v - ref:+.1f} |")
        lines.append("")
    sets = {} if quick else {name: rl.root_locus(Scenario(vehicle=vehicle_parameters(name)),
                                                 np.linspace(100.0, 800.0, 36)).linear_critical_speed_kmh
                             for name in dict.fromkeys(SUSPENSION_SETS + (vehicle_set,))}
    lines += _discussion(locus, cyc, results, numbers, phases, sens, sets, nadal_of(sc))
    lines += _parameter_table(sc)
    timing["total_s"] = time.time() - t0
    lines += ["## Run", "", "```", jsonout.dumps({k: round(v, 1) for k, v in timing.items()}), "```", ""]
    data = dict(linear=locus.as_json(), limit_cycle=cyc.as_json(), trials=results, process=numbers, patches=patches,
                patch_phases=phases,
                sensitivity=sens, timing=timing)
    jsonout.write(os.path.join(out, "report.json"), data)
    path = os.path.join(out, "report.md")
    with atomic_write(path) as f:
        f.write("\n".join(lines))
    return path
