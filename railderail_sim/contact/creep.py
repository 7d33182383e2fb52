"""Tangential wheel-rail contact on a Hertz ellipse: Kalker's linear theory and saturated laws.

Quantities and sign convention
------------------------------
Contact frame: x rolling direction, y lateral (in the contact plane), z contact normal. Creepages
(Kalker's definition): ``xi_x``, ``xi_y`` [-] = (velocity of the wheel material minus that of the
rail material at the contact point) / rolling speed V, ``phi`` [1/m] = (wheel - rail) angular
velocity about the contact normal / V. The returned ``Fx, Fy`` [N] and ``Mz`` [N m] are the
tangential force and spin moment exerted *by the rail on the wheel*, so they oppose the creepage.
The semi-axes are ``a`` (along x) and ``b`` (along y), from ``hertz.py``. ``G`` is the combined
shear modulus (G = E/(2(1+nu)) for equal materials), ``nu`` Poisson's ratio, ``N`` the normal load,
``mu`` the friction coefficient.

Kalker's linear theory (Kalker 1967 thesis; Kalker 1990, *Three-dimensional elastic bodies in
rolling contact*, Table E3; reproduced in Iwnicki (ed.) Handbook of Railway Vehicle Dynamics, 2006,
ch. 4) - the no-slip limit of small creepage:

    Fx = -G a b C11 xi_x
    Fy = -G a b C22 xi_y - G (ab)^{3/2} C23 phi
    Mz =  G (ab)^{3/2} C23 xi_y - G (ab)^2 C33 phi

Creep coefficients ``kalker_coefficients(a/b, nu)``: the table below, for nu = 0, 0.25, 0.5 and
g = min(a/b, b/a) = 0.1 ... 1.0 on both branches (a/b <= 1 and a/b > 1). Interpolation: linear in g
on each branch, and in nu a quadratic (Lagrange) fit of 1/C through the three tabulated nu (1/C is
nearly linear in nu, e.g. C11 -> pi^2/(4(1-nu)) for a/b -> 0). Below g = 0.1 (outside the table;
``hertz.py`` keeps g >= 1/30) the tabulated value at g = 0.1 is continued with the shape of
Kalker's asymptotic expansions (Kalker 1990, App. E; as implemented in CONTACT's ``linrol``):
a/b -> 0: C11 = pi^2/(4(1-nu)), C22 = pi^2/4, C23 = pi sqrt(g)/(3(1-nu)) (1 + nu(ln(16/g) - 5)),
C33 = pi^2/(16 (1-nu) g); b/a -> 0 with L = ln(16/g^2): C11 = 2pi/((L-2nu) g) (1 + (3-ln4)/(L-2nu)),
C22 = 2pi/(g((1-nu)L+2nu)) (1 + (1-nu)(3-ln4)/((1-nu)L+2nu)), C23 = 2pi/(3 g^{3/2}((1-nu)L-2+4nu));
C33 (b/a -> 0) is held at its g = 0.1 value (the table is nearly flat there). I.e.
C(g) = C_table(0.1) * C_asym(g)/C_asym(0.1), continuous at g = 0.1.

Transcription check of the table: C11, C22, C23 were compared entry by entry with the independent
transcription of Table E3 in CONTACT (Vollebregt & Kalker, subroutine ``linrol`` of the CONTACT
add-on example ``usetab_table.f90``, Apache-2.0); all entries agree except
C23(a/b = 0.8, nu = 0.25), which is 1.15 there: we use 1.25 because every other row has C23(nu=0) < C23(0.25) < C23(0.5) with
nearly constant ratios (1.03/1.14/1.29, 1.23/1.36/1.51), the column 1.14, x, 1.36 is smooth only for
x = 1.25 (with 1.15 the steps would be 0.01 then 0.21 against ~0.11 elsewhere: a misprint; its
second difference of ln C23, 0.16, is 3x the largest in the table interior). Further checks (tests):
C11 = C22 at nu = 0 on the whole table (a property of the linear theory), the asymptotes above at
g = 0.1 within 6 %, monotonicity in g and nu, and smooth second differences. C33 is not in CONTACT's
routine; its column was entered from the standard published table (Kalker 1990, Table E3) without a
second independent transcription at hand, and is checked only against the asymptote
pi^2/(16(1-nu)g) and for smoothness (single source; it only enters the spin moment Mz).

Kalker's coefficients tabulated per model (``kalker_table``, ``tabulated_coefficients``)
-----------------------------------------------------------------------------------------
The vehicle core calls the creep law on every loaded patch of every right-hand side, and
``kalker_coefficients`` was most of the law's time (the nu weights, two divisions for a/b and b/a, four
interpolations each with its own division, the branches and the range checks). Poisson's ratio is a model
parameter, so the model building (``vehicle.assemble.contact_array``) writes ``kalker_table(nu)`` into the
contact constants cp (``ContactConstants.kalker``): on each of Table E3's 18 segments of u (0.1 to 1.9, the
same u as above) and for each coefficient, the interpolation above at that nu is the ratio of a cubic and
a quadratic in the segment's fraction f, C = P(f)/Q(f) (P = c0 c1 c2, Q = w0 c1 c2 + w1 c0 c2 + w2 c0 c1
with c_j linear in f), so the table holds P's and Q's coefficients (``KalkerPiece``) and
``tabulated_coefficients(cp, a, b)`` is *the same function*, not an approximation of it: its only error is
rounding (largest relative difference to ``kalker_coefficients`` over a/b = 0.1-10, nu = 0-0.5: below
1e-14, ``tests/test_creep.py``). Outside the table's segments (a/b < 0.1 or > 10, the asymptotic
continuation with its logarithms and powers; the core's runs meet a/b 0.47-9.3) it calls
``kalker_coefficients``. ``creep_law`` is ``creep_forces`` given the coefficients. The direct function
stays for FASTSIM, Kik-Piotrowski and the methods, which call it once per patch, not per right-hand side.

Saturated laws (creep_forces model ids)
---------------------------------------
* ``LINEAR`` (0): the linear theory above, no friction limit.
* ``SHEN_HEDRICK_ELKINS`` (1, default): Shen, Hedrick & Elkins (1983), "A comparison of alternative
  creep force models for rail vehicle dynamic analysis", Proc. 8th IAVSD Symposium, 591-605 -
  Johnson-Vermeulen cubic applied to the resultant of the linear forces:
  beta = |F_lin|/(mu N), F = mu N (beta - beta^2/3 + beta^3/27) for beta < 3, F = mu N otherwise;
  Fx, Fy and Mz are all scaled by the common factor eps = F/|F_lin| (scaling Mz too is our choice;
  SHE give no spin-moment rule).
* ``POLACH`` (2): Polach's method (Polach 1999, "A fast wheel-rail forces calculation computer
  code", Vehicle System Dynamics 33 (Suppl.), 728-739; extended in Polach 2005, "Creep forces in
  simulations of traction vehicles running on adhesion limit", Wear 258, 992-1000). Through
  ``creep_forces`` it is used in its 1999 form (kA = kS = 1, constant friction): that form reproduces Kalker's linear
  theory exactly at small creepage for pure xi_x, pure xi_y and pure spin. ``polach_forces`` exposes
  the 2005 parameters: friction mu = mu0((1 - A) exp(-B w) + A) with slip velocity w = V s_C, and
  reduction factors kA (adhesion area) and kS (slip area); module constants ``POLACH_DRY_*`` hold
  the values recommended in Polach (2005, Table 1) for dry rail: kA = 1.00, kS = 0.40, mu0 = 0.55,
  A = 0.40, B = 0.60 s/m (quoted from the paper as recalled - see docs/contact-models.md).
  Mz (not given by Polach) is the linear-theory Mz times the translational saturation factor.
* ``FASTSIM`` (3): Kalker's FASTSIM (``fastsim.py``) on the ellipse, 20 x 20 elements.

All core functions are numba core (``railderail_sim.jit.core``), scalar and allocation-free. ``N <= 0``,
``a <= 0`` or ``b <= 0`` give zero forces; zero creepage gives zero force (no 0/0).
"""
import math

