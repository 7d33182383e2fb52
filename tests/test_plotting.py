"""The one plotting module: path checks before any work, one style, atomic writes, every method figure."""
import os

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure

from railderail_sim import jsonout, plotting
from railderail_sim.cli import main
from railderail_sim.methods import limit_cycle as lc
from railderail_sim.methods import root_locus as rl

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def plain_file_mode():
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@pytest.mark.parametrize("name, words", [
    ("figure.jpg", ["'", "figure.jpg", ".png, .pdf or .svg"]),
    ("figure", ["must end in"]),
    ("no-such-folder/figure.png", ["its folder", "no-such-folder", "does not exist"]),
])
def test_checked_path_rejects_bad_names(tmp_path, name, words):
    with pytest.raises(ValueError) as error:
        plotting.checked_path(tmp_path / name)
    for word in words:
        assert word in str(error.value)
    assert plotting.checked_path(tmp_path / "figure.PDF").name == "figure.PDF"


def test_figure_is_drawn_in_the_style_and_leaves_rc_params_alone(tmp_path):
    before = dict(matplotlib.rcParams)
    path = tmp_path / "f.png"
    with plotting.figure(path, (3.0, 2.0)) as fig:
        ax = fig.subplots()
        ax.plot([0, 1], [0, 1])
        label = ax.set_xlabel("x")
        assert label.get_fontsize() == plotting.STYLE["axes.labelsize"]
        assert ax.lines[0].get_linewidth() == plotting.STYLE["lines.linewidth"]
    assert dict(matplotlib.rcParams) == before
    assert path.read_bytes()[:8] == PNG_MAGIC
    assert os.stat(path).st_mode & 0o777 == plain_file_mode()


def test_a_failed_write_leaves_the_old_file_and_no_temporary_file(tmp_path):
    path = tmp_path / "f.png"
    path.write_bytes(b"old")
    fig = Figure()

    def broken_savefig(handle, **kwargs):
        handle.write(b"part of a figure")
        raise RuntimeError("disk full")

    fig.savefig = broken_savefig
    with pytest.raises(RuntimeError):
        plotting.write_figure(fig, path)
    assert path.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["f.png"]


def test_jsonout_write_is_atomic_with_plain_permissions(tmp_path):
    path = tmp_path / "r.json"
    jsonout.write(path, {"speed_kmh": float("nan")})
    assert path.read_text() == '{\n "speed_kmh": null\n}\n'
    assert os.stat(path).st_mode & 0o777 == plain_file_mode()
    assert [p.name for p in tmp_path.iterdir()] == ["r.json"]


def test_method_figures(tmp_path):
    speeds = np.linspace(100.0, 500.0, 5)
    locus = rl.RootLocus(speeds_kmh=speeds, eigenvalues=[np.array([-1.0 + 12j, v / 200 - 2.0 + 20j]) for v in speeds],
                         least_damping=np.linspace(0.05, -0.02, 5), least_mode=["wheelset"] * 5,
                         least_frequency_hz=np.full(5, 3.0), linear_critical_speed_kmh=380.0)
    cycle = lc.LimitCycle(nonlinear_critical_speed_kmh=320.0, tolerance_kmh=1.0, speeds_kmh=speeds,
                          amplitudes_m=np.array([1e-6, 1e-5, 5e-3, np.inf, np.inf]), excitation_amplitude_m=0.01,
                          excitation_length_m=20.0, excitation="lateral kink of 10 mm over 20 m from s = 100 m")
    trials = [{"radius_m": r, "critical_derailment_speed_kmh": v, "refined_speed_kmh": v - 3.0}
              for r, v in ((800.0, 255.0), (1000.0, 285.0))]
    position = np.linspace(0.0, 600.0, 50)
    drawn = {
        "root_locus.png": lambda p: plotting.root_locus_figure(locus, p),
        "limit_cycle.svg": lambda p: plotting.limit_cycle_figure(cycle, p, lc.THRESHOLD_M, 380.0),
        "critical_speed.pdf": lambda p: plotting.critical_speed_figure(trials, p),
        "process.png": lambda p: plotting.position_figure(p, [(position, np.sin(position), "R 1000 m")], "lift (mm)",
                                                          markers=(200.0, 400.0)),
    }
    for name, draw in drawn.items():
        draw(tmp_path / name)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(drawn)
    assert (tmp_path / "root_locus.png").read_bytes()[:8] == PNG_MAGIC
    assert (tmp_path / "limit_cycle.svg").read_text().lstrip().startswith("<?xml")
    assert (tmp_path / "critical_speed.pdf").read_bytes()[:5] == b"%PDF-"


@pytest.mark.parametrize("command, method", [
    (["root-locus", "--points", "5"], "railderail_sim.methods.root_locus.root_locus"),
    (["limit-cycle"], "railderail_sim.methods.limit_cycle.limit_cycle"),
    (["sweep", "--radii", "1000"], "railderail_sim.methods.sweep.sweep"),
    (["simulate"], "railderail_sim.vehicle.simulate.simulate"),
])
@pytest.mark.parametrize("plot, words", [
    ("/no/such/folder/x.png", ["'/no/such/folder/x.png'", "does not exist"]),
    ("x.jpg", ["'x.jpg'", ".png, .pdf or .svg"]),
])
def test_bad_plot_file_fails_before_the_method_runs(monkeypatch, capsys, command, method, plot, words):
    def never(*args, **kwargs):
        raise AssertionError("the method ran before the plot file was checked")

    monkeypatch.setattr(method, never)
    assert main([*command, "--plot", plot]) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert captured.out == "" and len(lines) == 1 and lines[0].startswith("railderail: error: plot file")
    for word in words:
        assert word in lines[0]


def test_simulate_plots_a_run_on_irregular_track(tmp_path, capsys):
    path = tmp_path / "run.png"
    assert main(["simulate", "--speed-kmh", "200", "--irregularity", "china-hsr", "--irregularity-seed", "2",
                 "--plot", str(path)]) in (0, None)
    capsys.readouterr()
    assert path.read_bytes()[:8] == PNG_MAGIC and path.stat().st_size > 20_000
