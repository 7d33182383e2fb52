"""Exact discrete elastic half-space normal contact (reference solution; plain numpy + FFT).

This is the "exact" (in the sense of Kalker's NORM / CONTACT) frictionless normal contact of two
elastic bodies whose undeformed separation ``h(x, y)`` is known on a rectangular grid of the
contact plane. It is an analysis tool (patch shape during flange climbing, check of the Hertz and
Kik-Piotrowski models), not part of the time-stepping loop.

Model
-----
Frame and signs. x (rolling direction, axis 1 of the arrays) and y (lateral, contact tangent
coordinate, axis 0) span the contact plane, z is the common normal. ``h(x, y)`` [m] is the
*undeformed separation* of the two surfaces measured along z (h >= 0 where the surfaces do not
touch; any offset is allowed, delta is measured from h = 0). The bodies are pressed together by the
rigid approach ``delta`` [m] (positive = towards each other). The compressive contact pressure
``p(x, y) >= 0`` [Pa] pushes both surfaces away from each other; the sum of the two surface
normal displacements (positive = separating, i.e. away from the other body) is

    u(x, y) = 1/(pi E*) int int p(x', y') / sqrt((x - x')^2 + (y - y')^2) dx' dy',

with ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 = 2 (1 - nu^2)/E`` for identical materials
(Boussinesq's point-load solution, Johnson, *Contact Mechanics*, 1985, §3.2, added for the two
bodies; identical materials -> no tangential/normal coupling, Johnson §5.1 / Kalker 1990).
The *deformed* gap is

    g(x, y) = h(x, y) - delta + u(x, y),

and the contact conditions (Signorini / complementarity) are

    g >= 0,   p >= 0,   p g = 0   everywhere,   N = int int p dx dy.

Discretisation (Kalker 1990, ch. 5, "NORM"; Johnson 1985, §3.9 and Love 1929 for the rectangle):
nx x ny rectangular elements dx x dy centred at (x_i, y_j); pressure constant on each element; the
conditions are collocated at the element centres. The displacement at a centre due to a unit
pressure on the element whose centre is at offset (X, Y) = (x_i - x_k, y_j - y_l) is the double
integral of the point-load solution over the rectangle (Love 1929):

    C(X, Y) = 1/(pi E*) [F(X + dx/2, Y + dy/2) - F(X + dx/2, Y - dy/2)
                         - F(X - dx/2, Y + dy/2) + F(X - dx/2, Y - dy/2)],
    F(s, t) = s asinh(t/|s|) + t asinh(s/|t|)      (F = 0 terms for s = 0 or t = 0).

F is the mixed antiderivative of 1/sqrt(s^2 + t^2) (d^2F/ds dt = 1/r). Love's/Johnson's form uses
``s ln(t + r) + t ln(s + r)``; it differs from F by s ln|s| + t ln|t|, terms of one variable
that cancel in the four-corner difference. The asinh form is free of the cancellation in
``s + r`` for s < 0. The self-influence (X = Y = 0) is
``C0 = 2/(pi E*) [dx asinh(dy/dx) + dy asinh(dx/dy)]``. The function ``influence_kernel`` is
checked in the tests against direct quadrature and the far field ``dx dy/(pi E* r)``.

C depends only on the index offsets, so the influence matrix is block-Toeplitz with Toeplitz
blocks: it is stored as the (2 ny - 1) x (2 nx - 1) kernel ``C[l + ny - 1, k + nx - 1]`` (offset l
rows, k columns) and applied as a linear convolution by FFT on a zero-padded (2 ny) x (2 nx) grid
(exact, no wrap-around: every offset -(n-1)..(n-1) maps to a distinct index modulo 2n).
Cost O(n log n) per product instead of O(n^2).

Solver (Polonsky & Keer 1999, Wear 231, 206-219): the conditions above are the optimality
conditions of the convex quadratic programme min_p 1/2 p.Cp + (h - delta).p, p >= 0 (with the
load constraint sum p dx dy = N and delta as its Lagrange multiplier when N is prescribed).
Conjugate gradients restricted to the current contact set Ic = {p > 0}:

    1. g = h + Cp; with N prescribed, subtract the mean of g over Ic (that mean is the current
       estimate of delta); with delta prescribed, subtract delta.
    2. G = sum_Ic g^2; direction t = g + beta (G/G_old) t_old on Ic, 0 elsewhere
       (beta = 0 after a change of the contact set by step 5, else 1).
    3. r = C t (minus its mean over Ic if N is prescribed); step tau = sum g t / sum r t.
    4. p <- p - tau t on Ic; negative pressures -> 0.
    5. Elements with p = 0 and g < 0 (penetration) enter: p = -tau g; reset the direction.
    6. With N prescribed, scale p to sum p dx dy = N.

Stopping criterion (ours): the complementarity residual of the current p,
``max(max_Ic |g|, max_{not Ic} max(-g, 0)) / max(u)`` (gap error in units of the largest elastic
displacement, u = Cp), below ``tol``, with an unchanged contact set in that iteration. The load
balance holds to rounding (step 6) when N is prescribed. Returned ``residual`` is this quantity
evaluated on the returned pressures (plus the relative load error).

Outputs of ``halfspace_patch``: pressures (ny, nx), the contact mask (p > 0), N, delta, area,
extents, pressure-weighted centroid, max pressure and the same per connected patch
(8-connectivity, ``scipy.ndimage.label``).
Extents: along each row (column) the contact edge lies between the last element in contact and
the first one out. Outside a smooth contact edge the deformed gap grows as d^(3/2) with the
distance d from the edge (Johnson 1985, §4.2 - the Hertz gap; true for any smooth-edged
frictionless contact), so the edge is located by linear interpolation of g^(2/3) through the first
two non-contact elements, clamped to the interval between the last contact centre and the first
non-contact centre. Where two free elements are not available (grid border, another patch) the
element edge is used. ``length`` = max x-edge - min x-edge over the region, ``width`` likewise in
y (bounding extents; for an ellipse 2a and 2b). ``area`` is the mean of the two chord sums
sum_rows (x_right - x_left) dy and sum_columns (y_right - y_left) dx with these refined edges
(``area_elements`` = number of contact elements x dx dy, the raw count, is also returned: on a
circle it scatters by up to ~2 % with the grid's position while the refined area stays within
0.6 % from ~10 elements per radius; tests/test_halfspace.py).

Assumptions: linear elastic half-spaces (the bodies are locally flat on the patch scale: the gap
h carries all the curvature), identical elastic constants of both bodies, frictionless normal
problem (no tangential tractions), small strains, the grid window contains the whole patch
(``truncated`` is reported and a RuntimeWarning issued if the contact reaches the window border).

References
----------
Love, A.E.H. (1929) The stress produced in a semi-infinite solid by pressure on part of the
boundary. Phil. Trans. R. Soc. London A 228, 377-420.
Johnson, K.L. (1985) Contact Mechanics. Cambridge University Press, §3.2, §3.9, §4.2.
Kalker, J.J. (1990) Three-dimensional Elastic Bodies in Rolling Contact. Kluwer, ch. 5.
Polonsky, I.A., Keer, L.M. (1999) A numerical method for solving rough contact problems based on
the multi-level multi-summation and conjugate gradient techniques. Wear 231, 206-219.
"""
import functools
import math
import warnings

