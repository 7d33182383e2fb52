"""Hertz elliptic normal contact (railderail_sim/contact/hertz.py)."""
import math

import numpy as np
import pytest
from scipy.special import ellipe, ellipk, ellipkm1

from railderail_sim.contact import hertz as hz

E_STEEL = 2.1e11
NU_STEEL = 0.28
E_STAR = hz.combined_modulus(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL)   # = E / (2 (1 - nu^2))

# Timoshenko & Goodier, Theory of Elasticity (2nd ed. 1951, §140): coefficients m, n of the Hertz
# semi-axes a = m (3 N / (4 E* (A + B)))^(1/3), b = n (...)^(1/3), cos(theta) = (B - A)/(A + B).
# (theta [deg], m, n) as printed.
MN_TABLE = [
    (0.5, 61.4, 0.1018), (1.0, 36.89, 0.1314), (1.5, 27.48, 0.1522), (2.0, 22.26, 0.1691),
    (3.0, 16.50, 0.1964), (4.0, 13.31, 0.2188), (6.0, 9.790, 0.2552), (8.0, 7.860, 0.2850),
    (10.0, 6.604, 0.3112), (20.0, 3.813, 0.4123), (30.0, 2.731, 0.4930), (35.0, 2.397, 0.5300),
    (40.0, 2.136, 0.5670), (45.0, 1.926, 0.6040), (50.0, 1.754, 0.6410), (55.0, 1.611, 0.6780),
    (60.0, 1.486, 0.7170), (65.0, 1.378, 0.7590), (70.0, 1.284, 0.8020), (75.0, 1.202, 0.8460),
    (80.0, 1.128, 0.8930), (85.0, 1.061, 0.9440), (90.0, 1.000, 1.000),
]
# rows checked to the printed precision (+-1.5 units of the last printed digit)
MN_STRICT = (30.0, 40.0, 45.0, 50.0, 60.0, 80.0, 85.0, 90.0)


def _mn(theta_deg, guarded=True):
    c = math.cos(math.radians(theta_deg))
    A, B = (1.0 - c) / 2.0, (1.0 + c) / 2.0       # A + B = 1, B >= A
    if guarded:
        ac, bc, _ = hz.hertz_shape(A, B, 1.0)
    else:
        gm = 1e-4
        ac, bc, _ = hz._shape_core(A, B, 1.0, gm, hz._ratio_of_g(gm))
    f = 0.75 ** (1.0 / 3.0)                         # (3 N/(4 E* (A+B)))^(1/3) with N = E* = A+B = 1
    return ac / f, bc / f


def test_elliptic_integrals_against_scipy():
    for k in (0.0, 1e-6, 0.1, 0.5, 0.9, 0.99, 0.999999):
        kc = math.sqrt((1 - k) * (1 + k))
        K, E, KmE = hz.ellip_ke(k, kc)
        assert K == pytest.approx(ellipkm1(kc * kc), rel=1e-13)   # K(m) with 1 - m = kc^2 given
        assert E == pytest.approx(ellipe(k * k), rel=1e-13)
        assert K - E == pytest.approx(KmE, rel=1e-9, abs=1e-15)
    # complementary modulus far below sqrt(machine eps): K ~ ln(4/kc)
    K, E, _ = hz.ellip_ke(1.0, 1e-30)
    assert K == pytest.approx(math.log(4e30), rel=1e-12)
    assert E == pytest.approx(1.0, rel=1e-12)
    # e -> 0: (K - E)/e^2 -> pi/4 without cancellation
    K, s = hz.ellip_k_s(1e-9, 1.0)
    assert K * s == pytest.approx(math.pi / 4.0, rel=1e-14)


def test_sphere_on_plane_and_two_spheres():
    N = 1.0e5
    for R1, R2 in ((0.46, math.inf), (0.46, 0.3), (0.05, 0.08)):
        R = 1.0 / (1.0 / R1 + (0.0 if math.isinf(R2) else 1.0 / R2))   # effective radius
        A = B = 1.0 / (2.0 * R)
        a, b, delta, p0 = hz.hertz_patch(A, B, E_STAR, N)
        a_ref = (3.0 * N * R / (4.0 * E_STAR)) ** (1.0 / 3.0)
        assert a == pytest.approx(a_ref, rel=1e-12)
        assert b == pytest.approx(a_ref, rel=1e-12)
        assert delta == pytest.approx(a_ref ** 2 / R, rel=1e-12)
        assert p0 == pytest.approx(3.0 * N / (2.0 * math.pi * a_ref ** 2), rel=1e-12)
        # N = 4/3 E* sqrt(R) delta^1.5
        _, _, C = hz.hertz_shape(A, B, E_STAR)
        assert C == pytest.approx(4.0 / 3.0 * E_STAR * math.sqrt(R), rel=1e-12)


@pytest.mark.parametrize("row", [r for r in MN_TABLE if r[0] in MN_STRICT])
def test_mn_table_printed_precision(row):
    theta, m, n = row
    mc, nc = _mn(theta)
    assert abs(mc - m) <= 1.5e-3 * max(1.0, 10 ** math.floor(math.log10(m)))
    assert abs(nc - n) <= 1.5e-3


def test_mn_table_all_rows_within_table_accuracy():
    # the classic table carries small errors (Cooper 1969); every row agrees within 0.8 %
    worst = 0.0
    for theta, m, n in MN_TABLE:
        mc, nc = _mn(theta, guarded=False)
        worst = max(worst, abs(mc / m - 1.0), abs(nc / n - 1.0))
    assert worst < 8e-3


