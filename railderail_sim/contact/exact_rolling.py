"""Kalker's exact theory of steady rolling contact on the half-space grid (reference; numpy + FFT, numba sweep).

The tangential half of CONTACT's "exact" rolling contact (Kalker 1990, ch. 5; Vollebregt's CONTACT):
the tractions, the stick and slip areas and the creep forces of two elastic half-spaces rolling steadily
with creepages xi_x, xi_y and spin phi, on the rectangular grid of the exact normal solver
(`halfspace.py`). An analysis tool (the check of the creep laws of `creep.py`), not part of the
time-stepping loop.

Model
-----
Frame and signs as in `creep.py` and `fastsim.py`: x rolling direction (axis 1 of the arrays), y lateral
(axis 0), z the common normal; the bodies roll in +x, so their material flows through the contact from the
leading edge (largest x) to the trailing edge. Creepages (Kalker): xi_x, xi_y [-] = (velocity of the
wheel's material minus the rail's at the reference point) / rolling speed, phi [1/m] = (wheel - rail)
angular velocity about z / rolling speed; the rigid slip per unit rolling distance at (x, y) is

    w_x = xi_x - phi y,    w_y = xi_y + phi x.

``p = (px, py)`` [Pa] is the traction on the wheel (the rail carries -p); u [m] the tangential surface
displacement of the wheel minus that of the rail. Identical elastic constants (G, nu): u does not depend
on the normal pressure and the normal displacement does not depend on p (quasi-identity, Johnson 1985
§5.1; Kalker 1990 §1.5), so the normal problem is solved first (`halfspace.halfspace_patch`, or a
prescribed Hertz pressure, `hertz_grid`) and only the tangential one here. Cerruti's point-load solution
(Johnson 1985, eq. 3.86), doubled for the two bodies:

    u_x = 1/(pi G) [((1 - nu)/r + nu x^2/r^3) Q_x + nu x y/r^3 Q_y],
    u_y = 1/(pi G) [nu x y/r^3 Q_x + ((1 - nu)/r + nu y^2/r^3) Q_y].

Steady rolling: a material point pair moves by -dx in the time it takes to roll dx, so the slip (the
velocity of the wheel's material relative to the rail's, per unit rolling distance) is

    s = w - du/dx.

Coulomb's law with the traction bound g = mu p_n (p_n the normal pressure):

    |p| <= g;   s = 0 where |p| < g (stick);   p = -g s/|s| where |p| = g (slip).

Discretisation (Kalker 1990, ch. 5; the CONTACT user guide, "steady state rolling"): nx x ny elements dx x
dy centred at (x_i, y_j), tractions piecewise constant, conditions collocated at the element centres. The
derivative is the backward (upwind) difference over one element, the displacement at the element the
material comes from minus the displacement here:

    s_I = w_I - (u(x_I + dx, y_I) - u(x_I, y_I)) / dx,

w evaluated at the element centre. u at a point due to a uniform unit traction on a rectangle (Cerruti's
solution integrated over it, our derivation; closed forms as in Kalker 1990 ch. 5): with the four-corner
sum [F](X, Y) = F(X+dx/2, Y+dy/2) - F(X+dx/2, Y-dy/2) - F(X-dx/2, Y+dy/2) + F(X-dx/2, Y-dy/2) of mixed
antiderivatives (d^2F/ds dt = the integrand),

    int int x^2/r^3 = [t asinh(s/|t|)],   int int y^2/r^3 = [s asinh(t/|s|)],   int int x y/r^3 = [-r],

    A_xx = 1/(pi G) ([t asinh(s/|t|)] + (1 - nu) [s asinh(t/|s|)]),   A_yy likewise with s <-> t,
    A_xy = A_yx = -nu/(pi G) [r]

(1/r = x^2/r^3 + y^2/r^3 gives back the normal kernel of `halfspace.py`; the tests compare these with
quadrature of the point-load solution). The slip is a convolution of p with the kernel
S(X) = -(A(X + dx) - A(X))/dx, applied by zero-padded FFT as in `halfspace.py` (exact, no wrap-around).

The rigid slip at the element centre (rather than at x + dx/2, the middle of the difference) is our
choice: on Hertz patches of a/b = 0.3, 1 and 3 at 32...128 elements it gives the spin force closest to
the grid-converged value (C23 within 0.2-0.5 % of it at 64 x 64, against 0.6-1.2 % with CONTACT's
default offset of dx/6 and 2.8-4 % with dx/2), and the discrete solution keeps Kalker's reciprocity
(the Fy per unit spin equals minus the Mz per unit lateral creepage, both = G c^3 C23) exactly on an
x-symmetric patch (the transpose of the steady-rolling operator is the operator reflected in x).

Solver (a line Gauss-Seidel in the spirit of CONTACT's SteadyGS, Vollebregt; our implementation): the
unknowns are, as in SteadyGS, the traction increments along the rolling direction. An element's update
moves the traction of the element and of the stick run behind it (downstream, up to the next slip or
exterior element) by one common increment, so that the increments between stick elements, which carry
their adhesion, stay; the slip at the element then changes by (A(0) - A(n dx))/dx times the increment
(n the run's length, a telescoped sum of S), and the element's Coulomb problem is solved exactly:
stick p = -B^-1 r, else p = -(B + lam)^-1 r with |p| = g (lam = |s|/g > 0, Newton on 1/|p(lam)| - 1/g,
linear in lam for B proportional to the identity), where r is the slip without the element's change
and B the diagonal coupling above (A_xy = 0 along a row). Rows are processed one after the other
(each element of a row from the trailing to the leading edge; its slips updated in the row itself
with the telescoped kernel, the slips of the rows still to come after the row by a 1-D FFT of the
row's change along x), i.e. an exact Gauss-Seidel in this ordering; every outer iteration (sweep)
starts from the slip recomputed by the 2-D FFT product. (The plain element-wise Gauss-Seidel on p diverges: its forward
sweep integrates the upwind difference; lagging the other rows' slips over a sweep diverges too.)
Measured: 50-120 sweeps to 1e-6 on 64 x 64 Hertz patches (a/b 1.7 ... 19, pure creepage to full
sliding), 0.3-0.8 s.

Convergence measure (ours): ``residual`` = max over the contact elements of the change one exact element
solve with the current slip would make, over max |p| (0 exactly at the discrete solution: every stick
element has s = 0, every slip element p = -g s/|s|, |p| <= g).

Outputs of ``exact_rolling``: tractions, slip, contact / stick / slip masks, Fx = sum px dA,
Fy = sum py dA, Mz = sum (x py - y px) dA about the coordinate origin (the reference point of the
creepages), the stick-area fraction.

Assumptions: linear elastic half-spaces of identical materials (no normal-tangential coupling), locally
flat bodies, quasi-static steady rolling (no inertia), Coulomb friction with one coefficient, creepages
constant over the patch (those of its reference point), the grid contains the patch and at least one
element upwind of it (the kernel reaches one element beyond the grid, so the patch may touch the border).

References
----------
Kalker, J.J. (1990) Three-dimensional Elastic Bodies in Rolling Contact. Kluwer, ch. 1, 5 and App. E.
Vollebregt, E.A.H. CONTACT user guide (Vtech CMCC; the open-source CONTACT, Apache-2.0) and "A new solver
for the elastic normal contact problem using conjugate gradients, deflation, and an FFT-based
preconditioner", J. Comput. Phys. 257 (2014) 333-351 (the solver family; SteadyGS).
Johnson, K.L. (1985) Contact Mechanics. Cambridge University Press, §3.4 (eq. 3.86), §5.1, §8.4.
"""
from dataclasses import dataclass, field
import functools
import math
import warnings

