"""Kik-Piotrowski (KP) non-elliptic normal contact and strip-FASTSIM creep forces (numba core).

Model (Kik & Piotrowski 1996; Piotrowski & Kik 2008)
----------------------------------------------------
Input is the undeformed normal separation ``gap(y)`` of wheel and rail along the lateral (tangent)
coordinate ``y = s`` of the contact, on a uniform grid, with min 0 at the point of first contact,
plus the wheel's longitudinal radius ``R(y)`` (rolling radius seen in the contact plane; the rail is
straight along x). The bodies approach by ``delta`` (rigid normal approach).

1. Patches. Strips are the grid cells (width ds, centred at the grid points). A *patch* is a
   contiguous run of strips with geometric interpenetration ``gap < delta``; runs separated by at
   least one strip with ``gap >= delta`` are separate patches (two-point contact, e.g. tread and
   flange). Each patch k has its own deepest point y0_k (min gap g_k) and local approach
   ``delta_k = delta - g_k``; patches do not interact elastically (as in KP).
2. Virtual penetration. The contact area is the interpenetration region of the undeformed
   profiles for the *reduced* approach ``eps * delta_k`` (Piotrowski & Kik 2008: the elastic
   surface displacement outside the loaded area makes the real patch smaller than the geometric
   overlap; for a sphere on a plane the overlap at approach delta has radius sqrt(2 R delta) while
   Hertz gives sqrt(R delta), i.e. eps = 0.5 exactly; KP recommend eps ~ 0.55 as a compromise over
   elliptic shapes, default ``EPS_DEFAULT = 0.55``). Interpenetration function
   ``f(y) = eps delta_k - (gap(y) - g_k)``, ``f > 0`` inside; the longitudinal half-length of each
   strip follows from the wheel's longitudinal curvature: ``x_L(y) = sqrt(2 R(y) f(y))``.
3. Pressure: semi-elliptic along x in every strip, proportional to the strip half-length:
   ``p(x, y) = p0 sqrt(x_L(y)^2 - x^2) / x_L0`` with x_L0 = x_L(y0) (Hertz's distribution when
   the region is an ellipse and R is constant).
4. Normal force (closed form, no iteration): the normal surface displacement of both bodies at
   the deepest point (x = 0, y = y0), computed with Boussinesq's solution, must equal ``delta_k``:

       delta_k = 1/(pi E*) int int p(x, y) / sqrt(x^2 + (y - y0)^2) dx dy,   E* = E/(2(1-nu^2))

   (identical materials), hence
   ``N_k = pi E* delta_k I_S / I_R`` with ``I_S = int int sqrt(x_L^2 - x^2) dA = sum pi x_L^2/2 ds``
   and ``I_R = int int sqrt(x_L^2 - x^2)/r dA``. The x-integral is closed form,
   ``int_{-L}^{L} sqrt(L^2 - x^2)/sqrt(x^2 + eta^2) dx = 2 c (K(k) - E(k))``, c = sqrt(L^2 + eta^2),
   k = L/c (derivation: x = L sin t), with K, E the complete elliptic integrals. K - E comes from
   Hastings' approximations in the complementary parameter m1 = k'^2 = (eta/c)^2 (Abramowitz & Stegun
   1964, 17.3.34 and 17.3.36; error below 2e-8 in each of K and E, one logarithm, several times cheaper
   than the arithmetic-geometric mean of ``hertz.ellip_ke``, which the strip integral calls two to four
   times per strip; k' is passed directly so that eta -> 0 is accurate). Over each strip (x_L constant)
   the y-integral is done by Gauss-Legendre (2 points far from y0, 4 points within two strips of
   y0); near y0 the logarithmic singularity 2c(K - E) ~ 2L(ln(4L/|eta|) - 1) is subtracted and
   integrated analytically. ``p0 = N_k x_L0 / I_S``.
   Check: for a sphere on a plane with eps = 0.5 this is Hertz exactly (N = 4/3 E* a^3/R).
5. Inverse: ``kp_delta_for_force`` finds delta for a total normal load by a safeguarded secant
   iteration on ln N(ln delta) (N ~ delta^1.5), bracketed, ~5-8 evaluations.
6. The vehicle core's patch (``kp_strip_force``): one patch given as m strips that cover exactly its
   extent, which the caller places at fixed fractions of it (``wheelset._discrete_normal``: 16 strips),
   so that the load moves continuously with the edges; the same strip integrals with Euler-Maclaurin
   end terms for I_S and the area (docs/contact-models.md gives the error against the converged KP).

Tangential problem (``kp_creep_forces``): FASTSIM (``fastsim.fastsim_strip``) strip by strip over
the KP patch, with the traction bound ``mu p(x, y)`` of the KP pressure (semi-elliptic in x) and
one set of flexibilities L1, L2, L3 (Kalker 1982) for the whole patch, taken from an *equivalent
ellipse*: a_eq/b_eq = (max length)/(width) of the patch and pi a_eq b_eq = patch area; Kalker's
C11, C22, C23 at a_eq/b_eq (``creep.kalker_coefficients``). This follows Piotrowski & Kik's
proposal to run FASTSIM on the non-elliptic patch with flexibilities from an equivalent ellipse;
the choice of the equivalent ellipse (length/width ratio and area) is ours and documented in
docs/contact-models.md. For an elliptic KP patch it reduces to FASTSIM on that ellipse (with a
semi-elliptic instead of parabolic bound) and to Kalker's linear theory at small creepage. The
spin term uses y measured from the patch's deepest point y0 (the contact reference point at which
the creepages must be given).

Limits: half-space theory (small patch compared with the profile radii is *not* needed laterally,
but the bodies must be locally flat on the patch scale), identical elastic constants for wheel and
rail, frictionless normal problem, no elastic interaction between separate patches, eps is an
empirical constant.

Data layout (allocation-free cores; the caller allocates):
``xl`` (n,) strip half-lengths [m] (0 outside patches), ``pid`` (n,) int patch index or -1,
``patches`` (max_patches, NPROP) float rows, one `DiscretePatch` record each.
``kp_patches`` is a Python convenience wrapper that allocates and returns a list of dicts.

References
----------
Kik, W., Piotrowski, J. (1996) A fast, approximate method to calculate normal load at contact
between wheel and rail and creep forces during rolling. In: Zobory, I. (ed.) Proc. 2nd Mini
Conference on Contact Mechanics and Wear of Rail/Wheel Systems, Budapest, 52-61.
Piotrowski, J., Kik, W. (2008) A simplified model of wheel/rail contact mechanics for non-Hertzian
problems and its application in rail vehicle dynamic simulations. Vehicle System Dynamics 46
(1-2), 27-48.
Johnson, K.L. (1985) Contact Mechanics, §3.2 (Boussinesq point load).
Kalker, J.J. (1982) Vehicle System Dynamics 11, 1-13 (FASTSIM).
"""
import math

