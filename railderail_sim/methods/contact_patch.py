"""The contact patches of one wheel at a given pose, in detail: what `contact-case` and the report show.

`wheel_patch_details` reads the patch rows that `wheelset.wheel_forces` fills while it computes the
forces (Hertz ellipse, creepages, creep forces), and adds on request the discrete Kik-Piotrowski patch
(its outline) and the exact half-space solution of each patch (`halfspace.halfspace_patch`, its
pressure): the undeformed separation is the patch's normal gap along the tangent coordinate,
h(x, s) = g_n(s) + x^2 / (2 R(s)), g_n = vertical gap x cos(contact angle), s = lateral track coordinate
/ cos, R the wheel's longitudinal radius in the contact plane r sqrt(1 + r'^2) (docs/contact-models.md;
the same locally plane reduction as the discrete model). With the exact model, Kalker's exact steady
rolling theory (`exact_rolling.exact_rolling`) then solves the tangential problem on that grid, with that
pressure, the patch's creepages (those of its contact point, the origin of x and s) and the friction
coefficient; beside it the creep laws of `creep.py` on the patch's creep ellipse at the same normal force
and creepages, for comparison.

Everything is in the left wheel's frame (a right wheel is passed mirrored): lateral positions, lateral
creepage and lateral creep force + toward the field side of its rail, contact angle + toward the flange.
"""
from __future__ import annotations

from dataclasses import dataclass, field
import math
import warnings

import numpy as np
from scipy.interpolate import CubicSpline

from ..contact import creep
from ..contact import exact_rolling as er
from ..contact import geometry as geo
from ..contact import halfspace as hs
from ..contact import kik_piotrowski as kp
from ..contact import wheelset as ws
from ..jsonout import NOT_WRITTEN, WRITTEN_IF_SET
from .wheel_rail_pair import WheelRailPair, gap_buffers
from ..contact.layout import W_SIZE, GeometryHeader, Patch, Wheel

GRID = (16, 256)                      # accepted half-space grid (elements per direction)
MIN_ELEMENTS_ACROSS = 16              # half-space: elements across the main patch (refined grid below)
CREEP_LAWS = {"she": creep.SHEN_HEDRICK_ELKINS, "polach": creep.POLACH, "fastsim": creep.FASTSIM}


@dataclass(frozen=True)
class Creepage:
    longitudinal: float
    lateral: float
    spin_1_m: float


@dataclass(frozen=True)
class CreepForce:
    longitudinal_N: float
    lateral_N: float
    spin_moment_Nm: float


@dataclass(frozen=True, kw_only=True)
class DiscretePatch:
    """The Kik-Piotrowski patch at the patch's normal approach; its outline +-half_length(s) for drawing."""
    length_m: float
    width_m: float
    area_m2: float
    p_max_Pa: float
    a_eq_m: float
    b_eq_m: float
    approach_m: float
    normal_force_N: float
    centroid_offset_m: float
    s: np.ndarray = field(metadata=NOT_WRITTEN)             # tangent coordinate (m) from the Hertz centre
    half_length: np.ndarray = field(metadata=NOT_WRITTEN)   # half-length in x (m) at s
    s_edges: tuple = field(metadata=NOT_WRITTEN)            # lateral ends of the patch (m)


@dataclass(frozen=True, kw_only=True)
class SeparatePatch:
    """One of the separate patches the half-space solution finds."""
    normal_force_N: float
    length_m: float
    width_m: float
    area_m2: float
    p_max_Pa: float
    centroid_offset_m: float


@dataclass(frozen=True, kw_only=True)
class HalfSpacePatch:
    """The exact half-space solution at the patch's normal force; its main patch's size."""
    length_m: float
    width_m: float
    area_m2: float
    p_max_Pa: float
    approach_m: float
    normal_force_N: float
    patch_count: int
    centroid_offset_m: float
    iterations: int
    converged: bool
    truncated: bool
    grid_x_s: list
    window_x_s_m: list
    elements_across_x_s: list
    patches: list
    x: np.ndarray = field(metadata=NOT_WRITTEN)             # grid along the rolling direction (m)
    s: np.ndarray = field(metadata=NOT_WRITTEN)             # grid along the tangent coordinate (m)
    pressure: np.ndarray = field(metadata=NOT_WRITTEN)      # (len(s), len(x)) Pa


@dataclass(frozen=True, kw_only=True)
class ExactRollingPatch:
    """Kalker's exact steady rolling on the half-space patch's grid and pressure, and the creep laws
    (`CREEP_LAWS`) on the patch's creep ellipse at the same normal force and creepages."""
    creep_force: CreepForce
    stick_fraction: float
    residual: float
    iterations: int
    converged: bool
    laws: dict                                              # law name -> CreepForce
    px: np.ndarray = field(metadata=NOT_WRITTEN)            # traction on the wheel (Pa), (len(s), len(x))
    py: np.ndarray = field(metadata=NOT_WRITTEN)
    stick: np.ndarray = field(metadata=NOT_WRITTEN)         # stick elements