import numpy as np

from ..jit import core, core_inline
from ..jsonout import NOT_WRITTEN
from . import halfspace as hs

WHO = "exact_rolling"
STICK, SLIP = 1.0, 2.0          # element states (0 = exterior)


# ---------------------------------------------------------------------------------------------
# influence coefficients and the FFT product
# ---------------------------------------------------------------------------------------------
def rectangle_tangential_displacement(X, Y, dx, dy, G, nu):
    """(A_xx, A_xy, A_yy) [m/Pa]: the combined tangential displacement (wheel minus rail) at offset (X, Y)
    from the centre of a dx x dy rectangle carrying a uniform unit traction, x component from an x
    traction (A_xx), y from x or x from y (A_xy), y from y (A_yy); G shear modulus, nu Poisson's ratio of
    both bodies. X, Y may be arrays (broadcast)."""
    ixx = hs.corners(lambda s, t: hs.s_asinh_t_over_s(t, s), X, Y, dx, dy)     # int int x^2 / r^3
    iyy = hs.corners(hs.s_asinh_t_over_s, X, Y, dx, dy)                          # int int y^2 / r^3
    ixy = -hs.corners(np.hypot, X, Y, dx, dy)                                    # int int x y / r^3
    c = 1.0 / (math.pi * G)
    return c * (ixx + (1.0 - nu) * iyy), c * nu * ixy, c * (iyy + (1.0 - nu) * ixx)