import numpy as np

from ..jit import core
from ..record import Record
from .creep import kalker_coefficients
from .fastsim import BOUND_ELLIPTIC, fastsim_strip, flexibilities
from .hertz import combined_modulus

EPS_DEFAULT = 0.55



class DiscretePatch(Record):
    """A row of the `patches` output of `kp_normal`: one Kik-Piotrowski patch."""
    normal_force = "N", "normal load of the patch"
    y_min = "m", "lateral extent: first interpolated zero of the interpenetration f"
    y_max = "m", "lateral extent: last zero of f"
    length = "m", "2 max x_L"
    width = "m", "y_max - y_min"
    area = "m^2", "sum of 2 x_L ds"
    y_centroid = "m", "pressure-weighted centroid y"
    p_max = "Pa", "maximum pressure"
    approach = "m", "local approach delta_k = delta - gap_min"
    y0 = "m", "y of the deepest point (the reference point of the creepages)"
    xl0 = "m", "x_L at y0"
    p0 = "Pa", "pressure at (0, y0)"
    a_eq = "m", "equivalent ellipse: semi-axis along x"
    b_eq = "m", "equivalent ellipse: lateral semi-axis"
    j0 = "-", "first strip index of the patch run"
    j1 = "-", "strip index just past the run"
    jm = "-", "strip index of the deepest point"


