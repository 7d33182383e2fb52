"""Hertz normal contact of two elastic bodies with an elliptic contact patch (numba core).

Model
-----
Two bodies with non-conformal, smooth surfaces touch at one point. Near that point the undeformed
normal separation is the quadric

    h(x, y) = A x^2 + B y^2,        A, B > 0 [1/m],

with x the rolling (longitudinal) and y the lateral direction of the contact plane. ``A`` and ``B``
are half the sums of the principal relative curvatures of the two surfaces (for the wheel-rail
contact: ``A = 1/(2 R_wheel_rolling)`` (the rail being straight), ``B = (1/R_wheel_profile +
1/R_rail_profile)/2`` with the convex-positive sign convention). The bodies are linearly elastic
half-spaces with the combined ("contact") modulus

    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2                       (Johnson 1985, eq. 4.22)

(``combined_modulus``). The contact is frictionless for the normal problem (the tangential
tractions of rolling do not change the normal solution, quasi-identity; Kalker 1990, ch. 1).

Hertz's solution (Johnson, *Contact Mechanics*, CUP 1985, §4.2, eqs. 4.36-4.41): the patch is an
ellipse with semi-axes ``a_maj >= b_min`` (the major axis lies along the direction of the
*smaller* curvature), the pressure is semi-ellipsoidal ``p = p0 sqrt(1 - x^2/a^2 - y^2/b^2)``,
``N = 2/3 pi a b p0``. With ``e^2 = 1 - (b_min/a_maj)^2`` and ``K(e), E(e)`` the complete
elliptic integrals of the first and second kind, and ``A_s <= B_l`` the smaller and larger of
(A, B):

    A_s = p0/E* * b/(e^2 a^2) * (K - E)                                 (4.36)
    B_l = p0/E* * b/(e^2 a^2) * ((a/b)^2 E - K)                         (4.37)
    delta = p0/E* * b * K                                                (4.38)
    B_l/A_s = ((a/b)^2 E - K) / (K - E)                                  (4.39)

so that, with ``g = b/a``,

    a_maj^3 = 3 N (K - E) / (2 pi A_s E* e^2),   b_min = g a_maj,
    delta   = A_s e^2 a_maj^2 K / (K - E),        p0 = 3 N / (2 pi a b),

and ``N = C delta^{3/2}`` with ``C = (delta / N^{2/3})^{-3/2}``. For ``A = B = 1/(2R)`` this
reduces to ``a = (3 N R / (4 E*))^{1/3}``, ``delta = a^2/R`` (sphere on a plane / two spheres,
Johnson eq. 4.22-4.23).

Numerics
--------
* ``K`` and ``K - E`` are evaluated by the arithmetic-geometric mean (Abramowitz & Stegun 1964,
  §17.6: ``K = pi / (2 a_N)``, ``E = K (1 - sum_n 2^{n-1} c_n^2)``), in a scaled form
  (``c_n = e q_n``, ``c_{n+1} = c_n^2 / (4 a_{n+1})``) that never subtracts nearly equal numbers:
  ``(K - E)/e^2`` is accurate to ~1e-15 relative for e -> 0 (limit pi/4) and for e -> 1, and the
  modulus ``e`` and the complementary modulus ``g = sqrt(1 - e^2)`` are passed separately so that
  g -> 0 (K ~ ln(4/g)) loses nothing.
* The ratio eq. 4.39 is rewritten ``B_l/A_s = (1/s - 1)/g^2`` with ``s = (K - E)/(K e^2)``, which is
  well conditioned at g -> 1 (value 1). It is solved for ``t = ln g`` by Newton's method started
  from a degree-8 Chebyshev fit of the inverse relation ln g(ln r) (fit error < 1.5e-6, slope from
  the fit): typically 2 evaluations of eq. 4.39 reach |ln g - ln g_exact| ~ 1e-12. A safeguarded
  secant (Illinois regula falsi on the bracket [ln g_min, 0], started from the Hamrock & Brewe (1983)
  estimate a/b ~ (B/A)^{2/pi}) is the fallback and serves other guard limits.

Near-conformal guard
--------------------
The semi-axis ratio is kept within ``[1/30, 30]`` (``G_MIN = 1/30``): if ``B_l/A_s`` exceeds the
ratio ``RATIO_MAX`` (= 237.01) that gives ``b/a = 1/30``, the *smaller* curvature is raised to
``B_l/RATIO_MAX`` (the larger one, which fixes the short axis, is kept). Reasons: (i) a very small
curvature sum along one direction means near-conformal contact, where the quadric gap is only a
local approximation and the half-space assumption of Hertz fails long before the predicted patch
length is reached (the real patch is bounded by the curvature change of the profiles; use the
non-elliptic Kik-Piotrowski model of ``kik_piotrowski.py`` there); (ii) Kalker's creep-coefficient
table (``creep.py``) is tabulated for g >= 0.1 and only asymptotic beyond; (iii) it keeps the
contact stiffness and patch finite and smooth when one curvature passes through zero during a
simulation (A_s <= 0 is then also handled: it is raised to ``B_l/RATIO_MAX``).
``hertz_guard_active(A, B)`` tells whether the guard acts.

Inputs/outputs are SI (m, 1/m, N, Pa). All functions are numba core (``railderail_sim.jit.core``), scalar
and allocation-free.

References
----------
Hertz, H. (1882) J. reine angew. Math. 92, 156-171.
Johnson, K.L. (1985) Contact Mechanics, Cambridge University Press, §4.2, eqs. 4.36-4.41.
Abramowitz, M., Stegun, I.A. (1964) Handbook of Mathematical Functions, §17.6 (AGM).
Hamrock, B.J., Brewe, D. (1983) J. Lubrication Technology 105, 171-177 (start value only).
Timoshenko, S.P., Goodier, J.N. (1951) Theory of Elasticity, 2nd ed., §140 (m, n table; tests).
"""
import math

