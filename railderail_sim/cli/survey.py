"""Subcommand survey: the physical speed limits of a line file's curves, defects and wind sites
(`methods.survey`; docs/supervision.md, "The survey")."""
from pathlib import Path

from .. import jsonout, plotting
from .methods import _common, _floats, _plot_path, base_scenario

DEFAULT_CACHE = "survey-cache"


def _text(values):
    return ",".join(f"{v:g}" for v in values)


def survey_command(parser):
    from ..methods import survey as sv, survey_profile
    from ..parameters import VEHICLE_SETS
    parser.add_argument("line", metavar="LINE.yaml",
                        help="a line file (docs/supervision.md, The line file) or a shipped line's name: table2, "
                             "hsr-300-demo")
    _common(parser)
    parser.add_argument("--frictions", default=None,
                        help=f"wheel-rail friction coefficients of the cases, comma-separated; default "
                             f"{_text(sv.DEFAULT_FRICTIONS)}")
    parser.add_argument("--vehicle-sets", default=None,
                        help=f"stand-in parameter sets of the cases, comma-separated; default {','.join(VEHICLE_SETS)} "
                             "(--vehicle-set and --friction give the reference case of the crosswind and fault tables)")
    parser.add_argument("--wind-speeds-m-s", default=None,
                        help="steady crosswinds from the inside of each curve for its crosswind table (m/s), "
                             f"comma-separated, or none; default {_text(sv.DEFAULT_WIND_SPEEDS_M_S)}")
    parser.add_argument("--faults", default=",".join(sv.SHIPPED_FAULTS),
                        help="faults of each curve's fault table (NAME@LOCATION, see --fault), comma-separated, or "
                             "none; default %(default)s")
    parser.add_argument("--cwc-speeds-kmh", default=None,
                        help="vehicle speeds of each wind site's characteristic wind curve (km/h); default "
                             f"{_text(sv.DEFAULT_CWC_SPEEDS_KMH)}")
    parser.add_argument("--tolerance-kmh", type=float, default=None,
                        help="bisection tolerance of the critical derailment and defect speeds (km/h); default 1")
    parser.add_argument("--start-kmh", type=float, default=sv.Staircase().start_kmh,
                        help="the staircase's entry speed (km/h); default %(default)s")
    parser.add_argument("--top-kmh", type=float, default=sv.Staircase().top_kmh,
                        help="the staircase's top speed (km/h): a curve that does not derail up to it reports it as "
                             "its limit; default %(default)s")
    parser.add_argument("--quick", action="store_true",
                        help="fewer cases: frictions 0.2 and 0.6, the reference set (--vehicle-set), one crosswind "
                             "(20 m/s), one characteristic wind speed (300 km/h), 4 km/h tolerance (the options given "
                             "override it)")
    parser.add_argument("--workers", type=int, default=None, help="local processes (default: CPU count)")
    parser.add_argument("--scheduler", default=None, help="address of a Dask distributed scheduler")
    parser.add_argument("--cache", default=DEFAULT_CACHE,
                        help="folder of the cases' results, keyed on their inputs and the sources: a second survey "
                             "reuses them and an interrupted one resumes; default %(default)s")
    parser.add_argument("--no-cache", action="store_true", help="compute every case, keep nothing")
    parser.add_argument("--out", metavar="FILE.json", help="also write the result's JSON to this file")
    parser.add_argument("--plot", metavar="FILE.png",
                        help="the speed profile along the line: permitted, critical derailment and safe speeds "
                             "(.png, .pdf or .svg)")

    def run(args):
        from ..line.file import load_line
        plot = _plot_path(args)
        if args.out and not Path(args.out).expanduser().resolve().parent.is_dir():
            raise ValueError(f"--out {args.out!r}: its folder does not exist")
        line = load_line(args.line)
        chosen = dict(sv.Settings().__dict__)
        if args.quick:
            chosen.update(sv.QUICK, vehicle_sets=(args.vehicle_set,))
        for key, text in (("frictions", args.frictions), ("wind_speeds_m_s", args.wind_speeds_m_s),
                          ("cwc_speeds_kmh", args.cwc_speeds_kmh)):
            if text is not None:
                chosen[key] = () if text.strip() == "none" else tuple(_floats(text, "--" + key.replace("_", "-")))
        if args.vehicle_sets is not None:
            chosen["vehicle_sets"] = tuple(s for s in args.vehicle_sets.split(",") if s)
        if args.tolerance_kmh is not None:
            chosen["tolerance_kmh"] = args.tolerance_kmh
        settings = sv.Settings(**dict(chosen, reference_set=args.vehicle_set, reference_friction=args.friction,
                                      faults=() if args.faults.strip() == "none" else
                                      tuple(f for f in args.faults.split(",") if f),
                                      start_kmh=args.start_kmh, top_kmh=args.top_kmh)).validated()
        base = base_scenario(args)
        result = sv.survey(line, base, settings, workers=args.workers, scheduler=args.scheduler,
                           progress=not args.json, cache=None if args.no_cache else args.cache)
        if args.out:
            result.save(args.out)
        if plot:
            plotting.survey_figure(result, survey_profile.permitted_profile(result),
                                   survey_profile.survey_targets(result), plot)
        print(jsonout.dumps(result.as_dict(), indent=1) if args.json else _human(result))
    return run


