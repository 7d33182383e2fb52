"""Kalker coefficients, creep-force laws, FASTSIM and Nadal (railderail_sim/contact)."""
import math

import numpy as np
import pytest

from railderail_sim.contact import creep as cr
from railderail_sim.contact import fastsim as fs
from railderail_sim.contact import hertz as hz
from railderail_sim.contact import nadal

E = 2.1e11
NU = 0.28
G = E / (2.0 * (1.0 + NU))
E_STAR = E / (2.0 * (1.0 - NU * NU))
MU = 0.3
N = 7.0e4
MODELS = (cr.LINEAR, cr.SHEN_HEDRICK_ELKINS, cr.POLACH, cr.FASTSIM)
SATURATED = (cr.SHEN_HEDRICK_ELKINS, cr.POLACH, cr.FASTSIM)


def _patch(ratio_BA=1.9):
    A = 1.0 / (2 * 0.43)
    a, b, _, _ = hz.hertz_patch(A, ratio_BA * A, E_STAR, N)
    return a, b


# --------------------------------------------------------------------------- Kalker table

# Kalker (1990), Three-dimensional elastic bodies in rolling contact, Table E3, as printed (three
# significant digits): {a/b: (C11, C22, C23, C33) at nu = 0, 0.25, 0.5}
KALKER_PRINTED = {
    0.1: ((2.51, 3.31, 4.85), (2.51, 2.52, 2.53), (0.334, 0.473, 0.731), (6.42, 8.28, 11.7)),
    0.5: ((2.88, 3.62, 4.83), (2.88, 3.01, 3.14), (0.827, 0.929, 1.07), (1.74, 1.93, 2.22)),
    1.0: ((3.40, 4.12, 5.20), (3.40, 3.67, 3.98), (1.33, 1.47, 1.63), (1.21, 1.19, 1.16)),
    1 / 0.5: ((4.37, 5.10, 6.11), (4.37, 4.90, 5.56), (2.35, 2.62, 2.96), (0.958, 0.819, 0.650)),
    1 / 0.1: ((10.7, 11.7, 12.9), (10.7, 12.8, 16.0), (12.2, 14.6, 18.0), (0.795, 0.526, 0.228)),
}


@pytest.mark.parametrize("a_over_b", sorted(KALKER_PRINTED))
def test_coefficients_are_kalkers_printed_values(a_over_b):
    for j, nu in enumerate((0.0, 0.25, 0.5)):
        c = cr.kalker_coefficients(a_over_b, nu)
        for value, printed in zip(c, KALKER_PRINTED[a_over_b]):
            half_digit = 0.5 * 10.0 ** (math.floor(math.log10(printed[j])) - 2)
            assert value == pytest.approx(printed[j], abs=half_digit), (nu, printed)


def test_c11_equals_c22_at_nu_zero():
    # property of the linear theory: for nu = 0 the longitudinal and lateral problems coincide
    assert np.array_equal(cr.KALKER_C11[:, 0], cr.KALKER_C22[:, 0])


def test_table_monotone_and_smooth():
    for tab in (cr.KALKER_C11, cr.KALKER_C22, cr.KALKER_C23):
        inc = np.diff(tab, axis=0) > 0                       # increasing from a/b=0.1 to b/a=0.1
        if tab is cr.KALKER_C11:
            # except C11(nu=0.5) for a/b <= 0.4 (4.85, 4.81, 4.80, 4.82: it turns up towards the
            # asymptote pi^2/(4(1-nu)) = 4.93, as printed by Kalker)
            assert np.all(inc[3:, 2])
            inc = inc[:, :2]
        assert np.all(inc)
        assert np.all(np.diff(tab, axis=1) > 0)              # increasing with nu
        d2 = np.diff(np.log(tab), 2, axis=0)
        assert np.abs(d2[1:14]).max() < 0.07                 # smooth (a misprint like 1.15 -> 0.16)
    d2 = np.diff(np.log(cr.KALKER_C33), 2, axis=0)
    assert np.abs(d2[3:16]).max() < 0.07
    assert np.all(np.diff(cr.KALKER_C33, axis=0) < 0)        # C33 decreases along the table
    # the corrected entry (CONTACT's transcription prints 1.15)
    assert cr.KALKER_C23[7, 1] == 1.25
    bad = cr.KALKER_C23.copy()
    bad[7, 1] = 1.15
    assert np.abs(np.diff(np.log(bad), 2, axis=0)[1:14]).max() > 0.1