import numpy as np

from ..jit import core, core_inline
from .fastsim import NX_DEFAULT, NY_DEFAULT, fastsim_forces
from .layout import KALKER_SEGMENTS, ContactConstants, KalkerPiece

LINEAR = 0
SHEN_HEDRICK_ELKINS = 1
POLACH = 2
FASTSIM = 3

# Polach (2005, Wear 258, Table 1) recommended parameters, dry conditions.
POLACH_DRY_KA = 1.00
POLACH_DRY_KS = 0.40
POLACH_DRY_MU0 = 0.55
POLACH_DRY_A = 0.40
POLACH_DRY_B = 0.60   # s/m

# ---------------------------------------------------------------------------------------------
# Kalker's Table E3. Rows: u = 0.1, 0.2, ..., 1.0 for a/b = u (a/b <= 1), then u = 1.1 ... 1.9 for
# b/a = 2 - u (a/b > 1; b/a = 0.9 ... 0.1). Columns: nu = 0, 0.25, 0.5.
# ---------------------------------------------------------------------------------------------
KALKER_NU = np.array([0.0, 0.25, 0.5])

KALKER_C11 = np.array([
    [2.51, 3.31, 4.85], [2.59, 3.37, 4.81], [2.68, 3.44, 4.80], [2.78, 3.53, 4.82],
    [2.88, 3.62, 4.83], [2.98, 3.72, 4.91], [3.09, 3.81, 4.97], [3.19, 3.91, 5.05],
    [3.29, 4.01, 5.12], [3.40, 4.12, 5.20],
    [3.51, 4.22, 5.30], [3.65, 4.36, 5.42], [3.82, 4.54, 5.58], [4.06, 4.78, 5.80],
    [4.37, 5.10, 6.11], [4.84, 5.57, 6.57], [5.57, 6.34, 7.34], [6.96, 7.78, 8.82],
    [10.7, 11.7, 12.9]])

