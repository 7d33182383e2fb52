"""Kalker's exact steady rolling contact (railderail_sim/contact/exact_rolling.py) against outside references.

References: Kalker's creep coefficients (Table E3 of Kalker 1990, in `creep.py`), the Coulomb limit mu N,
Cerruti's point-load solution (Johnson 1985, eq. 3.86) integrated by quadrature, FASTSIM. The numbers
quoted in docs/contact-models.md ("Exact steady rolling contact") come from these cases.
"""
import math
import warnings

import numpy as np
import pytest
from scipy import integrate

from railderail_sim.contact import creep, fastsim
from railderail_sim.contact import exact_rolling as er
from railderail_sim.contact import halfspace as hs

E = 2.1e11
NU_TABLE = 0.25                      # a column of Kalker's table: no interpolation in nu
NU = 0.28
N = 5.6e4
MU = 0.3


def _shear(nu):
    return E / (2.0 * (1.0 + nu))


def _ellipse(ratio, c=5e-3):
    """Semi-axes (a along x, b) with a/b = ratio and sqrt(ab) = c."""
    return c * math.sqrt(ratio), c / math.sqrt(ratio)


# --- influence coefficients -----------------------------------------------------------------------------
def _cerruti(x, y, nu):
    """Johnson (1985) eq. 3.86 on the surface, both bodies (x 2), G = 1: (u_xx, u_xy, u_yy) per unit load."""
    r = math.hypot(x, y)
    c = 1.0 / math.pi
    return (c * ((1 - nu) / r + nu * x * x / r ** 3), c * nu * x * y / r ** 3,
            c * ((1 - nu) / r + nu * y * y / r ** 3))


def test_influence_coefficients_against_quadrature():
    dx, dy, nu = 1.0e-3, 0.7e-3, NU
    # away from the element: 2-D quadrature of the point-load solution over the rectangle
    for X, Y in ((2e-3, 0.0), (0.0, 1.4e-3), (3e-3, 2.1e-3), (-2e-3, 1.4e-3), (1e-3, -0.7e-3)):
        ref = [integrate.dblquad(lambda t, s, k=k: _cerruti(X - s, Y - t, nu)[k], -dx / 2, dx / 2,
                                 -dy / 2, dy / 2, epsabs=1e-14, epsrel=1e-11)[0] for k in range(3)]
        got = er.rectangle_tangential_displacement(X, Y, dx, dy, 1.0, nu)
        for g, q in zip(got, ref):
            assert float(g) == pytest.approx(q, rel=1e-8, abs=1e-12 * abs(ref[0]))
    # the element itself: polar coordinates about the centre, int f(theta) R(theta) dtheta with R the
    # distance to the border (the 1/r singularity integrates out in r)
    def radius(th):
        return min(dx / 2 / max(abs(math.cos(th)), 1e-300), dy / 2 / max(abs(math.sin(th)), 1e-300))
    brk = [math.atan2(dy, dx), math.pi - math.atan2(dy, dx), math.pi + math.atan2(dy, dx),
           2 * math.pi - math.atan2(dy, dx)]
    ref_xx = integrate.quad(lambda th: ((1 - nu) + nu * math.cos(th) ** 2) * radius(th) / math.pi, 0,
                            2 * math.pi, points=brk, epsabs=1e-15, epsrel=1e-12, limit=200)[0]
    ref_yy = integrate.quad(lambda th: ((1 - nu) + nu * math.sin(th) ** 2) * radius(th) / math.pi, 0,
                            2 * math.pi, points=brk, epsabs=1e-15, epsrel=1e-12, limit=200)[0]
    axx, axy, ayy = er.rectangle_tangential_displacement(0.0, 0.0, dx, dy, 1.0, nu)
    assert float(axx) == pytest.approx(ref_xx, rel=1e-10)
    assert float(ayy) == pytest.approx(ref_yy, rel=1e-10)
    assert float(axy) == 0.0
    # the trace is the normal kernel of halfspace.py (1/r = x^2/r^3 + y^2/r^3), and the far field
    X, Y = 0.3, 0.2
    axx, axy, ayy = er.rectangle_tangential_displacement(X, Y, dx, dy, 1.0, nu)
    far = _cerruti(X, Y, nu)
    for g, f in zip((axx, axy, ayy), far):
        assert float(g) == pytest.approx(f * dx * dy, rel=1e-5)
    for X, Y in ((0.0, 0.0), (1e-3, 0.0), (2e-3, 1.4e-3)):
        axx, _, ayy = er.rectangle_tangential_displacement(X, Y, dx, dy, 1.0, 0.0)
        normal = hs.rectangle_displacement(X, Y, dx, dy, 1.0)
        assert float(axx + ayy) == pytest.approx(2.0 * normal, rel=1e-12)