def test_asymptotes_match_table_end_and_continuity():
    for j, nu in enumerate((0.0, 0.25, 0.5)):
        s = cr._asym_small_a(0.1, nu)
        for i, tab in enumerate((cr.KALKER_C11, cr.KALKER_C22, cr.KALKER_C23, cr.KALKER_C33)):
            assert s[i] == pytest.approx(tab[0, j], rel=0.06)
        s = cr._asym_small_b(0.1, nu)
        for i, tab in enumerate((cr.KALKER_C11, cr.KALKER_C22, cr.KALKER_C23)):
            assert s[i] == pytest.approx(tab[18, j], rel=0.05)
    for aob in (0.1, 10.0):
        lo = cr.kalker_coefficients(aob * (1 - 1e-9), NU)
        hi = cr.kalker_coefficients(aob * (1 + 1e-9), NU)
        assert np.allclose(lo, hi, rtol=1e-6)
    # beyond the table the asymptotic trend continues (a/b = 1/30 and 30 are reachable via hertz)
    c_small = cr.kalker_coefficients(1 / 30, NU)
    c_large = cr.kalker_coefficients(30.0, NU)
    assert c_small[3] > cr.kalker_coefficients(0.1, NU)[3]
    assert c_large[0] > cr.kalker_coefficients(10.0, NU)[0]
    assert np.all(np.isfinite(c_small)) and np.all(np.isfinite(c_large))


def test_nu_interpolation_between_columns():
    c25 = cr.kalker_coefficients(0.55, 0.25)
    c28 = cr.kalker_coefficients(0.55, 0.28)
    c50 = cr.kalker_coefficients(0.55, 0.5)
    assert all(lo < mid < hi for lo, mid, hi in zip(c25[:3], c28[:3], c50[:3]))
    with pytest.raises(ValueError):
        cr.kalker_coefficients(1.0, 0.6)
    with pytest.raises(ValueError):
        cr.kalker_coefficients(0.0, 0.3)


TABLE_RTOL = 1e-14        # the tabulated coefficients' bound against the direct function: rounding only


def _tabulated_error(cp, nu, ratios):
    """Largest relative difference per coefficient of `tabulated_coefficients(cp, ...)` from
    `kalker_coefficients(a/b, nu)` over the ratios a/b (b = 7 mm, a Hertz patch's size)."""
    worst = np.zeros(4)
    for r in ratios:
        b = 7.0e-3
        got = np.array(cr.tabulated_coefficients(cp, r * b, b))
        want = np.array(cr.kalker_coefficients(r * b / b, nu))
        worst = np.maximum(worst, np.abs(got / want - 1.0))
    return worst


def test_the_model_table_is_kalker_coefficients_to_rounding():
    """The model's table (`ContactConstants.kalker`, written by `contact_array` at its Poisson ratio) gives
    `kalker_coefficients` within TABLE_RTOL over a/b 0.05-20 (the table's segments are a/b 0.1-10, beyond
    them the direct function is called) at every Poisson ratio; a table built with another nu does not."""
    from railderail_sim.contact.layout import ContactConstants
    from railderail_sim.parameters import ContactParameters
    from railderail_sim.vehicle.assemble import contact_array
    ratios = np.concatenate([np.exp(np.linspace(math.log(0.05), math.log(20.0), 4001)),
                             [0.1, 1.0, 10.0, 1 / 30, 30.0, 0.1 * (1 + 1e-15), 10.0 * (1 - 1e-15)],
                             np.arange(1, 19) / 10.0, 1.0 / (2.0 - np.arange(10, 20) / 10.0)])
    for nu in (0.0, 0.1, 0.25, 0.28, 0.3, 0.45, 0.5):
        cp = contact_array(ContactParameters(poisson_ratio=nu))
        assert cp[ContactConstants.poisson_ratio] == nu
        worst = _tabulated_error(cp, nu, ratios)
        assert np.all(worst <= TABLE_RTOL), (nu, worst)
    # the table is the model's own: one built at another nu than the model's is off by far more than the bound
    cp = contact_array(ContactParameters(poisson_ratio=NU))
    cp[ContactConstants.kalker.columns] = cr.kalker_table(0.27).ravel()
    assert np.min(_tabulated_error(cp, NU, [0.5, 2.7, 9.0])) > 1e-4
    with pytest.raises(ValueError):
        cr.kalker_table(0.6)


# --------------------------------------------------------------------------- creep laws