def _speed(row):
    v = row["critical_derailment_speed_kmh"]
    return f"{v:.1f}" if row["derailed"] else f">{v:.0f}"


def _human(result):
    lines = [f"line {result.line['name']}: {result.line['length_m'] / 1000:g} km, line speed "
             f"{result.line['line_speed_kmh']:g} km/h; critical derailment speed = the lowest over "
             f"{len(result.settings['frictions'])} frictions x {len(result.settings['vehicle_sets'])} parameter sets",
             "curve  km          R (m)  cant  permitted  critical (spread, case)       margins intact   safe   "
             "wind, faults (change)"]
    for c in result.curves:
        changes = ", ".join([f"{w['wind_speed_m_s']:g} m/s {_change(w)}" for w in c["crosswind"]] +
                            [f"{f['fault']} {_change(f)}" for f in c["faults"]])
        case = c["lowest_case"]
        lines.append(f"{c['index']:5d}  {c['start_m'] / 1000:5.2f}-{c['end_m'] / 1000:5.2f} {c['radius_m']:6.0f} "
                     f"{c['cant_mm']:4.0f}  {c['permitted_speed_kmh']:9.0f}  {_speed(c):>6} ({c['spread_kmh']:4.1f}, "
                     f"{case['vehicle_set']} mu {case['friction']:g})  {c['margins_intact_up_to_kmh']:14.1f}  "
                     f"{c['safe_speed_kmh']:5.1f}   {changes}")
    for d in result.defects:
        broken = d["first_broken"]
        lines.append(f"defect {d['index']} at {d['position_m'] / 1000:.3f} km, {d['kind']} {d['size_mm']:g} mm: "
                     f"margins intact up to {d['margins_intact_up_to_kmh']:.1f} km/h, safe speed "
                     f"{d['safe_speed_kmh']:.1f} km/h"
                     + (f" (first broken: {broken['margin']} at {broken['speed_kmh']:.1f} km/h)" if broken else ""))
    for w in result.wind_sites:
        points = ", ".join(f"{v:g} km/h {u:.1f} m/s" if u is not None and u == u else f"{v:g} km/h -"
                           for v, u in zip(w["curve"]["speed_kmh"], w["curve"]["wind_speed_m_s"]))
        lines.append(f"wind site {w['name']} at {w['position_m'] / 1000:.3f} km ({w['track']}): {points}")
    return "\n".join(lines)


def _change(row):
    c = row["change_kmh"]
    return f"{c:+.1f}" if row["derailed"] else f"{c:+.1f} (no derailment)"
