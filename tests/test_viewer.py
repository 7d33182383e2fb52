"""Rerun views, headless: the .rrd of a recording has every view's entities and verifies."""
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest
from rerun.chunk import RrdReader

from railderail_monitor.recording import record_run
from railderail_monitor.replay import read_recording, write_rrd
from railderail_sim.cli import main


@pytest.fixture(scope="module")
def rrd(tmp_path_factory):
    from railderail_sim.vehicle.simulate import scenario, simulate

    folder = tmp_path_factory.mktemp("viewer")
    result = simulate(replace(scenario(radius=1000.0, speed_kmh=310.0), output_rate=200.0))
    record_run(folder / "run.mcap", result)
    return write_rrd(read_recording(folder / "run.mcap"), folder / "run.rrd"), len(result.time)


def test_rrd_has_the_views(rrd):
    path, samples = rrd
    summary = str(RrdReader(path).store().summary())
    rows = {}
    for line in summary.splitlines():
        entity, _, rest = line.partition(" rows=")
        if rest and "static=False" in rest:
            rows[entity] = rows.get(entity, 0) + int(rest.split()[0])
    for series in ("attack_angle/values", "wheel_lift_mm/values", "derailment_coefficient/values",
                   "unloading_ratio/values", "lateral_force_kN", "vertical_force_kN", "speed_kmh"):
        assert rows[f"/plots/{series}"] == samples, series
    for limit in ("attack_angle/limit_warning", "wheel_lift_mm/limit_warning", "wheel_lift_mm/limit_critical",
                  "derailment_coefficient/limit_critical", "unloading_ratio/limit_critical"):
        assert rows[f"/plots/{limit}"] >= 2, limit             # threshold lines drawn
    assert rows["/alerts"] >= 2                                 # alerts + the derailment as a text log
    frames = rows["/scene/track/wheelset_0"]
    assert frames >= samples / 8 - 2                            # 25 Hz of a 200 Hz run
    for body in ("car/body", "car/bogie_front", "car/bogie_rear", "wheelset_3", "contact_patches"):
        assert rows[f"/scene/track/{body}"] == frames or body == "contact_patches"
    assert rows["/scene/track/contact_patches"] > 0


def test_rrd_verifies(rrd):
    path, _ = rrd
    rerun = Path(sys.executable).parent / "rerun"
    done = subprocess.run([str(rerun), "rrd", "verify", str(path)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr


def test_replay_writes_rrd_from_the_command_line(rrd, capsys, tmp_path):
    path, _ = rrd
    out = tmp_path / "again.rrd"
    assert main(["replay", str(path.with_suffix(".mcap")), "--no-publish", "--rrd", str(out)]) == 0
    assert out.stat().st_size > 10000
    assert main(["replay", str(path.with_suffix(".mcap")), "--no-publish", "--rrd", str(tmp_path / "x.txt")]) == 2


@pytest.mark.timeout(400)
def test_live_viewer_node_writes_rrd(spawn, read_until, tmp_path):
    """The viewer node (`railderail view --rrd`), headless, over a short live run."""
    out = tmp_path / "live.rrd"
    viewer = spawn([sys.executable, "-m", "railderail_sim.cli", "view", "--rrd", str(out)])
    read_until(viewer, "showing /railderail in Rerun", timeout=60)
    simulator = spawn([sys.executable, "-m", "railderail_sim.node", "--ros-args", "-p", "speed_mode:=constant",
                       "-p", "speed_kmh:=310.0", "-p", "real_time_factor:=0.0", "-p", "wait_for_subscribers:=1"])
    assert simulator.wait(timeout=300) == 0         # a cold numba compile included
    import signal
    viewer.send_signal(signal.SIGINT)
    assert viewer.wait(timeout=30) == 0
    summary = str(RrdReader(out).store().summary())
    assert "/plots/wheel_lift_mm/values" in summary and "/scene/track/wheelset_0" in summary
    assert "/alerts" in summary                      # the derailment event at least
