"""Subcommands simulate, root-locus, limit-cycle, trial, sweep, real-track and report: parse, call `methods`,
print.

Every command takes the vehicle parameter set, wheel profile, contact model and friction; --json prints
one JSON object on stdout through the project's JSON encoder (speeds in km/h named *_kmh, SI elsewhere,
a speed never reached as null); --plot checks its file name before any computation (`plotting`).
"""
from dataclasses import replace
import json
import math
import os
import sys

from .. import jsonout, plotting
from ..atomic import atomic_write
from ..parameters import (CANT_RANGE_MM, FRICTION_RANGE, TRACK_MODELS, VEHICLE_SETS, ContactParameters,
                          TrackParameters, vehicle_parameters)
from ..track import irregularity as ir
from ..track import spectra as sp
from ..ranges import check_range
from ..vehicle.assemble import CONTACT_GEOMETRIES, FAULTS
from ..vehicle.simulate import Scenario, constant_speed


def _common(parser):
    parser.add_argument("--vehicle-set", default="hs19", choices=VEHICLE_SETS, help="suspension parameter set")
    parser.add_argument("--wheel", default="lm", help="wheel profile: lm, s1002 or a profile file")
    parser.add_argument("--rail", default="uic60", help="rail profile: uic60, uic60-mbench or a file")
    parser.add_argument("--contact", default="hertz", choices=("hertz", "discrete"), help="normal contact model")
    parser.add_argument("--creep", default="she", choices=("she", "polach", "fastsim", "linear"),
                        help="creep force law")
    parser.add_argument("--friction", type=float, default=0.3, help="wheel-rail friction coefficient")
    parser.add_argument("--geometry", default="table", choices=CONTACT_GEOMETRIES,
                        help="contact geometry: the precomputed contact table (online search outside it) or "
                             "the exact online search at every evaluation")
    parser.add_argument("--fault", action="append", default=[], metavar="NAME@LOCATION",
                        help="a suspension fault, repeatable: " + "; ".join(f"{name}@{'|'.join(locations)}" for
                                                                         name, locations in FAULTS.items())
                             + " (docs/vehicle-model.md, Suspension limits and faults)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def _track_args(parser, line, cant=True):
    """--track, --irregularity and --irregularity-seed (`line`: where a generated sample lies) and --cant-mm."""
    parser.add_argument("--track", default="rigid", choices=TRACK_MODELS,
                        help="rigid rails, or the elastic track: a co-running rail mass under each wheel "
                             "(docs/elastic-track.md); default %(default)s")
    if cant:
        parser.add_argument("--cant-mm", type=float, default=None,
                            help=f"cant height (mm, {CANT_RANGE_MM[0]:g}-{CANT_RANGE_MM[1]:g}; default: Table 2's "
                                 "175 mm)")
    parser.add_argument("--irregularity", default=ir.NONE, metavar="NAME|FILE.csv",
                        help=f"track irregularity: none, a spectrum ({', '.join(sp.SPECTRA)}; a random sample {line}, "
                             "from --irregularity-seed) or a CSV file (docs/track-irregularity.md)")
    parser.add_argument("--irregularity-seed", type=int, default=0,
                        help=f"seed of a generated irregularity (an integer in [{ir.SEEDS[0]}, {ir.SEEDS[1]}], "
                             "default %(default)s)")


def _wind_args(parser):
    """--wind-speed-m-s, --wind-direction-deg and --gust (loads.wind; docs/loads.md)."""
    from ..loads.wind import GUSTS
    parser.add_argument("--wind-speed-m-s", type=float, default=0.0,
                        help="wind speed (m/s; with --gust the gust's peak); default 0, still air")
    parser.add_argument("--wind-direction-deg", type=float, default=90.0,
                        help="where the wind comes from, relative to the direction of travel (deg, -180-180): "
                             "90 from the left (the inside of the default left curve), -90 from the right; "
                             "default %(default)s")
    parser.add_argument("--gust", default="none", choices=GUSTS,
                        help="steady wind (none) or the CEN extreme gust of EN 14067-6, peaking at the middle of "
                             "the circular curve; default %(default)s")


def wind(args):
    """The Wind of the --wind options (None without them or at zero speed: still air)."""
    from ..loads.wind import Wind
    if not hasattr(args, "wind_speed_m_s"):
        return None
    w = Wind(speed=args.wind_speed_m_s, direction_deg=args.wind_direction_deg, gust=args.gust).validated()
    return w if w.blows else None


def base_scenario(args, line_length_m=None, **track):
    """The Scenario of the common options (the faults checked here, before any run); with _track_args, the
    cant and the irregularity, a generated one over line_length_m (default: the line of the track's
    parameters)."""
    check_range("friction coefficient", args.friction, *FRICTION_RANGE, lo_open=True)
    if getattr(args, "cant_mm", None) is not None:
        track["cant_height"] = check_range("cant", args.cant_mm, *CANT_RANGE_MM, "mm") / 1000.0
    tp = TrackParameters(rail_profile=args.rail, **track)
    irregularity = None
    if hasattr(args, "irregularity"):
        irregularity = ir.resolve(args.irregularity, args.irregularity_seed, line_length_m or tp.line_length)
    return Scenario(vehicle=vehicle_parameters(args.vehicle_set), track=tp, irregularity=irregularity,
                    track_model=getattr(args, "track", "rigid"), wind=wind(args), faults=tuple(args.fault),
                    contact=ContactParameters(wheel_profile=args.wheel, normal_model=args.contact,
                                              creep_model=args.creep, friction_coefficient=args.friction,
                                              contact_geometry=args.geometry)).validated()


def _emit(args, obj, human):
    print(jsonout.dumps(obj, indent=1) if args.json else human)


def _plot_path(args):
    return plotting.checked_path(args.plot) if args.plot is not None else None


SHIPPED_SENSORS = "shipped"     # --sensors without a file


def simulate_command(parser):
    _common(parser)
    parser.add_argument("--radius", type=float, default=1000.0, help="curve radius (m)")
    parser.add_argument("--speed-kmh", type=float, default=300.0, help="constant speed (km/h)")
    parser.add_argument("--right", action="store_true", help="curve to the right (default: left)")
    parser.add_argument("--out", help="write the time histories to this .npz file (docs/output-format.md)")
    parser.add_argument("--rate", type=float, default=200.0, help="output rate (Hz)")
    parser.add_argument("--duration-s", type=float, default=None, metavar="S",
                        help="simulated time (s) from the start of the line; default: the whole line")
    parser.add_argument("--plot", metavar="FILE.png",
                        help="the run against position: rails, front wheelset, Y/Q, lift (.png, .pdf or .svg)")
    parser.add_argument("--sensors", nargs="?", const=SHIPPED_SENSORS, metavar="FILE.yaml",
                        help="also record what the on-board sensors measure (docs/onboard.md): the sensor set of "
                             "FILE.yaml, without a file the shipped one (railderail_sim/config/sensors.yaml); "
                             "stored in --out as sensor_<mount>_time, _acceleration, _angular_rate, ...")
    parser.add_argument("--sensor-seed", type=int, default=None,
                        help="seed of the sensors' noise, biases and lost samples (default: the sensor file's)")
    _track_args(parser, "along the line")
    _wind_args(parser)
    _supervision_args(parser)

    def run(args):
        if args.supervision is None and (args.closed_loop or args.odometer or args.critical_speed_kmh is not None):
            raise ValueError("--closed-loop, --odometer and --critical-speed-kmh need --supervision")
        if args.supervision is not None:
            return _supervised(args)
        from ..sensors import config as sensor_config
        from ..sensors.measure import SensorLog
        from ..vehicle.simulate import simulate
        plot = _plot_path(args)
        sc = _simulate_scenario(args)
        if args.out and not args.out.endswith(".npz"):
            raise ValueError(f"output file {args.out!r} must end in .npz")
        log = None
        if args.sensors is not None:
            sensors = sensor_config.load(None if args.sensors == SHIPPED_SENSORS else args.sensors)
            if args.sensor_seed is not None:
                sensors = replace(sensors, seed=args.sensor_seed)
            log = SensorLog(sensors.validated(sc.output_rate))
        elif args.sensor_seed is not None:
            raise ValueError("--sensor-seed needs --sensors")
        r = simulate(sc, observe=None if log is None else log.observe)
        if args.out:
            r.save(args.out, **({} if log is None else dict(extra=log.arrays(), extra_metadata=dict(
                sensors=sensor_config.metadata(log.sensors, args.sensors)))))
        if plot:
            plotting.run_figure(r, plot)
        s = r.summary()
        _emit(args, s, summary_text(s))
    return run


def _supervision_args(parser):
    """--supervision, --closed-loop, --critical-speed-kmh, --approach-m, --adhesion (docs/supervision.md)."""
    from ..supervision.braking import ADHESIONS
    parser.add_argument("--supervision", nargs="?", const="", metavar="SURVEY.json",
                        help="supervise the speed against a survey's JSON (its curve of the run's radius and cant, "
                             "placed on the run's curve), or without one the scenario's curve under "
                             "--critical-speed-kmh (railderail_monitor's supervisor)")
    parser.add_argument("--closed-loop", action="store_true",
                        help="with --supervision: brake on the supervisor's emergency brake command")
    parser.add_argument("--critical-speed-kmh", type=float, default=None,
                        help="the critical derailment speed of the scenario's curve (km/h; `railderail trial` "
                             "or the survey computes it), supervised less dV_ebi only: a survey's safe speed "
                             "also keeps every hazard margin")
    parser.add_argument("--approach-m", type=float, default=None,
                        help="metres of straight before the curve's entry transition (default: Table 2's 200)")
    parser.add_argument("--odometer", action="store_true",
                        help="with --supervision: the measured mode, the shipped odometer's speed and the position "
                             "integrated from it, supervised at the pessimistic end of its confidence interval")
    parser.add_argument("--adhesion", default="dry", choices=ADHESIONS,
                        help="the braking model's emergency decelerations: dry or wet rail; default %(default)s")


SUPERVISION_HOOK = "SUPERVISION"    # the name, in a command table's module, of the supervised run's "module:function"


def _supervised(args):
    """`simulate --supervision`: the run through the supervisor a command table's module names (railderail_monitor
    registers it), so that this package never imports the supervisor."""
    import importlib
    from importlib.metadata import entry_points
    from . import ENTRY_POINTS, _load
    targets = [getattr(importlib.import_module(p.module), SUPERVISION_HOOK, None)
               for p in sorted(entry_points(group=ENTRY_POINTS), key=lambda p: p.name)]
    targets = [t for t in targets if t]
    if not targets:
        raise ValueError("--supervision needs railderail_monitor's supervisor, which is not installed")
    if args.out or args.plot or args.sensors is not None:
        raise ValueError("--out, --plot and --sensors do not go with --supervision")
    if args.critical_speed_kmh is not None:
        check_range("critical derailment speed", args.critical_speed_kmh, 50.0, 800.0, "km/h")
    sc = _simulate_scenario(args)
    out, human = _load(targets[0])(args, sc)
    _emit(args, out, human)


def _simulate_scenario(args):
    """The Scenario of `simulate`'s options."""
    track = {} if args.approach_m is None else dict(straight_in=check_range("approach", args.approach_m, 0.0, 1e5, "m"))
    sc = base_scenario(args, radius=args.radius, direction=-1 if args.right else 1, **track)
    sc = replace(sc, speed_table=constant_speed(args.speed_kmh), output_rate=args.rate).validated()
    if args.duration_s is not None:
        line = sc.track.line_length
        check_range("--duration-s", args.duration_s, 0.0, (line - sc.start_position) / (args.speed_kmh / 3.6),
                    "s", lo_open=True)     # the rest of the line at the run's speed
        sc = replace(sc, end_position=sc.start_position + args.duration_s * args.speed_kmh / 3.6)
    return sc


def summary_text(s):
    """A run's summary (Result.summary) as a user reads it: rounded, with units, in EN 14363's notation (Y
    lateral, Q vertical wheel-rail force; docs/output-format.md)."""
    d = s["derailment"]
    lines = [f"status                        {s['status']}",
             f"simulated time                {s['duration_s']:.2f} s",
             f"car-body position at the end  {s['end_position_m']:.1f} m",
             f"largest attack angle, ws 0    {s['max_attack_angle_rad'] * 1e3:.2f} mrad",
             f"largest wheel lift h_p        {s['max_wheel_lift_m'] * 1e3:.2f} mm",
             f"largest lateral force Y       {s['max_lateral_force_n'] / 1e3:.1f} kN",
             f"largest vertical force Q      {s['max_vertical_force_n'] / 1e3:.1f} kN",
             f"largest derailment quotient   Y/Q {s['max_derailment_coefficient']:.3f}",
             f"track                         {s['track_model']}"]
    if d:
        lines.append(f"derailment                    wheelset {d['wheelset']} {d['wheel_side']} ({d['rail_side']} "
                     f"rail), {d['mechanism'].replace('_', ' ')}, t = {d['time_s']:.3f} s, "
                     f"{d['speed_kmh']:.1f} km/h")
    return "\n".join(lines)


def root_locus_command(parser):
    _common(parser)
    parser.add_argument("--from-kmh", type=float, default=100.0)
    parser.add_argument("--to-kmh", type=float, default=600.0)
    parser.add_argument("--points", type=int, default=101)
    parser.add_argument("--plot", metavar="FILE.png", help="root-locus and damping figure (.png, .pdf or .svg)")

    def run(args):
        import numpy as np
        from ..methods import root_locus as rl
        check_range("--points", args.points, 2, 2000)
        if args.from_kmh >= args.to_kmh:
            raise ValueError(f"speed range {args.from_kmh:g}-{args.to_kmh:g} km/h is empty")
        plot = _plot_path(args)
        res = rl.root_locus(base_scenario(args), np.linspace(args.from_kmh, args.to_kmh, args.points))
        if plot:
            plotting.root_locus_figure(res, plot)
        v = res.linear_critical_speed_kmh
        human = (f"linear critical speed: {v:.1f} km/h ({res.critical_mode} mode, {res.critical_frequency_hz:.2f} Hz)"
                 if math.isfinite(v) else f"stable up to {args.to_kmh:g} km/h")
        _emit(args, res.as_json(), human)
    return run


def limit_cycle_command(parser):
    from ..methods import limit_cycle as lc
    _common(parser)
    parser.add_argument("--method", default="bisection", choices=lc.METHODS,
                        help="bisection: the lowest speed at which the car keeps hunting after the kick; ramp-down: "
                             "a kick at the top speed, then the speed lowered in steps until the limit cycle dies "
                             "(the lowest speed holding one); default %(default)s")
    parser.add_argument("--from-kmh", type=float, default=200.0)
    parser.add_argument("--to-kmh", type=float, default=600.0)
    parser.add_argument("--step-kmh", type=float, default=50.0, help="scan step before the bisection or refinement")
    parser.add_argument("--tolerance-kmh", type=float, default=1.0, help="bisection tolerance, or the descent's "
                                                                          "finer step")
    parser.add_argument("--kink-mm", type=float, default=10.0,
                        help="the kick's amplitude (mm), the excitation unless --irregularity gives one")
    parser.add_argument("--kick-length-m", type=float, default=20.0, help="the kick's period length (m)")
    parser.add_argument("--kick-shape", default="kink", choices=tuple(lc.KICK_SHAPES),
                        help="kink: one cosine period to the left; s-kink: left then right; default %(default)s")
    _track_args(parser, f"over the first {lc.EXCITATION_M:g} m, smooth track after it", cant=False)
    parser.add_argument("--plot", metavar="FILE.png",
                        help="bifurcation diagram, both branches (.png, .pdf or .svg)")
    parser.add_argument("--sensitivity", action="store_true",
                        help="the stability study instead (docs/report/stability.md): what sets the hunting speed, "
                             "one sourced input at a time; needs --out")
    parser.add_argument("--out", help="with --sensitivity: the report folder (its cache/ keeps each run)")

    def run(args):
        import numpy as np
        if args.sensitivity:
            from ..methods import stability
            if not args.out:
                raise ValueError("--sensitivity needs --out DIR")
            res = stability.study(args.out, progress=None if args.json else lambda m: print(m, file=sys.stderr))
            _emit(args, res, f"stability study written to {args.out}")
            return
        if args.out:
            raise ValueError("--out is the --sensitivity study's folder; give --sensitivity too, or --plot")
        check_range("excitation amplitude", args.kink_mm, 0.1, 30.0, "mm")
        if args.step_kmh <= 0 or args.from_kmh >= args.to_kmh:
            raise ValueError(f"scan {args.from_kmh:g}-{args.to_kmh:g} km/h by {args.step_kmh:g} is empty")
        plot = _plot_path(args)
        res = lc.limit_cycle(base_scenario(args, line_length_m=lc.EXCITATION_M),
                             np.arange(args.from_kmh, args.to_kmh + 1e-9, args.step_kmh),
                             args.tolerance_kmh, amplitude=args.kink_mm / 1000.0, length=args.kick_length_m,
                             method=args.method, shape=args.kick_shape, branches=True,
                             progress=None if args.json else
                             lambda v, a, u: print(f"  {v:7.2f} km/h: amplitude {a * 1e3:.4f} mm"
                                                   f"{' (hunting)' if u else ''}", file=sys.stderr))
        if plot:
            plotting.limit_cycle_figure(res, plot, lc.THRESHOLD_M)
        v = res.nonlinear_critical_speed_kmh
        human = (f"nonlinear critical speed ({args.method}): {v:.1f} km/h (+/- {args.tolerance_kmh:g})"
                 if math.isfinite(v) else f"no limit cycle from {args.from_kmh:g} to {args.to_kmh:g} km/h")
        _emit(args, res.as_json(), human)
    return run


def _staircase_args(parser):
    parser.add_argument("--start-kmh", type=float, default=200.0, help="staircase entry speed")
    parser.add_argument("--step-kmh", type=float, default=5.0, help="staircase step")
    parser.add_argument("--hold-m", type=float, default=200.0, help="distance held at each speed")
    parser.add_argument("--acceleration", type=float, default=0.5, help="acceleration between holds (m/s^2)")
    parser.add_argument("--top-kmh", type=float, default=450.0, help="highest staircase speed")
    parser.add_argument("--no-refine", action="store_true", help="skip the bisection over constant speeds")
    parser.add_argument("--tolerance-kmh", type=float, default=1.0, help="bisection tolerance")


def _staircase(args):
    from ..methods.progressive_trial import Staircase
    return Staircase(start_kmh=args.start_kmh, step_kmh=args.step_kmh, hold_m=args.hold_m,
                     acceleration=args.acceleration, top_kmh=args.top_kmh)


def _trial_scenario(args):
    """The base scenario of a trial: an irregularity generated along the staircase's (longest) line."""
    from ..methods.progressive_trial import trial_track
    return base_scenario(args, line_length_m=trial_track(TrackParameters(), _staircase(args)).line_length)


def _trial_line(d):
    v = d["critical_derailment_speed_kmh"]
    if v is None or v != v:
        return f"R = {d['radius_m']:.0f} m: no derailment up to the top speed"
    line = (f"R = {d['radius_m']:.0f} m: critical derailment speed {v:.1f} km/h, wheelset {d['derailed_wheelset']} "
            f"{d['derailed_side']} wheel, {d['mechanism']} at {d['derailment_position_m']:.0f} m")
    rv = d.get("refined_speed_kmh")
    if rv is not None and rv == rv:
        line += (f"; constant speed on the Table 2 line: {rv:.1f} km/h ({d['refined_mechanism']}, "
                 f"{d['refined_side']} wheel of wheelset {d['refined_wheelset']}, {d['refined_section']} at "
                 f"{d['refined_position_m']:.0f} m)")
    return line


def trial_command(parser):
    _common(parser)
    parser.add_argument("--radius", type=float, default=1000.0, help="curve radius (m)")
    _staircase_args(parser)
    _track_args(parser, "along the staircase's line")
    _wind_args(parser)

    def run(args):
        from ..methods.progressive_trial import progressive_trial
        r = progressive_trial(_trial_scenario(args), args.radius, _staircase(args), refine=not args.no_refine,
                              tolerance_kmh=args.tolerance_kmh)
        d = r.as_json()
        _emit(args, d, _trial_line(d))
    return run


def _floats(text, name):
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise ValueError(f"{name} {text!r} is not a comma-separated list of numbers") from None
    if not values:
        raise ValueError(f"{name} is empty")
    return values


def sweep_command(parser):
    _common(parser)
    parser.add_argument("--radii", default="800,1000,1200,1400,1600,1800", help="curve radii (m), comma-separated")
    parser.add_argument("--cants-mm", default="175", help="cant heights (mm), comma-separated")
    parser.add_argument("--frictions", default=None, help="friction coefficients, comma-separated")
    parser.add_argument("--wheels", default=None, help="wheel profiles, comma-separated")
    parser.add_argument("--vehicle-sets", default=None, help="parameter sets, comma-separated")
    parser.add_argument("--workers", type=int, default=None, help="local processes (default: CPU count)")
    parser.add_argument("--scheduler", default=None, help="address of a Dask distributed scheduler")
    parser.add_argument("--plot", metavar="FILE.png",
                        help="critical derailment speed against radius (.png, .pdf or .svg)")
    _staircase_args(parser)
    _track_args(parser, "along the staircase's line, the same for every case", cant=False)
    _wind_args(parser)

    def run(args):
        from ..methods import sweep as sw
        plot = _plot_path(args)
        radii = _floats(args.radii, "--radii")
        for r in radii:
            from ..vehicle.simulate import RADIUS_RANGE
            check_range("curve radius", r, *RADIUS_RANGE, "m")
        cants = _floats(args.cants_mm, "--cants-mm")
        for c in cants:
            check_range("cant", c, *CANT_RANGE_MM, "mm")
        frictions = _floats(args.frictions, "--frictions") if args.frictions else [args.friction]
        wheels = args.wheels.split(",") if args.wheels else [args.wheel]
        sets = args.vehicle_sets.split(",") if args.vehicle_sets else [args.vehicle_set]
        for s in sets:
            vehicle_parameters(s)
        cases = sw.cases(radii, cants, frictions, wheels, sets)
        res = sw.sweep(cases, _trial_scenario(args), _staircase(args), refine=not args.no_refine,
                       tolerance_kmh=args.tolerance_kmh, workers=args.workers, scheduler=args.scheduler,
                       progress=not args.json)
        if plot:
            plotting.critical_speed_figure(res, plot)
        _emit(args, res, "\n".join(_trial_line(d) for d in res))
    return run


def cwc_command(parser):
    """`railderail cwc`: the characteristic wind curves (methods.cwc)."""
    _common(parser)
    parser.add_argument("--speeds-kmh", default="200,220,240,260,280,300,320,340,360",
                        help="vehicle speeds (km/h), comma-separated")
    parser.add_argument("--cases", default="straight,1.0",
                        help="curves of the figure, comma-separated: `straight`, or an uncompensated lateral "
                             "acceleration a_q (m/s^2) on a curve of Table 2's cant; default %(default)s")
    parser.add_argument("--tolerance-m-s", type=float, default=0.25, help="bisection tolerance (m/s)")
    parser.add_argument("--track", default="rigid", choices=TRACK_MODELS, help="track model; default %(default)s")
    parser.add_argument("--workers", type=int, default=None, help="local processes (default: CPU count)")
    parser.add_argument("--scheduler", default=None, help="address of a Dask distributed scheduler")
    parser.add_argument("--plot", metavar="FILE.png", help="the CWC figure (.png, .pdf or .svg)")

    def run(args):
        from ..methods import cwc as c
        plot = _plot_path(args)
        speeds = _floats(args.speeds_kmh, "--speeds-kmh")
        cases = []
        for v in (v.strip() for v in args.cases.split(",") if v.strip()):
            try:
                cases.append(None if v == "straight" else float(v))
            except ValueError:
                raise ValueError(f"--cases: {v!r} is neither `straight` nor an uncompensated acceleration in "
                                 "m/s^2") from None
        res = c.cwc(base_scenario(args), speeds, cases, tolerance=args.tolerance_m_s, workers=args.workers,
                    scheduler=args.scheduler, progress=not args.json)
        if plot:
            plotting.cwc_figure(res.curves(), plot, c.UNLOADING_LIMIT)
        lines = [f"{label}: " + ", ".join(f"{v:g} km/h {u:.1f} m/s" for v, u in zip(s, w))
                 for label, (s, w) in res.curves().items()]
        _emit(args, res.as_dict(), "\n".join(lines))
    return run


def report_command(parser):
    parser.add_argument("--out", default="report", help="output directory")
    parser.add_argument("--quick", action="store_true", help="fewer speeds and radii (a smoke run)")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--vehicle-set", default="hs19", choices=VEHICLE_SETS,
                        help="suspension parameter set of every run (default %(default)s)")
    parser.add_argument("--no-sensitivity", action="store_true",
                        help="leave out the sensitivity table (a trial per uncertain value: the dearest section)")

    def run(args):
        from ..methods.report import write_report
        path = write_report(args.out, quick=args.quick, workers=args.workers, vehicle_set=args.vehicle_set,
                            sensitivity=not args.no_sensitivity)
        print(f"report written to {path}")
    return run