import numpy as np
from scipy import ndimage

from .hertz import combined_modulus

MIN_ELEMENTS = 3          # minimum number of elements in each direction of the grid
_STRUCT8 = np.ones((3, 3), dtype=bool)


# ---------------------------------------------------------------------------------------------
# influence coefficients and the FFT product
# ---------------------------------------------------------------------------------------------
def s_asinh_t_over_s(s, t):
    """s asinh(t/|s|), 0 at s = 0: the mixed antiderivative of t^2/r^3 (r^2 = s^2 + t^2), and half of the
    one of 1/r (`_F`)."""
    s = np.asarray(s, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)
    abs_s = np.abs(s)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(abs_s > 0.0, s * np.arcsinh(t / np.where(abs_s > 0.0, abs_s, 1.0)), 0.0)


def _F(s, t):
    """Mixed antiderivative of 1/sqrt(s^2 + t^2), modulo one-variable terms (module docstring)."""
    return s_asinh_t_over_s(s, t) + s_asinh_t_over_s(t, s)


def corners(fun, X, Y, dx, dy):
    """The four-corner sum of a mixed antiderivative `fun` over a dx x dy rectangle centred at offset
    (X, Y): its integral over the rectangle."""
    hx, hy = 0.5 * dx, 0.5 * dy
    return fun(X + hx, Y + hy) - fun(X + hx, Y - hy) - fun(X - hx, Y + hy) + fun(X - hx, Y - hy)


