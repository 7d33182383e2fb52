"""`railderail bench`: the project's one benchmark; it prints figures, it is never a test.

Each group is a function returning {key: value} (this package's groups are in `railderail_sim.bench`);
groups are run in the order of `groups()` (or those named with --only) and their figures printed as a
table, or as one JSON object with --json. Timings are taken after compilation (numba's first call is
timed separately as `compile_s`).
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
                run_group = getattr(importlib.import_module(module), function)
            except ModuleNotFoundError as error:
                print(f"bench: group {name} is not available ({error})", file=sys.stderr)
                continue
            if not args.json:
                print(f"[{name}]", file=sys.stderr)
            for key, value in run_group().items():
                figures[key] = value
                if not args.json:
                    print(f"  {key:32s} {value:.6g}" if isinstance(value, float) else f"  {key:32s} {value}")
        if args.json:
            print(jsonout.dumps(figures, indent=1))
    return run
