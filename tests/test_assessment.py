"""The running-behaviour assessment (railderail_sim.assessment): the filters and weightings against their
tabulated gains, the comfort indices against the closed form of a sine, the sliding windows, and an
ideal-track steady-curving run against the hand calculation of its quasi-static quantities."""
from dataclasses import replace
import math

import numpy as np
import pytest

from railderail_sim.assessment import assess, comfort, en14363, filters, signals
from railderail_sim.parameters import GRAVITY, TrackParameters, vehicle_parameters

RATE = 200.0

# ISO 2631-1:1997 Table 3 (as tabulated in public ISO 2631 code; B): frequency (Hz), Wk, Wd
ISO_2631_TABLE = ((0.5, 0.419, 0.854), (0.63, 0.459, 0.944), (0.8, 0.477, 0.991), (1.0, 0.482, 1.011),
                  (1.25, 0.485, 1.007), (1.6, 0.493, 0.971), (2.0, 0.531, 0.891), (2.5, 0.633, 0.773),
                  (3.15, 0.807, 0.640), (4.0, 0.965, 0.514), (5.0, 1.039, 0.408))


@pytest.mark.parametrize("column, name", [(1, "Wk"), (2, "Wd")])
def test_iso_weightings_against_their_table(column, name):
    f = np.array([row[0] for row in ISO_2631_TABLE])
    table = np.array([row[column] for row in ISO_2631_TABLE])
    np.testing.assert_allclose(filters.weighting(name).gain(f), table, rtol=0.006)


def _factored(p, f):
    """H = Hh Hl Ht Hs written as the reference sheet's factors (../shared/reference section 4.2)."""
    s = 2j * np.pi * f
    w1, w2, w3, w4 = (2 * np.pi * x for x in (p.f1, p.f2, p.f3, p.f4))
    h = s * s / (s * s + w1 * s / p.q1 + w1 ** 2) * w2 ** 2 / (s * s + w2 * s / p.q1 + w2 ** 2)
    h = h * (1 + s / w3) / (1 + s / (p.q2 * w4) + s * s / w4 ** 2)
    if p.f5 is not None:
        w5, w6 = 2 * np.pi * p.f5, 2 * np.pi * p.f6
        h = h * (1 + s / (p.q3 * w5) + s * s / w5 ** 2) / (1 + s / (p.q4 * w6) + s * s / w6 ** 2)
    return p.k * h


@pytest.mark.parametrize("name", ["Wb", "Wd"])
def test_comfort_weightings_are_the_standards_factors(name):
    f = np.array([0.3, 0.5, 1.0, 2.0, 4.0, 6.3, 10.0, 16.0, 40.0, 90.0])
    np.testing.assert_allclose(filters.weighting(name).response(f), _factored(filters.WEIGHTINGS[name], f),
                               rtol=1e-9)
    if name == "Wb":      # BS 6841's step: 0.4 below 2 Hz, about 0.4 (f6/f5)^2 = 1.02 over 5-10 Hz
        assert filters.weighting("Wb").gain(1.0)[0] == pytest.approx(0.4, rel=0.05)
        assert np.all(np.abs(filters.weighting("Wb").gain([5.0, 6.3, 8.0]) - 1.024) < 0.05)


@pytest.mark.parametrize("direction", ["vertical", "lateral"])
def test_sperling_weighting_against_its_tabulated_form(direction):
    f = np.array([0.5, 1.0, 2.0, 3.0, 5.0, 8.0, 12.0, 20.0, 39.0])
    table = 0.588 * np.sqrt((1.911 * f ** 2 + (0.25 * f ** 2) ** 2)
                            / ((1 - 0.277 * f ** 2) ** 2 + (1.563 * f - 0.0368 * f ** 3) ** 2))
    scale = 1.25 if direction == "lateral" else 1.0
    np.testing.assert_allclose(filters.sperling_weighting(direction).gain(f), scale * table, rtol=1e-9)
    assert filters.sperling_weighting(direction).gain([0.4, 41.0]).max() == 0.0       # GB 5599's band
    # the spectral form against Sperling's single-frequency formula with GB 5599's F(f), within 3 %
    amplitude = 50.0                                                                     # cm/s^2
    g = np.array([1.0, 2.0, 3.0, 5.0, 8.0])
    wz_spectral = (filters.sperling_weighting(direction).gain(g) * amplitude) ** 0.3
    wz_table = 0.896 * (amplitude ** 3 * filters.sperling_correction(g, direction) / g) ** 0.1
    np.testing.assert_allclose(wz_spectral, wz_table, rtol=0.03)