def rectangle_displacement(X, Y, dx, dy, E_star):
    """Combined normal displacement [m] at offset (X, Y) from the centre of a dx x dy rectangle
    carrying unit uniform pressure (1 Pa), for two bodies of combined modulus E_star (Love 1929).
    X, Y may be arrays (broadcast)."""
    return corners(_F, X, Y, dx, dy) / (math.pi * E_star)


def influence_kernel(nx, ny, dx, dy, E_star):
    """(2 ny - 1, 2 nx - 1) kernel: entry [l + ny - 1, k + nx - 1] is the displacement [m/Pa] at
    an element centre due to unit pressure on the element k columns (x) and l rows (y) away."""
    X = np.arange(-(nx - 1), nx, dtype=np.float64) * dx
    Y = np.arange(-(ny - 1), ny, dtype=np.float64) * dy
    return rectangle_displacement(X[None, :], Y[:, None], dx, dy, E_star)


def circulant_spectrum(K, nx, ny):
    """rfft2 of a (2 ny - 1, 2 nx - 1) offset kernel (entry [l + ny - 1, k + nx - 1] for offset l rows,
    k columns) wrapped onto the (2 ny, 2 nx) circular grid, read-only: the spectrum of the exact linear
    convolution of an (ny, nx) field with K."""
    Kc = np.zeros((2 * ny, 2 * nx))
    # offset (l, k) -> index (l mod 2ny, k mod 2nx)
    Kc[:ny, :nx] = K[ny - 1:, nx - 1:]
    Kc[ny + 1:, :nx] = K[:ny - 1, nx - 1:]
    Kc[:ny, nx + 1:] = K[ny - 1:, :nx - 1]
    Kc[ny + 1:, nx + 1:] = K[:ny - 1, :nx - 1]
    Kf = np.fft.rfft2(Kc)
    Kf.setflags(write=False)
    return Kf


@functools.lru_cache(maxsize=16)
def _kernel_fft(nx, ny, dx, dy):
    """rfft2 of the kernel (E* = 1) wrapped onto the (2 ny, 2 nx) circular grid."""
    return circulant_spectrum(influence_kernel(nx, ny, dx, dy, 1.0), nx, ny)


class _Operator:
    """u = C p by FFT convolution (zero padding to 2 ny x 2 nx)."""

    def __init__(self, nx, ny, dx, dy, E_star):
        self.nx, self.ny = nx, ny
        self.Kf = _kernel_fft(nx, ny, float(dx), float(dy))
        self.scale = 1.0 / E_star
        self.shape = (2 * ny, 2 * nx)

    def __call__(self, p):
        full = np.fft.irfft2(np.fft.rfft2(p, s=self.shape) * self.Kf, s=self.shape)
        return full[:self.ny, :self.nx] * self.scale


def displacement(p, dx, dy, E, nu):
    """Combined normal surface displacement u = C p [m] of the (ny, nx) pressure field p [Pa]
    (FFT product; both bodies of modulus E and Poisson's ratio nu)."""
    p = np.asarray(p, dtype=np.float64)
    E_star = combined_modulus(E, nu, E, nu)
    return _Operator(p.shape[1], p.shape[0], dx, dy, E_star)(p)


# ---------------------------------------------------------------------------------------------
# input checks (shared with exact_rolling)
# ---------------------------------------------------------------------------------------------
def positive(name, value, unit, who="halfspace"):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{who}: {name} = {value!r} must be a number > 0 {unit}") from None
    if not (v > 0.0 and math.isfinite(v)):
        raise ValueError(f"{who}: {name} = {value!r} {unit} must be finite and > 0")
    return v


def check_material(E, nu, who="halfspace"):
    E = positive("E", E, "Pa", who)
    nu = float(nu)
    if not (0.0 <= nu < 0.5):
        raise ValueError(f"{who}: nu = {nu!r} must be within [0, 0.5)")
    return E, nu


