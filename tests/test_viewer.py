"""Rerun views, headless: the .rrd of a recording has every view's entities and verifies."""
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest
from rerun.chunk import RrdReader

from conftest import STARTUP_S
from railderail_monitor.recording.recorder import record_run
from railderail_monitor.recording.replay import read_recording, write_rrd
from railderail_sim.cli import main


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A derailing run with the shipped sensors on, recorded (sensor topics included) and written to .rrd:
    (rrd path, samples, the run's SensorLog, the run)."""
    from railderail_sim.sensors.config import load
    from railderail_sim.sensors.measure import SensorLog
    from railderail_sim.vehicle.simulate import scenario, simulate

    folder = tmp_path_factory.mktemp("viewer")
    log = SensorLog(replace(load(), seed=3))
    result = simulate(replace(scenario(radius=1000.0, speed_kmh=310.0), output_rate=200.0), observe=log.observe)
    record_run(folder / "run.mcap", result, sensor_log=log)
    return write_rrd(read_recording(folder / "run.mcap"), folder / "run.rrd"), len(result.time), log, result


@pytest.fixture(scope="module")
def rrd(run):
    return run[:2]


def entity_rows(path):
    """{entity: rows of temporal data} of an .rrd file's recording."""
    rows = {}
    for line in str(RrdReader(path).store().summary()).splitlines():
        entity, _, rest = line.partition(" rows=")
        if rest and "static=False" in rest:
            rows[entity] = rows.get(entity, 0) + int(rest.split()[0])
    return rows


def test_rrd_has_the_views(rrd):
    path, samples = rrd
    rows = entity_rows(path)
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
    read_until(viewer, "showing /railderail in Rerun", timeout=STARTUP_S)
    simulator = spawn([sys.executable, "-m", "railderail_sim.ros.node", "--ros-args", "-p", "speed_mode:=constant",
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

    from railderail_sim.ros import interface as m

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
    from railderail_monitor.warning.limits import default_limits
    from railderail_monitor.views.rerun_views import GREEN, ORANGE, RED, RunViewer
    from railderail_sim.ros import interface as m

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


def views(container):
    """The views of a blueprint container, depth first."""
    import rerun.blueprint as rrb

    return [v for c in container.contents for v in (views(c) if isinstance(c, rrb.Container) else [c])]


def test_the_sensors_tab_comes_with_the_first_sensor_message_and_not_without():
    import numpy as np
    import rerun.blueprint as rrb

    from railderail_monitor.views.rerun_views import RunViewer
    from railderail_sim.ros import interface as m
    from railderail_sim.ros import sensor_messages as sm
    from railderail_sim.sensors.config import default_set

    viewer = RunViewer(flush_every=10**6)
    for t in (0.0, 0.005, 0.01):
        synthetic(viewer, t)
    viewer.on_status(m.VehicleStatus(speed=80.0))             # the ground-truth topics only: no tab
    assert isinstance(viewer.blueprint().root_container, rrb.Vertical)
    assert not any(entity.startswith("/sensors") for entity in viewer.buffers)
    viewer.flush()                                             # and no estimate to make
    imu = sm.SensorConverter(default_set(), 200.0, 0.46).messages(
        {"bogie_rear_frame": dict(time=np.array([0.007, 0.012]), acceleration=np.array([[0.1, -9.0, 9.8]] * 2),
                                  angular_rate=np.zeros((2, 3)))})
    for _, topic, msg in imu:
        viewer.on_sensor(topic, msg)
    root = viewer.blueprint().root_container
    assert isinstance(root, rrb.Tabs) and [c.name for c in root.contents] == ["run", "sensors"]
    origins = {str(v.origin) for v in views(root.contents[1])}
    assert {"/sensors/bogie_frame/lateral", "/sensors/car_body/roll_rate", "/sensors/estimator/front"} <= origins
    times, values = viewer.buffers["/sensors/bogie_frame/lateral/bogie_rear_frame"]
    assert times == [0.007, 0.012] and values == [-9.0, -9.0]           # as measured, in the frame's axes
    peak = viewer.sensor_levels[("bogie_frame", "lateral")][0][1]
    assert viewer.buffers["/sensors/bogie_frame/lateral/limit_peak"][1] == [(peak, -peak)] * 2
    assert peak == pytest.approx(12.0 - (3300.0 + 2 * 1780.0) / 5000.0)    # 12 - M_b/5, M_b in t
    viewer.flush()           # a frame alone: the estimator lacks its mounts, nothing estimated, no error
    assert "/sensors/estimator/front/estimated" not in viewer.sensor_series


def test_rrd_has_the_sensors_views_and_the_estimate_beside_the_truth(run):
    import numpy as np

    from railderail_monitor.onboard import estimator
    from railderail_monitor.recording.replay import feed_viewer
    from railderail_monitor.views.rerun_views import RunViewer
    from railderail_sim.parameters import VehicleParameters
    from railderail_sim.sensors.sensor_set import AIR_SPRING_EFFECTIVE_AREA, MOUNTS

    path, samples, log, result = run
    measured = {mount: {"time": log.arrays()[f"sensor_{mount}_time"]} for mount in MOUNTS}
    rows = entity_rows(path)
    for mount in MOUNTS:
        group = "bogie_frame" if mount.endswith("_frame") else "_".join(mount.split("_")[:2])
        for plot in ("lateral", "vertical"):
            assert rows[f"/sensors/{group}/{plot}/{mount}"] == len(measured[mount]["time"]), (mount, plot)
    assert rows["/sensors/car_body/roll_rate/car_body_centre"] == len(measured["car_body_centre"]["time"])
    for line in ("bogie_frame/lateral/limit_peak", "bogie_frame/lateral/limit_bids",
                 "car_body/roll_rate/limit_roll_rate",
                 "estimator/rear/limit_warning"):
        assert rows[f"/sensors/{line}"] >= 2, line
    # the car body's raw reading carries the curve's steady part: no filtered rule's level drawn against it
    assert not any(e.startswith("/sensors/car_body/lateral/limit_") for e in rows)
    est = estimator.estimate(log.arrays(), VehicleParameters(), AIR_SPRING_EFFECTIVE_AREA)
    for bogie in estimator.BOGIES:
        assert rows[f"/sensors/estimator/{bogie}/estimated"] == len(est["time"]) > 0.9 * samples
        assert rows[f"/sensors/estimator/{bogie}/ground_truth"] == samples
    assert len(RrdReader(path).blueprints()) == 2          # the first one's, and with the sensors' tab

    # the values drawn are the estimator's on the run's own sensor arrays (the topics decoded: the air springs'
    # height went through a float32 Range)
    viewer = RunViewer(flush_every=10**9)
    show = feed_viewer(viewer)
    for item in read_recording(path.with_suffix(".mcap")).messages:
        show(*item)
    viewer._estimate(final=True)
    times, values = viewer.buffers["/sensors/estimator/rear/estimated"]
    assert np.array_equal(np.round(np.asarray(times) * 1e9), np.round(est["time"] * 1e9))
    assert np.allclose(values, est["unloading"][:, 2:], rtol=0.0, atol=1e-5)
    times, values = viewer.buffers["/sensors/estimator/front/ground_truth"]
    truth = estimator.truth(result.arrays(), VehicleParameters())
    assert np.array_equal(np.round(np.asarray(times) * 1e9), np.round(truth["time"] * 1e9))
    assert np.allclose(values, truth["unloading"][:, :2], rtol=0.0, atol=1e-12)


def test_sensor_topics_decode_back_into_the_run_s_sensor_arrays(run):
    import numpy as np

    from railderail_sim.ros import sensor_messages as sm

    path, _, log, _ = run
    record = sm.SensorRecord()
    for topic, _, _, _, msg in read_recording(path.with_suffix(".mcap")).messages:
        if msg is not None:
            record.add(topic, msg)
    got, want = record.arrays(), log.arrays()
    assert set(got) == set(want)
    stamps = record.stamps_ns()
    for name, values in want.items():
        signal = next(s for s in ("time", "acceleration", "angular_rate", "deflection", "pressure", "speed")
                      if name.endswith("_" + s))
        unit = name[len("sensor_"):-len(signal) - 1]
        if signal == "time":
            assert np.array_equal(stamps[unit], np.round(values * 1e9).astype(np.int64)), name
        elif signal == "deflection":       # the height sensor's Range is float32
            assert np.allclose(got[name], values, rtol=0.0, atol=1e-7), name
        else:
            assert np.array_equal(got[name], values), name               # bit for bit


def test_the_measured_monitor_s_alerts_are_in_the_rrd(tmp_path):
    from railderail_monitor.recording.replay import feed_viewer
    from railderail_monitor.views.rerun_views import RunViewer
    from railderail_sim.ros import interface as m

    viewer = RunViewer(flush_every=10**9)
    viewer.save(tmp_path / "alerts.rrd")
    alert = m.stamp(m.Alert(criterion="car_body_roll", severity=1, speed=60.0, message="measured warning: ..."), 58.4)
    feed_viewer(viewer)(m.ONBOARD_ALERTS, "railderail_msgs/msg/Alert", 58_400_000_000, b"", alert)
    viewer.close()
    assert entity_rows(tmp_path / "alerts.rrd")["/alerts"] == 1


def test_samples_scene_and_alerts_have_their_track_position(tmp_path):
    """The position timeline beside simulation time: a sample's place is the wheelset states' at its time
    (interpolated, mm), an alert's its own; every temporal entity of the .rrd is on both timelines."""
    from railderail_monitor.views.rerun_views import POSITION, TIMELINE, RunViewer
    from railderail_sim.ros import interface as m

    viewer = RunViewer(scene_rate=1000.0, flush_every=10**6)
    viewer.save(tmp_path / "place.rrd")
    for t in (0.0, 0.005, 0.01):
        synthetic(viewer, t)                                   # the car at 80 t m
    index = viewer._index([0.0, 0.0025, 0.01, 0.02])
    assert [column.timeline_name() for column in index] == [TIMELINE, POSITION]
    assert index[1].times.to_pylist() == [0, 200, 800, 800]    # held beyond the last state's sample
    alert = m.stamp(m.Alert(criterion="wheel_lift", severity=1, track_position=0.61, message="warning: ..."), 0.0075)
    viewer.on_alert(alert)
    viewer.close()
    rows = [line for line in str(RrdReader(tmp_path / "place.rrd").store().summary()).splitlines()
            if "static=False" in line]
    assert any(line.startswith("/alerts ") and "'track_position_mm'" in line for line in rows)
    assert any(line.startswith("/scene/track/wheelset_0 ") for line in rows)
    assert all(f"'{TIMELINE}'" in line and f"'{POSITION}'" in line for line in rows), rows


def test_no_static_component_shadows_the_frames_in_the_scene(rrd):
    """Rerun shows an entity's static component instead of its temporal one: the scene's frames (the wheels'
    colours by their lift levels, the bodies' transforms) must have no static twin, or every wheel stays green."""
    import re

    path, _ = rrd
    static, temporal = {}, {}
    for line in str(RrdReader(path).store().summary()).splitlines():
        entity, _, rest = line.partition(" rows=")
        found = re.search(r"cols=\[(.*)\]", rest)
        if entity.startswith("/scene/") and found:
            cols = {c.strip(" '") for c in found.group(1).split(",")}
            (static if "static=True" in rest else temporal).setdefault(entity, set()).update(cols)
    assert "Cylinders3D:colors" in temporal["/scene/track/wheelset_0"]
    for entity, cols in temporal.items():
        assert not cols & static.get(entity, set()), entity


def test_every_legend_of_the_sensors_tab_has_its_rows_height():
    """A legend taller than its plot is cut (the axle boxes' at 1920x1080, the tab in four rows): each row's share
    is its longest legend's entries and LEGEND_FRAME_ENTRIES more, the entries counted from the names the viewer
    gives each plot once every mount of the shipped set has sent and an estimate has come."""
    import numpy as np
    import rerun as rr

    from railderail_monitor.views.colours import ESTIMATE_COLORS, TRUTH_COLORS
    from railderail_monitor.views.rerun_views import RunViewer
    from railderail_monitor.views.sensor_tab import LEGEND_FRAME_ENTRIES
    from railderail_sim.ros import sensor_messages as sm
    from railderail_sim.sensors.config import default_set
    from railderail_sim.sensors.sensor_set import MOUNTS

    viewer = RunViewer(flush_every=10**6)
    names, log = {}, viewer.rec.log

    def naming(entity, archetype, **kwargs):       # the legend's entries of a plot: its series' names
        if isinstance(archetype, rr.SeriesLines):
            names.setdefault(entity.rsplit("/", 1)[0], set()).update(archetype.names.as_arrow_array().to_pylist())
        return log(entity, archetype, **kwargs)

    viewer.rec.log = naming
    imu = sm.SensorConverter(default_set(), 200.0, 0.46).messages(
        {mount: dict(time=np.array([0.007, 0.012]), acceleration=np.array([[0.1, -0.2, 9.8]] * 2),
                     angular_rate=np.zeros((2, 3))) for mount in MOUNTS})
    for _, topic, msg in imu:
        viewer.on_sensor(topic, msg)
    for series, colours in (("estimated", ESTIMATE_COLORS), ("ground_truth", TRUTH_COLORS)):
        viewer._estimated(series, np.array([0.007, 0.012]), np.zeros((2, 4)), colours)
    tab = viewer.sensors_view()
    shown = {str(view.origin) for row in tab.contents for view in row.contents}
    assert shown == set(names) and "/sensors/car_body/roll_rate" in shown
    assert tab.row_shares == [max(len(names[str(view.origin)]) for view in row.contents) + LEGEND_FRAME_ENTRIES
                              for row in tab.contents]
    assert max(len(entries) for entries in names.values()) == 9          # the bogie frames': 6 mounts, 3 levels


def test_an_alert_s_time_and_place_are_read_whole_in_its_text():
    """The alerts' log's timeline columns are as wide as their names, which cut sim_time's values: they are hidden
    and each entry says its time and place."""
    import rerun as rr

    from railderail_monitor.views.rerun_views import RunViewer
    from railderail_sim.ros import interface as m

    viewer = RunViewer(flush_every=10**6)
    logged, log = [], viewer.rec.log
    viewer.rec.log = lambda entity, archetype, **kwargs: (logged.append(archetype), log(entity, archetype, **kwargs))
    viewer.on_alert(m.stamp(m.Alert(criterion="wheel_lift", severity=1, track_position=7643.14, speed=81.4,
                                    message="warning: ..."), 113.685))
    assert [a.text.as_arrow_array().to_pylist() for a in logged if isinstance(a, rr.TextLog)] == [
        ["[ground_truth] t = 113.685 s, s = 7643.1 m, 293.0 km/h: warning: ..."]]
    alerts = next(view for view in views(viewer.run_view()) if str(view.origin) == "/alerts")
    assert not any(column["visible"] for column in
                   alerts.properties["TextLogColumns"].timeline_columns.as_arrow_array().to_pylist())