def displacement_kernels(nx, ny, dx, dy, G, nu):
    """(A_xx, A_xy, A_yy), each (2 ny - 1, 2 nx + 1): entry [l + ny - 1, k + nx] is the displacement at
    offset (k dx, l dy), k = -nx..nx, from an element of unit traction (one offset more than the grid on
    each side in x: the slip reads u one element upwind)."""
    X = np.arange(-nx, nx + 1, dtype=np.float64)[None, :] * dx
    Y = np.arange(-(ny - 1), ny, dtype=np.float64)[:, None] * dy
    return rectangle_tangential_displacement(X, Y, dx, dy, G, nu)


@functools.lru_cache(maxsize=8)
def _operator(nx, ny, dx, dy, G, nu):
    """The displacement kernels (read-only), the 2-D spectra of the slip kernels S = -(A(X+dx) - A(X))/dx
    and their 1-D spectra along x per row offset (for the update of the other rows after a row)."""
    disp = displacement_kernels(nx, ny, dx, dy, G, nu)
    slip = [-(a[:, 2:] - a[:, 1:-1]) / dx for a in disp]       # X = -(nx-1)..(nx-1) elements
    spectra = tuple(hs.circulant_spectrum(k, nx, ny) for k in slip)
    along_x = []
    for k in slip:
        wrapped = np.zeros((2 * ny - 1, 2 * nx))                 # offset k -> index k mod 2 nx
        wrapped[:, :nx] = k[:, nx - 1:]
        wrapped[:, nx + 1:] = k[:, :nx - 1]
        f = np.fft.rfft(wrapped, axis=1)
        f.setflags(write=False)
        along_x.append(f)
    for a in disp:
        a.setflags(write=False)
    return disp, spectra, tuple(along_x)


def _slip_of(spectra, px, py):
    """The elastic part of the slip, S * p, by the zero-padded FFT product."""
    ny, nx = px.shape
    shape = (2 * ny, 2 * nx)
    fx = np.fft.rfft2(px, s=shape)
    fy = np.fft.rfft2(py, s=shape)
    sxx, sxy, syy = spectra
    return (np.fft.irfft2(sxx * fx + sxy * fy, s=shape)[:ny, :nx],
            np.fft.irfft2(sxy * fx + syy * fy, s=shape)[:ny, :nx])


