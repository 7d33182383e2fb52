"""FASTSIM: Kalker's simplified theory of steady rolling contact on a Hertzian ellipse (numba core).

Model
-----
Kalker's *simplified theory* (Kalker 1973; algorithm FASTSIM, Kalker 1982) replaces the elastic
half-space by independent tangential springs ("Winkler bedding"): the surface displacement is
proportional to the local traction, ``u_i = L_i p_i``. With steady rolling in +x (material flows
from the leading edge ``x = +a(y)`` to the trailing edge ``x = -a(y)``) the slip is

    s = w - d u / dx,    w_x = xi_x - phi y,   w_y = xi_y + phi x,

(w the rigid slip per unit rolling distance: creepages xi_x, xi_y [-], spin phi [1/m]). In the
adhesion area s = 0, so the traction grows linearly along each strip; where ``|p|`` would exceed
the traction bound ``g = mu p_n`` the element slips and ``p`` is scaled back onto the bound in the
direction of the trial traction (Kalker's FASTSIM rule). One marching sweep per strip, no
iterations.

* Patch: the Hertz ellipse ``x^2/a^2 + y^2/b^2 <= 1`` (a along x = rolling, b along y).
* Traction bound: Kalker's *parabolic* pressure ``p_n = 2N/(pi a b) (1 - x^2/a^2 - y^2/b^2)``
  (Kalker 1982: with the parabolic bound the simplified theory's saturated law is close to the
  exact one; the total is N).
* Flexibilities (Kalker 1982; also Kalker 1990 §3.3, and Iwnicki (ed.) Handbook of Railway
  Vehicle Dynamics, 2006, ch. 4):

      L1 = 8 a / (3 G C11),   L2 = 8 a / (3 G C22),   L3 = pi a sqrt(a/b) / (4 G C23),

  chosen so that for vanishing creepage the simplified theory returns Kalker's *linear theory*
  forces: Fx = -G a b C11 xi_x (pure xi_x), Fy = -G a b C22 xi_y (pure xi_y) and
  Fy = -G (ab)^{3/2} C23 phi (pure spin). Check: with p_x = -(xi_x/L1)(a(y) - x),
  Fx = -(xi_x/L1) int 2 a(y)^2 dy = -(8 a^2 b / (3 L1)) xi_x; with
  p_y = -(phi/(2 L3))(a(y)^2 - x^2), Fy = -(pi a^3 b / (4 L3)) phi. (The spin moment of FASTSIM in
  the linear range is *not* Kalker's C33 value and the lateral-creepage moment is not the C23
  value: a known property of the simplified theory with one L per direction.)

Sign convention (same as ``creep.py``): creepages are (wheel - rail) material velocities at the
contact divided by the rolling speed; the returned forces/moment act *on the wheel* (from the
rail), i.e. they oppose the creepage: Fx = -G ab C11 xi_x in the linear limit.
Mz = int (x p_y - y p_x) dA about the ellipse centre.

Discretisation
--------------
``ny`` strips of equal width ``dy = 2b/ny`` centred at ``y_j = -b + (j + 1/2) dy``; each strip
(half-length ``a_j = a sqrt(1 - y_j^2/b^2)``) has ``nx`` elements of equal length ``2 a_j/nx``.
Tractions live at the element midpoints; the no-slip increment between two midpoints is the exact
integral of the (linear in x) rigid slip, and the traction bound is applied at the midpoints
(bounding at the element ends would force p = 0 at the trailing-edge node, where p_n = 0, and lose
~1/nx of the force even at vanishing creepage). Forces are integrated with the midpoint rule in
x (exact for the linear creepage part) and in y. Defaults ``nx = ny = 20`` (module constants
``NX_DEFAULT``, ``NY_DEFAULT``): small-creepage error vs. the linear theory +0.13 % for pure
creepage (midpoint rule in y on a(y)^2), +0.15 % for pure spin. The saturated limit is exactly
mu N: the discrete traction bound is normalised so that its element sum equals the strip load
integrated exactly in x, and the strip loads sum to N. Cost O(nx ny), no allocation.

``fastsim_strip`` is the single-strip kernel; ``kik_piotrowski.py`` reuses it on non-elliptic
patches with a semi-elliptic (instead of parabolic) traction bound (``BOUND_ELLIPTIC``).

References
----------
Kalker, J.J. (1982) A fast algorithm for the simplified theory of rolling contact. Vehicle System
Dynamics 11(1), 1-13.
Kalker, J.J. (1990) Three-dimensional Elastic Bodies in Rolling Contact. Kluwer, §3.3.
Vollebregt, E.A.H. (CONTACT user guide), documentation of the FASTSIM/simplified-theory options.
"""
import math