import numpy as np

from ..jit import core

# Limits of the near-conformal guard (see module docstring).
G_MIN = 1.0 / 30.0
# Curvature ratio B_l/A_s that gives b/a = G_MIN (eq. 4.39); = _ratio_of_g(G_MIN), checked by tests.
RATIO_MAX = 237.00941887786473
# Chebyshev fit (degree 8) of ln g versus ln r on [0, ln RATIO_MAX], u = 2 ln r / _FIT_X - 1
# (start values for the Newton solve; generated from _ratio_of_g on 6001 points, max error 1.5e-6)
_FIT_X = 5.46809988244613
_FIT_C = np.array([-1.7359932688013957, -1.7005028884020872, 0.036689289373879615,
                   -0.0004082349219365982, -0.0012847434444719229, 0.0003279954754690475,
                   -1.426463714403667e-05, -1.4672034959471673e-05, 4.929161337136233e-06])
_PI = math.pi
_AGM_MAXIT = 60


@core
def combined_modulus(E1, nu1, E2, nu2):
    """E* with 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2 [Pa] (Johnson 1985, §4.2); for two bodies of the same
    material its closed form E / (2 (1 - nu^2)), which the contact models use (wheel and rail steel)."""
    if E1 == E2 and nu1 == nu2:
        return E1 / (2.0 * (1.0 - nu1 * nu1))
    return 1.0 / ((1.0 - nu1 * nu1) / E1 + (1.0 - nu2 * nu2) / E2)


@core
def ellip_k_s(e, g):
    """Complete elliptic integral K and s = (K - E)/(K e^2) for modulus e, complementary g.

    ``e`` and ``g`` must satisfy e^2 + g^2 = 1 (both given to keep accuracy at either end).
    Returns (K, s); s -> 1/2 for e -> 0. Scaled AGM, see module docstring.
    """
    a = 1.0
    b = g
    q = 1.0          # c_n / e
    ssum = 0.5       # sum_n 2^(n-1) q_n^2, n = 0 term
    w = 0.5
    for _ in range(_AGM_MAXIT):
        a1 = 0.5 * (a + b)
        b = math.sqrt(a * b)
        a = a1
        q = e * q * q / (4.0 * a)
        w *= 2.0
        term = w * q * q
        ssum += term
        if e * q <= 1e-17 * a:
            break
    K = _PI / (2.0 * a)
    return K, ssum