def test_butterworth_edges_and_a_sine_through_a_filter():
    assert filters.force_low_pass().gain(20.0)[0] == pytest.approx(math.sqrt(0.5), rel=1e-9)
    assert filters.force_low_pass().gain(5.0)[0] == pytest.approx(1.0, abs=1e-4)
    np.testing.assert_allclose(filters.car_body_band_pass().gain([0.4, 10.0]), math.sqrt(0.5), rtol=1e-9)
    t = np.arange(0, 10.0, 1 / RATE)
    x = 3.0 * np.sin(2 * np.pi * 4.0 * t) + 7.0                      # a sine on a constant
    h = filters.car_body_band_pass().response(4.0)[0]
    expected = 3.0 * abs(h) * np.sin(2 * np.pi * 4.0 * t + np.angle(h))
    np.testing.assert_allclose(filters.car_body_band_pass().apply(x, RATE), expected, atol=0.01)
    np.testing.assert_allclose(filters.force_low_pass().apply(x, RATE),
                               7.0 + 3.0 * abs(filters.force_low_pass().response(4.0)[0])
                               * np.sin(2 * np.pi * 4.0 * t + np.angle(filters.force_low_pass().response(4.0)[0])),
                               atol=0.01)


@pytest.mark.parametrize("axis, frequency", [(1, 1.0), (1, 2.0), (2, 1.0), (2, 6.0)])
def test_comfort_of_a_sine_is_its_closed_form(axis, frequency):
    t = np.arange(0, 60.0, 1 / RATE)
    floor = np.zeros((len(t), 3))
    floor[:, 2] = GRAVITY
    amplitude = 0.3                                                  # m/s^2
    floor[:, axis] += amplitude * np.sin(2 * np.pi * frequency * t)
    w = filters.weighting("Wd" if axis == 1 else "Wb").gain(frequency)[0]
    (first, last, value), = comfort.n_mv(floor, RATE)
    assert (first, last) == (0, 12)
    assert value == pytest.approx(6.0 * w * amplitude / math.sqrt(2.0), rel=1e-4)
    direction = "lateral" if axis == 1 else "vertical"
    b = filters.sperling_weighting(direction).gain(frequency)[0]
    np.testing.assert_allclose(comfort.sperling(floor[:, axis], RATE, direction), (b * 100 * amplitude) ** 0.3,
                               rtol=1e-4)
    with pytest.raises(ValueError, match="at least one 5 s window"):
        comfort.n_mv(floor[:int(4.9 * RATE)], RATE)


def test_sliding_mean_and_percentiles():
    s = np.linspace(0.0, 100.0, 801)
    centres, means = en14363.sliding(s, 2.0 * s + 1.0, 2.0, 0.5, 10.0, 20.0)
    np.testing.assert_allclose(centres, np.arange(11.0, 19.01, 0.5))
    np.testing.assert_allclose(means, 2.0 * centres + 1.0, rtol=1e-12)     # a line: its value at the centre
    _, wave = en14363.sliding(s, np.sin(2 * np.pi * s / 2.0), 2.0, 0.5, 0.0, 100.0)
    assert np.abs(wave).max() < 1e-3                                         # a 2 m wave averages out
    _, rms = en14363.sliding(s, 3.0 * np.sin(2 * np.pi * s / 5.0), 10.0, 1.0, 0.0, 100.0, power=2)
    np.testing.assert_allclose(np.sqrt(rms), 3.0 / math.sqrt(2.0), rtol=1e-3)
    values = np.linspace(-10.0, 5.0, 1001)
    assert en14363.extreme(values) == pytest.approx(np.percentile(values, 0.15))


def test_prudhomme_and_the_limits_by_hand():
    q0 = vehicle_parameters().static_wheel_load                              # 56.06 kN
    assert q0 == pytest.approx((8000 + 1650 + 1780) * GRAVITY / 2)
    assert en14363.prudhomme_limit(q0) == pytest.approx((10 + 2 * 56.064 / 3) * 1e3, rel=1e-4)   # 47.38 kN
    assert en14363.prudhomme_limit(80e3, alpha=0.85) == pytest.approx(0.85 * (10 + 160 / 3) * 1e3)
    assert [en14363.q_max_limit(v / 3.6) for v in (160, 200.1, 250, 300, 350)] == [200e3, 180e3, 180e3, 170e3,
                                                                                  160e3]
    assert en14363.bogie_rms_limit(3300 + 2 * 1780) == pytest.approx((12 - 6.86 / 5) / 2)


