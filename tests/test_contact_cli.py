"""`railderail contact-geometry` and `railderail contact-case` through railderail_sim.cli.main."""
import contextlib
import io
import json
import math

import numpy as np
import pytest

from railderail_sim import cli, profiles

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def run_json(capsys, *args):
    assert cli.main([*args, "--json"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    return json.loads(captured.out)


def run_error(capsys, *args):
    assert cli.main(list(args)) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("railderail: error: ")
    return lines[0]


@pytest.fixture(scope="module")
def geometry_lm():
    out = io.StringIO()                      # module scope: capsys is per test, capture by hand
    with contextlib.redirect_stdout(out):
        assert cli.main(["contact-geometry", "--json"]) == 0
    return json.loads(out.getvalue())


# ------------------------------------------------------------------------------------------ geometry
def test_geometry_json_keys_and_si_units(geometry_lm):
    r = geometry_lm
    for key in ("equivalent_conicity", "equivalent_conicity_by_amplitude", "flange_height_m",
                "max_contact_angle_rad", "nadal_limit", "rail_head_width_m", "tables"):
        assert key in r
    t = r["tables"]
    keys = ["y_m", "delta_r_m", "roll_rad", "contact_angle_left_rad", "contact_angle_right_rad",
            "rolling_radius_left_m", "rolling_radius_right_m", "wheel_contact_y_left_m",
            "wheel_contact_y_right_m",
            "rail_contact_y_left_m", "rail_contact_y_right_m", "two_point_left", "two_point_right",
            "wheel_lift_left_m", "wheel_lift_right_m"]
    n = len(t["y_m"])
    assert n == 241                                    # -12 ... 12 mm in 0.1 mm steps (defaults)
    for key in keys:
        assert len(t[key]) == n, key
    assert t["y_m"][0] == pytest.approx(-0.012) and t["y_m"][-1] == pytest.approx(0.012)   # metres
    assert 0.45 < min(t["rolling_radius_left_m"]) < max(t["rolling_radius_left_m"]) < 0.5
    assert all(isinstance(v, bool) for v in t["two_point_left"])
    amps = [row["amplitude_m"] for row in r["equivalent_conicity_by_amplitude"]]
    assert amps == pytest.approx([k * 1e-3 for k in range(1, 9)])
    for row in r["equivalent_conicity_by_amplitude"]:
        assert row["harmonic_conicity"] == pytest.approx(row["equivalent_conicity"], rel=0.05)


def test_geometry_lm_values(geometry_lm):
    r = geometry_lm
    assert 0.0277 <= r["flange_height_m"] <= 0.0279
    assert 69.0 <= math.degrees(r["max_contact_angle_rad"]) <= 70.0
    t = math.tan(r["max_contact_angle_rad"])
    assert r["nadal_limit"] == pytest.approx((t - 0.3) / (1 + 0.3 * t), rel=1e-12)
    # without the contact search: the steepest chord between the profile's own points from the flange
    # tip to the rolling circle; the climbing wheelset's roll (a few mrad) tilts the contact a little more
    w = profiles.lm()
    flank = (w.y[:-1] >= w.y[np.argmax(w.z)]) & (w.y[1:] <= 0.0)
    steepest = float(np.max(np.arctan(-np.diff(w.z) / np.diff(w.y))[flank]))
    assert 0.0 <= r["max_contact_angle_rad"] - steepest < math.radians(0.5)
    t = math.tan(steepest)
    assert r["nadal_limit"] == pytest.approx((t - 0.3) / (1 + 0.3 * t), abs=0.02)
    assert 0.10 <= r["equivalent_conicity"] <= 0.13
    assert r["equivalent_conicity_amplitude_m"] == pytest.approx(0.003)
    assert r["rail_head_width_m"] == pytest.approx(0.07196, abs=1e-4)
    t = r["tables"]
    i0 = t["y_m"].index(0.0)
    assert t["delta_r_m"][i0] == pytest.approx(0.0, abs=1e-12)
    assert t["contact_angle_left_rad"][i0] == pytest.approx(t["contact_angle_right_rad"][i0], abs=1e-12)


def test_geometry_human_text_and_friction(capsys):
    assert cli.main(["contact-geometry", "--wheel", "s1002", "--friction", "0.36", "--y-max-mm", "10",
                     "--step-mm", "0.2"]) == 0
    out = capsys.readouterr().out
    assert "flange height" in out and "28.00 mm" in out
    assert "Nadal limit Y/Q" in out and "mu 0.36" in out
    assert "equivalent conicity" in out


def test_geometry_plot_writes_png(capsys, tmp_path):
    path = tmp_path / "geometry.png"
    r = run_json(capsys, "contact-geometry", "--step-mm", "0.25", "--plot", str(path))
    assert r["plot"] == str(path)
    assert path.read_bytes()[:8] == PNG_MAGIC
    assert [p.name for p in tmp_path.iterdir()] == ["geometry.png"]         # no temporary file left


def test_geometry_without_inclination_changes_conicity(capsys, geometry_lm):
    r = run_json(capsys, "contact-geometry", "--inclination", "0", "--step-mm", "0.2")
    assert r["inputs"]["inclination_rad"] == 0.0
    assert r["equivalent_conicity"] != pytest.approx(geometry_lm["equivalent_conicity"], rel=1e-3)


# ------------------------------------------------------------------------------------------ case
@pytest.mark.parametrize("model", ["hertz", "fastsim", "discrete"])
def test_case_load_sum_and_mirror_symmetry(capsys, model):
    r = run_json(capsys, "contact-case", "--contact", model, "--load-kn", "120")
    left, right = r["wheels"]
    assert left["P_N"] + right["P_N"] == pytest.approx(120e3, rel=1e-3)
    assert r["totals"]["force_N"][2] == pytest.approx(120e3, rel=1e-3)
    assert r["totals"]["force_N"][1] == pytest.approx(0.0, abs=1e-6 * 120e3)
    assert left["patch_count"] == right["patch_count"] >= 1
    for pl, pr in zip(left["patches"], right["patches"]):
        for key in ("rail_y_m", "wheel_y_m", "contact_angle_rad", "normal_force_N", "hertz_a_m",
                    "hertz_b_m", "creep_ellipse_a_m", "creep_ellipse_b_m", "length_m", "width_m"):
            assert pl[key] == pytest.approx(pr[key], rel=1e-9, abs=1e-12), key
        for group in ("creepage", "creep_force"):
            for key in pl[group]:
                assert pl[group][key] == pytest.approx(pr[group][key], rel=1e-9, abs=1e-12), key
    p = left["patches"][0]
    # SI units: a tread patch of a few mm, a normal force of tens of kN, a small contact angle
    assert 1e-3 < p["hertz_a_m"] < 2e-2 and 1e-3 < p["hertz_b_m"] < 2e-2
    assert 1e-3 < p["creep_ellipse_a_m"] < 2e-2 and 1e-3 < p["creep_ellipse_b_m"] < 2e-2
    assert 4e4 < p["normal_force_N"] < 8e4
    assert abs(p["contact_angle_rad"]) < 0.2
    assert -0.03 < p["rail_y_m"] < 0.03 and -0.03 < p["wheel_y_m"] < 0.03


def test_case_flange_contact_at_10_mm(capsys):
    r = run_json(capsys, "contact-case", "--lateral-mm", "10", "--yaw-mrad", "5")
    left = r["wheels"][0]
    assert max(p["contact_angle_rad"] for p in left["patches"]) > 1.0
    assert left["Q_over_P"] > 0.5
    assert r["pose"]["roll_source"] == "rigid contact"
    assert r["wheels"][0]["P_N"] + r["wheels"][1]["P_N"] == pytest.approx(r["inputs"]["load_N"], rel=1e-3)


def test_case_given_roll_and_free_spin(capsys):
    r = run_json(capsys, "contact-case", "--roll-mrad", "0.5", "--spin", "free")
    assert r["pose"]["roll_rad"] == pytest.approx(5e-4) and r["pose"]["roll_source"] == "input"
    assert r["totals"]["force_N"][0] == pytest.approx(0.0, abs=1e-3)
    assert r["wheels"][0]["P_N"] != pytest.approx(r["wheels"][1]["P_N"], rel=1e-3)


def test_case_halfspace_and_plot(capsys, tmp_path):
    path = tmp_path / "case.png"
    r = run_json(capsys, "contact-case", "--contact", "halfspace", "--grid", "32", "--plot", str(path))
    p = r["wheels"][0]["patches"][0]
    hs, kp = p["halfspace"], p["discrete"]
    assert hs["converged"] and not hs["truncated"]
    assert hs["normal_force_N"] == pytest.approx(p["normal_force_N"], rel=1e-6)
    # the report's KP patch is KP over the grid's cells of the interpenetration run (the fine picture); the
    # vehicle core's load, from wheelset.KP_STRIPS strips at fixed fractions of the patch, within 1e-3 of it on
    # the tread (docs/contact-models.md)
    assert kp["normal_force_N"] == pytest.approx(p["normal_force_N"], rel=1e-3)
    # the half-space and Kik-Piotrowski patches of the centred tread contact agree within ~25 %
    assert hs["length_m"] == pytest.approx(kp["length_m"], rel=0.25)
    assert hs["width_m"] == pytest.approx(kp["width_m"], rel=0.25)
    assert path.read_bytes()[:8] == PNG_MAGIC


def test_case_exact_rolling(capsys):
    """--contact exact: the hertz model's fields (same normal force, creepages and SHE forces), the exact
    normal patch, and the exact rolling solution beside the creep laws on the Hertz ellipse."""
    ref = run_json(capsys, "contact-case", "--lateral-mm", "8.7")
    r = run_json(capsys, "contact-case", "--lateral-mm", "8.7", "--contact", "exact", "--grid", "32")
    assert r["inputs"]["exact_rolling"] and r["inputs"]["halfspace"] and not ref["inputs"]["exact_rolling"]
    p, q = r["wheels"][0]["patches"][0], ref["wheels"][0]["patches"][0]
    for key in ("normal_force_N", "hertz_a_m", "hertz_b_m"):
        assert p[key] == pytest.approx(q[key], rel=1e-9)
    assert p["creep_force"] == pytest.approx(q["creep_force"], rel=1e-9)
    e = p["exact_rolling"]
    assert e["converged"] and e["residual"] < 1e-6 and 0.0 <= e["stick_fraction"] <= 1.0
    assert set(e["laws"]) == {"she", "polach", "fastsim"}
    assert e["laws"]["she"] == pytest.approx(q["creep_force"], rel=1e-9)
    # the flange-root patch (31 deg, xi_x = -1.3e-2, spin -1.1 1/m) slides: |F| ~ mu N, Fx close to SHE's
    f = e["creep_force"]
    assert math.hypot(f["longitudinal_N"], f["lateral_N"]) == pytest.approx(0.3 * p["normal_force_N"], rel=0.03)
    assert f["longitudinal_N"] == pytest.approx(q["creep_force"]["longitudinal_N"], rel=0.05)
    # the wheels' totals carry the exact rolling forces; SHE's, beside them, are the hertz model's totals
    for w, v in zip(r["wheels"], ref["wheels"]):
        assert w["creep_forces"] == "exact rolling" and v["creep_forces"] == "she" and "laws" not in v
        assert set(w["laws"]) == {"she", "polach", "fastsim"}
        for key in ("Q_N", "P_N", "Q_over_P", "longitudinal_force_on_rail_N", "force_on_rail_N"):
            assert w["laws"]["she"][key] == pytest.approx(v[key], rel=1e-9, abs=1e-6), key
        exact = [p["exact_rolling"]["creep_force"] for p in w["patches"]]
        assert w["longitudinal_force_on_rail_N"] == pytest.approx(-sum(e["longitudinal_N"] for e in exact), rel=1e-12)
        assert w["longitudinal_force_on_rail_N"] == pytest.approx(w["force_on_rail_N"][0], rel=1e-12)
        assert w["Q_N"] != pytest.approx(v["Q_N"], rel=1e-3)
    assert r["totals"]["force_N"][0] == pytest.approx(
        -sum(w["force_on_rail_N"][0] for w in r["wheels"]), rel=1e-12)
    assert cli.main(["contact-case", "--lateral-mm", "8.7", "--contact", "exact", "--grid", "32"]) == 0
    out = capsys.readouterr().out
    assert "creep forces exact rolling" in out and "with fastsim" in out
    assert "exact rolling" in out and "fastsim" in out and "stick" in out


def test_case_human_text(capsys):
    assert cli.main(["contact-case", "--lateral-mm", "-3", "--contact", "discrete"]) == 0
    out = capsys.readouterr().out
    assert "left wheel" in out and "right wheel" in out and "discrete (KP)" in out and "kN" in out


# ------------------------------------------------------------------------------------------ errors
@pytest.mark.parametrize("args, words", [
    (["contact-case", "--lateral-mm", "80"], ["lateral shift 80 mm", "accepted range"]),
    (["contact-case", "--load-kn", "-5"], ["load", "-5 kN", "(0, 1000]"]),
    (["contact-case", "--wheel", "no-such-wheel"], ["'no-such-wheel'", "lm"]),
    (["contact-case", "--yaw-mrad", "500"], ["yaw", "500 mrad", "[-100, 100]"]),
    (["contact-geometry", "--inclination", "1/2"], ["'1/2'", "0..1/10"]),
    (["contact-geometry", "--gauge-mm", "1380"], ["gauge 1380 mm", "does not fit"]),
    (["contact-geometry", "--amplitude-mm", "20"], ["amplitude", "20 mm", "12]"]),
    (["contact-geometry", "--plot", "/no/such/folder/x.png"], ["'/no/such/folder/x.png'", "does not exist"]),
])
def test_bad_input_gives_one_line_and_status_2(capsys, args, words):
    line = run_error(capsys, *args)
    for word in words:
        assert word in line


def test_unreadable_profile_file(capsys, tmp_path):
    bad = tmp_path / "wheel.txt"
    bad.write_text("# kind: wheel\n1 2\nnot numbers\n")
    line = run_error(capsys, "contact-geometry", "--wheel", str(bad))
    assert str(bad) in line or "wheel.txt" in line
    line = run_error(capsys, "contact-case", "--rail", str(tmp_path / "missing.prr"))
    assert "missing.prr" in line