def check_solver(tol, max_iter, who="halfspace"):
    tol = float(tol)
    if not (0.0 < tol < 1.0):
        raise ValueError(f"{who}: tol = {tol!r} must be within (0, 1)")
    if int(max_iter) != max_iter or int(max_iter) < 1:
        raise ValueError(f"{who}: max_iter = {max_iter!r} must be an integer >= 1")
    return tol, int(max_iter)


def centres(name, v, n, d, who="halfspace"):
    """The element-centre coordinates along one grid axis: v, checked, or centred on 0 when None."""
    if v is None:
        return (np.arange(n) - 0.5 * (n - 1)) * d
    v = np.asarray(v, dtype=np.float64)
    if v.shape != (n,) or abs((v[-1] - v[0]) / (n - 1) - d) > 1e-6 * d:
        raise ValueError(f"{who}: {name} must have {n} points spaced d{name} = {d!r} m")
    return v


def _uniform_axis(name, v):
    v = np.asarray(v, dtype=np.float64)
    if v.ndim != 1 or v.size < MIN_ELEMENTS:
        raise ValueError(f"halfspace: {name} must be a 1-D array of >= {MIN_ELEMENTS} points, "
                         f"got shape {v.shape}")
    d = np.diff(v)
    if not np.all(np.isfinite(v)) or not (d[0] > 0.0):
        raise ValueError(f"halfspace: {name} must be finite and strictly increasing")
    if np.max(np.abs(d - d[0])) > 1e-6 * d[0]:
        raise ValueError(f"halfspace: {name} must be uniformly spaced (relative spacing "
                         f"deviation {np.max(np.abs(d - d[0])) / d[0]:.2e} > 1e-6)")
    return v, float(d[0])


# ---------------------------------------------------------------------------------------------
# solver
# ---------------------------------------------------------------------------------------------
def _solve(op, h, dA, N, delta, tol, max_iter):
    """Polonsky-Keer constrained CG. Exactly one of N, delta is not None.
    Returns p, delta, u, iterations, residual (complementarity part), converged flag."""
    force_control = N is not None
    if force_control:
        # uniform start over the whole window (robust; the CG removes the excess)
        p = np.full(h.shape, N / (dA * h.size))
    else:
        over = np.maximum(delta - h, 0.0)
        p = over / over.max()                          # any positive start; scaled below
        u1 = op(p)
        inside = over > 0.0
        # scale so that the mean displacement over the overlap equals the mean overlap
        p *= np.mean(over[inside]) / max(np.mean(u1[inside]), 1e-300)
    t = np.zeros_like(p)
    G_old = 1.0
    reset = True
    residual = np.inf
    converged = False
    it = 0
    for it in range(1, max_iter + 1):
        Ic = p > 0.0
        if not np.any(Ic):                              # cannot happen with N > 0
            break
        u = op(p)
        g = h + u
        d_est = float(np.mean(g[Ic])) if force_control else delta
        g -= d_est
        scale = float(np.max(u))
        gi = g[Ic]
        go = g[~Ic]
        pen = float(-np.min(go)) if go.size else 0.0
        residual = max(float(np.max(np.abs(gi))), pen, 0.0) / max(scale, 1e-300)
        if residual < tol and not reset:
            converged = True
            break
        G = float(np.dot(gi, gi))
        if reset:
            t = np.where(Ic, g, 0.0)
        else:
            t = np.where(Ic, g + (G / G_old) * t, 0.0)
        G_old = G
        r = op(t)
        if force_control:
            r -= np.mean(r[Ic])
        rt = float(np.dot(r[Ic], t[Ic]))
        if rt == 0.0:                                   # exact solution on this set
            if residual < tol:
                converged = True
                break
            rt = 1e-300
        tau = float(np.dot(gi, t[Ic])) / rt
        p = np.where(Ic, p - tau * t, p)
        p[p < 0.0] = 0.0
        enter = (~Ic) & (g < 0.0)
        if np.any(enter):
            p[enter] = -tau * g[enter]
            reset = True
        else:
            reset = False
        if force_control:
            total = float(np.sum(p)) * dA
            if total > 0.0:
                p *= N / total
            else:                                       # everything left: restart uniformly
                p = np.full(h.shape, N / (dA * h.size))
                reset = True
        else:
            if not np.any(p > 0.0):                     # delta barely above min h
                p = np.where(h == h.min(), 1.0, 0.0) * (delta - h.min()) * 1e-3
                reset = True
    u = op(p)
    Ic = p > 0.0
    if force_control:
        delta = float(np.mean((h + u)[Ic]))
    return p, delta, u, it, residual, converged