def test_slip_operator_equals_the_direct_sum():
    """FFT slip of a random traction field = sum over elements of -(A(x_I + dx - x_J) - A(x_I - x_J))/dx."""
    nx, ny, dx, dy, G = 7, 5, 1.0e-3, 0.6e-3, _shear(NU)
    rng = np.random.default_rng(3)
    px, py = rng.normal(size=(ny, nx)), rng.normal(size=(ny, nx))
    _, spectra, _ = er._operator(nx, ny, dx, dy, G, NU)
    sx, sy = er._slip_of(spectra, px, py)
    x = np.arange(nx) * dx
    y = np.arange(ny) * dy
    for j in range(ny):
        for i in range(nx):
            X = x[i] - x[None, :]
            Y = y[j] - y[:, None]
            a1 = er.rectangle_tangential_displacement(X + dx, Y, dx, dy, G, NU)
            a0 = er.rectangle_tangential_displacement(X, Y, dx, dy, G, NU)
            kxx, kxy, kyy = (-(u1 - u0) / dx for u0, u1 in zip(a0, a1))
            assert sx[j, i] == pytest.approx(float((kxx * px + kxy * py).sum()), rel=1e-9, abs=1e-20)
            assert sy[j, i] == pytest.approx(float((kxy * px + kyy * py).sum()), rel=1e-9, abs=1e-20)


# --- Kalker's linear theory -------------------------------------------------------------------------------
# (a/b, errors of C11, C22, C23 at 64 x 64 as measured; docs/contact-models.md)
KALKER_CASES = (0.3, 1.0, 1.0 / 0.3)


@pytest.mark.parametrize("ratio", KALKER_CASES)
def test_small_creepage_gives_kalkers_coefficients(ratio):
    """Fx/(G c^2 xi_x) = C11, Fy/(G c^2 xi_y) = C22, Fy/(G c^3 phi) = C23 (Kalker's signs: forces on the
    wheel oppose the creepage), c = sqrt(ab), within 3 % of Table E3 on a 64 x 64 Hertz patch; rows of the
    table (a/b = 0.3, 1, b/a = 0.3) and its column nu = 0.25, so no interpolation enters."""
    a, b = _ellipse(ratio)
    c = math.sqrt(a * b)
    G = _shear(NU_TABLE)
    C11, C22, C23, _ = creep.kalker_coefficients(ratio, NU_TABLE)
    p, x, y, dx, dy = er.hertz_grid(a, b, N, 64, 64)
    xi, spin = 1e-6, 1e-4                          # |F| / (mu N) ~ 1e-3: the slip area is a row at most
    rx = er.exact_rolling(xi, 0.0, 0.0, p, dx, dy, E, NU_TABLE, MU, x=x, y=y)
    ry = er.exact_rolling(0.0, xi, 0.0, p, dx, dy, E, NU_TABLE, MU, x=x, y=y)
    rs = er.exact_rolling(0.0, 0.0, spin, p, dx, dy, E, NU_TABLE, MU, x=x, y=y)
    c11 = -rx.Fx / (G * c * c * xi)
    c22 = -ry.Fy / (G * c * c * xi)
    c23 = -rs.Fy / (G * c ** 3 * spin)
    assert c11 == pytest.approx(C11, rel=0.03)
    assert c22 == pytest.approx(C22, rel=0.03)
    assert c23 == pytest.approx(C23, rel=0.03)
    # the other sign of Kalker's coupling: Mz = +G c^3 C23 xi_y, equal to the spin's Fy coefficient
    # (reciprocity, exact on this x-symmetric grid up to the solver tolerance)
    assert ry.Mz / (G * c ** 3 * xi) == pytest.approx(c23, rel=1e-4)
    assert abs(rx.Fy) < 1e-6 * abs(rx.Fx) and abs(ry.Fx) < 1e-6 * abs(ry.Fy)
    # no slip at all (mu = inf) is the same limit
    r_inf = er.exact_rolling(xi, 0.0, 0.0, p, dx, dy, E, NU_TABLE, math.inf, x=x, y=y)
    assert r_inf.Fx == pytest.approx(rx.Fx, rel=2e-3)
    assert r_inf.stick_fraction == 1.0