NPROP = DiscretePatch.size()

# Gauss-Legendre nodes/weights on [-1, 1]
_G2X = 0.5773502691896257
_G4X1 = 0.3399810435848563
_G4X2 = 0.8611363115940526
_G4W1 = 0.6521451548625461
_G4W2 = 0.3478548451374538


# K(m) - E(m) = P(m1) + Q(m1) ln(1/m1), m1 = 1 - m: differences of Hastings' coefficients (A&S 17.3.34 for K,
# 17.3.36 for E)
_KME_P = (0.38629436112, 0.09666344259 - 0.44325141463, 0.03590092383 - 0.06260601220,
          0.03742563713 - 0.04757383546, 0.01451196212 - 0.01736506451)
_KME_Q = (0.5, 0.12498593597 - 0.24998368310, 0.06880248576 - 0.09200180037,
          0.03328355346 - 0.04069697526, 0.00441787012 - 0.00526449639)


@core
def _k_minus_e(kc):
    """K(k) - E(k) from the complementary modulus kc = sqrt(1 - k^2), 0 < kc <= 1 (absolute error < 4e-8)."""
    m1 = kc * kc
    p = _KME_P[0] + m1 * (_KME_P[1] + m1 * (_KME_P[2] + m1 * (_KME_P[3] + m1 * _KME_P[4])))
    q = _KME_Q[0] + m1 * (_KME_Q[1] + m1 * (_KME_Q[2] + m1 * (_KME_Q[3] + m1 * _KME_Q[4])))
    return p - q * math.log(m1)


@core
def _kernel(L, eta):
    """int_{-L}^{L} sqrt(L^2 - x^2)/sqrt(x^2 + eta^2) dx = 2 c (K(k) - E(k)); eta != 0."""
    c = math.sqrt(L * L + eta * eta)
    return 2.0 * c * _k_minus_e(abs(eta) / c)


@core
def _glog(eta):
    """Antiderivative of ln|eta|: eta (ln|eta| - 1), 0 at eta = 0."""
    if eta == 0.0:
        return 0.0
    return eta * (math.log(abs(eta)) - 1.0)


@core
def _strip_IR(L, e1, e2, near):
    """int_{e1}^{e2} 2c(K-E) d eta for one strip of half-length L, eta relative to y0."""
    hm = 0.5 * (e2 - e1)
    cm = 0.5 * (e2 + e1)
    if not near:
        return hm * (_kernel(L, cm - hm * _G2X) + _kernel(L, cm + hm * _G2X))
    # subtract the log singularity -2L ln|eta| and integrate it exactly
    tot = -2.0 * L * (_glog(e2) - _glog(e1))
    s = 0.0
    for i in range(4):
        if i == 0:
            t, w = -_G4X2, _G4W2
        elif i == 1:
            t, w = -_G4X1, _G4W1
        elif i == 2:
            t, w = _G4X1, _G4W1
        else:
            t, w = _G4X2, _G4W2
        eta = cm + hm * t
        s += w * (_kernel(L, eta) + 2.0 * L * math.log(abs(eta)))
    return tot + hm * s


@core
def _run_end(gap, delta, r0, n):
    """End (exclusive) of the run of strips with gap < delta starting at r0."""
    r1 = r0
    while r1 < n and gap[r1] < delta:
        r1 += 1
    return r1