KALKER_C22 = np.array([
    [2.51, 2.52, 2.53], [2.59, 2.63, 2.66], [2.68, 2.75, 2.81], [2.78, 2.88, 2.98],
    [2.88, 3.01, 3.14], [2.98, 3.14, 3.31], [3.09, 3.28, 3.48], [3.19, 3.41, 3.65],
    [3.29, 3.54, 3.82], [3.40, 3.67, 3.98],
    [3.51, 3.81, 4.16], [3.65, 3.99, 4.39], [3.82, 4.21, 4.67], [4.06, 4.50, 5.04],
    [4.37, 4.90, 5.56], [4.84, 5.48, 6.31], [5.57, 6.40, 7.51], [6.96, 8.14, 9.79],
    [10.7, 12.8, 16.0]])

KALKER_C23 = np.array([
    [0.334, 0.473, 0.731], [0.483, 0.603, 0.809], [0.607, 0.715, 0.889], [0.720, 0.823, 0.977],
    [0.827, 0.929, 1.07], [0.930, 1.03, 1.18], [1.03, 1.14, 1.29], [1.13, 1.25, 1.40],
    [1.23, 1.36, 1.51], [1.33, 1.47, 1.63],
    [1.44, 1.59, 1.77], [1.58, 1.75, 1.94], [1.76, 1.95, 2.18], [2.01, 2.23, 2.50],
    [2.35, 2.62, 2.96], [2.88, 3.24, 3.70], [3.79, 4.32, 5.01], [5.72, 6.63, 7.89],
    [12.2, 14.6, 18.0]])