def test_exact_normal_pressure_then_rolling():
    """The tangential problem on the grid and pressure of the exact normal solver (elliptic gap, B/A = 3):
    C11 and C22 within 3 % of Kalker's table at the patch's own a/b."""
    A = 1.0 / (2.0 * 0.46)
    B = 3.0 * A
    from railderail_sim.contact import hertz
    a, b, _, _ = hertz.hertz_patch(A, B, hertz.combined_modulus(E, NU_TABLE, E, NU_TABLE), N)
    s = np.linspace(-1.1 * b, 1.1 * b, 64)
    h, x, dx, dy = hs.wheelrail_gap(s, B * s * s, 1.0 / (2.0 * A), 1.1 * a, 64)
    sol = hs.halfspace_patch(h, dx, dy, E, NU_TABLE, N=N, x=x, y=s)
    C11, C22, _, _ = creep.kalker_coefficients(a / b, NU_TABLE)
    G = _shear(NU_TABLE)
    xi = 1e-6
    rx = er.exact_rolling(xi, 0.0, 0.0, sol["pressure"], dx, dy, E, NU_TABLE, MU, x=x, y=s)
    ry = er.exact_rolling(0.0, xi, 0.0, sol["pressure"], dx, dy, E, NU_TABLE, MU, x=x, y=s)
    assert rx.normal_force == pytest.approx(N, rel=1e-9)
    assert -rx.Fx / (G * a * b * xi) == pytest.approx(C11, rel=0.03)
    assert -ry.Fy / (G * a * b * xi) == pytest.approx(C22, rel=0.03)


# --- full sliding, FASTSIM, symmetry -----------------------------------------------------------------------
def test_full_sliding_reaches_mu_n():
    a, b = 6.9e-3, 2.55e-3                         # the centred LM tread patch (docs/contact-report.md)
    p, x, y, dx, dy = er.hertz_grid(a, b, N, 48, 48)
    prev = 0.0
    for xi in (5e-4, 2e-3, 5e-3, 2e-2):
        r = er.exact_rolling(0.6 * xi, 0.8 * xi, 0.0, p, dx, dy, E, NU, MU, x=x, y=y)
        total = math.hypot(r.Fx, r.Fy) / (MU * N)
        assert prev < total <= 1.0 + 1e-9
        prev = total
    assert r.stick_fraction == 0.0 and bool(r.slip[r.contact].all())
    # every element on its bound (sum |p| dA = mu N); the resultant a little less (the directions differ)
    assert float(np.hypot(r.px, r.py).sum() * (x[1] - x[0]) * (y[1] - y[0])) == pytest.approx(MU * N, rel=1e-12)
    assert math.hypot(r.Fx, r.Fy) == pytest.approx(MU * N, rel=1e-4)
    # against the slip, which is the creepage plus the (small) elastic part -du/dx: within 0.3 deg of it
    assert math.degrees(abs(math.atan2(-r.Fy, -r.Fx) - math.atan2(0.8, 0.6))) < 0.3
    # with spin, full sliding still puts every element on its bound; the resultant is below mu N by
    # the spread of the slip's direction over the patch (here w_y = -2 x against xi_x = -0.2: ~2 deg)
    r = er.exact_rolling(-0.2, 0.0, -2.0, p, dx, dy, E, NU, MU, x=x, y=y)
    assert r.stick_fraction == 0.0
    assert 0.999 < math.hypot(r.Fx, r.Fy) / (MU * N) < 1.0