# ---------------------------------------------------------------------------------------------
# the element problem, the row sweep and the residual (numba core)
# ---------------------------------------------------------------------------------------------
@core_inline
def _element_traction(rx, ry, bx, by, g):
    """Coulomb's law at one element whose slip is s = r + (bx px, by py): (px, py, STICK or SLIP)."""
    px = -rx / bx
    py = -ry / by
    if px * px + py * py <= g * g:
        return px, py, STICK
    # slip: p = -(B + lam)^-1 r, |p| = g; 1/|p(lam)| rises from below 1/g, nearly linearly
    lam = 0.0
    for _ in range(50):
        qx = bx + lam
        qy = by + lam
        px = -rx / qx
        py = -ry / qy
        n2 = px * px + py * py
        n = math.sqrt(n2)
        step = (1.0 / n - 1.0 / g) * (n2 * n) / (px * px / qx + py * py / qy)
        lam = max(lam - step, 0.0)
        if abs(step) <= 1e-13 * (bx + lam):
            break
    px = -rx / (bx + lam)
    py = -ry / (by + lam)
    f = g / math.sqrt(px * px + py * py)         # exactly on the bound
    return px * f, py * f, SLIP


@core
def _row_sweep(j, px, py, sx, sy, bound, active, status, axx, ayy, inv_dx, dpx_row, dpy_row):
    """One Gauss-Seidel pass over row j (module docstring): updates p, the row's slip and status, and
    returns the row's traction change in dpx_row, dpy_row and its largest element change."""
    ny, nx = px.shape
    c = ny - 1
    a0x = axx[c, nx]
    a0y = ayy[c, nx]
    change = 0.0
    for k in range(nx):
        dpx_row[k] = 0.0
        dpy_row[k] = 0.0
    for i in range(nx):                            # trailing (small x) to leading edge
        if not active[j, i]:
            continue
        lo = i                                     # the stick run behind element i moves with it
        while lo > 0 and active[j, lo - 1] and status[j, lo - 1] == STICK:
            lo -= 1
        n_run = i - lo + 1
        bx = (a0x - axx[c, nx + n_run]) * inv_dx
        by = (a0y - ayy[c, nx + n_run]) * inv_dx
        qx, qy, st = _element_traction(sx[j, i] - bx * px[j, i], sy[j, i] - by * py[j, i], bx, by,
                                       bound[j, i])
        status[j, i] = st
        dpx = qx - px[j, i]
        dpy = qy - py[j, i]
        if dpx == 0.0 and dpy == 0.0:
            continue
        change = max(change, math.sqrt(dpx * dpx + dpy * dpy))
        for k in range(lo, i + 1):
            px[j, k] += dpx
            py[j, k] += dpy
            dpx_row[k] += dpx
            dpy_row[k] += dpy
        # the run's slip along the row: the telescoped sum of S, -(A(X_lo + dx) - A(X_i)) / dx
        for ii in range(nx):
            k1 = ii - lo + 1 + nx
            k0 = ii - i + nx
            sx[j, ii] -= (axx[c, k1] - axx[c, k0]) * dpx * inv_dx
            sy[j, ii] -= (ayy[c, k1] - ayy[c, k0]) * dpy * inv_dx
    return change


@core
def _residual(px, py, sx, sy, bound, active, bx, by, status):
    """Largest change one exact element solve would make (module docstring); sets each element's state."""
    ny, nx = px.shape
    worst = 0.0
    for j in range(ny):
        for i in range(nx):
            if not active[j, i]:
                status[j, i] = 0.0
                continue
            qx, qy, st = _element_traction(sx[j, i] - bx * px[j, i], sy[j, i] - by * py[j, i], bx, by,
                                           bound[j, i])
            status[j, i] = st
            worst = max(worst, math.hypot(qx - px[j, i], qy - py[j, i]))
    return worst