KALKER_C33 = np.array([
    [6.42, 8.28, 11.7], [3.46, 4.27, 5.66], [2.49, 2.96, 3.72], [2.02, 2.32, 2.77],
    [1.74, 1.93, 2.22], [1.56, 1.68, 1.86], [1.43, 1.50, 1.60], [1.34, 1.37, 1.42],
    [1.27, 1.27, 1.27], [1.21, 1.19, 1.16],
    [1.16, 1.11, 1.06], [1.10, 1.04, 0.954], [1.05, 0.965, 0.852], [1.01, 0.892, 0.751],
    [0.958, 0.819, 0.650], [0.912, 0.747, 0.549], [0.868, 0.674, 0.446], [0.828, 0.601, 0.341],
    [0.795, 0.526, 0.228]])

_LN4 = math.log(4.0)


@core
def _nu_weights(nu):
    """The quadratic Lagrange weights through nu = 0, 0.25, 0.5 (`_nu_interp`)."""
    return 8.0 * (nu - 0.25) * (nu - 0.5), -16.0 * nu * (nu - 0.5), 8.0 * nu * (nu - 0.25)


@core
def _nu_interp(c0, c1, c2, w):
    """Quadratic Lagrange interpolation of 1/C through nu = 0, 0.25, 0.5 with the weights w (`_nu_weights`):
    1 / (w0 / c0 + w1 / c1 + w2 / c2) over a common denominator, one division."""
    return c0 * c1 * c2 / (w[0] * c1 * c2 + w[1] * c0 * c2 + w[2] * c0 * c1)


@core
def _table_at(tab, row, frac, w):
    c0 = tab[row, 0] + frac * (tab[row + 1, 0] - tab[row, 0])
    c1 = tab[row, 1] + frac * (tab[row + 1, 1] - tab[row, 1])
    c2 = tab[row, 2] + frac * (tab[row + 1, 2] - tab[row, 2])
    return _nu_interp(c0, c1, c2, w)


@core
def _asym_small_a(g, nu):
    """Kalker's asymptotes for a/b = g -> 0: (C11, C22, C23, C33)."""
    c11 = math.pi * math.pi / (4.0 * (1.0 - nu))
    c22 = math.pi * math.pi / 4.0
    c23 = math.pi * math.sqrt(g) / (3.0 * (1.0 - nu)) * (1.0 + nu * (math.log(16.0 / g) - 5.0))
    c33 = math.pi * math.pi / (16.0 * (1.0 - nu) * g)
    return c11, c22, c23, c33


@core
def _asym_small_b(g, nu):
    """Kalker's asymptotes for b/a = g -> 0: (C11, C22, C23); C33 not used."""
    lam = math.log(16.0 / (g * g))
    d1 = lam - 2.0 * nu
    c11 = 2.0 * math.pi / (d1 * g) * (1.0 + (3.0 - _LN4) / d1)
    d2 = (1.0 - nu) * lam + 2.0 * nu
    c22 = 2.0 * math.pi / (g * d2) * (1.0 + (1.0 - nu) * (3.0 - _LN4) / d2)
    c23 = 2.0 * math.pi / (3.0 * g ** 1.5 * ((1.0 - nu) * lam - 2.0 + 4.0 * nu))
    return c11, c22, c23