@core
def _run_force(s0, ds, gap, R_long, r0, r1, delta, eps, Estar):
    """Normal load and integrals of one patch run [r0, r1). Returns (N, IS, jm, dk, xl0)."""
    jm = r0
    for j in range(r0 + 1, r1):
        if gap[j] < gap[jm]:
            jm = j
    gmin = gap[jm]
    dk = delta - gmin
    h = eps * dk
    IS = 0.0
    IR = 0.0
    y0 = s0 + jm * ds
    for j in range(r0, r1):
        f = h - (gap[j] - gmin)
        if f <= 0.0:
            continue
        L = math.sqrt(2.0 * R_long[j] * f)
        IS += 0.5 * math.pi * L * L * ds
        yj = s0 + j * ds - y0
        IR += _strip_IR(L, yj - 0.5 * ds, yj + 0.5 * ds, abs(j - jm) <= 2)
    xl0 = math.sqrt(2.0 * R_long[jm] * h)
    if IR <= 0.0:
        return 0.0, IS, jm, dk, xl0
    N = math.pi * Estar * dk * IS / IR
    return N, IS, jm, dk, xl0

_SQRT_EDGE = 2.0 * 0.0608875    # -2 zeta(-1/2, 1/2) = -2 (2^-1/2 - 1) zeta(-1/2)


@core
def kp_strip_force(f, R_long, m, ds, y0, f_edges, f0, approach, Estar, xl):
    """KP normal load of one patch sampled by m strips that cover exactly its extent (allocation-free).

    Strip i is [i ds, (i + 1) ds]; f[i] is the virtual interpenetration eps delta_k - (gap - g_k) and
    R_long[i] the wheel's longitudinal radius at its centre (i + 0.5) ds; y0 the deepest point in the same
    coordinate; approach delta_k. Fills xl[:m] with the strips' half-lengths (0 where f <= 0). Unlike
    `kp_normal`, whose strips are the grid's cells, the strips here move with the patch's edges (the
    caller places them at fixed fractions of its extent), so the load is continuous in the approach and
    in the pose at any m; the strip integrals are those of `kp_normal` (`_strip_IR`, the logarithmic
    singularity integrated exactly within 2.5 strips of y0). Returns (N, IS, xlmax, area).
    """
    IS = 0.0
    IR = 0.0
    xlmax = 0.0
    area = 0.0
    for i in range(m):
        fi = f[i]
        if fi <= 0.0:
            xl[i] = 0.0
            continue
        L = math.sqrt(2.0 * R_long[i] * fi)
        xl[i] = L
        IS += 0.5 * math.pi * L * L * ds
        area += 2.0 * L * ds
        if L > xlmax:
            xlmax = L
        e1 = i * ds - y0
        e2 = e1 + ds
        IR += _strip_IR(L, e1, e2, abs(e1 + 0.5 * ds) <= 2.5 * ds)
    # I_S = pi int R f dy: the midpoint sum above with its Euler-Maclaurin end terms, h^2/24 (g'(b) - g'(a)),
    # the slopes of g = R f at the edges from the parabola through the edge value and the two outer strips
    # (exact for a parabolic gap: the midpoint sum alone is 1/(2 m^2) high there)
    if m >= 2:
        fa, fb = f_edges
        ga = R_long[0] * fa
        gb = R_long[m - 1] * fb
        g0 = R_long[0] * max(f[0], 0.0)
        g1 = R_long[1] * max(f[1], 0.0)
        gm = R_long[m - 1] * max(f[m - 1], 0.0)
        gn = R_long[m - 2] * max(f[m - 2], 0.0)
        slope_a = -8.0 / 3.0 * ga + 3.0 * g0 - g1 / 3.0          # h g'(a)
        slope_b = 8.0 / 3.0 * gb - 3.0 * gm + gn / 3.0           # h g'(b)
        IS += math.pi * ds / 24.0 * (slope_b - slope_a)
        # the area int 2 x_L dy: x_L ~ sqrt(distance) at an edge where f = 0, where the midpoint sum is high by
        # -2 zeta(-1/2, 1/2) h sqrt(h dL^2/dy) (Hurwitz's zeta; the slope again from the outer strips)
        if fa == 0.0:
            area -= _SQRT_EDGE * ds * math.sqrt(max(3.0 * xl[0] * xl[0] - xl[1] * xl[1] / 3.0, 0.0))
        if fb == 0.0:
            area -= _SQRT_EDGE * ds * math.sqrt(max(3.0 * xl[m - 1] * xl[m - 1] - xl[m - 2] * xl[m - 2] / 3.0, 0.0))
    # the longest strip at the deepest point (between the strips' centres in general)
    i0 = min(max(int(y0 / ds), 0), m - 1)
    if f0 > 0.0:
        xlmax = max(xlmax, math.sqrt(2.0 * R_long[i0] * f0))
    if IR <= 0.0 or IS <= 0.0:
        return 0.0, IS, xlmax, area
    return math.pi * Estar * approach * IS / IR, IS, xlmax, area


