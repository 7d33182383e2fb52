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
    for series in ("attack_angle_mrad/values", "speed_kmh"):
        assert rows[f"/plots/{series}"] == samples, series
    for entity in ("wheel_lift_mm", "derailment_coefficient", "unloading_ratio", "lateral_force_kN",
                   "vertical_force_kN"):
        assert rows[f"/plots/{entity}/left"] == rows[f"/plots/{entity}/right"] == samples, entity
    for limit in ("wheel_lift_mm/limit_warning", "wheel_lift_mm/limit_critical",
                  "derailment_coefficient/limit_critical", "unloading_ratio/limit_critical"):
        assert rows[f"/plots/{limit}"] >= 2, limit             # threshold lines drawn
    # the attack angle stays far below its 0.06 rad level: no line to flatten it
    assert "/plots/attack_angle_mrad/limit_warning" not in rows
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
    assert "/plots/wheel_lift_mm/left" in summary and "/scene/track/wheelset_0" in summary
    assert "/alerts" in summary                      # the derailment event at least


def synthetic(viewer, t, attack=0.0, lift=0.0, qp=0.2, load=56_000.0):
    """One sample of states and forces into a RunViewer (every wheel alike)."""
    import numpy as np

    from railderail_sim import ros_interface as m

    states = m.WheelsetStates(sample=int(t * 200), track_position=80.0 * t, speed=80.0)
    m.stamp(states, t)
    states.attack_angle = np.array([attack, 0.0, 0.0, 0.0])
    states.wheel_lift = np.full(8, lift)
    forces = m.ContactForces(sample=states.sample, track_position=states.track_position, speed=80.0)
    m.stamp(forces, t)
    forces.derailment_coefficient = np.full(8, qp)
    forces.vertical_force = np.full(8, load)
    forces.contact_count = np.full(8, 1, dtype=np.uint8)
    forces.patch_length = np.full(8, 0.012)
    forces.patch_width = np.full(8, 0.01)
    viewer.on_forces(forces)
    viewer.on_states(states)


def test_attack_angle_line_appears_at_half_its_level_and_patches_show_the_worst_level():
    from railderail_monitor.criteria import default_limits
    from railderail_monitor.viewer import GREEN, ORANGE, RED, RunViewer
    from railderail_sim import ros_interface as m

    limits = default_limits()
    viewer = RunViewer(scene_rate=1000.0, flush_every=10**6)
    synthetic(viewer, 0.0, attack=0.004)
    assert "/plots/attack_angle_mrad/limit_warning" not in viewer.buffers
    synthetic(viewer, 0.005, attack=0.5 * limits.attack_angle)
    times, values = viewer.buffers["/plots/attack_angle_mrad/limit_warning"]
    assert values == [limits.attack_angle * 1e3]              # in mrad, like the attack angle
    colours = viewer.scene["patch_col"]
    assert colours[-8:] == [GREEN] * 8
    synthetic(viewer, 0.010, qp=limits.derailment_coefficient)                           # Q/P: warning
    assert colours[-8:] == [ORANGE] * 8
    synthetic(viewer, 0.015, load=(1 - limits.wheel_unloading_critical) * limits.static_wheel_load)   # unloading
    assert colours[-8:] == [RED] * 8
    synthetic(viewer, 0.020)
    assert colours[-8:] == [GREEN] * 8
    event = m.DerailmentEvent(wheelset=0, wheel_side="left", rail_side="inner", mechanism="wheel_unloading")
    m.stamp(event, 0.022)
    viewer.on_derailment(event)
    synthetic(viewer, 0.025)
    assert colours[-8:] == [RED] * 8                            # at the derailment every patch is red
