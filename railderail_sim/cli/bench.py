"""`railderail bench`: the project's one benchmark; it prints figures, it is never a test.

Each group is a function returning {key: value} (this package's groups are in `railderail_sim.bench`);
groups are run in the order of `groups()` (or those named with --only) and their figures printed as a
table, or as one JSON object with --json. Timings are taken after compilation (numba's first call is
timed separately as `compile_s`). A group's module may hold the project's targets for its figures,
`TARGETS = {key: (at least, why a figure falls short)}`: the table prints each figure against its target
and, where it falls short, by how much and why (docs/performance.md); the JSON holds the figures only.
"""
from __future__ import annotations

import argparse
import importlib
import sys

from .. import jsonout

GROUPS = {
    "contact": "railderail_sim.bench.contact:run",
    "vehicle": "railderail_sim.bench.vehicle:run",
    "methods": "railderail_sim.bench.methods:run",
    "assessment": "railderail_sim.bench.assessment:run",
}
ENTRY_POINTS = "railderail.bench"    # groups of the packages built on this one (railderail_monitor: "ros")


def groups():
    """{name: "module:function"}: GROUPS, then those registered under ENTRY_POINTS."""
    from importlib.metadata import entry_points

    found = dict(GROUPS)
    for point in sorted(entry_points(group=ENTRY_POINTS), key=lambda p: p.name):
        found.setdefault(point.name, point.value)
    return found


def against(value, target, why):
    """A figure's column beside its target (at least `target`): met, or short by how much and why."""
    if not value >= target:          # NaN (not measured here) is not met either
        return f"   target {target:g}: short by {target / value:.2f} x ({why})" if value > 0.0 else \
            f"   target {target:g}: not measured ({why})"
    return f"   target {target:g}: met"


def command(parser: argparse.ArgumentParser):
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    known = groups()
    parser.add_argument("--only", default="", help=f"comma-separated groups of {', '.join(known)}")
    parser.add_argument("--profile", action="store_true",
                        help="instead of the groups: where the vehicle core's time goes (docs/performance.md)")
    parser.add_argument("--cases", default="", help="with --profile: comma-separated cases (default: all)")

    def run(args):
        if args.profile:
            from ..bench import profile
            result = profile.profile([n for n in args.cases.split(",") if n])
            print(jsonout.dumps(result, indent=1) if args.json else profile.text(result))
            return
        names = [n for n in args.only.split(",") if n] or list(known)
        unknown = [n for n in names if n not in known]
        if unknown:
            raise ValueError(f"unknown benchmark group(s) {', '.join(unknown)}; choose from {', '.join(known)}")
        figures = {}
        for name in names:
            module, _, function = known[name].partition(":")
            try:
                group = importlib.import_module(module)
            except ModuleNotFoundError as error:
                print(f"bench: group {name} is not available ({error})", file=sys.stderr)
                continue
            if not args.json:
                print(f"[{name}]", file=sys.stderr)
            targets = getattr(group, "TARGETS", {})
            for key, value in getattr(group, function)().items():
                figures[key] = value
                if not args.json:
                    print(f"  {key:40s} {value:.6g}{against(value, *targets[key]) if key in targets else ''}"
                          if isinstance(value, float) else f"  {key:40s} {value}")
        if args.json:
            print(jsonout.dumps(figures, indent=1))
    return run