def _run_edges(mask_line, busy_line, gap_line, coord):
    """Contact edges of every run of True in mask_line along one grid line.

    busy_line marks all contact elements (of any patch); an edge is refined only where the two
    elements beyond it are free. Returns a list of (left, right, refined) per run."""
    n = mask_line.size
    d = coord[1] - coord[0]
    idx = np.flatnonzero(mask_line)
    if idx.size == 0:
        return []
    br = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate(([idx[0]], idx[br + 1]))
    ends = np.concatenate((idx[br], [idx[-1]]))

    def edge(i_in, step):
        i1 = i_in + step            # first free element
        i2 = i_in + 2 * step        # second free element
        e_elem = coord[i_in] + 0.5 * step * d
        if not (0 <= i1 < n and 0 <= i2 < n) or busy_line[i1] or busy_line[i2]:
            return e_elem, False
        q1 = max(gap_line[i1], 0.0) ** (2.0 / 3.0)
        q2 = max(gap_line[i2], 0.0) ** (2.0 / 3.0)
        if not (q2 > q1):
            return e_elem, False
        # zero of the straight line through (coord[i1], q1) and (coord[i2], q2), clamped
        e = coord[i1] - step * d * q1 / (q2 - q1)
        lo, hi = sorted((coord[i_in], coord[i1]))
        return min(max(e, lo), hi), True

    out = []
    for j0, j1 in zip(starts, ends):
        a, oka = edge(j0, -1)
        b, okb = edge(j1, +1)
        out.append((a, b, oka and okb))
    return out


def _region_props(mask, busy, p, gap, x, y, dA):
    """Properties of one contact region (mask; busy = all contact elements), gap-refined edges."""
    dx = x[1] - x[0]
    dy = y[1] - y[0]
    xl, xr, yl, yr = np.inf, -np.inf, np.inf, -np.inf
    refined = True
    area_rows = 0.0
    area_cols = 0.0
    for j in np.flatnonzero(mask.any(axis=1)):
        for a, b, ok in _run_edges(mask[j], busy[j], gap[j], x):
            xl, xr, refined = min(xl, a), max(xr, b), refined and ok
            area_rows += (b - a) * dy
    for i in np.flatnonzero(mask.any(axis=0)):
        for a, b, ok in _run_edges(mask[:, i], busy[:, i], gap[:, i], y):
            yl, yr, refined = min(yl, a), max(yr, b), refined and ok
            area_cols += (b - a) * dx
    pm = np.where(mask, p, 0.0)
    Nk = float(pm.sum()) * dA
    n_el = int(mask.sum())
    jmax, imax = np.unravel_index(int(np.argmax(pm)), pm.shape)
    jj, ii = np.nonzero(mask)
    if Nk > 0.0:
        xc = float((pm.sum(axis=0) * x).sum() * dA / Nk)
        yc = float((pm.sum(axis=1) * y).sum() * dA / Nk)
    else:
        xc = yc = float("nan")
    return {
        "N": Nk,
        "area": 0.5 * (area_rows + area_cols),
        "area_elements": n_el * dA,
        "n_elements": n_el,
        "length": float(xr - xl),
        "width": float(yr - yl),
        "x_min": float(xl), "x_max": float(xr), "y_min": float(yl), "y_max": float(yr),
        "centroid": (xc, yc),
        "area_centroid": (float(x[ii].mean()), float(y[jj].mean())),
        "p_max": float(pm[jmax, imax]),
        "p_max_at": (float(x[imax]), float(y[jmax])),
        "edges_refined": bool(refined),
        "elements_x": int(np.count_nonzero(mask.any(axis=0))),
        "elements_y": int(np.count_nonzero(mask.any(axis=1))),
    }