# ---------------------------------------------------------------------------------------------
# the library function
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class RollingContact:
    """The steady-rolling solution (SI; arrays (ny, nx), axis 1 = x rolling, axis 0 = y)."""
    Fx: float                      # creep force on the wheel, sum px dA [N]
    Fy: float
    Mz: float                      # spin moment about the origin, sum (x py - y px) dA [N m]
    normal_force: float            # sum p_n dA [N]
    stick_fraction: float          # stick elements / contact elements
    residual: float
    iterations: int
    converged: bool
    px: np.ndarray = field(metadata=NOT_WRITTEN)          # traction on the wheel [Pa]
    py: np.ndarray = field(metadata=NOT_WRITTEN)
    slip_x: np.ndarray = field(metadata=NOT_WRITTEN)      # slip per rolling distance [-]
    slip_y: np.ndarray = field(metadata=NOT_WRITTEN)
    contact: np.ndarray = field(metadata=NOT_WRITTEN)     # p_n > 0
    stick: np.ndarray = field(metadata=NOT_WRITTEN)
    slip: np.ndarray = field(metadata=NOT_WRITTEN)
    x: np.ndarray = field(metadata=NOT_WRITTEN)           # element centres [m]
    y: np.ndarray = field(metadata=NOT_WRITTEN)