@core
def _check_inputs(s, gap, R_long, E, nu, eps):
    n = s.shape[0]
    if n < 2 or gap.shape[0] != n or R_long.shape[0] != n:
        raise ValueError("kik_piotrowski: s, gap, R_long must have the same length >= 2")
    if not (E > 0.0) or not (nu >= 0.0 and nu < 0.5):
        raise ValueError("kik_piotrowski: need E > 0 and 0 <= nu < 0.5")
    if not (eps > 0.0 and eps <= 1.0):
        raise ValueError("kik_piotrowski: eps must be within (0, 1]")


@core
def kp_normal_force(s, gap, R_long, delta, E, nu, eps):
    """Total KP normal load [N] for approach delta [m] (sum over patches); allocation-free."""
    _check_inputs(s, gap, R_long, E, nu, eps)
    if not (delta > 0.0):
        return 0.0
    n = s.shape[0]
    ds = s[1] - s[0]
    Estar = combined_modulus(E, nu, E, nu)
    Ntot = 0.0
    j = 0
    while j < n:
        if gap[j] < delta:
            r1 = _run_end(gap, delta, j, n)
            N, IS, jm, dk, xl0 = _run_force(s[0], ds, gap, R_long, j, r1, delta, eps, Estar)
            Ntot += N
            j = r1
        else:
            j += 1
    return Ntot