def halfspace_patch(h, dx, dy, E, nu, N=None, delta=None, tol=1e-8, max_iter=500, x=None, y=None):
    """Exact discrete half-space normal contact for the undeformed separation h.

    Parameters
    ----------
    h : (ny, nx) array [m], undeformed separation at the element centres; axis 1 = x (rolling,
        spacing dx), axis 0 = y (lateral / contact tangent s, spacing dy). Any offset.
    dx, dy : element sizes [m] (> 0).
    E, nu : Young's modulus [Pa] and Poisson's ratio of both bodies (E* = E / (2 (1 - nu^2))).
    N : total normal force [N] (>= 0), or
    delta : rigid approach [m] measured from h = 0 (exactly one of N, delta).
    tol : relative tolerance of the complementarity residual (0 < tol < 1).
    max_iter : maximum number of CG iterations (>= 1).
    x, y : optional 1-D element-centre coordinates [m] (default: centred, x_i = (i - (nx-1)/2) dx);
        used for the centroid and the extents.

    Returns a dict: ``pressure`` (ny, nx) [Pa], ``contact`` (ny, nx) bool, ``gap`` deformed gap
    h - delta + u (ny, nx) [m], ``N`` [N], ``delta`` [m], ``area`` (gap-refined) and
    ``area_elements`` (element count x dx dy) [m^2], ``n_elements``, ``length`` (x extent),
    ``width`` (y extent) [m], ``x_min, x_max, y_min, y_max``, ``centroid`` (pressure-weighted
    (x, y)), ``area_centroid``, ``p_max`` [Pa], ``p_max_at`` (x, y), ``edges_refined`` (all
    edges interpolated, else some at element edges), ``elements_x``, ``elements_y`` (columns /
    rows touched), ``patches`` (list of dicts with the same geometric keys per connected region,
    sorted by decreasing force), ``iterations``, ``residual`` (max of the complementarity residual
    and the relative load error), ``converged``, ``truncated`` (contact touches the window border),
    ``x``, ``y`` (element-centre coordinates).
    With no contact (N = 0, or delta <= min h) everything is zero and ``patches`` empty.
    """
    h = np.asarray(h, dtype=np.float64)
    if h.ndim != 2:
        raise ValueError(f"halfspace: h must be a 2-D (ny, nx) array, got shape {h.shape}")
    ny, nx = h.shape
    if nx < MIN_ELEMENTS or ny < MIN_ELEMENTS:
        raise ValueError(f"halfspace: grid {ny} x {nx} (ny x nx) too small; need at least "
                         f"{MIN_ELEMENTS} elements in each direction")
    if not np.all(np.isfinite(h)):
        raise ValueError("halfspace: h contains NaN or inf; it must be finite everywhere")
    dx = positive("dx", dx, "m")
    dy = positive("dy", dy, "m")
    E, nu = check_material(E, nu)
    if (N is None) == (delta is None):
        raise ValueError("halfspace: give exactly one of N (force, >= 0 N) and delta (approach, m)")
    if N is not None:
        N = float(N)
        if not (N >= 0.0 and math.isfinite(N)):
            raise ValueError(f"halfspace: N = {N!r} N must be finite and >= 0")
    else:
        delta = float(delta)
        if not math.isfinite(delta):
            raise ValueError(f"halfspace: delta = {delta!r} m must be finite")
    tol, max_iter = check_solver(tol, max_iter)
    x = centres("x", x, nx, dx)
    y = centres("y", y, ny, dy)

    E_star = combined_modulus(E, nu, E, nu)
    dA = dx * dy
    empty = {
        "pressure": np.zeros_like(h), "contact": np.zeros(h.shape, dtype=bool),
        "N": 0.0, "delta": 0.0 if N is not None else delta, "area": 0.0, "area_elements": 0.0,
        "n_elements": 0, "edges_refined": True, "elements_x": 0, "elements_y": 0,
        "length": 0.0, "width": 0.0, "x_min": np.nan, "x_max": np.nan, "y_min": np.nan,
        "y_max": np.nan, "centroid": (np.nan, np.nan), "area_centroid": (np.nan, np.nan),
        "p_max": 0.0, "p_max_at": (np.nan, np.nan), "patches": [], "iterations": 0,
        "residual": 0.0, "converged": True, "truncated": False, "x": x, "y": y,
    }
    if N is not None and N == 0.0:
        empty["delta"] = float(h.min())           # surfaces just touch
        empty["gap"] = h - h.min()
        return empty
    if delta is not None and delta <= float(h.min()):
        empty["gap"] = h - delta
        return empty

    op = _Operator(nx, ny, dx, dy, E_star)
    p, delta, u, iters, res, converged = _solve(op, h, dA, N, delta, tol, max_iter)
    if not converged:
        warnings.warn(f"halfspace: not converged in {max_iter} iterations "
                      f"(residual {res:.2e} > tol {tol:.1e})", RuntimeWarning, stacklevel=2)
    gap = h - delta + u
    contact = p > 0.0
    Ntot = float(p.sum()) * dA
    if N is not None:
        res = max(res, abs(Ntot - N) / N)
    truncated = bool(contact[0, :].any() or contact[-1, :].any()
                     or contact[:, 0].any() or contact[:, -1].any())
    if truncated:
        warnings.warn("halfspace: the contact region reaches the border of the grid window; "
                      "enlarge the window", RuntimeWarning, stacklevel=2)
    labels, n_lab = ndimage.label(contact, structure=_STRUCT8)
    patches = [_region_props(labels == k, contact, p, gap, x, y, dA)
               for k in range(1, n_lab + 1)]
    patches.sort(key=lambda d: -d["N"])
    whole = _region_props(contact, contact, p, gap, x, y, dA)
    whole.update({
        "pressure": p, "contact": contact, "gap": gap, "N": Ntot, "delta": float(delta),
        "patches": patches, "iterations": int(iters), "residual": float(res),
        "converged": bool(converged), "truncated": truncated, "x": x, "y": y,
    })
    return whole