def test_linear_theory_sign_convention():
    a, b = _patch()
    C11, C22, C23, C33 = cr.kalker_coefficients(a / b, NU)
    Fx, Fy, Mz = cr.creep_forces(cr.LINEAR, 1e-3, 0.0, 0.0, a, b, N, MU, G, NU)
    assert Fx == pytest.approx(-G * a * b * C11 * 1e-3, rel=1e-14) and Fy == 0 and Mz == 0
    Fx, Fy, Mz = cr.creep_forces(cr.LINEAR, 0.0, 1e-3, 0.0, a, b, N, MU, G, NU)
    assert Fy == pytest.approx(-G * a * b * C22 * 1e-3, rel=1e-14)
    assert Mz == pytest.approx(G * (a * b) ** 1.5 * C23 * 1e-3, rel=1e-14)
    Fx, Fy, Mz = cr.creep_forces(cr.LINEAR, 0.0, 0.0, 0.1, a, b, N, MU, G, NU)
    assert Fy == pytest.approx(-G * (a * b) ** 1.5 * C23 * 0.1, rel=1e-14)
    assert Mz == pytest.approx(-G * (a * b) ** 2 * C33 * 0.1, rel=1e-14)


@pytest.mark.parametrize("model", SATURATED)
@pytest.mark.parametrize("ratio", (0.3, 1.9, 8.0))
def test_small_creepage_tends_to_linear_theory(model, ratio):
    a, b = _patch(ratio)
    tol = 0.01 if model != cr.FASTSIM else 0.02
    for xi in ((1e-5, 0.0, 0.0), (0.0, 1e-5, 0.0), (0.0, 0.0, 1e-5)):
        lin = cr.creep_forces(cr.LINEAR, *xi, a, b, N, MU, G, NU)
        sat = cr.creep_forces(model, *xi, a, b, N, MU, G, NU)
        i = 0 if xi[0] else 1
        assert sat[i] == pytest.approx(lin[i], rel=tol)


@pytest.mark.parametrize("model", SATURATED)
def test_large_creepage_saturates_at_mu_n(model):
    a, b = _patch()
    for xi in ((0.1, 0.0, 0.0), (0.0, 0.1, 0.0), (0.07, 0.07, 0.0)):
        Fx, Fy, Mz = cr.creep_forces(model, *xi, a, b, N, MU, G, NU)
        assert math.hypot(Fx, Fy) == pytest.approx(MU * N, rel=0.01)
    Fx, Fy, _ = cr.creep_forces(model, 0.1, 0.0, 0.0, a, b, N, MU, G, NU)
    assert Fx < 0 and abs(Fy) < 1e-9 * MU * N