import numpy as np

from ..jit import core

NX_DEFAULT = 20
NY_DEFAULT = 20

BOUND_PARABOLIC = 0   # p_n(x) = p_c (1 - x^2/xl^2) along a strip
BOUND_ELLIPTIC = 1    # p_n(x) = p_c sqrt(1 - x^2/xl^2)


@core
def flexibilities(a, b, G, C11, C22, C23):
    """Kalker's FASTSIM flexibilities (L1, L2, L3) [m/Pa] for semi-axes a (x), b (y)."""
    L1 = 8.0 * a / (3.0 * G * C11)
    L2 = 8.0 * a / (3.0 * G * C22)
    L3 = math.pi * a * math.sqrt(a / b) / (4.0 * G * C23)
    return L1, L2, L3


@core
def _bound(kind, pc, x, xl):
    r = 1.0 - (x / xl) * (x / xl)
    if r <= 0.0:
        return 0.0
    if kind == BOUND_PARABOLIC:
        return pc * r
    return pc * math.sqrt(r)


@core
def fastsim_strip(xi_x, xi_y, phi, y, xl, nx, mu, pc, kind, L1, L2, L3):
    """Integrate one strip at lateral position y with half-length xl [m].

    The strip runs from x = +xl (leading edge, traction 0) to x = -xl with nx elements; tractions
    live at the element midpoints x_i = xl - (i + 1/2) dx. The traction bound is mu * p_n(x_i),
    p_n = pc (1 - x^2/xl^2) (kind BOUND_PARABOLIC) or pc sqrt(1 - x^2/xl^2) (BOUND_ELLIPTIC), pc the
    strip's pressure at x = 0 [Pa]. Returns (fx, fy, mz) per unit strip width [N/m, N/m, N]:
    int p_x dx, int p_y dx, int (x p_y - y p_x) dx (midpoint rule).
    """
    fx = 0.0
    fy = 0.0
    mz = 0.0
    if xl <= 0.0 or nx <= 0:
        return fx, fy, mz
    dx = 2.0 * xl / nx
    # normalise the discrete bound so that its midpoint sum equals the exact strip integral
    # (4/3 or pi/2 times pc*xl): full sliding then gives exactly mu * (strip load)
    if kind == BOUND_PARABOLIC:
        pc = pc / (1.0 + 0.5 / (nx * nx))
    else:
        sm = 0.0
        for i in range(nx):
            t = 1.0 - (i + 0.5) * 2.0 / nx
            sm += math.sqrt(1.0 - t * t)
        pc = pc * (0.5 * math.pi) / (sm * 2.0 / nx)
    wx = xi_x / L1 - phi * y / L3          # traction increment per unit length, x
    wy0 = xi_y / L2
    wys = phi / L3
    # leading edge -> first midpoint: length dx/2, centre xl - dx/4
    h = 0.5 * dx
    xc = xl - 0.25 * dx
    px = 0.0
    py = 0.0
    for i in range(nx):
        xm = xl - (i + 0.5) * dx
        px = px - wx * h
        py = py - (wy0 + wys * xc) * h
        gb = mu * _bound(kind, pc, xm, xl)
        pt = math.sqrt(px * px + py * py)
        if pt > gb:
            if pt > 0.0:
                sc = gb / pt
                px *= sc
                py *= sc
        fx += px
        fy += py
        mz += xm * py - y * px
        # next step: midpoint i -> midpoint i+1, length dx, centre = element boundary
        h = dx
        xc = xm - 0.5 * dx
    return fx * dx, fy * dx, mz * dx