@core
def ellip_ke(k, kc):
    """Complete elliptic integrals (K, E, K - E) for modulus k, complementary modulus kc.

    k^2 + kc^2 = 1; pass both so that k -> 1 (kc -> 0) and k -> 0 stay accurate. K - E is
    returned without cancellation. kc must be > 0.
    """
    K, s = ellip_k_s(k, kc)
    d = K * s * k * k
    return K, K - d, d


@core
def _ratio_of_g(g):
    """Curvature ratio B_l/A_s >= 1 that gives the semi-axis ratio g = b_min/a_maj (eq. 4.39)."""
    e = math.sqrt((1.0 - g) * (1.0 + g))
    K, s = ellip_k_s(e, g)
    return (1.0 / s - 1.0) / (g * g)


@core
def _solve_g_bracket(r, g_min):
    """Semi-axis ratio g = b/a in [g_min, 1] for curvature ratio r = B_l/A_s >= 1 (eq. 4.39).

    Safeguarded secant (Illinois regula falsi) on the bracket [ln g_min, 0]; used for any g_min
    and as the fallback of ``_solve_g``.
    """
    if r <= 1.0:
        return 1.0
    lr = math.log(r)
    t_lo = math.log(g_min)      # f(t_lo) >= 0
    t_hi = 0.0                  # f(t_hi) = -lr < 0
    f_lo = math.log(_ratio_of_g(g_min)) - lr
    if f_lo <= 0.0:
        return g_min
    f_hi = -lr
    # start: Hamrock-Brewe a/b ~ r^(2/pi)
    t = -(2.0 / _PI) * lr
    if t <= t_lo or t >= t_hi:
        t = 0.5 * (t_lo + t_hi)
    f = math.log(_ratio_of_g(math.exp(t))) - lr
    # initial secant partner: the bracket end on the other side
    if f > 0.0:
        t_lo, f_lo = t, f
    else:
        t_hi, f_hi = t, f
    side = 0
    for _ in range(100):
        # regula falsi with Illinois modification
        tn = (t_lo * f_hi - t_hi * f_lo) / (f_hi - f_lo)
        if not (t_lo < tn < t_hi):
            tn = 0.5 * (t_lo + t_hi)
        fn = math.log(_ratio_of_g(math.exp(tn))) - lr
        if abs(fn) < 1e-13 or (t_hi - t_lo) < 1e-14:
            return math.exp(tn)
        if fn > 0.0:
            t_lo, f_lo = tn, fn
            if side == 1:
                f_hi *= 0.5
            side = 1
        else:
            t_hi, f_hi = tn, fn
            if side == -1:
                f_lo *= 0.5
            side = -1
    return math.exp(0.5 * (t_lo + t_hi))


@core
def _fit_lng(x):
    """Chebyshev fit of ln g versus x = ln r on [0, ln RATIO_MAX]: value and d(ln g)/dx.

    Max error 1.5e-6 in ln g; only a start value for the Newton iteration of ``_solve_g``.
    """
    u = 2.0 * x / _FIT_X - 1.0
    # Clenshaw for the value and the derivative (d/du of the series, times du/dx)
    b1 = 0.0
    b2 = 0.0
    d1 = 0.0
    d2 = 0.0
    for k in range(_FIT_C.shape[0] - 1, 0, -1):
        b0 = 2.0 * u * b1 - b2 + _FIT_C[k]
        d0 = 2.0 * u * d1 - d2 + 2.0 * b1
        b2 = b1
        b1 = b0
        d2 = d1
        d1 = d0
    val = u * b1 - b2 + _FIT_C[0]
    der = u * d1 - d2 + b1
    return val, der * 2.0 / _FIT_X