@core
def kp_normal(s, gap, R_long, delta, E, nu, eps, xl, pid, patches):
    """KP normal contact for approach delta: fills xl, pid, patches; returns the number of patches.

    s (n,) uniform lateral grid [m]; gap (n,) undeformed normal separation [m] (min 0); R_long (n,)
    wheel longitudinal radius [m]; delta [m]; E [Pa], nu; eps virtual-penetration factor.
    Outputs (caller-allocated): xl (n,) half-lengths, pid (n,) int patch index (-1 outside),
    patches (maxp, NPROP) rows (`DiscretePatch`). Patches beyond maxp are ignored (their strips
    keep pid = -1 and xl = 0); the return value counts the stored patches.
    """
    _check_inputs(s, gap, R_long, E, nu, eps)
    n = s.shape[0]
    maxp = patches.shape[0]
    for j in range(n):
        xl[j] = 0.0
        pid[j] = -1
    for k in range(maxp):
        for c in range(patches.shape[1]):
            patches[k, c] = 0.0
    if not (delta > 0.0):
        return 0
    ds = s[1] - s[0]
    s0 = s[0]
    Estar = combined_modulus(E, nu, E, nu)
    np_ = 0
    j = 0
    while j < n and np_ < maxp:
        if not (gap[j] < delta):
            j += 1
            continue
        r0 = j
        r1 = _run_end(gap, delta, r0, n)
        j = r1
        N, IS, jm, dk, xl0 = _run_force(s0, ds, gap, R_long, r0, r1, delta, eps, Estar)
        if IS <= 0.0:
            continue
        gmin = gap[jm]
        h = eps * dk
        area = 0.0
        xlmax = 0.0
        ymom = 0.0
        jfirst = -1
        jlast = -1
        for i in range(r0, r1):
            f = h - (gap[i] - gmin)
            if f > 0.0:
                L = math.sqrt(2.0 * R_long[i] * f)
                xl[i] = L
                pid[i] = np_
                area += 2.0 * L * ds
                ymom += (s0 + i * ds) * 0.5 * math.pi * L * L * ds
                if L > xlmax:
                    xlmax = L
                if jfirst < 0:
                    jfirst = i
                jlast = i
        # lateral extent: linear interpolation of f to its zero beyond the first/last inner strip
        f_in = h - (gap[jfirst] - gmin)
        if jfirst > 0:
            f_out = h - (gap[jfirst - 1] - gmin)
            ymin = s0 + jfirst * ds - ds * f_in / (f_in - f_out)
        else:
            ymin = s0 - 0.5 * ds
        f_in = h - (gap[jlast] - gmin)
        if jlast < n - 1:
            f_out = h - (gap[jlast + 1] - gmin)
            ymax = s0 + jlast * ds + ds * f_in / (f_in - f_out)
        else:
            ymax = s0 + (n - 1) * ds + 0.5 * ds
        width = ymax - ymin
        p0 = N * xl0 / IS
        row = patches[np_]
        row[DiscretePatch.normal_force] = N
        row[DiscretePatch.y_min] = ymin
        row[DiscretePatch.y_max] = ymax
        row[DiscretePatch.length] = 2.0 * xlmax
        row[DiscretePatch.width] = width
        row[DiscretePatch.area] = area
        row[DiscretePatch.y_centroid] = ymom / IS
        row[DiscretePatch.p_max] = p0 * xlmax / xl0
        row[DiscretePatch.approach] = dk
        row[DiscretePatch.y0] = s0 + jm * ds
        row[DiscretePatch.xl0] = xl0
        row[DiscretePatch.p0] = p0
        ratio = xlmax / (0.5 * width)
        row[DiscretePatch.a_eq] = math.sqrt(area / math.pi * ratio)
        row[DiscretePatch.b_eq] = math.sqrt(area / (math.pi * ratio))
        row[DiscretePatch.j0] = r0
        row[DiscretePatch.j1] = r1
        row[DiscretePatch.jm] = jm
        np_ += 1
    return np_


@core
def kp_delta_for_force(s, gap, R_long, N_target, E, nu, eps):
    """Approach delta [m] at which the total KP normal load equals N_target [N] (0 if N <= 0).

    Safeguarded secant on ln N versus ln delta (N ~ delta^1.5), relative tolerance 1e-10 on N.
    """
    _check_inputs(s, gap, R_long, E, nu, eps)
    if not (N_target > 0.0):
        return 0.0
    lt = math.log(N_target)
    # first guess: 0.1 mm, then the power law N ~ delta^1.5 to build a bracket
    d1 = 1e-4
    N1 = kp_normal_force(s, gap, R_long, d1, E, nu, eps)
    for _ in range(60):
        if N1 > 0.0:
            break
        d1 *= 4.0
        N1 = kp_normal_force(s, gap, R_long, d1, E, nu, eps)
    if not (N1 > 0.0):
        raise ValueError("kp_delta_for_force: no contact found (check gap has min 0)")
    x1 = math.log(d1)
    f1 = math.log(N1) - lt
    x2 = x1 - f1 / 1.5
    N2 = kp_normal_force(s, gap, R_long, math.exp(x2), E, nu, eps)
    f2 = math.log(N2) - lt if N2 > 0.0 else -1e3
    lo, flo, hi, fhi = x1, f1, x2, f2
    if f1 > f2:
        lo, flo, hi, fhi = x2, f2, x1, f1
    # expand to a bracket flo < 0 < fhi
    for _ in range(60):
        if flo < 0.0:
            break
        lo -= 1.0
        Nl = kp_normal_force(s, gap, R_long, math.exp(lo), E, nu, eps)
        flo = math.log(Nl) - lt if Nl > 0.0 else -1e3
    for _ in range(60):
        if fhi > 0.0:
            break
        hi += 1.0
        fhi = math.log(kp_normal_force(s, gap, R_long, math.exp(hi), E, nu, eps)) - lt
    # Illinois regula falsi
    side = 0
    x = 0.5 * (lo + hi)
    for _ in range(100):
        x = (lo * fhi - hi * flo) / (fhi - flo)
        if not (lo < x < hi):
            x = 0.5 * (lo + hi)
        Nx = kp_normal_force(s, gap, R_long, math.exp(x), E, nu, eps)
        fx = math.log(Nx) - lt if Nx > 0.0 else -1e3
        if abs(fx) < 1e-10 or hi - lo < 1e-13:
            return math.exp(x)
        if fx < 0.0:
            lo, flo = x, fx
            if side == -1:
                fhi *= 0.5
            side = -1
        else:
            hi, fhi = x, fx
            if side == 1:
                flo *= 0.5
            side = 1
    return math.exp(x)


