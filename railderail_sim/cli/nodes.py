"""`railderail simulator-params`: the simulator node's parameter file (every parameter of
`railderail_sim.node.PARAMETERS` with its default, unit, meaning and accepted values).

The shipped copy, railderail_sim/config/simulator.yaml (package data, and installed to
share/railderail/config/ for ROS users and the launch file), is this command's output: a test
compares them, so that the file cannot drift from the node's declarations. Regenerate it after a
change of the table with REGENERATE.
"""
from __future__ import annotations

import argparse
import sys
from importlib.resources import files
from pathlib import Path

from ..atomic import atomic_write

SHIPPED = files("railderail_sim") / "config" / "simulator.yaml"
REGENERATE = "railderail simulator-params --out railderail_sim/config/simulator.yaml"


def simulator_parameter_file():
    """The text of the simulator's parameter file: the node's defaults."""
    from ..ros import node_parameters
    from ..ros.node import PARAMETERS

    header = ["Parameters of the railderail simulator node (railderail_simulator), each at its default.",
              "A ROS 2 parameter file:  railderail-simulator --ros-args --params-file THIS_FILE.yaml",
              f"Made by `{REGENERATE}` from the node's parameter table (railderail_sim/ros/node.py);",
              "copy it and change the values you need. Read-only parameters cannot change while the node runs."]
    return node_parameters.parameter_file("railderail_simulator", PARAMETERS, header)


def simulator_params_command(parser: argparse.ArgumentParser):
    parser.add_argument("--out", metavar="FILE.yaml", help="write the file here (default: print it)")

    def run(args):
        text = simulator_parameter_file()
        if args.out is None:
            sys.stdout.write(text)
            return
        if not args.out.endswith((".yaml", ".yml")):
            raise ValueError(f"--out {args.out}: the parameter file's name must end in .yaml")
        if not Path(args.out).parent.is_dir():
            raise ValueError(f"--out {args.out}: its folder {Path(args.out).parent} does not exist")
        with atomic_write(args.out) as handle:
            handle.write(text)
        print(f"wrote {args.out}", file=sys.stderr)
    return run