@core
def _solve_g(r, g_min):
    """Semi-axis ratio g = b/a in [g_min, 1] for curvature ratio r = B_l/A_s >= 1 (eq. 4.39).

    For the standard guard (g_min = G_MIN): one Newton step in t = ln g, from a Chebyshev fit of the
    inverse relation (error < 1.5e-6) with the fit's slope, which leaves an error below 1e-8 in ln g
    (one evaluation of eq. 4.39 through the elliptic integrals; tests/test_hertz.py checks it against
    the bracketing solver). Falls back to the bracketing solver otherwise.
    """
    if r <= 1.0:
        return 1.0
    x = math.log(r)
    if g_min != G_MIN or x >= _FIT_X:
        return _solve_g_bracket(r, g_min)
    t, dtdx = _fit_lng(x)
    tmin = math.log(g_min)
    # one Newton step with the fit's slope: the fit is within 1.5e-6 of ln g and its slope within ~1e-3
    # of the true one, so the step leaves an error of order 1e-9 in ln g (checked in tests/test_hertz.py)
    f = math.log(_ratio_of_g(math.exp(t))) - x
    t = min(max(t - f * dtdx, tmin), 0.0)
    return math.exp(t)


@core
def hertz_guard_active(A, B):
    """True when the near-conformal guard changes the smaller curvature (see module docstring)."""
    cs = min(A, B)
    cl = max(A, B)
    return cs * RATIO_MAX < cl


@core
def _shape_core(A, B, E_star, g_min, ratio_max):
    """hertz_shape with an explicit guard (g_min, ratio_max = _ratio_of_g(g_min))."""
    if not (E_star > 0.0):
        raise ValueError("hertz_shape: E_star must be > 0")
    cl = max(A, B)
    if not (cl > 0.0):
        raise ValueError("hertz_shape: at least one curvature sum must be > 0")
    cs = min(A, B)
    if cs * ratio_max < cl:        # near-conformal guard (also cs <= 0)
        cs = cl / ratio_max
        g = g_min
    else:
        g = _solve_g(cl / cs, g_min)
    e = math.sqrt((1.0 - g) * (1.0 + g))
    K, s = ellip_k_s(e, g)
    # (K - E)/e^2 = K s
    amaj3 = 3.0 * K * s / (2.0 * _PI * cs * E_star)      # a_maj^3 / N
    amaj = amaj3 ** (1.0 / 3.0)
    bmin = g * amaj
    # delta / N^(2/3) = A_s e^2 a^2 K/(K-E) = A_s a^2 / s
    dcoef = cs * amaj * amaj / s
    C = dcoef ** -1.5
    if A <= B:
        return amaj, bmin, C
    return bmin, amaj, C


@core
def hertz_shape(A, B, E_star):
    """Load-independent Hertz coefficients for the gap h = A x^2 + B y^2.

    Parameters: A (x, rolling) and B (y, lateral) relative curvature sums/2 [1/m], E_star [Pa].
    Returns (ax_coef, by_coef, stiffness_C) with a = ax_coef*N^(1/3) (semi-axis along x),
    b = by_coef*N^(1/3) (along y), N = stiffness_C * delta^(3/2) [N/m^1.5].
    Both orientations (A < B: long axis along x; A > B: along y) are handled. The semi-axis ratio
    is guarded to [1/30, 30] (module docstring). Raises ValueError if max(A, B) <= 0 or E_star <= 0.
    """
    return _shape_core(A, B, E_star, G_MIN, RATIO_MAX)


@core
def hertz_patch(A, B, E_star, N):
    """Hertz patch for normal load N [N]: returns (a, b, delta, p0).

    a along x (rolling), b along y (lateral) [m], delta the normal approach [m], p0 the maximum
    pressure [Pa]. N <= 0 gives (0, 0, 0, 0).
    """
    if not (N > 0.0):
        return 0.0, 0.0, 0.0, 0.0
    ac, bc, C = hertz_shape(A, B, E_star)
    n13 = N ** (1.0 / 3.0)
    a = ac * n13
    b = bc * n13
    delta = (N / C) ** (2.0 / 3.0)
    p0 = 1.5 * N / (_PI * a * b)
    return a, b, delta, p0


@core
def hertz_force(A, B, E_star, delta):
    """Normal load N = C delta^(3/2) for approach delta [m] (0 for delta <= 0)."""
    if not (delta > 0.0):
        return 0.0
    ac, bc, C = hertz_shape(A, B, E_star)
    return C * delta * math.sqrt(delta)