@core
def fastsim_core(xi_x, xi_y, phi, a, b, N, mu, L1, L2, L3, nx, ny):
    """FASTSIM on the ellipse (a, b) with given flexibilities; returns (Fx, Fy, Mz) on the wheel.

    N [N] normal load (parabolic traction bound), mu friction coefficient, nx x ny elements.
    Returns zeros for N <= 0, a <= 0 or b <= 0.
    """
    if not (N > 0.0) or not (a > 0.0) or not (b > 0.0):
        return 0.0, 0.0, 0.0
    dy = 2.0 * b / ny
    # parabolic pressure p00 (1 - x^2/a^2 - y^2/b^2), p00 scaled so that the strip sum of the
    # (exactly integrated, see fastsim_strip) strip loads is N: full sliding gives exactly mu N
    sw = 0.0
    for j in range(ny):
        y = -b + (j + 0.5) * dy
        r = 1.0 - (y / b) * (y / b)
        sw += r * math.sqrt(r)
    p00 = N / (4.0 / 3.0 * a * sw * dy)
    Fx = 0.0
    Fy = 0.0
    Mz = 0.0
    for j in range(ny):
        y = -b + (j + 0.5) * dy
        r = 1.0 - (y / b) * (y / b)
        xl = a * math.sqrt(r)
        fx, fy, mz = fastsim_strip(xi_x, xi_y, phi, y, xl, nx, mu, p00 * r,
                                   BOUND_PARABOLIC, L1, L2, L3)
        Fx += fx * dy
        Fy += fy * dy
        Mz += mz * dy
    return Fx, Fy, Mz


@core
def fastsim_forces(xi_x, xi_y, phi, a, b, N, mu, G, C11, C22, C23, nx, ny):
    """FASTSIM creep forces (Fx, Fy, Mz) on the wheel with Kalker's L1, L2, L3 from C11, C22, C23.

    a (x), b (y) semi-axes [m], N [N], mu [-], G [Pa]; C11, C22, C23 Kalker's coefficients for a/b
    and nu (``creep.kalker_coefficients``); nx x ny elements (defaults NX_DEFAULT, NY_DEFAULT).
    """
    if not (N > 0.0) or not (a > 0.0) or not (b > 0.0):
        return 0.0, 0.0, 0.0
    L1, L2, L3 = flexibilities(a, b, G, C11, C22, C23)
    return fastsim_core(xi_x, xi_y, phi, a, b, N, mu, L1, L2, L3, nx, ny)


@core
def fastsim_tractions(xi_x, xi_y, phi, a, b, N, mu, L1, L2, L3, xs, ys, px, py, slip):
    """Traction field of FASTSIM at the element midpoints, for plots (fills caller arrays).

    Arrays of shape (ny, nx): xs, ys coordinates [m], px, py tractions on the wheel [Pa],
    slip = 1 where the element is on the traction bound (slip area), else 0.
    """
    ny = px.shape[0]
    nx = px.shape[1]
    dy = 2.0 * b / ny
    sw = 0.0
    for j in range(ny):
        y = -b + (j + 0.5) * dy
        r = 1.0 - (y / b) * (y / b)
        sw += r * math.sqrt(r)
    p00 = N / (4.0 / 3.0 * a * sw * dy) / (1.0 + 0.5 / (nx * nx))
    for j in range(ny):
        y = -b + (j + 0.5) * dy
        r = 1.0 - (y / b) * (y / b)
        xl = a * math.sqrt(r)
        dx = 2.0 * xl / nx
        wx = xi_x / L1 - phi * y / L3
        h = 0.5 * dx
        xc = xl - 0.25 * dx
        pxc = 0.0
        pyc = 0.0
        for i in range(nx):
            xm = xl - (i + 0.5) * dx
            pxc = pxc - wx * h
            pyc = pyc - (xi_y / L2 + phi * xc / L3) * h
            gb = mu * _bound(BOUND_PARABOLIC, p00 * r, xm, xl)
            pt = math.sqrt(pxc * pxc + pyc * pyc)
            sl = 0.0
            if pt > gb:
                sl = 1.0
                if pt > 0.0:
                    pxc *= gb / pt
                    pyc *= gb / pt
            xs[j, i] = xm
            ys[j, i] = y
            px[j, i] = pxc
            py[j, i] = pyc
            slip[j, i] = sl
            h = dx
            xc = xm - 0.5 * dx


def traction_field(xi_x, xi_y, phi, a, b, N, mu, G, C11, C22, C23, nx=NX_DEFAULT, ny=NY_DEFAULT):
    """Python convenience wrapper (allocates): dict of (ny, nx) arrays xs, ys, px, py, slip."""
    shape = (int(ny), int(nx))
    xs = np.zeros(shape)
    ys = np.zeros(shape)
    px = np.zeros(shape)
    py = np.zeros(shape)
    slip = np.zeros(shape)
    L1, L2, L3 = flexibilities(a, b, G, C11, C22, C23)
    fastsim_tractions(float(xi_x), float(xi_y), float(phi), float(a), float(b), float(N), float(mu),
                      L1, L2, L3, xs, ys, px, py, slip)
    return {"xs": xs, "ys": ys, "px": px, "py": py, "slip": slip}