@core
def kalker_coefficients(a_over_b, nu):
    """Kalker's linear-theory creep coefficients (C11, C22, C23, C33) for a/b and Poisson's ratio.

    a/b > 0 (a along the rolling direction), 0 <= nu <= 0.5. Table E3 of Kalker (1990) with the
    interpolation/extrapolation described in the module docstring.
    """
    if not (a_over_b > 0.0):
        raise ValueError("kalker_coefficients: a/b must be > 0")
    if not (nu >= 0.0 and nu <= 0.5):
        raise ValueError("kalker_coefficients: nu must be within [0, 0.5]")
    w = _nu_weights(nu)
    if a_over_b <= 1.0:
        u = a_over_b
    else:
        u = 2.0 - 1.0 / a_over_b
    if u < 0.1:
        # a/b < 0.1: continue the table with the asymptotic shape
        g = a_over_b
        t11 = _nu_interp(KALKER_C11[0, 0], KALKER_C11[0, 1], KALKER_C11[0, 2], w)
        t22 = _nu_interp(KALKER_C22[0, 0], KALKER_C22[0, 1], KALKER_C22[0, 2], w)
        t23 = _nu_interp(KALKER_C23[0, 0], KALKER_C23[0, 1], KALKER_C23[0, 2], w)
        t33 = _nu_interp(KALKER_C33[0, 0], KALKER_C33[0, 1], KALKER_C33[0, 2], w)
        s11, s22, s23, s33 = _asym_small_a(g, nu)
        r11, r22, r23, r33 = _asym_small_a(0.1, nu)
        return t11 * s11 / r11, t22 * s22 / r22, t23 * s23 / r23, t33 * s33 / r33
    if u > 1.9:
        g = 1.0 / a_over_b
        t11 = _nu_interp(KALKER_C11[18, 0], KALKER_C11[18, 1], KALKER_C11[18, 2], w)
        t22 = _nu_interp(KALKER_C22[18, 0], KALKER_C22[18, 1], KALKER_C22[18, 2], w)
        t23 = _nu_interp(KALKER_C23[18, 0], KALKER_C23[18, 1], KALKER_C23[18, 2], w)
        t33 = _nu_interp(KALKER_C33[18, 0], KALKER_C33[18, 1], KALKER_C33[18, 2], w)
        s11, s22, s23 = _asym_small_b(g, nu)
        r11, r22, r23 = _asym_small_b(0.1, nu)
        return t11 * s11 / r11, t22 * s22 / r22, t23 * s23 / r23, t33
    v = (u - 0.1) * 10.0
    row = int(math.floor(v))
    if row > 17:
        row = 17
    if row < 0:
        row = 0
    frac = v - row
    return (_table_at(KALKER_C11, row, frac, w), _table_at(KALKER_C22, row, frac, w),
            _table_at(KALKER_C23, row, frac, w), _table_at(KALKER_C33, row, frac, w))


def kalker_table(nu):
    """Kalker's coefficients at Poisson's ratio nu as the exact rational pieces of `tabulated_coefficients`:
    an array (KALKER_SEGMENTS, 4, KalkerPiece.size()) for `ContactConstants.kalker` (module docstring).

    Plain float arithmetic (no transcendental function), so the same on every CPU.
    """
    if not (0.0 <= nu <= 0.5):
        raise ValueError("kalker_table: nu must be within [0, 0.5]")
    w0, w1, w2 = 8.0 * (nu - 0.25) * (nu - 0.5), -16.0 * nu * (nu - 0.5), 8.0 * nu * (nu - 0.25)    # _nu_weights
    out = np.zeros((KALKER_SEGMENTS, 4, KalkerPiece.size()))
    for c, tab in enumerate((KALKER_C11, KALKER_C22, KALKER_C23, KALKER_C33)):
        for row in range(KALKER_SEGMENTS):
            t0, t1, t2 = (float(v) for v in tab[row])
            d0, d1, d2 = (float(tab[row + 1, j] - tab[row, j]) for j in range(3))   # c_j = t_j + f d_j (_table_at)
            piece = out[row, c]
            num, den = KalkerPiece.numerator, KalkerPiece.denominator
            piece[num + 0] = t0 * t1 * t2
            piece[num + 1] = d0 * t1 * t2 + t0 * d1 * t2 + t0 * t1 * d2
            piece[num + 2] = d0 * d1 * t2 + d0 * t1 * d2 + t0 * d1 * d2
            piece[num + 3] = d0 * d1 * d2
            piece[den + 0] = w0 * t1 * t2 + w1 * t0 * t2 + w2 * t0 * t1
            piece[den + 1] = w0 * (d1 * t2 + t1 * d2) + w1 * (d0 * t2 + t0 * d2) + w2 * (d0 * t1 + t0 * d1)
            piece[den + 2] = w0 * d1 * d2 + w1 * d0 * d2 + w2 * d0 * d1
    return out


_PIECE = KalkerPiece.size()


@core_inline
def _piece(cp, o, f):
    """P(f) / Q(f) of the KalkerPiece at cp[o:] (Horner)."""
    n = KalkerPiece.numerator
    d = KalkerPiece.denominator
    return ((cp[o + n] + f * (cp[o + n + 1] + f * (cp[o + n + 2] + f * cp[o + n + 3])))
            / (cp[o + d] + f * (cp[o + d + 1] + f * cp[o + d + 2])))