@dataclass(frozen=True, kw_only=True)
class ContactPatch:
    """One contact patch of a wheel (SI, the wheel's own frame); length x width are those of the most
    exact model computed (half-space, else the normal model's patch)."""
    rail_y_m: float
    wheel_y_m: float
    lead_x_m: float
    contact_angle_rad: float
    rolling_radius_m: float
    vertical_gap_m: float
    normal_approach_m: float
    normal_force_N: float
    hertz_a_m: float
    hertz_b_m: float
    hertz_p0_Pa: float
    relative_curvature_A_1_m: float
    relative_curvature_B_1_m: float
    creep_ellipse_a_m: float
    creep_ellipse_b_m: float
    length_m: float
    width_m: float
    creepage: Creepage
    creep_force: CreepForce
    force_on_wheel_N: list
    lever_arm_m: list                 # the contact point from the wheelset centre (x, y, z)
    discrete: DiscretePatch | None = field(default=None, metadata=WRITTEN_IF_SET)
    halfspace: HalfSpacePatch | None = field(default=None, metadata=WRITTEN_IF_SET)
    exact_rolling: ExactRollingPatch | None = field(default=None, metadata=WRITTEN_IF_SET)


def steady_rolling(speed, spin):
    """The `motion` of `wheelset.wheel_forces` in steady rolling: centre velocity (speed, 0, 0), no angular
    velocity but the spin about the axle."""
    return (speed, 0.0, 0.0, 0.0, 0.0, 0.0, spin, speed)


def left_wheel_patches(cg, cp, pose, speed, spin):
    """The patch rows (Patch) that `wheelset.wheel_forces` fills at `pose` in steady rolling
    (centre velocity (speed, 0, 0), no angular velocity but the spin)."""
    scratch = ws.contact_scratch(cg)
    rec = np.zeros(W_SIZE)
    ws.wheel_forces(cg, cp, 0, pose, steady_rolling(speed, spin), scratch, ws.candidates()[0], False, rec)
    return scratch.patches[:int(rec[Wheel.contact_count])].copy()


def wheel_patch_details(pair: WheelRailPair, pose, speed, spin, grid=64) -> list[ContactPatch]:
    """The patches of the left wheel at `pose` (the left-wheel form of either wheel) with a normal force,
    with the discrete patch when the pair's normal model is discrete, the half-space solution on a
    `grid` x `grid` window when its model has one (halfspace, exact) and the exact rolling solution on it
    with the exact model."""
    cg = pair.cg
    y, z = pose[0], pose[1]
    r0 = cg[GeometryHeader.nominal_radius]
    E, nu = pair.contact.youngs_modulus, pair.contact.poisson_ratio
    mu = pair.contact.friction_coefficient
    out = []
    for row in left_wheel_patches(cg, pair.cp, pose, speed, spin):
        p = Patch.split(row)
        normal = p["normal_force"]
        if normal <= 0.0:
            continue
        slope = p["slope"]
        cd = 1.0 / math.sqrt(1.0 + slope * slope)
        sd = slope * cd
        fx, ft = p["creep_force_x"], p["creep_force_lateral"]
        ha, hb = p["hertz_a"], p["hertz_b"]
        discrete = halfspace = rolling = None
        length, width = 2.0 * p["half_length"], 2.0 * p["half_width"]
        if pair.contact.normal_model == "discrete":
            discrete = _discrete_patch(cg, pose, int(p["grid_index"]), p["gap"], cd, E, nu)
        if pair.halfspace:
            halfspace = _halfspace_patch(cg, pose, int(p["grid_index"]), p["gap"], cd, normal, E, nu, grid)
            length, width = halfspace.length_m, halfspace.width_m
        creepage = (p["creepage_x"], p["creepage_y"], p["spin_creepage"])
        if pair.exact_rolling:
            rolling = _exact_rolling_patch(halfspace, tuple(map(float, creepage)),
                                           (float(p["creep_a"]), float(p["creep_b"])), float(normal), E, nu, mu)
        out.append(ContactPatch(
            rail_y_m=p["y"] - cg[GeometryHeader.rail_axis_y], wheel_y_m=p["wheel_y"], lead_x_m=p["x"],
            contact_angle_rad=math.atan(slope), rolling_radius_m=p["radius"],
            vertical_gap_m=p["gap"], normal_approach_m=p["approach"], normal_force_N=normal,
            hertz_a_m=ha, hertz_b_m=hb, hertz_p0_Pa=1.5 * normal / (math.pi * ha * hb),
            relative_curvature_A_1_m=p["curvature_a"], relative_curvature_B_1_m=p["curvature_b"],
            creep_ellipse_a_m=p["creep_a"], creep_ellipse_b_m=p["creep_b"], length_m=length,
            width_m=width,
            creepage=Creepage(*creepage), creep_force=CreepForce(fx, ft, p["spin_moment"]),
            force_on_wheel_N=[fx, normal * -sd + ft * cd, normal * cd + ft * sd],
            lever_arm_m=[p["x"], p["y"] - y, p["z"] - (r0 + z)],
            discrete=discrete, halfspace=halfspace, exact_rolling=rolling))
    return out