def test_johnson_relations_hold():
    # eqs. 4.36-4.38 of Johnson (1985) with the computed a, b, delta, p0
    A, B, N = 1.1, 4.7, 8.0e4
    a, b, delta, p0 = hz.hertz_patch(A, B, E_STAR, N)
    assert a > b                                  # long axis along the smaller curvature (x)
    e2 = 1.0 - (b / a) ** 2
    K, E = ellipk(e2), ellipe(e2)
    assert A == pytest.approx(p0 / E_STAR * b / (e2 * a * a) * (K - E), rel=1e-10)
    assert B == pytest.approx(p0 / E_STAR * b / (e2 * a * a) * ((a / b) ** 2 * E - K), rel=1e-10)
    assert delta == pytest.approx(p0 / E_STAR * b * K, rel=1e-10)
    assert N == pytest.approx(2.0 / 3.0 * math.pi * a * b * p0, rel=1e-12)


def test_force_delta_consistency():
    for A, B in ((1.0, 1.0), (1.16, 1.67), (1.16, 40.0), (30.0, 1.2), (1.0, 200.0)):
        for N in (1.0e3, 5.0e4, 2.0e5):
            a, b, delta, p0 = hz.hertz_patch(A, B, E_STAR, N)
            assert hz.hertz_force(A, B, E_STAR, delta) == pytest.approx(N, rel=1e-12)
            ac, bc, C = hz.hertz_shape(A, B, E_STAR)
            assert a == pytest.approx(ac * N ** (1 / 3), rel=1e-14)
            assert C * delta ** 1.5 == pytest.approx(N, rel=1e-12)


def test_swap_symmetry():
    for A, B in ((0.7, 3.2), (1.16, 1.67), (2.0, 150.0)):
        a1, b1, d1, p1 = hz.hertz_patch(A, B, E_STAR, 6.0e4)
        a2, b2, d2, p2 = hz.hertz_patch(B, A, E_STAR, 6.0e4)
        assert a1 == pytest.approx(b2, rel=1e-13)
        assert b1 == pytest.approx(a2, rel=1e-13)
        assert d1 == pytest.approx(d2, rel=1e-13)
        assert p1 == pytest.approx(p2, rel=1e-13)


def test_near_conformal_guard():
    assert hz.RATIO_MAX == pytest.approx(hz._ratio_of_g(hz.G_MIN), rel=1e-14)
    # just inside the guard: ratio solved, a/b < 30
    a, b, _ = hz.hertz_shape(1.0, 0.99 * hz.RATIO_MAX, E_STAR)
    assert 25.0 < a / b < 30.0
    assert not hz.hertz_guard_active(1.0, 0.99 * hz.RATIO_MAX)
    # beyond: clipped to exactly 30, both orientations; smaller curvature <= 0 also handled
    for A, B in ((1.0, 1e4), (1e-9, 5.0), (0.0, 5.0), (-0.3, 5.0)):
        assert hz.hertz_guard_active(A, B)
        a, b, C = hz.hertz_shape(A, B, E_STAR)
        assert a / b == pytest.approx(30.0, rel=1e-12)
        a2, b2, C2 = hz.hertz_shape(B, A, E_STAR)
        assert b2 / a2 == pytest.approx(30.0, rel=1e-12)
        assert np.isfinite([a, b, C]).all() and C > 0
    # continuity across the guard
    a1, b1, C1 = hz.hertz_shape(1.0, hz.RATIO_MAX * (1 - 1e-9), E_STAR)
    a2, b2, C2 = hz.hertz_shape(1.0, hz.RATIO_MAX * (1 + 1e-9), E_STAR)
    assert a1 == pytest.approx(a2, rel=1e-6) and C1 == pytest.approx(C2, rel=1e-6)


def test_bad_input_and_zero_load():
    assert hz.hertz_patch(1.0, 2.0, E_STAR, 0.0) == (0.0, 0.0, 0.0, 0.0)
    assert hz.hertz_patch(1.0, 2.0, E_STAR, -5.0) == (0.0, 0.0, 0.0, 0.0)
    assert hz.hertz_force(1.0, 2.0, E_STAR, -1e-6) == 0.0
    with pytest.raises(ValueError):
        hz.hertz_shape(-1.0, 0.0, E_STAR)
    with pytest.raises(ValueError):
        hz.hertz_shape(1.0, 1.0, 0.0)


def test_wheel_rail_example():
    # CRH3-like tread contact: wheel r = 0.43 m, rail crown 0.3 m, flat tread, Q = 70 kN
    A = 1.0 / (2 * 0.43)
    B = 0.5 / 0.3
    a, b, delta, p0 = hz.hertz_patch(A, B, E_STAR, 7.0e4)
    assert 5e-3 < a < 8e-3 and 4e-3 < b < 6e-3
    assert 0.8e9 < p0 < 1.5e9
    assert 5e-5 < delta < 1.5e-4


def test_one_newton_step_matches_the_bracketing_solver():
    """_solve_g takes one Newton step from its Chebyshev start; it must agree with the bracketing
    solver of eq. 4.39 to far below any physical tolerance over the whole guarded range."""
    import math
    import numpy as np
    from railderail_sim.contact import hertz as H
    ratios = np.exp(np.linspace(1e-3, H._FIT_X - 1e-6, 4001))
    err = max(abs(math.log(H._solve_g(r, H.G_MIN)) - math.log(H._solve_g_bracket(r, H.G_MIN))) for r in ratios)
    assert err < 1e-9
