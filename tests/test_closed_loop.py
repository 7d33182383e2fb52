"""The closed loop of the batch path (railderail_sim/supervision/closed_loop.py with the supervisor of
railderail_monitor/supervision/loop.py): the supervisor's emergency brake prevents the derailment the open
run has, the run is deterministic, the braked rows are those of an open run of the braked speed table (the
table's swap leaves no trace), the speed follows the braking model, and the command line says when a run
starts inside its braking distance."""
from dataclasses import replace
import json

import numpy as np
import pytest

from railderail_monitor.supervision.curves import KMH, SupervisionLimits, Target
from railderail_monitor.supervision.loop import Controller, scenario_targets, watching
from railderail_monitor.supervision.supervisor import Supervisor
from railderail_sim.cli import main
from railderail_sim.sensors import config as sensor_config
from railderail_sim.supervision.braking import BrakingModel
from railderail_sim.supervision.closed_loop import BrakeCommand, braked_table, run_closed_loop
from railderail_sim.vehicle.simulate import Checkpoints, curve_extent, run_to_stop, scenario, simulate

LIMITS = SupervisionLimits()
BRAKING = BrakingModel()
# R 1000 m at 320 km/h derails (the model's critical derailment speed there is about 290 km/h); the supervisor
# is given 270 km/h, and 2500 m of straight before the entry transition
SCENARIO = replace(scenario(radius=1000.0, speed_kmh=320.0),
                   track=replace(scenario().track, straight_in=2500.0)).validated()


def _closed(closed=True, odometer=None):
    controller = Controller(Supervisor(scenario_targets(SCENARIO.track, 270 * KMH, LIMITS), BRAKING, LIMITS),
                            odometer, seed=3)
    return run_closed_loop(SCENARIO, controller if closed else watching(controller), BRAKING), controller


@pytest.fixture(scope="module")
def runs():
    return _closed(False), _closed(), _closed()


def test_the_closed_loop_prevents_the_derailment(runs):
    (open_run, watched), (closed, controller), _ = runs
    assert open_run.result.status == "derailed" and open_run.commands == []
    assert [a.level for a in watched.supervisor.alerts] == ["indication", "warning", "intervention"]
    assert closed.result.status == "finished" and closed.result.derailment is None
    (command,) = closed.commands
    target = scenario_targets(SCENARIO.track, 270 * KMH, LIMITS)[0]
    assert command.release_speed_m_s == target.speed_limit_m_s
    assert command.position_m < SCENARIO.track.straight_in
    assert controller.lowest_speed == pytest.approx(target.speed_limit_m_s, abs=1e-6)
    # the open run is the plain run: the supervisor watching changes nothing
    assert np.array_equal(open_run.result.rows, simulate(SCENARIO).rows)


def test_the_closed_loop_is_deterministic_and_its_swap_leaves_no_trace(runs):
    _, (a, _), (b, _) = runs
    assert np.array_equal(a.result.rows, b.result.rows)
    assert np.array_equal(a.result.rows, simulate(a.result.scenario).rows)


def test_a_closed_loop_going_on_from_its_open_run_is_the_loop_run_from_the_start(runs):
    """The warning evaluation's closed loops read their approach from the open run's rows and go on from its
    state there (`Checkpoints`, one per second of the open run here): the same rows and commands bit for bit;
    a supervisor that never brakes gives the open run itself; another scenario's checkpoints are refused."""
    (open_run, _), (closed, _), _ = runs
    checkpoints = Checkpoints()
    run_to_stop(SCENARIO, 1.0, checkpoints)
    assert len(checkpoints.forks) > 10 and np.array_equal(checkpoints.rows, open_run.result.rows)
    followed = run_closed_loop(SCENARIO, Controller(Supervisor(scenario_targets(SCENARIO.track, 270 * KMH, LIMITS),
                                                               BRAKING, LIMITS), None, seed=3),
                               BRAKING, checkpoints=checkpoints)
    assert followed.commands == closed.commands and followed.result.rows.tobytes() == closed.result.rows.tobytes()
    watched = watching(Controller(Supervisor(scenario_targets(SCENARIO.track, 270 * KMH, LIMITS), BRAKING, LIMITS)))
    unbraked = run_closed_loop(SCENARIO, watched, BRAKING, checkpoints=checkpoints)
    assert unbraked.commands == [] and unbraked.result.rows.tobytes() == open_run.result.rows.tobytes()
    with pytest.raises(ValueError, match="another run"):
        run_closed_loop(replace(SCENARIO), watched, BRAKING, checkpoints=checkpoints)


