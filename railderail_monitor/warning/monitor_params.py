"""The monitor's parameter file and `railderail monitor-params`.

The monitor node's thresholds are ROS 2 parameters (`warning.limits.Limits`). Their defaults are those of
the parameter file shipped with the package, railderail_monitor/config/monitor.yaml (installed as
package data and to share/railderail/config/): the standard `railderail_monitor: ros__parameters:`
layout, every parameter with a comment giving its unit, meaning and source. The four values that
depend on the car and the profiles (wheel lift levels from the flange height, Nadal's limit, the
static wheel load) were computed once from the model by

    railderail monitor-params --out railderail_monitor/config/monitor.yaml

which is also how a user makes the file of another wheel, rail, friction or vehicle set and gives it
to the node: `railderail-monitor --ros-args --params-file FILE.yaml`. A test checks that the shipped
file is what the model gives today. The node reads the shipped file with PyYAML (no model, no numba).
"""
from __future__ import annotations

import argparse
import math
import sys
from dataclasses import fields
from pathlib import Path

from railderail_sim.atomic import atomic_write

from .limits import NODE, SIGNALS, SIGNALS_MEANING, Limits, limits_for_model, model_basis

REGENERATE = "railderail monitor-params --out railderail_monitor/config/monitor.yaml"


def limits_of_car(wheel="lm", rail="uic60", friction=0.3, vehicle_set="hs19"):
    """(Limits, model basis) of the car of `vehicle_set` with these profiles and friction (builds the
    model's rigid-contact geometry: imports the numba core)."""
    from railderail_sim.parameters import ContactParameters, TrackParameters, vehicle_parameters
    from railderail_sim.vehicle.assemble import build_model

    contact = ContactParameters(wheel_profile=wheel, friction_coefficient=friction,
                                contact_geometry="online")     # the limits need no contact table
    try:
        model = build_model(vehicle_parameters(vehicle_set), TrackParameters(rail_profile=rail), contact)
    except OSError as error:        # an unreadable profile file
        raise ValueError(f"{error.filename}: cannot read it ({error.strerror or error})") from None
    return limits_for_model(model, friction), model_basis(model)


def _number(value):
    return ".nan" if math.isnan(value) else repr(float(value))


def parameter_file(limits, basis, command):
    """The text of the monitor's parameter file for `limits`, made from the model `basis` by `command`."""
    lines = [
        f"# Parameters of the railderail monitor node ({NODE}): the thresholds of its derailment criteria.",
        "# A ROS 2 parameter file:  railderail-monitor --ros-args --params-file THIS_FILE.yaml",
        f"# Made by `{command}`:",
        "# make a new file for another car rather than editing the model-dependent values by hand.",
        f"# The model: flange height {basis['flange_height'] * 1e3:.3f} mm, largest contact angle "
        f"{math.degrees(basis['max_contact_angle']):.2f} deg, static wheel load {basis['static_wheel_load']:.2f} N,",
        f"# largest flange angle {math.degrees(basis['flange_angle']):.2f} deg over a flange face of "
        f"{basis['flange_length'] * 1e3:.2f} mm.",
        "# NaN (.nan) disables a level. Units SI; '-' = dimensionless.",
        f"{NODE}:",
        "  ros__parameters:",
        f"    # -: {SIGNALS_MEANING}. Accepted: one of {', '.join(SIGNALS)}. Read-only.",
        f'    signals: "{SIGNALS[0]}"',
    ]
    for f in fields(Limits):
        meta = f.metadata
        lines.append(f"    # {meta['unit'] or '-'}: {meta['meaning']}. Source: {meta['source']}.")
        lines.append(f"    {f.name}: {_number(getattr(limits, f.name))}")
    return "\n".join(lines) + "\n"


def command(parser: argparse.ArgumentParser):
    """`railderail monitor-params`: the monitor's parameter file of a wheel, rail, friction and car."""
    from railderail_sim.parameters import VEHICLE_SETS

    parser.add_argument("--out", metavar="FILE.yaml", help="write the file here (default: print it)")
    parser.add_argument("--wheel", default="lm", metavar="NAME_OR_FILE",
                        help="wheel profile: lm, s1002 or a profile file (default %(default)s)")
    parser.add_argument("--rail", default="uic60", metavar="NAME_OR_FILE",
                        help="rail profile: uic60, uic60-mbench or a profile file (default %(default)s)")
    parser.add_argument("--friction", type=float, default=0.3, metavar="MU",
                        help="wheel-rail friction coefficient of Nadal's limit (default %(default)s)")
    parser.add_argument("--vehicle-set", default="hs19", choices=VEHICLE_SETS,
                        help="vehicle parameter set: its static wheel load (default %(default)s)")

    def run(args):
        if args.out is not None:
            if not args.out.endswith((".yaml", ".yml")):
                raise ValueError(f"--out {args.out}: the parameter file's name must end in .yaml")
            if not Path(args.out).parent.is_dir():
                raise ValueError(f"--out {args.out}: its folder {Path(args.out).parent} does not exist")
        made_by = (f"railderail monitor-params --wheel {args.wheel} --rail {args.rail} "
                   f"--friction {args.friction:g} --vehicle-set {args.vehicle_set}")
        text = parameter_file(*limits_of_car(args.wheel, args.rail, args.friction, args.vehicle_set), made_by)
        if args.out is None:
            sys.stdout.write(text)
        else:
            with atomic_write(args.out) as handle:
                handle.write(text)
            print(f"wrote {args.out}", file=sys.stderr)
    return run