def _exact_rolling_patch(hsp, creepage, ellipse, normal, E, nu, mu):
    """Kalker's exact steady rolling on the half-space patch `hsp` (its grid and pressure; x and s measured
    from the contact point, where the creepages are), and the creep laws on `ellipse` (a, b) at `normal`."""
    x, s = hsp.x, hsp.s
    with warnings.catch_warnings():        # not converged: reported by `converged`
        warnings.simplefilter("ignore", RuntimeWarning)
        sol = er.exact_rolling(*creepage, hsp.pressure, x[1] - x[0], s[1] - s[0], E, nu, mu, x=x, y=s)
    shear = E / (2.0 * (1.0 + nu))
    laws = {name: CreepForce(*creep.creep_forces(law, *creepage, *ellipse, normal, mu, shear, nu))
            for name, law in CREEP_LAWS.items()}
    return ExactRollingPatch(creep_force=CreepForce(sol.Fx, sol.Fy, sol.Mz), stick_fraction=sol.stick_fraction,
                             residual=sol.residual, iterations=sol.iterations, converged=sol.converged, laws=laws,
                             px=sol.px, py=sol.py, stick=sol.stick)


def gap_run(cg, pose, jm, gmin, cd, margin=0):
    """Normal gap (m), tangent coordinate s (m, from the deepest grid point, + field side) and wheel
    longitudinal radius (m) along the patch's interpenetration run on the wheel grid (the vehicle core,
    `wheelset._discrete_normal`, samples the same trace-line gap at KP_STRIPS strips across the KP patch instead),
    and the run's first and last index in them; `margin` extends the run on both sides (for the
    half-space window) up to the next gap maximum."""
    y, z, phi, psi = pose
    gap, ys = gap_buffers(cg)
    ja, jb = geo.run_bounds(cg, y, z, phi, psi, jm, gap, ys)
    j0, j1 = geo.trace_gap(cg, y, z, phi, psi, gap, ys)
    lo, hi = ja, jb
    for _ in range(margin):
        if lo - 1 >= j0 and gap[lo - 1] >= gap[lo]:
            lo -= 1
        if hi + 1 < j1 and gap[hi + 1] >= gap[hi]:
            hi += 1
    j = np.arange(lo, hi + 1)
    wheel_z, wheel_slope, _ = geo.wheel_table(cg)
    zw = wheel_z[j]
    sw = wheel_slope[j]
    R = (cg[GeometryHeader.nominal_radius] + zw) * np.sqrt(1.0 + sw * sw)
    n_run = jb - ja + 1
    ds = abs((ys[jb] - ys[ja]) / ((n_run - 1) * cd)) if n_run > 1 else cg[GeometryHeader.wheel_step]
    s = (j - jm) * ds
    g = (gap[lo:hi + 1] - gmin) * cd
    return s, g, R, ja - lo, jb - lo


def _discrete_patch(cg, pose, jm, gmin, cd, E, nu):
    """The Kik-Piotrowski patch over the interpenetration run at the patch's normal approach: KP on the grid's
    cells (`kik_piotrowski.kp_patches`), the fine picture of the patch whose load the vehicle core takes from its
    strips (within 1e-3 on the tread, docs/contact-models.md)."""
    s, g, R, _, _ = gap_run(cg, pose, jm, gmin, cd)
    xl, _, plist, _ = kp.kp_patches(s - s[0], g, R, -gmin * cd, E, nu, kp.EPS_DEFAULT, 1)
    q = plist[0]
    shift = s[0] + q["y0"]
    return DiscretePatch(length_m=q["length"], width_m=q["width"], area_m2=q["area"], p_max_Pa=q["p_max"],
                         a_eq_m=q["a_eq"], b_eq_m=q["b_eq"], approach_m=q["approach"],
                         normal_force_N=q["normal_force"], centroid_offset_m=q["y_centroid"] - q["y0"],
                         s=s - shift, half_length=xl,
                         s_edges=(s[0] + q["y_min"] - shift, s[0] + q["y_max"] - shift))