def test_the_speed_follows_the_braking_model(runs):
    _, (closed, _), _ = runs
    (c,) = closed.commands
    arrays = closed.result.arrays()
    expected = [max(BRAKING.speed_after(c.speed_m_s, s - c.position_m), c.release_speed_m_s) if s >= c.position_m
                else c.speed_m_s for s in arrays["position"]]
    assert np.max(np.abs(arrays["speed"] - expected)) < 2e-3
    assert np.min(arrays["speed"]) == pytest.approx(c.release_speed_m_s)


def test_the_measured_mode_brakes_earlier(runs):
    # the odometer's speed error (V_ura) and position error move the intervention forward; it still prevents
    _, (truth, _), _ = runs
    measured, controller = _closed(odometer=sensor_config.load(None).odometer)
    assert measured.result.status == "finished"
    assert measured.commands[0].position_m < truth.commands[0].position_m - 100.0
    assert controller.steps == pytest.approx(measured.result.time[-1] * 10.0, abs=2)     # the odometer's 10 Hz


def test_a_run_inside_its_braking_distance_says_so_and_brakes_at_once(capsys):
    status = main(["simulate", "--radius", "1000", "--speed-kmh", "320", "--supervision", "--critical-speed-kmh",
                   "270", "--approach-m", "300", "--closed-loop", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert status == 0 and out["started_inside_braking_distance"] and out["closed_loop"]
    assert out["brake_commands"][0]["time_s"] == 0.0 and out["alerts"][0]["level"] == "intervention"
    assert out["lowest_speed_kmh"] < 320.0 and set(out) >= {"status", "derailment", "brake_commands"}
    assert main(["simulate", "--closed-loop"]) == 2
    assert "need --supervision" in capsys.readouterr().err


def test_a_stop_target_brakes_to_a_stand_before_it():
    # a target of 0 (a stop: the survey kept no margin at any speed it tried): the brake runs the train down to
    # the simulator's slowest speed and the run ends where the braking model stops it, before the target's
    # start as the EBD places it (its foot, dV_ebi at 0, lets the front reach the start at 7.5 km/h; the brake
    # comes at the first row past the EBI, up to one output period late)
    sc = replace(SCENARIO, speed_table=scenario(speed_kmh=200.0).speed_table)
    start, end = curve_extent(sc.track)
    controller = Controller(Supervisor([Target(start, end, 0.0, "stop").validated()], BRAKING, LIMITS))
    run = run_closed_loop(sc, controller, BRAKING)
    (command,) = run.commands
    assert command.release_speed_m_s == 0.0 and run.result.derailment is None
    stand = command.position_m + BRAKING.braking_distance(command.speed_m_s, 0.0)
    assert run.stopped_at_m == stand and run.result.position[-1] == pytest.approx(stand, abs=0.1)
    assert run.result.speed[-1] == pytest.approx(30 * KMH)
    front = stand + sc.vehicle.bogie_semi_distance + sc.vehicle.wheelbase_semi
    assert 0.0 < front - start < BRAKING.deceleration_distance(7.5 * KMH, 0.0) + command.speed_m_s / sc.output_rate
    # the speed beyond the lowest simulated is the braking model's down to it
    s = run.result.position
    expected = np.maximum([BRAKING.speed_after(command.speed_m_s, x - command.position_m) for x in s], 30 * KMH)
    assert np.max(np.abs(run.result.speed[s >= command.position_m] - expected[s >= command.position_m])) < 1e-3


@pytest.mark.slow
def test_braking_to_low_speed_stays_accurate():
    # the wheelset spin mode stiffens as the speed falls: braked from 300 to 40 km/h on R 1000 m (the brake on
    # the straight before it), the default tolerances against 100 times tighter ones (docs/supervision.md)
    base = scenario(radius=1000.0, speed_kmh=300.0)
    command = BrakeCommand(0.0, 100.0, 300 * KMH, 40 * KMH)
    table = braked_table(base.speed_table, command, BRAKING)
    end = table[-2, 0] + 50.0
    sc = replace(base, track=replace(base.track, straight_in=1500.0).with_line_length(end + 300.0),
                 speed_table=table, end_position=end).validated()
    a = simulate(sc).arrays()
    b = simulate(replace(sc, rtol=sc.rtol / 100, atol=sc.atol / 100)).arrays()
    assert len(a["time"]) == len(b["time"]) and a["speed"][-1] == pytest.approx(40 * KMH)
    low = a["speed"] < 100 * KMH
    assert np.max(np.abs(a["wheelset_lateral"] - b["wheelset_lateral"])[low]) < 2e-6
    assert np.max(np.abs(a["attack_angle"] - b["attack_angle"])[low]) < 2e-6
    assert np.max(np.abs(a["vertical_force"] - b["vertical_force"])[low]) < 2e3
    expected = [max(BRAKING.speed_after(command.speed_m_s, s - command.position_m), command.release_speed_m_s)
                for s in a["position"]]
    assert np.max(np.abs(a["speed"] - expected)) < 1e-3