@core
def kp_creep_forces(s, xl, patches, k, xi_x, xi_y, phi, mu, G, nu, nx):
    """Creep forces (Fx, Fy) on the wheel for KP patch k by strip-wise FASTSIM.

    s (n,) grid, xl (n,) and patches from ``kp_normal``; creepages xi_x, xi_y [-] and spin phi
    [1/m] at the patch's reference point y0 = patches[k, DiscretePatch.y0]; mu friction coefficient; G [Pa]
    shear modulus; nu Poisson's ratio; nx elements per strip (e.g. fastsim.NX_DEFAULT). Sign
    convention as creep.py (forces oppose the creepage).
    """
    row = patches[k]
    N = row[DiscretePatch.normal_force]
    if not (N > 0.0):
        return 0.0, 0.0
    ds = s[1] - s[0]
    s0 = s[0]
    aeq = row[DiscretePatch.a_eq]
    beq = row[DiscretePatch.b_eq]
    C11, C22, C23, C33 = kalker_coefficients(aeq / beq, nu)
    L1, L2, L3 = flexibilities(aeq, beq, G, C11, C22, C23)
    p0 = row[DiscretePatch.p0]
    xl0 = row[DiscretePatch.xl0]
    y0 = row[DiscretePatch.y0]
    j0 = int(row[DiscretePatch.j0])
    j1 = int(row[DiscretePatch.j1])
    Fx = 0.0
    Fy = 0.0
    for j in range(j0, j1):
        L = xl[j]
        if L <= 0.0:
            continue
        y = s0 + j * ds - y0
        fx, fy, mz = fastsim_strip(xi_x, xi_y, phi, y, L, nx, mu, p0 * L / xl0,
                                   BOUND_ELLIPTIC, L1, L2, L3)
        Fx += fx * ds
        Fy += fy * ds
    return Fx, Fy


def kp_patches(s, gap, R_long, delta, E, nu, eps=EPS_DEFAULT, max_patches=4):
    """Python convenience wrapper (allocates): returns (xl, pid, a dict of DiscretePatch fields per patch,
    patches)."""
    s = np.ascontiguousarray(s, dtype=np.float64)
    gap = np.ascontiguousarray(gap, dtype=np.float64)
    R_long = np.ascontiguousarray(R_long, dtype=np.float64)
    n = s.shape[0]
    xl = np.zeros(n)
    pid = np.full(n, -1, dtype=np.int64)
    patches = np.zeros((int(max_patches), NPROP))
    m = kp_normal(s, gap, R_long, float(delta), float(E), float(nu), float(eps), xl, pid, patches)
    out = []
    for k in range(m):
        d = {field.name: float(patches[k, field]) for field in DiscretePatch}
        for field in (DiscretePatch.j0, DiscretePatch.j1, DiscretePatch.jm):
            d[field.name] = int(d[field.name])
        out.append(d)
    return xl, pid, out, patches