@core_inline
def tabulated_coefficients(cp, a, b):
    """Kalker's (C11, C22, C23, C33) for semi-axes a (along x), b > 0 from the contact constants' table
    (`ContactConstants.kalker`, at their Poisson ratio): `kalker_coefficients(a / b, nu)` to rounding, with
    one division and no branch on nu (module docstring); outside Table E3 (a/b < 0.1 or > 10) that function.

    Hand-written in the core: it runs on every loaded patch of every right-hand side (inlined into
    `wheelset.wheel_forces`, which passes cp on).
    """
    if a <= b:
        u = a / b
    else:
        u = 2.0 - b / a
    if not (u >= 0.1 and u <= 1.9):
        return kalker_coefficients(a / b, cp[ContactConstants.poisson_ratio])
    v = (u - 0.1) * 10.0
    row = min(int(v), KALKER_SEGMENTS - 1)
    f = v - row
    o = ContactConstants.kalker + 4 * _PIECE * row
    return _piece(cp, o, f), _piece(cp, o + _PIECE, f), _piece(cp, o + 2 * _PIECE, f), _piece(cp, o + 3 * _PIECE, f)


@core
def linear_forces(xi_x, xi_y, phi, a, b, G, C11, C22, C23, C33):
    """Kalker's linear theory (Fx, Fy, Mz) on the wheel for given coefficients (no friction cap)."""
    ab = a * b
    sab = math.sqrt(ab)
    Fx = -G * ab * C11 * xi_x
    Fy = -G * ab * C22 * xi_y - G * ab * sab * C23 * phi
    Mz = G * ab * sab * C23 * xi_y - G * ab * ab * C33 * phi
    return Fx, Fy, Mz


@core
def she_factor(F_lin, mu_N):
    """Shen-Hedrick-Elkins saturation ratio F/F_lin for the resultant linear force F_lin >= 0."""
    if not (mu_N > 0.0):
        return 0.0
    beta = F_lin / mu_N
    if beta < 3.0:
        return 1.0 - beta / 3.0 + beta * beta / 27.0
    return mu_N / F_lin


@core
def polach_forces(xi_x, xi_y, phi, a, b, N, mu0, G, C11, C22, C23, C33, V, kA, kS, A_ratio,
                  B_decay):
    """Polach's creep forces (Fx, Fy, Mz) on the wheel (Polach 1999; 2005 extension).

    mu0 maximum friction coefficient; V [m/s] rolling speed (only used by the friction decrease);
    kA, kS reduction factors (adhesion/slip area); A_ratio = mu_inf/mu0, B_decay [s/m] the
    exponential friction decrease mu = mu0((1 - A)exp(-B w) + A), w = V s_C. With kA = kS = 1 and
    A_ratio = 1 this is the 1999 method. Mz: linear-theory Mz times the translational saturation
    factor (not part of Polach's method).
    """
    if not (N > 0.0) or not (a > 0.0) or not (b > 0.0) or not (mu0 > 0.0):
        return 0.0, 0.0, 0.0
    # spin-augmented lateral creepage (Polach 1999)
    syc = xi_y + phi * a
    if abs(syc) <= abs(xi_y):
        syc = xi_y
    sc = math.sqrt(xi_x * xi_x + syc * syc)
    if sc == 0.0:
        return 0.0, 0.0, 0.0
    mu = mu0 * ((1.0 - A_ratio) * math.exp(-B_decay * V * sc) + A_ratio)
    muN = mu * N
    # contact-elasticity coefficient C (N/m^3) from Kalker's coefficients, direction of the
    # translational creepage (so that the small-creepage limit is Kalker's linear theory)
    s = math.sqrt(xi_x * xi_x + xi_y * xi_y)
    if s > 0.0:
        cdir = math.sqrt((C11 * xi_x) ** 2 + (C22 * xi_y) ** 2) / s
    else:
        cdir = C22
    Cc = 3.0 * G * cdir / (8.0 * a)
    eps = (2.0 / 3.0) * Cc * math.pi * a * a * b * sc / muN
    ea = kA * eps
    F = 2.0 * muN / math.pi * (ea / (1.0 + ea * ea) + math.atan(kS * eps))
    Fx = -F * xi_x / sc
    Fy = -F * xi_y / sc
    # spin contribution to the lateral force
    fac = 1.0 + 6.3 * (1.0 - math.exp(-a / b))
    epsm = (8.0 / 3.0) * G * b * math.sqrt(a * b) / muN * C23 * sc / fac
    e2 = epsm * epsm
    dl = (e2 - 1.0) / (e2 + 1.0)
    omd2 = 4.0 * e2 / ((e2 + 1.0) * (e2 + 1.0))          # 1 - delta^2 without cancellation
    KM = abs(epsm) * (dl * dl * dl / 3.0 - dl * dl / 2.0 + 1.0 / 6.0) - math.sqrt(omd2 ** 3) / 3.0
    FyS = -9.0 / 16.0 * a * muN * KM * fac * phi / sc     # Polach's sign: along the creepage
    Fy -= FyS
    # spin moment: linear theory scaled by the translational saturation
    ab = a * b
    sab = math.sqrt(ab)
    Mz = G * ab * sab * C23 * xi_y - G * ab * ab * C33 * phi
    Flin = G * ab * cdir * sc
    if Flin > 0.0:
        Mz *= F / Flin
    return Fx, Fy, Mz