def _solve(h, dx, dy, E, nu, normal, x, su):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return hs.halfspace_patch(h, dx, dy, E, nu, N=normal, x=x, y=su)


def _halfspace_patch(cg, pose, jm, gmin, cd, normal, E, nu, grid):
    """Exact half-space solution of one patch at normal force `normal` (see the module docstring).

    The first window is the patch's interpenetration run (plus a few samples) by +-1.05 sqrt(2 R delta)
    along x; a window the contact reaches is enlarged, and a window the contact fills by less than 60 %
    in either direction is shrunk once to the contact's extent plus 15 % (so that the grid resolves it)."""
    margin = 3
    delta_geo = -gmin * cd
    s, g, R, ia, ib = gap_run(cg, pose, jm, gmin, cd, margin=margin)
    if len(s) < 3:
        raise ValueError("half-space: the patch is narrower than three grid points of the wheel table")

    def fit(s, g):
        # the samples are exact at the wheel grid points (0.125 mm in y_p, up to ~0.4 mm in s on a
        # steep flange); a cubic spline between them keeps the gap's curvature, which linear
        # interpolation would lose on a patch only a few samples wide
        return CubicSpline(s, g) if len(s) >= 4 else (lambda q: np.interp(q, s, g))

    spline = fit(s, g)
    s_lo, s_hi = s[0], s[-1]
    x_half = 1.05 * math.sqrt(2.0 * float(R.max()) * delta_geo)
    zoomed = False
    best = None
    for _ in range(8):
        su = np.linspace(s_lo, s_hi, grid)
        h, x, dx, dy = hs.wheelrail_gap(su, spline(su), np.interp(su, s, R), x_half, grid)
        sol = _solve(h, dx, dy, E, nu, normal, x, su)
        if sol["truncated"]:
            if best is not None:                       # the zoom went too far: keep the last good one
                break
            x_half *= 1.25
            if s_lo <= s[0] and s_hi >= s[-1]:
                margin = margin * 2 + int(0.2 * (ib - ia))
                s, g, R, ia, ib = gap_run(cg, pose, jm, gmin, cd, margin=margin)
                spline = fit(s, g)
            s_lo, s_hi = s[0], s[-1]
            continue
        best = (sol, su, x, x_half, h)
        width, length = sol["y_max"] - sol["y_min"], sol["x_max"] - sol["x_min"]
        if zoomed or (width >= 0.6 * (s_hi - s_lo) and length >= 0.6 * 2.0 * x_half):
            break
        zoomed = True
        s_lo = max(s[0], sol["y_min"] - 0.15 * width - dy)
        s_hi = min(s[-1], sol["y_max"] + 0.15 * width + dy)
        x_half = min(x_half, 1.15 * max(abs(sol["x_min"]), abs(sol["x_max"])) + dx)
    if best is None:
        best = (sol, su, x, x_half, h)
    sol, su, x, x_half, h = best
    main = sol["patches"][0] if sol["patches"] else sol
    # a main patch still spanning few elements (e.g. the window holds a second, distant elastic patch,
    # so the zoom above could not shrink it): refine the grid to MIN_ELEMENTS_ACROSS elements across
    ny = nx = grid
    if sol["patches"] and min(main["elements_x"], main["elements_y"]) < MIN_ELEMENTS_ACROSS:
        ny = min(GRID[1] * 2, grid * math.ceil(MIN_ELEMENTS_ACROSS / max(main["elements_y"], 1)))
        nx = min(GRID[1] * 2, grid * math.ceil(MIN_ELEMENTS_ACROSS / max(main["elements_x"], 1)))
        su = np.linspace(su[0], su[-1], ny)
        h, x, dx, dy = hs.wheelrail_gap(su, spline(su), np.interp(su, s, R), x_half, nx)
        sol = _solve(h, dx, dy, E, nu, normal, x, su)
        main = sol["patches"][0] if sol["patches"] else sol
    return HalfSpacePatch(
        length_m=main["length"], width_m=main["width"], area_m2=main["area"], p_max_Pa=main["p_max"],
        approach_m=sol["delta"] - float(h.min()), normal_force_N=sol["N"], patch_count=len(sol["patches"]),
        centroid_offset_m=main["centroid"][1], iterations=sol["iterations"], converged=sol["converged"],
        truncated=sol["truncated"], grid_x_s=[nx, ny], window_x_s_m=[float(2 * x_half), float(su[-1] - su[0])],
        elements_across_x_s=[int(main["elements_x"]), int(main["elements_y"])],
        patches=[SeparatePatch(normal_force_N=q["N"], length_m=q["length"], width_m=q["width"],
                               area_m2=q["area"], p_max_Pa=q["p_max"], centroid_offset_m=q["centroid"][1])
                 for q in sol["patches"]],
        x=x, s=su, pressure=sol["pressure"])
