"""Track alignment: curvature and cant ramps, exact heading, position by quadrature, defect shape."""
import math

import pytest
from scipy.integrate import quad

from railderail_sim.track import alignment as A


@pytest.fixture(scope="module")
def track():
    return A.pack_track(200.0, 200.0, 1000.0, 200.0, 200.0, 1000.0, 0.175)


def test_curvature_and_cant_follow_table_2(track):
    assert A.curvature(track, 100.0) == (0.0, 0.0)
    k, dk = A.curvature(track, 300.0)
    assert k == pytest.approx(0.5e-3) and dk == pytest.approx(1e-3 / 200.0)
    assert A.curvature(track, 800.0)[0] == pytest.approx(1e-3)
    assert A.curvature(track, 1500.0)[0] == pytest.approx(0.5e-3)
    # cant: 175 mm over 1.5 m between rail centres, the left curve raises the right rail (negative roll)
    assert A.cant(track, 800.0)[0] == pytest.approx(-math.asin(0.175 / 1.5))
    assert A.cant(track, 300.0)[0] == pytest.approx(-math.asin(0.0875 / 1.5))
    assert [A.section(track, s) for s in (100, 300, 800, 1500, 1700)] == [0, 1, 2, 1, 0]


def test_right_curve_is_mirror_of_left(track):
    right = A.pack_track(200.0, 200.0, 1000.0, 200.0, 200.0, 1000.0, 0.175, direction=-1)
    for s in (150.0, 333.0, 900.0, 1555.0):
        assert A.curvature(right, s)[0] == -A.curvature(track, s)[0]
        assert A.cant(right, s)[0] == -A.cant(track, s)[0]
        xl, yl, hl, _ = A.frame(track, s)
        xr, yr, hr, _ = A.frame(right, s)
        assert xr == pytest.approx(xl, abs=1e-9) and yr == pytest.approx(-yl, abs=1e-9)
        assert hr == pytest.approx(-hl, abs=1e-12)


@pytest.mark.parametrize("s", [0.0, 123.4, 399.99, 400.01, 777.7, 1399.5, 1612.3, 1850.0])
def test_position_matches_quadrature_of_the_heading(track, s):
    h = lambda u: A._heading_exact(track, u)  # noqa: E731
    pts = [p for p in (200.0, 400.0, 1400.0, 1600.0) if p < s]
    x = quad(lambda u: math.cos(h(u)), 0.0, s, points=pts or None, limit=400, epsabs=1e-12)[0]
    y = quad(lambda u: math.sin(h(u)), 0.0, s, points=pts or None, limit=400, epsabs=1e-12)[0]
    X, Y, heading, _ = A.frame(track, s)
    assert X == pytest.approx(x, abs=2e-7) and Y == pytest.approx(y, abs=2e-7)


def test_heading_of_the_curve_is_the_arc_angle(track):
    # heading at the end = 2 transitions (each L/(2R)) + circle L/R
    assert A.frame(track, 1800.0)[2] == pytest.approx(200 / 2000 * 2 + 1.0)


@pytest.mark.parametrize("s", [-50.0, 0.0, 200.0, 300.0, 400.0, 777.7, 1400.0, 1555.0, 1800.0, 2500.0])
def test_a_bodys_track_lookup_is_frame_curvature_and_cant_bit_for_bit(track, s):
    """`body_frame` (the vehicle core's one lookup per body) gives what frame, curvature and cant give, to
    the last bit, at section breaks and beyond the line's ends too."""
    X, Y, heading, roll = A.frame(track, s)
    assert A.body_frame(track, s) == (X, Y, heading, roll, A.curvature(track, s)[0], A.cant(track, s)[1])
