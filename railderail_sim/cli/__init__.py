"""The `railderail` command (`python -m railderail_sim.cli` runs it too).

The package holds the command-line layer only: each subcommand module (`contact`, `methods`, `bench`)
parses its arguments, calls the library and prints; this file stays free of heavy imports.

Subcommands come from command tables: this package's COMMANDS below, and any other package's table
registered under the entry-point group `railderail.commands` (railderail_monitor registers the ROS
commands in its `commands.py`), so that this package never imports the packages built on it. To add
a subcommand, write a function

    def my_command(parser: argparse.ArgumentParser) -> Callable[[argparse.Namespace], int | None]

in any module: it adds the subcommand's arguments to `parser` and returns the function that runs
the subcommand on the parsed arguments (returning an exit status; None means 0). Then add a line
`Command("name", "one-line help", "module.path:my_command")` to a table. Only the chosen
subcommand's module is imported, so `railderail --help` stays fast whatever the modules import.

Errors: bad arguments, and a ValueError raised while running (bad input found by the API layer),
are printed as one line `railderail: error: <message>` on stderr with exit status 2, no traceback.
"""
from __future__ import annotations

import argparse
import importlib
import sys
from typing import Callable, NamedTuple, NoReturn

from railderail_sim import __version__

PROG = "railderail"


class Command(NamedTuple):
    name: str
    help: str
    target: str  # "module:function" that adds the arguments and returns the runner


COMMANDS: tuple[Command, ...] = (
    Command("version", "print the railderail version", "railderail_sim.cli:version_command"),
    Command("contact-geometry", "contact geometry, conicity, Nadal limit of a wheel/rail pair (--json, --plot)",
            "railderail_sim.cli.contact:geometry_command"),
    Command("contact-case", "contact patches and forces of a loaded wheelset (--json, --plot)",
            "railderail_sim.cli.contact:case_command"),
    Command("climb", "wheel-climb rig: L/V at the climb, climb distance, Nadal's limit against attack angle "
            "(--json, --plot)", "railderail_sim.cli.climb:climb_command"),
    Command("bench", "print the performance figures (add --json)", "railderail_sim.cli.bench:command"),
    Command("simulate", "run the car over the line at a constant speed (--out FILE.npz)",
            "railderail_sim.cli.methods:simulate_command"),
    Command("root-locus", "linear critical speed: eigenvalues against speed (--json, --plot)",
            "railderail_sim.cli.methods:root_locus_command"),
    Command("limit-cycle", "nonlinear critical speed after a lateral kink (--json, --plot)",
            "railderail_sim.cli.methods:limit_cycle_command"),
    Command("trial", "progressive trial: critical derailment speed on a curve (--json)",
            "railderail_sim.cli.methods:trial_command"),
    Command("sweep", "progressive trial over radii and other parameters, in parallel or on Dask (--json)",
            "railderail_sim.cli.methods:sweep_command"),
    Command("survey", "a line file's physical speed limits: each curve's critical derailment speed over frictions "
            "and parameter sets, each defect's and wind site's limit, their sensitivities (--json, --plot)",
            "railderail_sim.cli.survey:survey_command"),
    Command("cwc", "characteristic wind curves of EN 14067-6 under the CEN extreme gust (--json, --plot)",
            "railderail_sim.cli.methods:cwc_command"),
    Command("real-track", "the progressive trial on rigid and elastic track with irregularities, several seeds "
            "(report section)", "railderail_sim.cli.methods:real_track_command"),
    Command("report", "write the report: every method beside the paper's numbers (--out DIR)",
            "railderail_sim.cli.methods:report_command"),
    Command("simulator-params", "the simulator node's parameter file: every parameter at its default, with comments",
            "railderail_sim.cli.nodes:simulator_params_command"),
    Command("track-irregularity", "a random track irregularity from a spectrum, as a CSV file (--plot)",
            "railderail_sim.cli.track:irregularity_command"),
)
ENTRY_POINTS = "railderail.commands"


def commands() -> tuple[Command, ...]:
    """Every registered subcommand: this package's COMMANDS, then the tables of the entry-point group
    ENTRY_POINTS (in the order of their names), each table a tuple of Command-like triples."""
    from importlib.metadata import entry_points

    found = list(COMMANDS)
    for point in sorted(entry_points(group=ENTRY_POINTS), key=lambda p: p.name):
        found.extend(Command(*c) for c in point.load())
    return tuple(found)


def version_command(parser: argparse.ArgumentParser) -> Callable[[argparse.Namespace], None]:
    return lambda args: print(f"{PROG} {__version__}")


class _Parser(argparse.ArgumentParser):
    """ArgumentParser that reports a usage error as one line (exit status 2)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _load(target: str) -> Callable[[argparse.ArgumentParser], Callable]:
    module, _, function = target.partition(":")
    return getattr(importlib.import_module(module), function)


def build_parser(argv: list[str]) -> argparse.ArgumentParser:
    """Parser with every subcommand; only the one named in `argv` gets its arguments (and import)."""
    parser = _Parser(
        prog=PROG,
        description="Simulate a CRH3 car over-speeding on a curve, predict its critical derailment "
        "speed and warn before derailment.",
    )
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands",
                                       parser_class=_Parser)
    chosen = next((arg for arg in argv if not arg.startswith("-")), None)
    for command in commands():
        subparser = subparsers.add_parser(command.name, help=command.help, description=command.help)
        if command.name == chosen:
            subparser.set_defaults(run=_load(command.target)(subparser))
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(argv)
    args = parser.parse_args(argv)
    if args.command is None:
        parser.error("no command given")
    try:
        status = args.run(args)
    except ValueError as error:
        print(f"{PROG}: error: {error}", file=sys.stderr)
        return 2
    except RuntimeError as error:
        # a diverged simulation is a result to report in one line, not a crash; the module is looked up
        # rather than imported, so that commands that never simulate do not load the numba core
        simulate = sys.modules.get("railderail_sim.vehicle.simulate")
        if simulate is None or not isinstance(error, simulate.SimulationDiverged):
            raise
        print(f"{PROG}: error: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    return 0 if status is None else status