def test_partial_slip_structure():
    """Stick at the leading edge, slip at the trailing edge; |p| <= mu p_n; slip elements carry the bound
    against their slip; stick elements do not slip."""
    a, b = 6.9e-3, 2.55e-3
    p, x, y, dx, dy = er.hertz_grid(a, b, N, 48, 48)
    r = er.exact_rolling(1e-3, 0.0, 0.0, p, dx, dy, E, NU, MU, x=x, y=y, tol=1e-8)
    assert 0.3 < r.stick_fraction < 0.95
    t = np.hypot(r.px, r.py)
    assert np.all(t <= MU * p * (1 + 1e-12) + 1e-9)
    row = r.contact[24]
    lead, trail = np.flatnonzero(row)[-1], np.flatnonzero(row)[0]
    assert r.stick[24, lead] and r.slip[24, trail]
    s = np.hypot(r.slip_x, r.slip_y)
    sl = r.slip
    cos = -(r.px[sl] * r.slip_x[sl] + r.py[sl] * r.slip_y[sl]) / (t[sl] * s[sl])
    assert np.all(cos > 1 - 1e-9)
    assert np.all(t[sl] == pytest.approx(MU * p[sl], rel=1e-12))
    assert float(s[r.stick].max()) < 1e-6 * float(s[sl].max())


FASTSIM_CASES = (  # (a, b, (xi_x, xi_y, phi), tolerance on the resultant, relative)
    (6.9e-3, 2.55e-3, (1e-3, 0.0, 0.0), 0.03),
    (6.9e-3, 2.55e-3, (0.0, 1e-3, 0.0), 0.03),
    (6.0e-3, 3.5e-3, (2e-3, 1e-3, 0.3), 0.05),
    (6.0e-3, 3.5e-3, (0.01, 0.01, 0.0), 0.03),
)


@pytest.mark.parametrize("a, b, cr, tol", FASTSIM_CASES)
def test_fastsim_agrees_at_moderate_creepage(a, b, cr, tol):
    G = _shear(NU)
    p, x, y, dx, dy = er.hertz_grid(a, b, N, 48, 48)
    r = er.exact_rolling(*cr, p, dx, dy, E, NU, MU, x=x, y=y)
    C11, C22, C23, _ = creep.kalker_coefficients(a / b, NU)
    fx, fy, _ = fastsim.fastsim_forces(*cr, a, b, N, MU, G, C11, C22, C23, 20, 20)
    assert math.hypot(fx - r.Fx, fy - r.Fy) < tol * math.hypot(r.Fx, r.Fy)


def test_fastsim_overestimates_the_spin_force():
    """Pure spin on the tread patch: FASTSIM's lateral force is 5-25 % above the exact one (Kalker's
    simplified theory saturates the spin force too slowly; docs/contact-models.md gives the numbers)."""
    a, b = 6.9e-3, 2.55e-3
    G = _shear(NU)
    C11, C22, C23, _ = creep.kalker_coefficients(a / b, NU)
    p, x, y, dx, dy = er.hertz_grid(a, b, N, 48, 48)
    for phi in (1.0, 2.0):
        r = er.exact_rolling(0.0, 0.0, phi, p, dx, dy, E, NU, MU, x=x, y=y)
        _, fy, _ = fastsim.fastsim_forces(0.0, 0.0, phi, a, b, N, MU, G, C11, C22, C23, 20, 20)
        assert r.Fy < 0.0 and 1.05 < fy / r.Fy < 1.25