@core
def creep_forces(model_id, xi_x, xi_y, phi, a, b, N, mu, G, nu):
    """Creep forces (Fx, Fy, Mz) on the wheel for the selected model.

    model_id: LINEAR, SHEN_HEDRICK_ELKINS, POLACH (1999 form) or FASTSIM (20 x 20). Inputs:
    creepages xi_x, xi_y [-], spin phi [1/m], semi-axes a (x), b (y) [m], normal load N [N], friction
    coefficient mu, shear modulus G [Pa], Poisson's ratio nu. Zero forces for N <= 0 or a, b <= 0.
    """
    if not (N > 0.0) or not (a > 0.0) or not (b > 0.0):
        return 0.0, 0.0, 0.0
    C11, C22, C23, C33 = kalker_coefficients(a / b, nu)
    return creep_law(model_id, xi_x, xi_y, phi, a, b, N, mu, G, C11, C22, C23, C33)


@core
def creep_law(model_id, xi_x, xi_y, phi, a, b, N, mu, G, C11, C22, C23, C33):
    """`creep_forces` given Kalker's coefficients (`kalker_coefficients`, `tabulated_coefficients`) for a/b;
    N, a and b > 0."""
    if model_id == LINEAR:
        return linear_forces(xi_x, xi_y, phi, a, b, G, C11, C22, C23, C33)
    if model_id == SHEN_HEDRICK_ELKINS:
        Fx, Fy, Mz = linear_forces(xi_x, xi_y, phi, a, b, G, C11, C22, C23, C33)
        F = math.sqrt(Fx * Fx + Fy * Fy)
        if F == 0.0:
            if mu > 0.0:
                return Fx, Fy, Mz
            return 0.0, 0.0, 0.0
        e = she_factor(F, mu * N)
        return Fx * e, Fy * e, Mz * e
    if model_id == POLACH:
        return polach_forces(xi_x, xi_y, phi, a, b, N, mu, G, C11, C22, C23, C33,
                             0.0, 1.0, 1.0, 1.0, 0.0)
    if model_id == FASTSIM:
        return fastsim_forces(xi_x, xi_y, phi, a, b, N, mu, G, C11, C22, C23,
                              NX_DEFAULT, NY_DEFAULT)
    raise ValueError("creep_forces: model_id must be 0 LINEAR, 1 SHEN_HEDRICK_ELKINS, 2 POLACH "
                     "or 3 FASTSIM")
