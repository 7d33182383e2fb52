"""`railderail bench`: the project's one benchmark; it prints figures, it is never a test.

Each group is a function returning {key: value}; groups are run in the order of GROUPS (or those named
with --only) and their figures printed as a table, or as one JSON object with --json. Timings are taken
after compilation (numba's first call is timed separately as `compile_s`).
"""
from __future__ import annotations

import argparse
import importlib
import json
import sys

GROUPS = {
    "contact": "railderail_sim.contact.benchmark:run",
    "vehicle": "railderail_sim.vehicle.benchmark:run",
    "methods": "railderail_sim.methods.benchmark:run",
    "ros": "railderail_monitor.benchmark:run",
}


def command(parser: argparse.ArgumentParser):
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--only", default="", help=f"comma-separated groups of {', '.join(GROUPS)}")

    def run(args):
        names = [n for n in args.only.split(",") if n] or list(GROUPS)
        unknown = [n for n in names if n not in GROUPS]
        if unknown:
            raise ValueError(f"unknown benchmark group(s) {', '.join(unknown)}; choose from {', '.join(GROUPS)}")
        figures = {}
        for name in names:
            module, _, function = GROUPS[name].partition(":")
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
            print(json.dumps(figures, indent=1))
    return run
