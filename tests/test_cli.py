"""The `railderail` command: help, version, one-line errors with exit status 2."""
import subprocess
import sys

import pytest

import railderail_sim
from railderail_sim import cli


def run(venv_bin, *args):
    return subprocess.run([venv_bin / "railderail", *args], capture_output=True, text=True, timeout=60)


def test_help_lists_commands(venv_bin):
    result = run(venv_bin, "--help")
    assert result.returncode == 0
    names = [command.name for command in cli.commands()]
    assert {"simulate", "trial", "demo", "replay", "warnings"} <= set(names)     # both packages' tables
    for name in names:
        assert name in result.stdout


def test_version(venv_bin):
    result = run(venv_bin, "version")
    assert (result.returncode, result.stdout) == (0, f"railderail {railderail_sim.__version__}\n")


@pytest.mark.parametrize("args, message", [
    ([], "railderail: error: no command given"),
    (["no-such-command"], "railderail: error: argument COMMAND: invalid choice: 'no-such-command'"),
    (["version", "--bogus"], "railderail: error: unrecognized arguments: --bogus"),
])
def test_bad_arguments_give_one_line_and_status_2(venv_bin, args, message):
    result = run(venv_bin, *args)
    assert result.returncode == 2
    assert result.stdout == ""
    assert len(result.stderr.splitlines()) == 1
    assert result.stderr.startswith(message)


def failing_command(parser):
    parser.add_argument("--speed-kmh", type=float, required=True)

    def run_it(args):
        raise ValueError(f"speed_kmh must be in 0..500, got {args.speed_kmh}")
    return run_it


def test_value_error_gives_one_line_and_status_2(monkeypatch, capsys):
    monkeypatch.setattr(cli, "COMMANDS", cli.COMMANDS + (
        cli.Command("fail", "always fails", f"{__name__}:failing_command"),))
    assert "fail" in [command.name for command in cli.commands()]
    assert cli.main(["fail", "--speed-kmh", "900"]) == 2
    captured = capsys.readouterr()
    assert captured.err == "railderail: error: speed_kmh must be in 0..500, got 900.0\n"
    assert captured.out == ""


def diverging_command(parser):
    def run_it(args):
        from railderail_sim.vehicle.simulate import SimulationDiverged
        raise SimulationDiverged("the simulation diverged at t = 1.5 s, track position 40.00 m: the step size fell")
    return run_it


def raising_command(parser):
    def run_it(args):
        raise RuntimeError("a defect, not a result")
    return run_it


def test_a_diverged_simulation_gives_one_line_and_status_1_other_errors_their_traceback(monkeypatch, capsys):
    monkeypatch.setattr(cli, "COMMANDS", cli.COMMANDS + (
        cli.Command("diverge", "diverges", f"{__name__}:diverging_command"),
        cli.Command("defect", "has a defect", f"{__name__}:raising_command")))
    assert cli.main(["diverge"]) == 1
    captured = capsys.readouterr()
    assert captured.err == ("railderail: error: the simulation diverged at t = 1.5 s, track position 40.00 m: "
                            "the step size fell\n")
    with pytest.raises(RuntimeError, match="a defect"):
        cli.main(["defect"])


def test_help_imports_no_heavy_modules():
    code = ("import sys\nfrom railderail_sim import cli\ntry:\n    cli.main(['--help'])\n"
            "except SystemExit:\n    pass\nprint(sorted({'numba', 'rclpy', 'scipy'} & set(sys.modules)))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert result.stdout.splitlines()[-1] == "[]"


def test_simulate_for_a_duration_prints_rounded_values_with_units(capsys):
    assert cli.main(["simulate", "--radius", "1000", "--speed-kmh", "280", "--duration-s", "0.4"]) == 0
    out = capsys.readouterr().out
    rows = {line[:30].strip(): line[30:] for line in out.splitlines()}
    # 0.4 s at 280 km/h from the start: 31.1 m, up to the output period (5 ms, 0.4 m) the run stops on
    assert rows["simulated time"].endswith(" s") and 0.4 <= float(rows["simulated time"][:-2]) <= 0.41
    assert 31.1 <= float(rows["car-body position at the end"][:-2]) <= 31.5
    for line in out.splitlines():
        assert line.split()[-1] in ("s", "m", "mrad", "mm", "kN", "finished", "rigid") or "Y/Q" in line, line
        assert not any(len(word.split(".")[-1]) > 3 for word in line.split() if word.replace(".", "").isdigit())
    assert cli.main(["simulate", "--speed-kmh", "280", "--duration-s", "99"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("railderail: error: --duration-s 99 s is outside the accepted range (0, 23.") and \
        err.count("\n") == 1