def test_symmetry_and_determinism():
    a, b = 6.0e-3, 3.5e-3
    p, x, y, dx, dy = er.hertz_grid(a, b, N, 32, 32)
    kw = dict(x=x, y=y, tol=1e-9)
    r = er.exact_rolling(1e-3, 8e-4, 0.4, p, dx, dy, E, NU, MU, **kw)
    m = er.exact_rolling(1e-3, -8e-4, -0.4, p, dx, dy, E, NU, MU, **kw)     # mirrored in y
    assert m.Fx == pytest.approx(r.Fx, rel=1e-6)
    assert m.Fy == pytest.approx(-r.Fy, rel=1e-6)
    assert m.Mz == pytest.approx(-r.Mz, rel=1e-6)
    o = er.exact_rolling(-1e-3, -8e-4, -0.4, p, dx, dy, E, NU, MU, **kw)    # odd in all creepages
    assert (o.Fx, o.Fy, o.Mz) == pytest.approx((-r.Fx, -r.Fy, -r.Mz), rel=1e-6)
    q = er.exact_rolling(0.0, 8e-4, 0.0, p, dx, dy, E, NU, MU, **kw)
    qm = er.exact_rolling(0.0, -8e-4, 0.0, p, dx, dy, E, NU, MU, **kw)
    assert qm.Fy == pytest.approx(-q.Fy, rel=1e-6)
    again = er.exact_rolling(1e-3, 8e-4, 0.4, p, dx, dy, E, NU, MU, **kw)
    assert np.array_equal(again.px, r.px) and again.Fy == r.Fy
    zero = er.exact_rolling(0.0, 0.0, 0.0, p, dx, dy, E, NU, MU, **kw)
    assert (zero.Fx, zero.Fy, zero.Mz, zero.residual) == (0.0, 0.0, 0.0, 0.0) and zero.converged


def test_not_converged_warns():
    p, x, y, dx, dy = er.hertz_grid(6e-3, 3.5e-3, N, 24, 24)
    with pytest.warns(RuntimeWarning, match="not converged"):
        r = er.exact_rolling(1e-3, 0.0, 0.0, p, dx, dy, E, NU, MU, max_iter=2)
    assert not r.converged and r.iterations == 2


@pytest.mark.parametrize("change, words", [
    (dict(xi_x=math.nan), "xi_x = nan must be a finite number"),
    (dict(phi="spin"), "phi = 'spin' must be a finite number"),
    (dict(pressure=np.ones(5)), "pressure must be a 2-D"),
    (dict(pressure=np.ones((2, 5))), "at least 3 x 3"),
    (dict(pressure=-np.ones((4, 4))), "pressure must be finite and >= 0 Pa"),
    (dict(dx=0.0), "dx = 0.0 m must be finite and > 0"),
    (dict(E=-1.0), "E = -1.0 Pa must be finite and > 0"),
    (dict(nu=0.5), "nu = 0.5 must be within [0, 0.5)"),
    (dict(mu=0.0), "mu = 0.0 must be within (0, inf]"),
    (dict(mu=math.nan), "mu = nan must be within (0, inf]"),
    (dict(tol=1.0), "tol = 1.0 must be within (0, 1)"),
    (dict(max_iter=0), "max_iter = 0 must be an integer >= 1"),
    (dict(x=np.zeros(3)), "x must have 4 points spaced dx"),
])
def test_bad_input_names_the_value_and_range(change, words):
    args = dict(xi_x=1e-3, xi_y=0.0, phi=0.0, pressure=np.ones((4, 4)), dx=1e-3, dy=1e-3, E=E, nu=NU,
                mu=MU)
    args.update(change)
    with pytest.raises(ValueError, match="^exact_rolling: .*" + _escape(words)):
        er.exact_rolling(**args)
    with pytest.raises(ValueError, match=r"exact_rolling: nx = 2 must be an integer >= 3"):
        er.hertz_grid(1e-3, 1e-3, N, 2, 8)
    with pytest.raises(ValueError, match=r"exact_rolling: N = -1.0 N must be finite and > 0"):
        er.hertz_grid(1e-3, 1e-3, -1.0)


def _escape(text):
    import re
    return re.escape(text)