def _finite(name, value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = math.nan
    if not math.isfinite(v):
        raise ValueError(f"{WHO}: {name} = {value!r} must be a finite number (any sign)")
    return v


def exact_rolling(xi_x, xi_y, phi, pressure, dx, dy, E, nu, mu, *, x=None, y=None, tol=1e-6,
                  max_iter=500) -> RollingContact:
    """Kalker's exact steady rolling contact on a grid (module docstring).

    xi_x, xi_y [-], phi [1/m]: creepages and spin (finite); pressure: (ny, nx) normal pressure p_n >= 0
    [Pa] at the element centres (contact where > 0), e.g. ``halfspace_patch(...)["pressure"]`` or
    ``hertz_grid``; dx, dy [m] element sizes (> 0); E [Pa] (> 0), nu [0, 0.5) of both bodies; mu the
    friction coefficient, (0, inf] (inf: no slip, Kalker's linear theory); x, y element-centre coordinates
    [m] (default centred on 0; the creepages refer to the origin); tol in (0, 1) on ``residual``;
    max_iter >= 1 sweeps (a RuntimeWarning if not converged)."""
    xi_x, xi_y, phi = _finite("xi_x", xi_x), _finite("xi_y", xi_y), _finite("phi", phi)
    p_n = np.asarray(pressure, dtype=np.float64)
    if p_n.ndim != 2 or min(p_n.shape) < hs.MIN_ELEMENTS:
        raise ValueError(f"{WHO}: pressure must be a 2-D (ny, nx) array of at least {hs.MIN_ELEMENTS} x "
                         f"{hs.MIN_ELEMENTS} elements, got shape {p_n.shape}")
    if not np.all(np.isfinite(p_n)) or float(p_n.min()) < 0.0:
        raise ValueError(f"{WHO}: pressure must be finite and >= 0 Pa everywhere (min {float(np.nanmin(p_n))!r})")
    ny, nx = p_n.shape
    dx = hs.positive("dx", dx, "m", WHO)
    dy = hs.positive("dy", dy, "m", WHO)
    E, nu = hs.check_material(E, nu, WHO)
    mu = float(mu)
    if not mu > 0.0:
        raise ValueError(f"{WHO}: friction coefficient mu = {mu!r} must be within (0, inf]")
    tol, max_iter = hs.check_solver(tol, max_iter, WHO)
    x = hs.centres("x", x, nx, dx, WHO)
    y = hs.centres("y", y, ny, dy, WHO)

    G = E / (2.0 * (1.0 + nu))
    disp, spectra, along_x = _operator(nx, ny, dx, dy, G, nu)
    axx, _, ayy = disp
    rxx, rxy, ryy = along_x
    active = p_n > 0.0
    bound = np.where(active, math.inf, 0.0) if math.isinf(mu) else mu * p_n
    wx = np.broadcast_to(xi_x - phi * y[:, None], p_n.shape)
    wy = np.broadcast_to(xi_y + phi * x[None, :], p_n.shape)
    px = np.zeros_like(p_n)
    py = np.zeros_like(p_n)
    status = np.zeros_like(p_n)
    dpx_row = np.zeros(nx)
    dpy_row = np.zeros(nx)
    # the single element's coupling (n_run = 1), for the residual
    bx = (axx[ny - 1, nx] - axx[ny - 1, nx + 1]) / dx
    by = (ayy[ny - 1, nx] - ayy[ny - 1, nx + 1]) / dx
    rows = np.flatnonzero(active.any(axis=1))
    last = int(rows[-1]) if rows.size else -1
    residual = 0.0
    sweeps = 0
    while True:
        ux, uy = _slip_of(spectra, px, py)
        sx = wx + ux
        sy = wy + uy
        worst = _residual(px, py, sx, sy, bound, active, bx, by, status)
        scale = float(np.max(np.hypot(px, py)))
        residual = worst / scale if scale > 0.0 else (0.0 if worst == 0.0 else math.inf)
        if residual < tol or sweeps == max_iter:
            break
        sweeps += 1
        for j in rows:
            if _row_sweep(j, px, py, sx, sy, bound, active, status, axx, ayy, 1.0 / dx, dpx_row,
                          dpy_row) == 0.0:
                continue
            if j == last:
                continue
            # the slips of the rows still to come in this sweep (the others are recomputed before the
            # next): row j's change convolved along x with S at each row offset
            fx = np.fft.rfft(dpx_row, n=2 * nx)
            fy = np.fft.rfft(dpy_row, n=2 * nx)
            offsets = slice(ny, ny + last - j)             # row offsets 1 .. last - j
            sx[j + 1:last + 1] += np.fft.irfft(rxx[offsets] * fx + rxy[offsets] * fy, n=2 * nx)[:, :nx]
            sy[j + 1:last + 1] += np.fft.irfft(rxy[offsets] * fx + ryy[offsets] * fy, n=2 * nx)[:, :nx]
    converged = residual < tol
    if not converged:
        warnings.warn(f"{WHO}: not converged in {max_iter} sweeps (residual {residual:.2e} > tol {tol:.1e})",
                      RuntimeWarning, stacklevel=2)
    dA = dx * dy
    n_contact = int(active.sum())
    stick = status == STICK
    return RollingContact(
        Fx=float(px.sum() * dA), Fy=float(py.sum() * dA),
        Mz=float((x[None, :] * py - y[:, None] * px).sum() * dA), normal_force=float(p_n.sum() * dA),
        stick_fraction=float(stick.sum() / n_contact) if n_contact else 0.0, residual=float(residual),
        iterations=sweeps, converged=bool(converged), px=px, py=py,
        slip_x=np.where(active, sx, 0.0), slip_y=np.where(active, sy, 0.0), contact=active, stick=stick,
        slip=status == SLIP, x=x, y=y)


def hertz_grid(a, b, N, nx=64, ny=64):
    """Hertz's pressure p0 sqrt(1 - x^2/a^2 - y^2/b^2) on nx x ny elements that tile the ellipse's
    bounding box [-a, a] x [-b, b] exactly, scaled so that sum p dA = N (then full sliding gives exactly
    mu N). a (along x) and b [m] > 0, N [N] > 0. Returns (pressure, x, y, dx, dy)."""
    a = hs.positive("a", a, "m", WHO)
    b = hs.positive("b", b, "m", WHO)
    N = hs.positive("N", N, "N", WHO)
    for name, n in (("nx", nx), ("ny", ny)):
        if int(n) != n or int(n) < hs.MIN_ELEMENTS:
            raise ValueError(f"{WHO}: {name} = {n!r} must be an integer >= {hs.MIN_ELEMENTS}")
    nx, ny = int(nx), int(ny)
    dx, dy = 2.0 * a / nx, 2.0 * b / ny
    x = -a + (np.arange(nx) + 0.5) * dx
    y = -b + (np.arange(ny) + 0.5) * dy
    shape = np.sqrt(np.maximum(1.0 - (x[None, :] / a) ** 2 - (y[:, None] / b) ** 2, 0.0))
    return shape * (N / (shape.sum() * dx * dy)), x, y, dx, dy
