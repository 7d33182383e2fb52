"""`railderail climb`: the wheel-climb rig (`methods.climb`): parse, call the library, print.

One attack angle (--attack-angle-mrad), or the curve over attack angles (--sweep-attack-angle-mrad), for one
friction coefficient or, when sweeping, several (--friction 0.3,0.5). --json prints one JSON object (SI
units) through the project's encoder, --plot writes the run's L/V and lift against distance, or for a sweep
the L/V at the climb and the climb distance against the attack angle.
"""
from __future__ import annotations

import argparse

from .. import plotting
from ..vehicle.assemble import CREEP_MODELS
from .contact import compute_and_print


def _numbers(text, option):
    try:
        values = [float(v) for v in str(text).split(",") if v.strip()]
    except ValueError:
        raise ValueError(f"{option} {text!r} is not a comma-separated list of numbers") from None
    if not values:
        raise ValueError(f"{option} is empty")
    return values


def climb_command(parser: argparse.ArgumentParser):
    from ..methods import climb as c
    from ..parameters import VehicleParameters
    parser.add_argument("--wheel", default="lm", metavar="NAME_OR_FILE",
                        help="wheel profile: lm, s1002 or a file (default %(default)s)")
    parser.add_argument("--rail", default="uic60", metavar="NAME_OR_FILE",
                        help="rail profile: uic60, uic60-mbench or a file (default %(default)s)")
    parser.add_argument("--attack-angle-mrad", type=float, default=10.0,
                        help="attack angle, the wheelset's yaw toward the flanging rail (mrad, "
                             f"{c.ATTACK_ANGLE_MRAD[0]:g}-{c.ATTACK_ANGLE_MRAD[1]:g}; default %(default)s)")
    parser.add_argument("--sweep-attack-angle-mrad", default=None, metavar="A1,A2,...",
                        help="run every attack angle of the list (mrad), e.g. "
                             + ",".join(f"{a:g}" for a in c.DEFAULT_SWEEP_MRAD))
    parser.add_argument("--friction", default="0.3",
                        help="wheel-rail friction coefficient, 0-1 (0: a frictionless flange); when sweeping a "
                             "comma-separated list (default %(default)s)")
    parser.add_argument("--creep", choices=tuple(CREEP_MODELS), default=c.DEFAULT_CREEP,
                        help="creep law (default %(default)s: it bounds the lateral force of the flange's large "
                             "spin, which she saturates like a creepage; docs/climb.md)")
    parser.add_argument("--speed-kmh", type=float, default=c.DEFAULT_SPEED_KMH,
                        help=f"rolling speed (km/h, {c.SPEED_KMH[0]:g}-{c.SPEED_KMH[1]:g}; default %(default)s)")
    parser.add_argument("--wheel-load-kn", type=float, default=None,
                        help="vertical load per wheel (kN; default the CRH3 static wheel load, "
                             f"{VehicleParameters().static_wheel_load / 1e3:.1f} kN)")
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    parser.add_argument("--plot", metavar="FILE.png",
                        help="L/V and lift against distance; with a sweep, L/V at the climb and climb distance "
                             "against the attack angle (.png, .pdf or .svg)")

    def run(args):
        frictions = _numbers(args.friction, "--friction")
        options = dict(wheel=args.wheel, rail=args.rail, speed_kmh=args.speed_kmh, creep=args.creep,
                       wheel_load_kn=args.wheel_load_kn)
        if args.sweep_attack_angle_mrad is not None:
            angles = _numbers(args.sweep_attack_angle_mrad, "--sweep-attack-angle-mrad")
            compute_and_print(args, lambda: c.climb_sweep(angles, frictions, **options), plotting.climb_sweep_figure)
            return
        if len(frictions) > 1:
            raise ValueError(f"--friction {args.friction!r}: several friction coefficients need "
                             "--sweep-attack-angle-mrad")
        compute_and_print(args, lambda: c.climb(attack_angle_mrad=args.attack_angle_mrad, friction=frictions[0],
                                                **options), plotting.climb_figure)
    return run
