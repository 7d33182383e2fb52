"""`railderail contact-geometry` and `railderail contact-case`: parse, call the library, print.

contact-geometry: `methods.contact_geometry` of a wheel/rail pair (`methods.wheel_rail_pair`);
contact-case: `methods.contact_case`, one loaded wheelset. --json prints the result's `as_dict()` through
the project's JSON encoder (SI units), --plot writes the figure (`plotting`), otherwise a short text.
Bad input raises ValueError naming the value and its accepted range: one line, exit status 2.
"""
from __future__ import annotations

import argparse

from .. import jsonout, plotting
from ..parameters import ContactParameters, TrackParameters, VehicleParameters


def _pair_arguments(parser):
    parser.add_argument("--wheel", default="lm", metavar="NAME_OR_FILE",
                        help="wheel profile: lm, s1002 or a file (default %(default)s)")
    parser.add_argument("--rail", default="uic60", metavar="NAME_OR_FILE",
                        help="rail profile: uic60, uic60-mbench or a file (default %(default)s)")
    parser.add_argument("--gauge-mm", type=float, default=TrackParameters.gauge * 1e3,
                        help="track gauge, measured 14 mm below the rail top (default %(default)s mm)")
    parser.add_argument("--inclination", default="1/40",
                        help="rail inclination as a slope, e.g. 1/40 or 0 (default %(default)s)")
    parser.add_argument("--back-to-back-mm", type=float, default=ContactParameters.back_to_back * 1e3,
                        help="wheelset back-to-back distance; rolling circles 70 mm from the back faces "
                             "(default %(default)s mm)")
    parser.add_argument("--radius-m", type=float, default=VehicleParameters.rolling_radius,
                        help="nominal rolling radius (default %(default)s m)")
    parser.add_argument("--friction", type=float, default=ContactParameters.friction_coefficient,
                        help="friction coefficient (default %(default)s)")
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")


def _pair(args, **more):
    from ..methods.wheel_rail_pair import build_pair
    return build_pair(args.wheel, args.rail, gauge_mm=args.gauge_mm, inclination=args.inclination,
                      back_to_back_mm=args.back_to_back_mm, radius_m=args.radius_m, friction=args.friction,
                      **more)


def compute_and_print(args, compute, draw):
    """Check the plot file, compute the result, draw it, print it as JSON (--json) or as text."""
    with _one_line_errors():
        plot = plotting.checked_path(args.plot) if args.plot is not None else None
        result = compute()
        if plot is not None:
            draw(result, plot)
    if args.json:
        obj = result.as_dict()
        if plot is not None:
            obj["plot"] = str(plot)
        print(jsonout.dumps(obj))
    else:
        print(result.text())
        if plot is not None:
            print(f"  plot written to {plot}")


class _one_line_errors:
    """Context manager: a multi-line ValueError message becomes one line."""

    def __enter__(self):
        return self

    def __exit__(self, kind, error, tb):
        if kind is not None and issubclass(kind, ValueError) and "\n" in str(error):
            raise ValueError(" ".join(str(error).split())) from None
        return False


def geometry_command(parser: argparse.ArgumentParser):
    _pair_arguments(parser)
    parser.add_argument("--y-max-mm", type=float, default=12.0,
                        help="table range: lateral shift -y..y (default %(default)s mm)")
    parser.add_argument("--step-mm", type=float, default=0.1, help="table step (default %(default)s mm)")
    parser.add_argument("--amplitude-mm", type=float, default=3.0,
                        help="amplitude of the equivalent conicity (default %(default)s mm, EN 15302)")
    parser.add_argument("--plot", metavar="FILE.png", help="write the contact-geometry figure")

    def run(args):
        from ..methods.contact_geometry import contact_geometry
        compute_and_print(args, lambda: contact_geometry(_pair(args), y_max_mm=args.y_max_mm, step_mm=args.step_mm,
                                            amplitude_mm=args.amplitude_mm),
             plotting.contact_geometry_figure)
    return run


def _pair_of_loads(text):
    """'10,10' -> (10.0, 10.0): the argument of --wheel-loads-kn."""
    parts = text.split(",")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not LEFT,RIGHT in kN, e.g. 10,10") from None
    if len(values) != 2:
        raise argparse.ArgumentTypeError(f"{text!r} has {len(values)} values; give LEFT,RIGHT in kN, e.g. 10,10")
    return values


def case_command(parser: argparse.ArgumentParser):
    from ..methods.wheel_rail_pair import MODELS, static_wheelset_load
    _pair_arguments(parser)
    parser.add_argument("--lateral-mm", type=float, default=0.0,
                        help="wheelset lateral shift, + left (default %(default)s mm)")
    parser.add_argument("--yaw-mrad", type=float, default=0.0,
                        help="wheelset yaw angle, + heading to the left (default %(default)s mrad)")
    parser.add_argument("--roll-mrad", type=float, default=None,
                        help="wheelset roll (default: the rigid-contact roll at this shift and yaw)")
    parser.add_argument("--load-kn", type=float, default=None,
                        help=f"vertical wheelset load (default: the CRH3 static axle load, "
                             f"{static_wheelset_load() / 1e3:.1f} kN)")
    parser.add_argument("--wheel-loads-kn", type=_pair_of_loads, default=None, metavar="LEFT,RIGHT",
                        help="the vertical force of each wheel on its rail (kN), as the Manchester benchmark "
                             "prescribes them; vertical position and roll follow (instead of --load-kn and "
                             "--roll-mrad)")
    parser.add_argument("--speed-kmh", type=float, default=300.0,
                        help="rolling speed (default %(default)s km/h)")
    parser.add_argument("--youngs-gpa", type=float, default=ContactParameters.youngs_modulus / 1e9,
                        help="Young's modulus of wheel and rail (default %(default)s GPa)")
    parser.add_argument("--poisson", type=float, default=ContactParameters.poisson_ratio,
                        help="Poisson's ratio (default %(default)s)")
    parser.add_argument("--contact", choices=tuple(MODELS), default="hertz",
                        help="hertz (Hertz + SHE), fastsim (Hertz + FASTSIM), discrete (Kik-Piotrowski + "
                             "SHE), halfspace (discrete + exact half-space patches), exact (hertz + exact "
                             "half-space patches + Kalker's exact rolling on them, beside SHE, Polach and "
                             "FASTSIM); default %(default)s")
    parser.add_argument("--spin", choices=("nominal", "free"), default="nominal",
                        help="wheelset spin: nominal = v / r0 as in the vehicle model (default), free = the "
                             "spin at which the total longitudinal force vanishes")
    parser.add_argument("--pitch-rate-rad-s", type=float, default=None, metavar="W",
                        help="prescribed angular velocity of the wheelset about its axle, + rolling forward "
                             "(rad/s; instead of --spin)")
    parser.add_argument("--grid", type=int, default=64,
                        help="half-space grid, elements per direction (default %(default)s)")
    parser.add_argument("--plot", metavar="FILE.png", help="draw the contact patches of both wheels")

    def run(args):
        from ..methods.contact_case import contact_case
        compute_and_print(args, lambda: contact_case(_pair(args, youngs_gpa=args.youngs_gpa, poisson=args.poisson,
                                              model=args.contact),
                                        lateral_mm=args.lateral_mm, yaw_mrad=args.yaw_mrad,
                                        roll_mrad=args.roll_mrad, load_kn=args.load_kn,
                                        wheel_loads_kn=args.wheel_loads_kn, speed_kmh=args.speed_kmh,
                                        grid=args.grid, spin=args.spin, pitch_rate_rad_s=args.pitch_rate_rad_s),
             plotting.contact_case_figure)
    return run
