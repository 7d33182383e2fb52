"""Critical-speed methods checked against physics that does not come from the code."""
import json
import math

import numpy as np
import pytest

from railderail_sim.cli import main
from railderail_sim.contact import conicity
from railderail_sim.methods import limit_cycle as lc
from railderail_sim.methods import root_locus as rl
from railderail_sim.methods.progressive_trial import Staircase, progressive_trial
from railderail_sim.methods.sweep import cases, sweep
from railderail_sim.parameters import ContactParameters, TrackParameters, vehicle_parameters
from railderail_sim.vehicle.simulate import Scenario, constant_speed, simulate, straight_track
from railderail_sim.vehicle.assemble import contact_geometry
from railderail_sim.vehicle.linear import active_states, equilibrium


def test_free_wheelset_eigenvalue_is_the_kinematic_frequency():
    """Without primary guidance each wheelset's eigenvalue is Klingel's kinematic frequency V / lambda,
    lambda = 2 pi sqrt(e r0 / gamma) with the profile pair's conicity at the centre."""
    veh = vehicle_parameters(primary_lateral_stiffness=0.0, primary_longitudinal_stiffness=0.0,
                             primary_lateral_damping=0.0)
    sc = Scenario(vehicle=veh, track=straight_track(), speed_table=constant_speed(60.0))
    model, x0, rolling_radius = equilibrium(sc)
    lam, _ = rl._modes(model, x0, active_states(model), 60.0, rolling_radius)
    table = conicity.rigid_table(contact_geometry(ContactParameters(), TrackParameters(), 0.46), 0.003, 1e-5)
    i0 = len(table.y) // 2
    gamma = (table.delta_r[i0 + 1] - table.delta_r[i0 - 1]) / (4 * (table.y[i0 + 1] - table.y[i0]))
    f_kin = (60.0 / 3.6) / (2 * math.pi * math.sqrt(table.contact_half_distance * 0.46 / gamma))
    f = lam.imag / (2 * math.pi)
    closest = f[np.argmin(np.abs(f - f_kin))]
    assert closest == pytest.approx(f_kin, rel=0.03)
    # four free wheelsets: four such modes, none of them damped (a free wheelset is never stable)
    near = np.abs(f - f_kin) < 0.05 * f_kin
    assert near.sum() >= 4 and np.all(lam.real[near] > -0.05)


@pytest.fixture(scope="module")
def locus():
    return rl.root_locus(Scenario(), np.linspace(200.0, 700.0, 11))


def test_root_locus_finds_a_hunting_instability(locus):
    v = locus.linear_critical_speed_kmh
    assert 200.0 < v < 700.0
    assert locus.critical_mode == "wheelset"
    assert 1.0 < locus.critical_frequency_hz < 10.0
    assert locus.least_damping[0] > 0.0 > locus.least_damping[-1]


def test_limit_cycle_classifies_stable_and_unstable_runs(locus):
    assert lc.final_amplitude(Scenario(), 200.0) < lc.THRESHOLD_M
    # at the linear critical speed a kicked car keeps hunting: nonlinear critical speed <= linear one
    assert lc.final_amplitude(Scenario(), locus.linear_critical_speed_kmh) > lc.THRESHOLD_M


def test_trial_detects_a_forced_derailment_and_not_the_balance_speed():
    forced = simulate(Scenario(track=TrackParameters(radius=800.0), speed_table=constant_speed(400.0),
                               output_rate=50.0))
    assert forced.status == "derailed" and forced.derailment["position_m"] < 800.0
    calm = simulate(Scenario(track=TrackParameters(radius=800.0), output_rate=20.0,
                             speed_table=constant_speed(TrackParameters(radius=800.0).speed_at_cant_deficiency(0.0) * 3.6)))
    assert calm.status == "finished" and calm.derailment is None
    assert np.max(calm.wheel("wheel_lift")) < 0.005


QUICK = Staircase(start_kmh=280.0, step_kmh=10.0, hold_m=100.0, acceleration=1.0, top_kmh=340.0)


def test_progressive_trial_reports_speed_wheel_place_and_mechanism():
    r = progressive_trial(Scenario(), 1000.0, QUICK, refine=False)
    assert 280.0 < r.critical_derailment_speed_kmh <= 340.0
    assert r.derailed_wheelset in (0, 1, 2, 3) and r.derailed_side in ("inner", "outer")
    assert r.mechanism in ("flange_climbing", "wheel_unloading")
    assert r.last_safe_speed_kmh < r.critical_derailment_speed_kmh


def _same(a, b):
    return json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


def test_sweep_on_dask_equals_the_local_run():
    from dask.distributed import LocalCluster
    cl = cases(radii=(1000.0,))
    local = sweep(cl, stair=QUICK, refine=False, workers=1, progress=False)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = sweep(cl, stair=QUICK, refine=False, scheduler=cluster.scheduler_address, progress=False)
    assert _same(local, remote)