def real_track_command(parser):
    """The rows go to OUT/real-track.jsonl as each track's radii finish; a second run with the same --out keeps
    the rows it finds and runs only the missing cases, so that a long study can be stopped and resumed."""
    parser.add_argument("--out", default="report", help="output directory (default %(default)s)")
    parser.add_argument("--tracks", default="rigid,elastic", help="track models, comma-separated")
    parser.add_argument("--spectra", default="erri-low,erri-high",
                        help=f"irregularity spectra, comma-separated ({', '.join(sp.SPECTRA)})")
    parser.add_argument("--seeds", default="1,2,3", help="irregularity seeds, comma-separated")
    parser.add_argument("--radii", default="800,1000,1200,1400,1600,1800", help="curve radii (m), comma-separated")
    parser.add_argument("--no-sharp", action="store_true", help="leave out the sharp-curve case")
    parser.add_argument("--workers", type=int, default=None, help="local processes (default: CPU count)")
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")

    def run(args):
        from ..methods import real_track as rt
        from ..parameters import TRACK_MODELS
        from ..vehicle.simulate import RADIUS_RANGE
        models = [m for m in args.tracks.split(",") if m]
        for m in models:
            if m not in TRACK_MODELS:
                raise ValueError(f"--tracks: {m!r} is not one of {', '.join(TRACK_MODELS)}")
        spectra = [s for s in args.spectra.split(",") if s]
        for s in spectra:
            if s not in sp.SPECTRA:
                raise ValueError(f"--spectra: {s!r} is not one of {', '.join(sp.SPECTRA)}")
        try:
            seeds = [ir.check_seed(int(v)) for v in args.seeds.split(",") if v.strip()]
        except ValueError as e:
            raise ValueError(str(e) if "seed" in str(e) else
                             f"--seeds {args.seeds!r} is not a comma-separated list of integers") from None
        if not (models and spectra and seeds):
            raise ValueError("--tracks, --spectra and --seeds need at least one value each")
        radii = [check_range("curve radius", r, *RADIUS_RANGE, "m") for r in _floats(args.radii, "--radii")]
        os.makedirs(args.out, exist_ok=True)
        cache = os.path.join(args.out, "real-track.jsonl")
        known = [json.loads(line) for line in open(cache)] if os.path.exists(cache) else []

        def done(row):
            with open(cache, "a") as f:
                f.write(jsonout.dumps(row) + "\n")

        tracks = rt.tracks(models, spectra, seeds)
        rows = rt.study(tracks, radii, workers=args.workers, progress=not args.json, known=known, done=done)
        sharp = [] if args.no_sharp else rt.sharp_curve(rt.tracks(models, spectra[-1:], seeds[:1]),
                                                        workers=args.workers, progress=not args.json,
                                                        known=known, done=done)
        summaries = rt.summary(rows)
        plotting.real_track_figure(summaries, os.path.join(args.out, "real_track.png"))
        with atomic_write(os.path.join(args.out, "real-track.md")) as f:
            f.write("\n".join(rt.markdown(rows, sharp, "real_track.png")) + "\n")
        if args.json:
            print(jsonout.dumps(dict(summary=summaries, sharp_curve=sharp), indent=1))
        else:
            print(f"real-track section written to {os.path.join(args.out, 'real-track.md')}")
    return run
