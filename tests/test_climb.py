"""The wheel-climb rig (`methods.climb`, `railderail climb`) against outside references: Nadal's limit at large
attack angle (Nadal 1908; Wu & Wilson in Iwnicki's Handbook, 2006; Marquis & Greif, ASME JRC2011-56064: the
limit holds when the lateral creep force is saturated), tan(delta) on a frictionless flange (the force
balance of the contact plane), the L/V at the climb rising as the attack angle falls (Wu & Wilson; Elkins &
Wu 1999) and the climb distance falling as it rises (Wu & Wilson; TCRP Report 71 Vol. 5, eq. 2.4)."""
import json
import math

import pytest

from railderail_sim.cli import main
from railderail_sim.contact.nadal import nadal_limit
from railderail_sim.methods import climb as c
from railderail_sim.methods.wheel_rail_pair import build_pair


@pytest.fixture(scope="module")
def pair():
    return build_pair()


@pytest.fixture(scope="module")
def curve(pair):
    """Climbs at three attack angles, friction 0.3."""
    return {a: c.climb(attack_angle_mrad=a, friction=0.3, pair=pair) for a in (3.0, 10.0, 30.0)}


def test_large_attack_angle_climbs_at_nadals_limit(curve):
    # saturated lateral creep (30 mrad): within 2 % of Nadal at the contact angle reached (69.5 deg, 1.318)
    run = curve[30.0]
    assert run.climbed
    assert run.nadal_limit == pytest.approx(nadal_limit(run.max_contact_angle_rad, 0.3), rel=1e-12)
    assert math.degrees(run.max_contact_angle_rad) == pytest.approx(69.5, abs=0.5)
    assert run.climb_lv == pytest.approx(run.nadal_limit, rel=0.02)
    assert run.climb_lv >= run.nadal_limit * 0.995      # Nadal is the lower bound: creep is at most saturated


def test_frictionless_flange_climbs_at_tan_delta(pair):
    run = c.climb(attack_angle_mrad=10.0, friction=0.0, pair=pair)
    assert run.climbed
    assert run.climb_lv == pytest.approx(math.tan(run.climb_contact_angle_rad), rel=1e-3)
    assert run.climb_lv == pytest.approx(math.tan(run.max_contact_angle_rad), rel=5e-3)
    assert run.nadal_limit == pytest.approx(math.tan(run.max_contact_angle_rad), rel=1e-12)


def test_lv_at_climb_rises_as_the_attack_angle_falls(curve):
    lv = [curve[a].climb_lv for a in (30.0, 10.0, 3.0)]
    assert lv[0] < lv[1] < lv[2]
    assert lv[2] > 1.15 * lv[0]                          # at 3 mrad well above Nadal (Elkins & Wu's curves)


def test_climb_distance_falls_as_the_attack_angle_rises(curve):
    d = [curve[a].climb_distance_m for a in (3.0, 10.0, 30.0)]
    assert d[0] > d[1] > d[2] > 0.0


def test_result_does_not_depend_on_the_ramp(pair, curve):
    slow = c.climb(attack_angle_mrad=10.0, friction=0.3, pair=pair, ramp_per_s=0.5 * c.RAMP_PER_S)
    run = curve[10.0]
    assert slow.climb_lv == pytest.approx(run.climb_lv, rel=0.01)
    assert slow.climb_distance_m == pytest.approx(run.climb_distance_m, rel=0.05)
    assert slow.peak_lv == pytest.approx(run.peak_lv, rel=0.02)


@pytest.mark.parametrize("kwargs, message", [
    (dict(attack_angle_mrad=60.0), "attack angle --attack-angle-mrad 60 mrad is outside the accepted range [0, 50]"),
    (dict(attack_angle_mrad=-1.0), "attack angle --attack-angle-mrad -1 mrad"),
    (dict(friction=1.5), "friction coefficient --friction 1.5 is outside the accepted range [0, 1]"),
    (dict(speed_kmh=0.0), "speed --speed-kmh 0 km/h is outside the accepted range [1, 300]"),
    (dict(wheel_load_kn=0.0), "wheel load --wheel-load-kn 0 kN is outside the accepted range (0, 500]"),
    (dict(creep="coulomb"), "creep law --creep 'coulomb' is unknown"),
    (dict(creep="linear", friction=0.0), "creep law --creep linear has no friction limit"),
    (dict(ramp_per_s=0.0), "lateral force ramp 0 wheel loads per s is outside the accepted range (0, 10]"),
])
def test_bad_input_names_the_value_and_the_range(kwargs, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")
                       .replace("]", r"\]")):
        c.climb(**kwargs)


def test_command_line_errors_are_one_line(capsys):
    assert main(["climb", "--friction", "0.3,0.5"]) == 2
    assert "several friction coefficients need --sweep-attack-angle-mrad" in capsys.readouterr().err
    assert main(["climb", "--sweep-attack-angle-mrad", "5,x"]) == 2
    assert "--sweep-attack-angle-mrad '5,x' is not a comma-separated list of numbers" in capsys.readouterr().err
    assert main(["climb", "--plot", "climb.txt"]) == 2
    assert "must end in" in capsys.readouterr().err


def test_command_line_sweep_json_and_plot(tmp_path, capsys):
    plot = tmp_path / "sweep.png"
    assert main(["climb", "--sweep-attack-angle-mrad", "20,30", "--friction", "0.3,0.5", "--json",
                 "--plot", str(plot)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert plot.stat().st_size > 0
    rows = out["sweep"]
    assert [(r["friction"], r["attack_angle_rad"]) for r in rows] == [(0.3, 0.02), (0.3, 0.03), (0.5, 0.02),
                                                                       (0.5, 0.03)]
    for r in rows:
        assert {"climb_lv", "peak_lv", "climb_distance_m", "nadal_limit", "max_contact_angle_rad"} <= set(r)
        assert r["climb_lv"] == pytest.approx(r["nadal_limit"], rel=0.05)