# ---------------------------------------------------------------------------------------------
# wheel-rail gap
# ---------------------------------------------------------------------------------------------
def wheelrail_gap(s, gap_lateral, R_long, x_half_length, nx):
    """Undeformed separation h(x, s) = gap_lateral(s) + x^2 / (2 R_long(s)) of wheel and rail.

    s : (ny,) uniform lateral contact coordinate [m] (the tangent coordinate of the contact
        geometry; rows of h). gap_lateral : (ny,) undeformed normal separation along s [m].
    R_long : wheel longitudinal radius in the contact plane [m], scalar or (ny,) (> 0; the rail
        is straight along x). x_half_length : half-length of the x window [m] (> 0).
    nx : number of x points (>= 3) uniformly over [-x_half_length, x_half_length] (odd nx puts a
        point on x = 0).
    Returns (h, x, dx, dy): h (ny, nx), x (nx,), dx = x[1] - x[0], dy = s[1] - s[0]; call
    ``halfspace_patch(h, dx, dy, E, nu, N=..., x=x, y=s)``.
    """
    s, dy = _uniform_axis("s", s)
    g = np.asarray(gap_lateral, dtype=np.float64)
    if g.shape != s.shape or not np.all(np.isfinite(g)):
        raise ValueError(f"halfspace: gap_lateral must be finite with the shape of s {s.shape}, "
                         f"got {g.shape}")
    R = np.broadcast_to(np.asarray(R_long, dtype=np.float64), s.shape) if np.ndim(R_long) == 0 \
        else np.asarray(R_long, dtype=np.float64)
    if R.shape != s.shape:
        raise ValueError(f"halfspace: R_long must be a scalar or have the shape of s {s.shape}, "
                         f"got {R.shape}")
    if not np.all(R > 0.0) or not np.all(np.isfinite(R)):
        raise ValueError(f"halfspace: R_long must be finite and > 0 m (min {float(np.min(R))!r})")
    L = positive("x_half_length", x_half_length, "m")
    if int(nx) != nx or int(nx) < MIN_ELEMENTS:
        raise ValueError(f"halfspace: nx = {nx!r} must be an integer >= {MIN_ELEMENTS}")
    x = np.linspace(-L, L, int(nx))
    h = g[:, None] + x[None, :] ** 2 / (2.0 * R[:, None])
    return h, x, float(x[1] - x[0]), dy