@pytest.mark.parametrize("model", MODELS)
def test_forces_are_odd_in_creepage(model):
    a, b = _patch()
    for xi in ((2e-4, -1e-4, 0.05), (3e-3, 1e-3, -0.4), (0.0, 0.0, 1.0), (0.02, 0.0, 0.0)):
        f1 = np.array(cr.creep_forces(model, *xi, a, b, N, MU, G, NU))
        f2 = np.array(cr.creep_forces(model, *(-v for v in xi), a, b, N, MU, G, NU))
        assert np.allclose(f1, -f2, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("model", MODELS)
def test_no_nan_for_zero_load_or_zero_creepage(model):
    a, b = _patch()
    assert cr.creep_forces(model, 1e-3, 1e-3, 0.1, a, b, 0.0, MU, G, NU) == (0.0, 0.0, 0.0)
    assert cr.creep_forces(model, 1e-3, 1e-3, 0.1, 0.0, 0.0, 0.0, MU, G, NU) == (0.0, 0.0, 0.0)
    f = cr.creep_forces(model, 0.0, 0.0, 0.0, a, b, N, MU, G, NU)
    assert np.all(np.isfinite(f)) and np.allclose(f, 0.0)


def test_unknown_model_raises():
    a, b = _patch()
    with pytest.raises(ValueError):
        cr.creep_forces(7, 1e-3, 0.0, 0.0, a, b, N, MU, G, NU)


def test_she_curve_values():
    # beta = 1.5: F/(mu N) = 1.5 - 0.75 + 0.125 = 0.875; beta >= 3: 1
    assert cr.she_factor(1.5, 1.0) * 1.5 == pytest.approx(0.875, rel=1e-14)
    assert cr.she_factor(3.0, 1.0) * 3.0 == pytest.approx(1.0, rel=1e-14)
    assert cr.she_factor(10.0, 1.0) * 10.0 == pytest.approx(1.0, rel=1e-14)


def test_polach_2005_dry_parameters():
    a, b = _patch()
    C11, C22, C23, C33 = cr.kalker_coefficients(a / b, NU)
    args = (a, b, N, cr.POLACH_DRY_MU0, G, C11, C22, C23, C33)
    # reduced initial slope (kA + kS)/2 = 0.7 of Kalker's
    Fx, _, _ = cr.polach_forces(1e-6, 0.0, 0.0, *args, 0.0, cr.POLACH_DRY_KA, cr.POLACH_DRY_KS,
                                cr.POLACH_DRY_A, cr.POLACH_DRY_B)
    assert Fx / (-G * a * b * C11 * 1e-6) == pytest.approx(0.7, rel=1e-3)
    # friction falls with slip velocity toward A mu0; at V = 0 the limit is mu0 N
    V = 83.3
    F_lo, _, _ = cr.polach_forces(0.01, 0.0, 0.0, *args, V, cr.POLACH_DRY_KA, cr.POLACH_DRY_KS,
                                  cr.POLACH_DRY_A, cr.POLACH_DRY_B)
    F_hi, _, _ = cr.polach_forces(0.5, 0.0, 0.0, *args, V, cr.POLACH_DRY_KA, cr.POLACH_DRY_KS,
                                  cr.POLACH_DRY_A, cr.POLACH_DRY_B)
    assert abs(F_hi) < abs(F_lo) < cr.POLACH_DRY_MU0 * N
    assert abs(F_hi) == pytest.approx(cr.POLACH_DRY_A * cr.POLACH_DRY_MU0 * N, rel=0.05)


# --------------------------------------------------------------------------- FASTSIM

def test_fastsim_flexibilities_reproduce_linear_theory():
    a, b = _patch(3.0)
    C11, C22, C23, C33 = cr.kalker_coefficients(a / b, NU)
    L1, L2, L3 = fs.flexibilities(a, b, G, C11, C22, C23)
    assert 8 * a * a * b / (3 * L1) == pytest.approx(G * a * b * C11, rel=1e-14)
    assert math.pi * a ** 3 * b / (4 * L3) == pytest.approx(G * (a * b) ** 1.5 * C23, rel=1e-14)


def test_fastsim_grid_convergence():
    a, b = _patch()
    C11, C22, C23, _ = cr.kalker_coefficients(a / b, NU)
    xi = (6e-4, -4e-4, 0.2)
    ref = np.array(fs.fastsim_forces(*xi, a, b, N, MU, G, C11, C22, C23, 320, 320))
    errs = []
    for n in (10, 20, 40, 80):
        f = np.array(fs.fastsim_forces(*xi, a, b, N, MU, G, C11, C22, C23, n, n))
        errs.append(np.linalg.norm(f[:2] - ref[:2]) / np.linalg.norm(ref[:2]))
    assert errs[1] < 0.01                            # default 20 x 20 within 1 %
    assert errs[3] < errs[1] < errs[0]
    assert errs[3] < 2e-3


def test_fastsim_traction_field_consistent_with_forces():
    a, b = _patch()
    C11, C22, C23, _ = cr.kalker_coefficients(a / b, NU)
    xi = (1e-3, 5e-4, 0.1)
    fld = fs.traction_field(*xi, a, b, N, MU, G, C11, C22, C23, nx=20, ny=20)
    ny, nx = fld["px"].shape
    dy = 2 * b / ny
    dxs = 2 * np.sqrt(np.maximum(a * a * (1 - (fld["ys"][:, 0] / b) ** 2), 0)) / nx
    Fx = np.sum(fld["px"] * dxs[:, None]) * dy
    Fy = np.sum(fld["py"] * dxs[:, None]) * dy
    ref = fs.fastsim_forces(*xi, a, b, N, MU, G, C11, C22, C23, 20, 20)
    assert Fx == pytest.approx(ref[0], rel=1e-12) and Fy == pytest.approx(ref[1], rel=1e-12)
    assert 0 < fld["slip"].sum() < fld["slip"].size            # partial slip at this creepage
    assert fld["slip"][:, 0].sum() == 0                          # leading edge sticks


# --------------------------------------------------------------------------- Nadal

def test_nadal_hand_values():
    d70 = math.radians(70.0)
    assert nadal.nadal_limit(d70, 0.3) == pytest.approx(1.3416, abs=1e-4)
    assert nadal.nadal_limit(d70, 0.36) == pytest.approx(1.200, abs=1e-3)
    assert nadal.nadal_limit(math.radians(60.0), 0.3) == pytest.approx(0.9424, abs=1e-4)
    assert nadal.nadal_limit(d70, 0.0) == pytest.approx(math.tan(d70), rel=1e-14)


def test_nadal_inverses():
    for ang_deg, mu in ((70.0, 0.3), (65.0, 0.25), (75.0, 0.4)):
        ang = math.radians(ang_deg)
        L = nadal.nadal_limit(ang, mu)
        assert nadal.nadal_flange_angle(L, mu) == pytest.approx(ang, rel=1e-12)
        assert nadal.nadal_friction(L, ang) == pytest.approx(mu, rel=1e-12)
    assert nadal.nadal_flange_angle(5.0, 0.3) == pytest.approx(math.pi / 2)