STEADY_KMH = 250.0


@pytest.fixture(scope="module")
def steady(tmp_path_factory):
    """An ideal-track run into a R 1000 m curve and on along it (4.5 s of the curve), saved as .npz."""
    from railderail_sim.vehicle.simulate import scenario, simulate
    track = TrackParameters(radius=1000.0, straight_in=50.0, transition_in=150.0, curve_length=400.0,
                            transition_out=100.0, straight_out=100.0)
    sc = replace(scenario(radius=1000.0, speed_kmh=STEADY_KMH), track=track, end_position=560.0)
    result = simulate(sc)
    assert result.status == "finished"
    path = tmp_path_factory.mktemp("assess") / "steady.npz"
    result.save(path)
    return result, path


def test_steady_curving_gives_the_quasi_static_closed_forms(steady):
    result, path = steady
    a = assess.assess(signals.from_npz(path))
    curve = [r for r in a.rows if r.section.startswith("curve R 1000 m")]
    vp, track, v = vehicle_parameters(), result.scenario.track, STEADY_KMH / 3.6
    aq = track.uncompensated_acceleration(v)                                  # 3.65 m/s^2
    theta = track.cant_angle
    normal = GRAVITY * math.cos(theta) + v * v / track.radius * math.sin(theta)
    car = vp.car_body_mass + 2 * vp.bogie_frame_mass + 4 * vp.wheelset_mass
    per_wheelset = 0.25 * vp.car_body_mass + 0.5 * vp.bogie_frame_mass + vp.wheelset_mass
    per_bogie = 0.5 * vp.car_body_mass + vp.bogie_frame_mass + 2 * vp.wheelset_mass

    def total(quantity, wheelsets):
        return sum(r.value for r in curve if r.quantity == quantity and r.wheelset in wheelsets)

    # the rails take the car's whole centrifugal force less the cant's share, outward (- y on a left curve)
    assert total("Y_qst", range(4)) == pytest.approx(-car * aq, rel=0.02)
    for bogie in (0, 1):
        assert total("Y_qst", (2 * bogie, 2 * bogie + 1)) == pytest.approx(-per_bogie * aq, rel=0.02)
    for i in range(4):              # each wheelset carries its share pressed onto the canted track
        assert total("Q_qst", (i,)) == pytest.approx(per_wheelset * normal, rel=0.02)
    # the floor reads the uncompensated acceleration turned by the car body's roll on its suspension
    arrays = result.arrays()
    position = arrays["position"]
    roll = float(np.median(arrays["body_states"][(position > 250.0), 0, 2]))
    ydd_qst, = [r for r in curve if r.quantity == "ydd_qst"]
    assert ydd_qst.value == pytest.approx(aq * math.cos(roll) + normal * math.sin(roll), rel=0.02)
    assert ydd_qst.passes is False                                             # 250 km/h is far above balance
    outer = [r for r in curve if r.quantity == "Y_qst" and r.side == "right"]
    assert all(r.value < 0 for r in outer)                                     # track axes: the outer rail pushed right


def test_assessment_rows_and_json(steady):
    _, path = steady
    a = assess.assess(signals.from_npz(path))
    d = a.as_dict()
    assert set(d) == {"static_wheel_load_kN", "standard", "run_conditions", "quantities"}
    assert d["static_wheel_load_kN"] == pytest.approx(56.064, rel=1e-4)
    for row in d["quantities"]:
        assert set(row) == {"quantity", "name", "section", "wheelset", "side", "value", "limit", "unit", "passes"}
        assert row["quantity"] in assess.QUANTITIES
    found = {row["quantity"] for row in d["quantities"]}
    assert found == set(assess.QUANTITIES)
    y = [row for row in d["quantities"] if row["quantity"] == "sum_Y_2m"][0]
    assert y["unit"] == "kN" and y["limit"] == pytest.approx(47.376, rel=1e-3) and y["side"] is None
    table = a.markdown()
    assert "| curve R 1000 m" in table and "Closest to its limit" in table
    # rows in words with units, the magnitude against the limit and the sign apart: the outer wheels' Y_qst
    # pushes right (-), 250 km/h on R 1000 m with 175 mm cant is 558 mm of cant deficiency
    assert "sum_Y_2m" not in table and "| track-shift force ΣY, 2 m mean |" in table
    row = next(line for line in table.splitlines() if "| quasi-static lateral wheel force Y_qst |" in line)
    cells = [c.strip() for c in row.split("|")]
    assert float(cells[4]) > 0 and cells[5] == "−" and cells[7] == "kN"
    (curve,) = d["run_conditions"]["curves"]
    e, g = 1.5, 9.81
    aq = TrackParameters(radius=1000.0).uncompensated_acceleration(STEADY_KMH / 3.6)
    assert curve["cant_deficiency_mm"] == pytest.approx(e * aq / g * 1e3, rel=0.01) and curve["outside_test_conditions"]
    assert f"up to {curve['cant_deficiency_mm']:.0f} mm, OUTSIDE the standard's test conditions (up to 165 mm" in table
    assert d["run_conditions"]["comfort_indicative"] and "N_MV from" in table and "indicative" in table