def test_cli_refuses_out_of_range_input(capsys):
    assert main(["trial", "--radius", "100"]) == 2
    assert "curve radius 100 m is outside the accepted range" in capsys.readouterr().err
    assert main(["sweep", "--radii", "800,abc"]) == 2
    assert "--radii '800,abc' is not a comma-separated list" in capsys.readouterr().err
    assert main(["limit-cycle", "--kink-mm", "50"]) == 2
    assert "excitation amplitude 50 mm is outside" in capsys.readouterr().err
    assert main(["simulate", "--cant-mm", "250"]) == 2
    assert "cant 250 mm is outside the accepted range [0, 200] mm" in capsys.readouterr().err
    assert main(["simulate", "--irregularity", "erri-high", "--irregularity-seed", "-1"]) == 2
    assert "seed -1 is outside the accepted range: an integer in [0, 999999]" in capsys.readouterr().err
    assert main(["trial", "--irregularity", "missing.csv"]) == 2
    assert "irregularity file 'missing.csv' cannot be read" in capsys.readouterr().err
    with pytest.raises(SystemExit) as stop:
        main(["simulate", "--track", "soft"])
    assert stop.value.code == 2 and "invalid choice: 'soft'" in capsys.readouterr().err


def _irregular_run(capsys, seed):
    assert main(["simulate", "--speed-kmh", "250", "--irregularity", "erri-high", "--irregularity-seed", str(seed),
                 "--json"]) in (0, None)
    return json.loads(capsys.readouterr().out)


def test_simulate_on_irregular_track_is_reproducible_and_feels_it(capsys):
    first, again, other = _irregular_run(capsys, 7), _irregular_run(capsys, 7), _irregular_run(capsys, 8)
    assert first == again and first != other
    assert main(["simulate", "--speed-kmh", "250", "--json"]) in (0, None)
    smooth = json.loads(capsys.readouterr().out)
    # the rails' unevenness loads and unloads the wheels: peaks above the smooth track's
    assert first["max_vertical_force_n"] > 1.05 * smooth["max_vertical_force_n"]


def test_real_track_study_writes_its_section_and_resumes(tmp_path, capsys):
    args = ["real-track", "--tracks", "rigid", "--spectra", "erri-low", "--seeds", "1", "--radii", "1800",
            "--no-sharp", "--workers", "1", "--out", str(tmp_path), "--json"]
    assert main(args) in (0, None)
    first = json.loads(capsys.readouterr().out)
    rows = [json.loads(line) for line in open(tmp_path / "real-track.jsonl")]
    assert [(r["model"], r["irregularity"], r["seed"], r["radius_m"]) for r in rows] == [
        ("rigid", "none", 0, 1800.0), ("rigid", "erri-low", 1, 1800.0)]
    smooth, rough = first["summary"][0], first["summary"][1]
    assert (smooth["irregularity"], rough["irregularity"]) == ("none", "erri-low")
    assert 350.0 < smooth["mean_kmh"] < 450.0 and rough["mean_kmh"] == rows[1]["critical_derailment_speed_kmh"]
    text = (tmp_path / "real-track.md").read_text()
    assert "| rigid | erri-low | 1800 |" in text and (tmp_path / "real_track.png").stat().st_size > 0
    # a second run finds every case in the rows file and runs none again
    assert main(args) in (0, None)
    assert json.loads(capsys.readouterr().out) == first
    assert len(open(tmp_path / "real-track.jsonl").readlines()) == 2


def test_real_track_refuses_bad_lists(capsys):
    assert main(["real-track", "--tracks", "soft"]) == 2
    assert "--tracks: 'soft' is not one of rigid, elastic" in capsys.readouterr().err
    assert main(["real-track", "--seeds", "1,x"]) == 2
    assert "--seeds '1,x' is not a comma-separated list of integers" in capsys.readouterr().err
    assert main(["real-track", "--seeds", ""]) == 2
    assert "need at least one value each" in capsys.readouterr().err
    assert main(["real-track", "--spectra", "erri-medium"]) == 2
    assert "--spectra: 'erri-medium' is not one of" in capsys.readouterr().err


def _started(item):
    import time
    return time.monotonic_ns()


def test_run_all_starts_the_dearest_inputs_first_and_returns_them_in_order():
    from railderail_sim.methods.parallel import run_all
    cost = [1.0, 5.0, 3.0, 4.0, 2.0]
    started = run_all(_started, range(5), workers=1, progress=False, cost=cost)
    assert sorted(range(5), key=lambda i: started[i]) == [1, 3, 2, 4, 0]    # one worker: one after another
    with pytest.raises(ValueError, match="4 costs given for 5 inputs"):
        run_all(_started, range(5), workers=1, progress=False, cost=cost[:4])


def test_simulated_duration_is_the_line_at_the_table_speeds():
    sc = Scenario(speed_table=constant_speed(288.0))
    assert sc.simulated_duration() == pytest.approx(sc.track.line_length / 80.0, rel=1e-12)
    # 40 m/s over the first 1000 m, 80 m/s from 2000 m, a linear ramp between: dt = ds / v, so the ramp
    # takes 1000 m ln 2 / 40 m/s
    ramp = Scenario(speed_table=np.array([[0.0, 40.0], [1000.0, 40.0], [2000.0, 80.0], [3000.0, 80.0]]),
                    end_position=3000.0)
    assert ramp.simulated_duration() == pytest.approx(25.0 + 25.0 * math.log(2.0) + 12.5, rel=1e-12)