def test_bad_input_is_one_line(tmp_path, steady):
    result, _ = steady
    arrays = dict(result.arrays())
    del arrays["vertical_force"]
    with pytest.raises(ValueError, match="has no vertical_force"):
        signals.from_arrays(arrays)
    short = {k: v[:100] for k, v in result.arrays().items()}
    with pytest.raises(ValueError, match="no track section of at least 100 m"):
        assess.assess(signals.from_arrays(short))
    np.savez(tmp_path / "foreign.npz", x=np.zeros(3))
    with pytest.raises(ValueError, match="has no time, position"):
        signals.from_npz(tmp_path / "foreign.npz")
    with pytest.raises(ValueError, match="no such file"):
        signals.from_npz(tmp_path / "missing.npz")
    (tmp_path / "notes.npz").write_text("speed 280 km/h, R 1000 m\n")
    with pytest.raises(ValueError, match=r"notes.npz is not a .npz archive .* starts with b'spee'") as refused:
        signals.from_npz(tmp_path / "notes.npz")
    assert "pickle" not in str(refused.value)


def test_a_recording_gives_the_runs_force_quantities(tmp_path, steady):
    from railderail_monitor.recording.assess import run_signals
    from railderail_monitor.recording.recorder import record_run

    result, path = steady
    mcap = tmp_path / "steady.mcap"
    record_run(mcap, result)
    from_run = assess.assess(signals.from_npz(path))
    from_recording = assess.assess(run_signals(mcap))
    forces = ("sum_Y_2m", "Y_Q_2m", "Q_max", "Q_qst", "Y_qst", "sum_Y_rms")
    key = lambda r: (r.quantity, r.section, r.wheelset, r.side)           # noqa: E731
    run_rows = {key(r): r.value for r in from_run.rows if r.quantity in forces and r.quantity != "sum_Y_rms"}
    rec_rows = {key(r): r.value for r in from_recording.rows}
    assert {q for q, *_ in rec_rows} == set(forces)
    for k, value in run_rows.items():
        assert rec_rows[k] == pytest.approx(value, rel=1e-9, abs=1e-6)
    assert "carries no accelerations" in from_recording.notes[0]


def test_assess_command(tmp_path, steady, capsys):
    import json
    from railderail_sim.cli import main

    _, path = steady
    assert main(["assess", str(path), "--json", "--plot", str(tmp_path / "a.png")]) == 0
    d = json.loads(capsys.readouterr().out)
    assert set(d) == {"static_wheel_load_kN", "standard", "run_conditions", "quantities"}
    assert (tmp_path / "a.png").stat().st_size > 10_000
    assert main(["assess", str(path)]) == 0
    assert capsys.readouterr().out.startswith(f"Assessment of {path}")
    for argv, message in ((["assess", str(tmp_path / "none.npz")], "no such file"),
                          (["assess", str(tmp_path / "a.png")], "assess reads a run (.npz"),
                          (["assess"], "no file given"),
                          (["assess", str(path), "--plot", str(tmp_path / "a.txt")], "must end in")):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1


def test_a_runs_start_up_can_be_left_out(steady):
    result, path = steady
    sig = signals.from_npz(path)
    later = sig.after(100.0)
    assert later.position[0] >= 100.0 and later.position[1] - later.position[0] == pytest.approx(
        sig.position[1] - sig.position[0])
    assert len(later.time) == len(later.vertical_force) == len(later.floor["front"]) < len(sig.time)
    assert min(sec.start for sec in assess.assess(later).sections) >= 100.0
    with pytest.raises(ValueError, match="before the assessment's start at 900 m"):
        sig.after(900.0)
