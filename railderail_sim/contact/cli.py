"""`railderail contact-geometry` and `railderail contact-case`: the contact modules as stand-alone tools.

contact-geometry
    Rigid contact geometry of a wheel/rail pair over the wheelset's lateral shift y (no yaw):
    rolling-radius difference Delta r(y), wheelset roll, contact angles, rolling radii, contact
    positions on wheel and rail, two-point flags, wheel lift (`conicity.rigid_table`); equivalent
    conicity by EN 15302 Annex B (`conicity.equivalent_conicity`, harmonic value beside it) over
    amplitudes 1..8 mm; flange height, maximum contact angle, Nadal's limit there, rail head width.
    The plot is the set a Simpack/VAMPIRE user checks first: contact points on wheel and rail
    joined by lines, Delta r(y), contact angle(y) of both wheels, conicity versus amplitude.

contact-case
    One wheelset in the spirit of CONTACT's wheelset mode: prescribed lateral shift y, yaw psi, roll
    (default: the rigid-contact roll at that y and psi) and vertical load; the wheelset's vertical
    position is solved so that the summed vertical contact force of its two wheels equals the load
    (the elastic contact decides how the wheels share it). Creepages come from the kinematics of
    steady rolling: centre velocity (v, 0, 0), no angular velocity besides the spin v / r0 about the
    axle (`wheelset.wheel_forces` with vel = (v, 0, 0), omega = 0, spin = v / r0); no contact damping
    (quasi-static). Models:
        hertz      Hertz (equivalent ellipse from the patch curvatures) + Shen-Hedrick-Elkins
        fastsim    Hertz + FASTSIM
        discrete   Kik-Piotrowski normal + SHE on its equivalent ellipse
        halfspace  as discrete (load sharing and creep forces); each patch is in addition solved by
                   the exact half-space solver (`halfspace.halfspace_patch`) at the discrete patch's
                   normal force, for its shape, size and pressure: the undeformed separation is the
                   patch's normal gap along the tangent coordinate, h(x, s) = g_n(s) + x^2 / (2 R(s)),
                   g_n = vertical gap x cos(contact angle), s = lateral track coordinate / cos, R the
                   wheel's longitudinal radius in the contact plane r sqrt(1 + r'^2)
                   (docs/contact-models.md; the same locally plane reduction as the discrete model).
    Per-patch quantities are computed by `wheel_patch_details`, which follows `wheelset.wheel_forces` step by
    step; its force sums are checked against `wheelset.wheel_forces` on every call.

Sign conventions of the output: totals in track axes (x forward, y left, z up), forces on the wheelset.
Per wheel, everything is in that wheel's own frame (the right wheel mirrored into the left-wheel
form of `geometry`): lateral positions, lateral creepage and lateral creep force + toward the field
side of its rail, contact angle + toward the flange, spin likewise mirrored; so a centred wheelset
gives identical left and right values. Q (+ toward the field side) and P (+ down) are the forces on
the rail. Yaw psi > 0 turns the wheelset's heading to the left (toward the left rail).

Bad input raises ValueError naming the value and its accepted range (the CLI prints one line, exit 2).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import tempfile
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from .. import profiles
from ..parameters import ContactParameters, TrackParameters, VehicleParameters
from ..ranges import check_range
from ..vehicle.assemble import contact_array, contact_geometry as pack_geometry
from . import conicity
from . import geometry as geo
from . import halfspace as hs
from . import kik_piotrowski as kp
from . import wheelset as ws
from .nadal import nadal_limit

# accepted ranges (user units: mm, km/h, kN, GPa, mrad)
GAUGE_MM = (1000.0, 1700.0)
BACK_TO_BACK_MM = (900.0, 1700.0)
INCLINATION_MAX = 0.1                 # slope 1:10
RADIUS_M = (0.2, 0.7)
FRICTION = (0.0, 1.0)                 # (0, 1]
Y_MAX_MM = (1.0, 40.0)
STEP_MM = (0.01, 1.0)
AMPLITUDE_MM = (0.0, 40.0)            # (0, y_max]
LOAD_KN = (0.0, 1000.0)               # (0, 1000]
SPEED_KMH = (1.0, 600.0)
YAW_MRAD = (-100.0, 100.0)
ROLL_MRAD = (-50.0, 50.0)
YOUNGS_GPA = (50.0, 500.0)
POISSON = (0.0, 0.5)                  # [0, 0.5)
GRID = (16, 256)
MIN_ELEMENTS_ACROSS = 16              # half-space: elements across the main patch (refined grid below)
TREAD_ANGLE_MAX = 0.5                 # rad: the centred wheelset must touch its rails below this angle
CONICITY_AMPLITUDES_MM = (1, 2, 3, 4, 5, 6, 7, 8)
TIP_MARGIN = 5.0e-4                   # m: contact closer than this to the flange tip / profile end = lost
MODELS = {  # name: (normal model, creep model, half-space)
    "hertz": ("hertz", "she", False),
    "fastsim": ("hertz", "fastsim", False),
    "discrete": ("discrete", "she", False),
    "halfspace": ("discrete", "she", True),
}
SIDES = ("left", "right")


def static_wheelset_load(vp: VehicleParameters | None = None) -> float:
    """Static vertical load of one wheelset of the CRH3 car (N): twice its static wheel load."""
    return 2.0 * (vp or VehicleParameters()).static_wheel_load


# ------------------------------------------------------------------------------------------------
# input checks
# ------------------------------------------------------------------------------------------------
def parse_inclination(text) -> float:
    """Rail inclination as an angle (rad) from '1/40', '1:40', '0' or a decimal slope ('0.025')."""
    s = str(text).strip()
    try:
        for sep in ("/", ":"):
            if sep in s:
                num, den = s.split(sep)
                ratio = float(num) / float(den)
                break
        else:
            ratio = float(s)
    except (ValueError, ZeroDivisionError):
        ratio = float("nan")
    if not (math.isfinite(ratio) and 0.0 <= ratio <= INCLINATION_MAX):
        raise ValueError(f"rail inclination {s!r} is not a slope within 0..1/10 (give e.g. 1/40, 1:20 or 0)")
    return math.atan(ratio)


def _profile(name_or_path, kind):
    """profiles.resolve with file-system errors turned into one-line ValueErrors."""
    try:
        return profiles.resolve(name_or_path, kind)
    except OSError as error:
        raise ValueError(f"{kind} profile file {str(name_or_path)!r} cannot be read "
                         f"({error.strerror or error})") from None
    except UnicodeDecodeError:
        raise ValueError(f"{kind} profile file {str(name_or_path)!r} is not a text profile "
                         "(plain text or SIMPACK .prw/.prr)") from None


def _plot_path(path):
    """Check an output plot path early (before any computation); returns a Path or None."""
    if path is None:
        return None
    p = Path(path).expanduser()
    if p.suffix.lower() not in (".png", ".pdf", ".svg"):
        raise ValueError(f"plot file {str(path)!r} must end in .png, .pdf or .svg")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"plot file {str(path)!r}: its folder {str(parent)!r} does not exist")
    return p


def write_figure(fig, path):
    """Save a matplotlib figure atomically: a temporary file in the same folder, then a rename."""
    path = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix, dir=path.parent or ".")
    except OSError as error:
        raise ValueError(f"plot file {str(path)!r} cannot be written ({error.strerror or error})") from None
    try:
        with os.fdopen(fd, "wb") as handle:
            fig.savefig(handle, format=path.suffix.lstrip(".").lower(), dpi=120)
        os.replace(tmp, path)
    except BaseException as error:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(error, OSError):
            raise ValueError(f"plot file {str(path)!r} cannot be written ({error.strerror or error})") from None
        raise


def _new_figure(width, height):
    from matplotlib.figure import Figure          # no pyplot: no global backend state
    return Figure(figsize=(width, height), layout="constrained")


# ------------------------------------------------------------------------------------------------
# the wheel/rail pair
# ------------------------------------------------------------------------------------------------
@dataclass
class Setup:
    """A wheel/rail pair placed as a wheelset on its track, with the packed geometry `cg`."""
    wheel: profiles.Profile
    rail: profiles.Profile
    contact: ContactParameters
    track: TrackParameters
    radius: float
    inclination_text: str
    cg: np.ndarray

    def inputs(self):
        return {
            "wheel": self.wheel.name, "rail": self.rail.name,
            "gauge_m": self.track.gauge, "gauge_depth_m": self.track.gauge_depth,
            "inclination": self.inclination_text, "inclination_rad": self.track.rail_inclination,
            "back_to_back_m": self.contact.back_to_back,
            "rolling_circle_from_back_m": self.contact.rolling_circle_from_back,
            "rolling_circle_half_distance_m": self.contact.rolling_circle_half_distance,
            "nominal_rolling_radius_m": self.radius,
            "friction": self.contact.friction_coefficient,
        }


def build_setup(wheel="lm", rail="uic60", *, gauge_mm=1435.0, inclination="1/40", back_to_back_mm=1353.0,
                radius_m=0.46, friction=0.3, youngs_gpa=210.0, poisson=0.28, model="hertz") -> Setup:
    """Check the inputs, read the profiles and pack the contact geometry (SI inside)."""
    gauge = check_range("gauge", gauge_mm, *GAUGE_MM, "mm") * 1e-3
    b2b = check_range("back-to-back distance", back_to_back_mm, *BACK_TO_BACK_MM, "mm") * 1e-3
    radius = check_range("nominal rolling radius", radius_m, *RADIUS_M, "m")
    mu = check_range("friction coefficient", friction, *FRICTION, "", lo_open=True)
    E = check_range("Young's modulus", youngs_gpa, *YOUNGS_GPA, "GPa") * 1e9
    nu = check_range("Poisson's ratio", poisson, *POISSON, "", hi_open=True)
    if model not in MODELS:
        raise ValueError(f"contact model {model!r} is unknown; choose one of {', '.join(MODELS)}")
    incl = parse_inclination(inclination)
    w = _profile(wheel, "wheel")
    r = _profile(rail, "rail")
    normal, creep, _ = MODELS[model]
    # the contact calculator answers with the exact search (the contact table is the time loop's shortcut)
    contact = ContactParameters(wheel_profile=w, back_to_back=b2b, youngs_modulus=E, poisson_ratio=nu,
                                friction_coefficient=mu, contact_damping=0.0, normal_model=normal,
                                creep_model=creep, contact_geometry="online")
    track = TrackParameters(gauge=gauge, rail_inclination=incl, rail_profile=r)
    cg = pack_geometry(contact, track, radius)
    setup = Setup(wheel=w, rail=r, contact=contact, track=track, radius=radius,
                  inclination_text=str(inclination).strip(), cg=cg)
    _check_centred_fit(setup, gauge_mm, back_to_back_mm)
    return setup


def _buffers(cg):
    nw = int(cg[geo.GeometryHeader.wheel_points])
    return np.zeros(nw), np.zeros(nw)


def _check_centred_fit(setup, gauge_mm, back_to_back_mm):
    cg = setup.cg
    z, phi, ok = conicity.rigid_pose(cg, 0.0, 0.0)
    row = conicity.deepest_patch(cg, 0.0, z, phi, 0.0)[0] if ok else None
    angle = math.atan(row[geo.Patch.slope]) if row is not None else float("nan")
    # the flange face: steepest point between the flange tip and the rolling circle
    nw = int(cg[geo.GeometryHeader.wheel_points])
    wz = cg[geo.H_SIZE:geo.H_SIZE + nw]
    slope = cg[geo.H_SIZE + nw:geo.H_SIZE + 2 * nw]
    tip = int(np.argmax(wz))
    j0 = int(round(-cg[geo.GeometryHeader.wheel_y0] / cg[geo.GeometryHeader.wheel_step]))
    y_face = cg[geo.GeometryHeader.wheel_y0] + (tip + int(np.argmin(slope[tip:j0 + 1]))) * cg[geo.GeometryHeader.wheel_step]
    on_tread = row is not None and row[geo.Patch.wheel_y] > y_face
    if not (ok and abs(angle) < TREAD_ANGLE_MAX and on_tread):
        what = ("finds no rail under its wheels" if not math.isfinite(angle) else
                f"touches its rails at a contact angle of {math.degrees(angle):.1f} deg" if on_tread else
                f"touches its rails with the flange ({row[geo.Patch.wheel_y] * 1e3:.1f} mm from the rolling circle, "
                f"beyond the flange face at {y_face * 1e3:.1f} mm)")
        raise ValueError(f"gauge {gauge_mm:g} mm with back-to-back {back_to_back_mm:g} mm does not fit "
                         f"{setup.wheel.name} on {setup.rail.name}: the centred wheelset {what}; the "
                         f"tread must carry it (contact angle below {math.degrees(TREAD_ANGLE_MAX):.0f} "
                         "deg), e.g. 1435 / 1353 mm")


def contact_range(cg, psi=0.0, y_hi=0.1, tol=1e-5):
    """Largest lateral shift (m) for which the rigid wheelset still touches both rails with the
    climbing wheel's contact short of its flange tip and the other wheel's contact inside its profile
    (the same for -y by mirror symmetry)."""
    tip = cg[geo.GeometryHeader.flange_tip_y]
    y_end = cg[geo.GeometryHeader.wheel_y0] + (cg[geo.GeometryHeader.wheel_points] - 1) * cg[geo.GeometryHeader.wheel_step]

    def fits(y):
        z, phi, ok = conicity.rigid_pose(cg, y, psi)
        if not ok:
            return False
        for yy, pp, ss in ((y, phi, psi), (-y, -phi, -psi)):
            row, _ = conicity.deepest_patch(cg, yy, z, pp, ss)
            if row is None or not (tip + TIP_MARGIN < row[geo.Patch.wheel_y] < y_end - TIP_MARGIN):
                return False
        return True

    if fits(y_hi):
        return y_hi
    lo, hi = 0.0, y_hi
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        if fits(mid):
            lo = mid
        else:
            hi = mid
    return lo


# ------------------------------------------------------------------------------------------------
# contact-geometry
# ------------------------------------------------------------------------------------------------
def geometry_report(setup: Setup, *, y_max_mm=12.0, step_mm=0.1, amplitude_mm=3.0):
    """Rigid contact tables, conicity, flange data and Nadal's limit of a wheel/rail pair (dict, SI)."""
    y_max = check_range("table range --y-max-mm", y_max_mm, *Y_MAX_MM, "mm") * 1e-3
    step = check_range("table step --step-mm", step_mm, *STEP_MM, "mm") * 1e-3
    if y_max / step > 4000:
        raise ValueError(f"table step {step_mm:g} mm over +-{y_max_mm:g} mm gives more than 8000 rows; "
                         f"use a step of at least {y_max_mm / 4000:g} mm")
    amp = check_range("conicity amplitude --amplitude-mm", amplitude_mm, 0.0, y_max_mm, "mm", lo_open=True) * 1e-3
    cg = setup.cg
    mu = setup.contact.friction_coefficient
    table = conicity.rigid_table(cg, y_max, step)
    ge, wavelength = conicity.equivalent_conicity(table, amp)
    by_amp = []
    for a_mm in CONICITY_AMPLITUDES_MM:
        a = a_mm * 1e-3
        if a > table.y[-1] + 1e-12:
            break
        g, lam = conicity.equivalent_conicity(table, a)
        by_amp.append({"amplitude_m": a, "equivalent_conicity": g, "harmonic_conicity":
                       float(conicity.harmonic_conicity(table, a)), "wavelength_m": lam})
    angles = np.maximum(table.contact_angle_left, table.contact_angle_right)
    i_max = int(np.argmax(angles))
    max_angle, y_peak = conicity.max_contact_angle(cg, table)
    flange_angle = setup.wheel.max_flange_angle()
    on_flange = np.nonzero((table.y >= 0.0) & (table.contact_angle_left > 0.6 * flange_angle))[0]
    nadal = float(nadal_limit(max_angle, mu))
    report = {
        "command": "contact-geometry",
        "inputs": {**setup.inputs(), "y_max_m": y_max, "step_m": step, "amplitude_m": amp},
        "equivalent_conicity": ge,
        "equivalent_conicity_method": "EN 15302:2008+A1:2010 Annex B (integration of the kinematic "
                                      "wheelset motion)",
        "equivalent_conicity_amplitude_m": amp,
        "harmonic_conicity": float(conicity.harmonic_conicity(table, amp)),
        "kinematic_wavelength_m": wavelength,
        "equivalent_conicity_by_amplitude": by_amp,
        "contact_half_distance_m": table.contact_half_distance,
        "flange_height_m": float(cg[geo.GeometryHeader.flange_height]),
        "flange_tip_y_m": float(cg[geo.GeometryHeader.flange_tip_y]),
        "max_flange_angle_rad": flange_angle,
        "max_contact_angle_rad": max_angle,
        "max_contact_angle_at_y_m": y_peak,
        "max_contact_angle_table_rad": float(angles[i_max]),
        "flange_contact_shift_m": float(table.y[on_flange[0]]) if len(on_flange) else None,
        "friction": mu,
        "nadal_limit": nadal,
        "nadal_formula": "(tan d - mu) / (1 + mu tan d) at d = max_contact_angle_rad (the table's largest "
                         "contact angle refined between its neighbouring rows)",
        "rail_head_width_m": float(cg[geo.GeometryHeader.rail_head_width]),
        "rail_head_width_depth_m": setup.track.gauge_depth,
        "tables": {
            "y_m": table.y.tolist(),
            "delta_r_m": table.delta_r.tolist(),
            "roll_rad": table.roll.tolist(),
            "vertical_m": table.z.tolist(),
            "contact_angle_left_rad": table.contact_angle_left.tolist(),
            "contact_angle_right_rad": table.contact_angle_right.tolist(),
            "rolling_radius_left_m": table.radius_left.tolist(),
            "rolling_radius_right_m": table.radius_right.tolist(),
            "wheel_contact_y_left_m": table.contact_y_left.tolist(),
            "wheel_contact_y_right_m": table.contact_y_right.tolist(),
            "rail_contact_y_left_m": table.rail_y_left.tolist(),
            "rail_contact_y_right_m": table.rail_y_right.tolist(),
            "two_point_left": table.two_point_left.tolist(),
            "two_point_right": table.two_point_right.tolist(),
            "wheel_lift_left_m": table.lift_left.tolist(),
            "wheel_lift_right_m": table.lift_right.tolist(),
        },
    }
    return report




def geometry_text(report):
    """Short human summary (mm, deg) of a geometry report."""
    i = report["inputs"]
    lines = [
        f"contact geometry: wheel {i['wheel']} on rail {i['rail']}, inclination {i['inclination']}, "
        f"gauge {i['gauge_m'] * 1e3:.1f} mm (at {i['gauge_depth_m'] * 1e3:g} mm), back-to-back "
        f"{i['back_to_back_m'] * 1e3:.1f} mm, rolling circles "
        f"{i['rolling_circle_half_distance_m'] * 2e3:.1f} mm apart, r0 "
        f"{i['nominal_rolling_radius_m'] * 1e3:.1f} mm",
        f"  flange height                 {report['flange_height_m'] * 1e3:.2f} mm",
        f"  max flange angle (profile)    {math.degrees(report['max_flange_angle_rad']):.2f} deg",
        f"  max contact angle             {math.degrees(report['max_contact_angle_rad']):.2f} deg "
        f"(at y = {report['max_contact_angle_at_y_m'] * 1e3:.1f} mm)",
    ]
    if report["flange_contact_shift_m"] is not None:
        lines.append(f"  flange contact from           y = {report['flange_contact_shift_m'] * 1e3:.1f} mm")
    else:
        lines.append("  flange contact                not reached within the table (increase --y-max-mm)")
    lines += [
        f"  Nadal limit Q/P               {report['nadal_limit']:.3f} (mu {report['friction']:g}, at the max "
        "contact angle)",
        f"  rail head width               {report['rail_head_width_m'] * 1e3:.2f} mm "
        f"(at {report['rail_head_width_depth_m'] * 1e3:g} mm)",
        f"  equivalent conicity           {report['equivalent_conicity']:.4f} (EN 15302 Annex B, amplitude "
        f"{report['equivalent_conicity_amplitude_m'] * 1e3:g} mm; harmonic "
        f"{report['harmonic_conicity']:.4f}; wavelength {report['kinematic_wavelength_m']:.2f} m)",
        "  amplitude mm   EN 15302   harmonic   wavelength m",
    ]
    for row in report["equivalent_conicity_by_amplitude"]:
        lines.append(f"  {row['amplitude_m'] * 1e3:12g}   {row['equivalent_conicity']:8.4f}   "
                     f"{row['harmonic_conicity']:8.4f}   {row['wavelength_m']:12.2f}")
    return "\n".join(lines)


def plot_geometry(report, setup: Setup, path):
    """2 x 2 figure: contact-point plot, Delta r(y), contact angles(y), conicity vs amplitude."""
    import matplotlib
    cg = setup.cg
    t = {k: np.asarray(v) for k, v in report["tables"].items()}
    y_mm = t["y_m"] * 1e3
    fig = _new_figure(11.0, 8.0)
    ax = fig.subplots(2, 2)
    # (a) contact points on wheel and rail, left wheel, centred drawing of both profiles
    a = ax[0, 0]
    axis_y = cg[geo.GeometryHeader.rail_axis_y]
    ry = np.linspace(cg[geo.GeometryHeader.rail_y0], cg[geo.GeometryHeader.rail_y0] + (cg[geo.GeometryHeader.rail_points] - 2) * cg[geo.GeometryHeader.rail_step], 1500)
    rz = np.array([geo.rail_height(cg, v)[0] for v in ry])
    z0 = t["vertical_m"][len(t["y_m"]) // 2]
    lift = 8e-3                                       # wheel drawn 8 mm above its centred position
    wy = setup.wheel.y
    wz = setup.wheel.z - float(setup.wheel.eval(0.0))
    wheel_Y = cg[geo.GeometryHeader.rolling_circle_distance] + wy
    wheel_Z = z0 - wz + lift
    a.plot((ry - axis_y) * 1e3, rz * 1e3, "k-", lw=1.5, label=f"rail {setup.rail.name}")
    a.plot((wheel_Y - axis_y) * 1e3, wheel_Z * 1e3, "b-", lw=1.5,
           label=f"wheel {setup.wheel.name} (+{lift * 1e3:g} mm)")
    cmap = matplotlib.colormaps["viridis"]
    stride = max(1, int(round(0.5e-3 / (t["y_m"][1] - t["y_m"][0]))))
    y_span = max(abs(t["y_m"][0]), abs(t["y_m"][-1]))
    for k in range(0, len(t["y_m"]), stride):
        yp = t["wheel_contact_y_left_m"][k]
        rail_Y = t["rail_contact_y_left_m"][k] + axis_y
        wheel_pt = (cg[geo.GeometryHeader.rolling_circle_distance] + yp, z0 - (float(setup.wheel.eval(yp)) - float(setup.wheel.eval(0.0)))
                    + lift)
        rail_pt = (rail_Y, geo.rail_height(cg, rail_Y)[0])
        colour = cmap(0.5 + 0.5 * t["y_m"][k] / y_span)
        a.plot([(wheel_pt[0] - axis_y) * 1e3, (rail_pt[0] - axis_y) * 1e3],
               [wheel_pt[1] * 1e3, rail_pt[1] * 1e3], "-", color=colour, lw=0.6)
    a.set_xlim((wheel_Y[0] - axis_y) * 1e3 - 3.0, (ry[-1] - axis_y) * 1e3 + 5.0)
    a.set_ylim(min(-40.0, 1e3 * float(wheel_Z.min()) - 3.0), 25.0)
    a.set_aspect("equal")
    a.set_xlabel("lateral position from the rail head axis [mm] (left rail, + field side)")
    a.set_ylabel("height [mm]")
    a.set_title(f"contact points, y = {t['y_m'][0] * 1e3:g} ... {t['y_m'][-1] * 1e3:g} mm "
                "(colour: y, every 0.5 mm)", fontsize=9)
    a.legend(fontsize=8, loc="upper right")
    # (b) Delta r(y)
    b = ax[0, 1]
    b.plot(y_mm, t["delta_r_m"] * 1e3, "k-")
    b.set_xlabel("wheelset lateral shift y [mm] (+ left)")
    b.set_ylabel("rolling radius difference r_L - r_R [mm]")
    b.set_title("Delta r(y)", fontsize=9)
    b.grid(alpha=0.3)
    # (c) contact angles
    c = ax[1, 0]
    c.plot(y_mm, np.degrees(t["contact_angle_left_rad"]), "b-", label="left wheel")
    c.plot(y_mm, np.degrees(t["contact_angle_right_rad"]), "r--", label="right wheel")
    c.set_xlabel("wheelset lateral shift y [mm] (+ left)")
    c.set_ylabel("contact angle [deg] (+ toward the flange)")
    c.set_title(f"contact angle; max {math.degrees(report['max_contact_angle_rad']):.2f} deg, "
                f"Nadal limit {report['nadal_limit']:.3f} at mu {report['friction']:g}", fontsize=9)
    c.legend(fontsize=8)
    c.grid(alpha=0.3)
    # (d) conicity vs amplitude
    d = ax[1, 1]
    rows = report["equivalent_conicity_by_amplitude"]
    amps = [r["amplitude_m"] * 1e3 for r in rows]
    d.plot(amps, [r["equivalent_conicity"] for r in rows], "ko-", label="EN 15302 Annex B")
    d.plot(amps, [r["harmonic_conicity"] for r in rows], "s--", color="0.5", label="harmonic")
    d.axvline(report["equivalent_conicity_amplitude_m"] * 1e3, color="0.8", lw=0.8)
    d.set_xlabel("amplitude [mm]")
    d.set_ylabel("equivalent conicity tan(gamma_e) [-]")
    d.set_title(f"equivalent conicity; {report['equivalent_conicity']:.4f} at "
                f"{report['equivalent_conicity_amplitude_m'] * 1e3:g} mm", fontsize=9)
    d.legend(fontsize=8)
    d.grid(alpha=0.3)
    fig.suptitle(f"{setup.wheel.name} on {setup.rail.name}, inclination {setup.inclination_text}, gauge "
                 f"{setup.track.gauge * 1e3:g} mm, back-to-back {setup.contact.back_to_back * 1e3:g} mm",
                 fontsize=10)
    write_figure(fig, path)


def geometry_command(parser: argparse.ArgumentParser):
    _pair_arguments(parser)
    parser.add_argument("--friction", type=float, default=ContactParameters.friction_coefficient,
                        help="friction coefficient for Nadal's limit (default %(default)s)")
    parser.add_argument("--y-max-mm", type=float, default=12.0,
                        help="table range: lateral shift -y..y (default %(default)s mm)")
    parser.add_argument("--step-mm", type=float, default=0.1, help="table step (default %(default)s mm)")
    parser.add_argument("--amplitude-mm", type=float, default=3.0,
                        help="amplitude of the equivalent conicity (default %(default)s mm, EN 15302)")
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    parser.add_argument("--plot", metavar="FILE.png", help="write the contact-geometry figure")

    def run(args):
        with _one_line_errors():
            plot = _plot_path(args.plot)
            setup = build_setup(args.wheel, args.rail, gauge_mm=args.gauge_mm, inclination=args.inclination,
                                back_to_back_mm=args.back_to_back_mm, radius_m=args.radius_m,
                                friction=args.friction)
            report = geometry_report(setup, y_max_mm=args.y_max_mm, step_mm=args.step_mm,
                                     amplitude_mm=args.amplitude_mm)
            if plot is not None:
                plot_geometry(report, setup, plot)
                report["plot"] = str(plot)
        _print_result(args, report, geometry_text, plot)
    return run


# ------------------------------------------------------------------------------------------------
# contact-case
# ------------------------------------------------------------------------------------------------
def _mirror(pose, side):
    y, z, phi, psi = pose
    return (y, z, phi, psi) if side == 0 else (-y, z, -phi, -psi)


def _wheel_forces(cg, cp, side, pose, speed, spin, tracked=False):
    """wheelset.wheel_forces for steady rolling: returns (force, moment, rec), track axes."""
    rec = np.zeros(ws.W_SIZE)
    fm = ws.wheel_forces(cg, cp, side, pose, (speed, 0.0, 0.0, 0.0, 0.0, 0.0, spin, speed), ws.contact_scratch(cg),
                         ws.candidates()[0], tracked, rec)
    return np.array(fm[:3]), np.array(fm[3:]), rec


def _vertical_force(cg, cp, pose, speed, spin):
    return sum(_wheel_forces(cg, cp, side, pose, speed, spin)[0][2] for side in (0, 1))


def _discrete_arrays(cg, pose, jm, gmin, cd, margin=0):
    """Normal gap (m), tangent coordinate s (m, from the deepest grid point, + field side) and wheel
    longitudinal radius (m) along the patch's interpenetration run, as in `wheelset._discrete_normal`;
    `margin` extends the run on both sides (for the half-space window) up to the next gap maximum."""
    y, z, phi, psi = pose
    gap, ys = _buffers(cg)
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
    R = (cg[geo.GeometryHeader.nominal_radius] + zw) * np.sqrt(1.0 + sw * sw)
    n_run = jb - ja + 1
    ds = abs((ys[jb] - ys[ja]) / ((n_run - 1) * cd)) if n_run > 1 else cg[geo.GeometryHeader.wheel_step]
    s = (j - jm) * ds
    g = (gap[lo:hi + 1] - gmin) * cd
    return s, g, R, ja - lo, jb - lo


def wheel_patch_details(setup: Setup, cp, pose, speed, spin, model, grid):
    """Per-patch contact data of the left wheel at `pose` (the left-wheel form of either wheel), read from
    the patch rows that `wheelset.wheel_forces` fills while it computes the forces; plus the discrete
    patch's outline and the half-space solution when asked."""
    cg = setup.cg
    scratch = ws.contact_scratch(cg)
    patches = scratch.patches
    rec = np.zeros(ws.W_SIZE)
    ws.wheel_forces(cg, cp, 0, pose, (speed, 0.0, 0.0, 0.0, 0.0, 0.0, spin, speed), scratch, ws.candidates()[0], False,
                  rec)
    count = int(rec[ws.Wheel.contact_count])
    E = setup.contact.youngs_modulus
    nu = cp[ws.ContactConstants.poisson_ratio]
    discrete = int(cp[ws.ContactConstants.normal_model]) == ws.NORMAL_DISCRETE
    out, plot = [], []
    for k in range(count):
        row = patches[k].copy()
        normal = row[geo.Patch.normal_force]
        if normal <= 0.0:
            continue
        slope = row[geo.Patch.slope]
        cd = 1.0 / math.sqrt(1.0 + slope * slope)
        sd = slope * cd
        jm = int(row[geo.Patch.grid_index])
        fx, ft = row[geo.Patch.creep_force_x], row[geo.Patch.creep_force_lateral]
        ha, hb = row[geo.Patch.hertz_a], row[geo.Patch.hertz_b]
        a, b = row[geo.Patch.half_length], row[geo.Patch.half_width]
        p = {
            "rail_y_m": row[geo.Patch.y] - cg[geo.GeometryHeader.rail_axis_y],
            "wheel_y_m": row[geo.Patch.wheel_y],
            "lead_x_m": row[geo.Patch.x],
            "contact_angle_rad": math.atan(slope),
            "rolling_radius_m": row[geo.Patch.radius],
            "vertical_gap_m": row[geo.Patch.gap],
            "normal_approach_m": row[geo.Patch.approach],
            "normal_force_N": normal,
            "hertz_a_m": ha,
            "hertz_b_m": hb,
            "hertz_p0_Pa": 1.5 * normal / (math.pi * ha * hb),
            "relative_curvature_A_1_m": row[geo.Patch.curvature_a],
            "relative_curvature_B_1_m": row[geo.Patch.curvature_b],
            "creep_ellipse_a_m": row[geo.Patch.creep_a],
            "creep_ellipse_b_m": row[geo.Patch.creep_b],
            "length_m": 2.0 * a,
            "width_m": 2.0 * b,
            "creepage": {"longitudinal": row[geo.Patch.creepage_x], "lateral": row[geo.Patch.creepage_y], "spin_1_m": row[geo.Patch.spin_creepage]},
            "creep_force": {"longitudinal_N": fx, "lateral_N": ft, "spin_moment_Nm": row[geo.Patch.spin_moment]},
            "force_on_wheel_N": [fx, normal * -sd + ft * cd, normal * cd + ft * sd],
        }
        pd = {"a": ha, "b": hb, "kind": "hertz", "angle": math.atan(slope), "N": normal,
              "rail_y": p["rail_y_m"]}
        if discrete:
            s, g, R, _, _ = _discrete_arrays(cg, pose, jm, row[geo.Patch.gap], cd)
            xl, _, plist, _ = kp.kp_patches(s - s[0], g, R, -row[geo.Patch.gap] * cd, E, nu, kp.EPS_DEFAULT, 1)
            q = plist[0]
            p["discrete"] = {"length_m": q["length"], "width_m": q["width"], "area_m2": q["area"],
                             "p_max_Pa": q["p_max"], "a_eq_m": q["a_eq"], "b_eq_m": q["b_eq"],
                             "approach_m": q["approach"], "normal_force_N": q["normal_force"],
                             "centroid_offset_m": q["y_centroid"] - q["y0"]}
            shift = s[0] + q["y0"]
            pd.update(kind="discrete", s=s - shift, xl=xl, p0=q["p0"], xl0=q["xl0"],
                      s_edges=(s[0] + q["y_min"] - shift, s[0] + q["y_max"] - shift))
            if MODELS[model][2]:
                p["halfspace"], pd["halfspace"] = _halfspace_patch(cg, pose, jm, row[geo.Patch.gap], cd, normal,
                                                                   E, nu, grid)
                hsd = p["halfspace"]
                p["length_m"], p["width_m"] = hsd["length_m"], hsd["width_m"]
        out.append(p)
        plot.append(pd)
    return out, plot


def _halfspace_patch(cg, pose, jm, gmin, cd, normal, E, nu, grid):
    """Exact half-space solution of one patch at normal force `normal` (see the module docstring).

    The first window is the patch's interpenetration run (plus a few samples) by +-1.05 sqrt(2 R delta)
    along x; a window the contact reaches is enlarged, and a window the contact fills by less than 60 %
    in either direction is shrunk once to the contact's extent plus 15 % (so that the grid resolves it)."""
    margin = 3
    delta_geo = -gmin * cd
    s, g, R, ia, ib = _discrete_arrays(cg, pose, jm, gmin, cd, margin=margin)
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
        Ru = np.interp(su, s, R)
        h, x, dx, dy = hs.wheelrail_gap(su, spline(su), Ru, x_half, grid)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            sol = hs.halfspace_patch(h, dx, dy, E, nu, N=normal, x=x, y=su)
        if sol["truncated"]:
            if best is not None:                       # the zoom went too far: keep the last good one
                break
            x_half *= 1.25
            if s_lo <= s[0] and s_hi >= s[-1]:
                margin = margin * 2 + int(0.2 * (ib - ia))
                s, g, R, ia, ib = _discrete_arrays(cg, pose, jm, gmin, cd, margin=margin)
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
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            sol = hs.halfspace_patch(h, dx, dy, E, nu, N=normal, x=x, y=su)
        main = sol["patches"][0] if sol["patches"] else sol
    info = {
        "length_m": main["length"], "width_m": main["width"], "area_m2": main["area"],
        "p_max_Pa": main["p_max"], "approach_m": sol["delta"] - float(h.min()),
        "normal_force_N": sol["N"], "patch_count": len(sol["patches"]),
        "centroid_offset_m": main["centroid"][1], "iterations": sol["iterations"],
        "converged": sol["converged"], "truncated": sol["truncated"], "grid_x_s": [nx, ny],
        "window_x_s_m": [float(2 * x_half), float(su[-1] - su[0])],
        "elements_across_x_s": [int(main["elements_x"]), int(main["elements_y"])],
        "patches": [{"normal_force_N": q["N"], "length_m": q["length"], "width_m": q["width"],
                     "area_m2": q["area"], "p_max_Pa": q["p_max"], "centroid_offset_m": q["centroid"][1]}
                    for q in sol["patches"]],
    }
    return info, {"x": x, "s": su, "pressure": sol["pressure"]}


def _free_spin(cg, cp, pose, speed, spin0):
    """Spin (rad/s) at which the wheelset's total longitudinal contact force vanishes (free rolling)."""
    def fx(spin):
        return sum(_wheel_forces(cg, cp, side, pose, speed, spin)[0][0] for side in (0, 1))

    lo, hi = spin0 * 0.995, spin0 * 1.005
    f_lo, f_hi = fx(lo), fx(hi)
    while f_lo * f_hi > 0.0 and hi - lo < 0.2 * spin0:
        lo, hi = lo - 0.005 * spin0, hi + 0.005 * spin0
        f_lo, f_hi = fx(lo), fx(hi)
    if f_lo * f_hi > 0.0:
        return spin0 if abs(fx(spin0)) < 1e-6 else float("nan")
    return brentq(fx, lo, hi, xtol=1e-12 * spin0, rtol=1e-14)


def contact_case(setup: Setup, *, lateral_mm=0.0, yaw_mrad=0.0, roll_mrad=None, load_kn=None, speed_kmh=300.0,
                 model="hertz", grid=64, spin="nominal"):
    """Solve one wheelset contact case; returns (result dict in SI, plot data).

    spin: "nominal" = v / r0 (as the vehicle model), "free" = the spin at which the total longitudinal
    contact force of the wheelset vanishes (solved together with the vertical position)."""
    if spin not in ("nominal", "free"):
        raise ValueError(f"spin {spin!r} is unknown; choose nominal or free")
    if model not in MODELS:
        raise ValueError(f"contact model {model!r} is unknown; choose one of {', '.join(MODELS)}")
    if MODELS[model][:2] != (setup.contact.normal_model, setup.contact.creep_model):
        raise ValueError(f"contact model {model!r} does not match the setup's models "
                         f"({setup.contact.normal_model}, {setup.contact.creep_model}); build it with model=")
    cg = setup.cg
    psi = check_range("yaw --yaw-mrad", yaw_mrad, *YAW_MRAD, "mrad") * 1e-3
    speed = check_range("speed --speed-kmh", speed_kmh, *SPEED_KMH, "km/h") / 3.6
    if load_kn is None:
        load_kn = static_wheelset_load() / 1e3
    load = check_range("vertical wheelset load --load-kn", load_kn, *LOAD_KN, "kN", lo_open=True) * 1e3
    grid = int(check_range("half-space grid --grid", grid, *GRID, "elements"))
    y = float(lateral_mm) * 1e-3
    if not math.isfinite(y):
        raise ValueError(f"lateral shift {lateral_mm!r} mm is not a number")
    y_lim = contact_range(cg, psi)
    if abs(y) > y_lim:
        raise ValueError(f"lateral shift {lateral_mm:g} mm (--lateral-mm) is beyond what {setup.wheel.name} "
                         f"on {setup.rail.name} can contact at yaw {yaw_mrad:g} mrad; accepted range "
                         f"{-y_lim * 1e3:.1f}..{y_lim * 1e3:.1f} mm (beyond it a contact passes the flange "
                         "tip or the end of the wheel profile)")
    z_rigid, phi_rigid, _ = conicity.rigid_pose(cg, y, psi)
    if roll_mrad is None:
        phi, roll_source = phi_rigid, "rigid contact"
    else:
        phi = check_range("roll --roll-mrad", roll_mrad, *ROLL_MRAD, "mrad") * 1e-3
        roll_source = "input"
    gap, ys = _buffers(cg)
    gl0, _ = geo.min_gap(cg, y, 0.0, phi, psi, gap, ys)
    gr0, _ = geo.min_gap(cg, -y, 0.0, -phi, -psi, gap, ys)
    if max(gl0, gr0) >= geo.NO_RAIL_GAP:
        raise ValueError(f"roll {phi * 1e3:g} mrad at lateral shift {lateral_mm:g} mm leaves a wheel without "
                         "rail under it; use a roll nearer the rigid-contact roll "
                         f"{phi_rigid * 1e3:.2f} mrad")
    z_touch = -min(gl0, gr0)
    cp = contact_array(setup.contact)
    spin_nominal = speed / setup.radius
    free = spin == "free"

    def spin_at(zz):
        return _free_spin(cg, cp, (y, zz, phi, psi), speed, spin_nominal) if free else spin_nominal

    def excess(zz):
        return _vertical_force(cg, cp, (y, zz, phi, psi), speed, spin_at(zz)) - load

    step = 1e-4
    z_lo = z_touch - step
    while excess(z_lo) <= 0.0:
        step *= 2.0
        z_lo = z_touch - step
        if step > 0.02:
            raise ValueError(f"vertical wheelset load {load_kn:g} kN is not reached within 20 mm of "
                             f"interpenetration; accepted range (0, {LOAD_KN[1]:g}] kN")
    z = brentq(excess, z_lo, z_touch, xtol=1e-14, rtol=1e-13, maxiter=200)
    pose = (y, z, phi, psi)
    spin = spin_at(z)
    if not math.isfinite(spin):
        raise ValueError("spin free: no spin within +-10 % of v / r0 balances the longitudinal forces; "
                         "use --spin nominal")
    wheels, plot = [], []
    total_f, total_m = np.zeros(3), np.zeros(3)
    for side in (0, 1):
        f, m, rec = _wheel_forces(cg, cp, side, pose, speed, spin)
        total_f += f
        total_m += m
        patches, pdata = wheel_patch_details(setup, cp, _mirror(pose, side), speed, spin, model, grid)
        wheels.append({
            "side": SIDES[side],
            "Q_N": rec[ws.Wheel.lateral_force], "P_N": rec[ws.Wheel.vertical_force], "Q_over_P": rec[ws.Wheel.derailment_coefficient],
            "longitudinal_force_on_rail_N": rec[ws.Wheel.longitudinal_force],
            "wheel_lift_m": rec[ws.Wheel.wheel_lift], "min_gap_m": rec[ws.Wheel.min_gap],
            "patch_count": len(patches), "patches": patches,
        })
        plot.append(pdata)
    result = {
        "command": "contact-case",
        "inputs": {**setup.inputs(), "model": model, "normal_model": setup.contact.normal_model,
                   "creep_model": setup.contact.creep_model, "halfspace": MODELS[model][2],
                   "lateral_m": y, "yaw_rad": psi, "roll_rad": phi if roll_mrad is not None else None,
                   "load_N": load, "speed_m_s": speed, "youngs_modulus_Pa": setup.contact.youngs_modulus,
                   "poisson_ratio": setup.contact.poisson_ratio,
                   "halfspace_grid": [grid, grid] if MODELS[model][2] else None, "spin": spin},
        "pose": {"lateral_m": y, "yaw_rad": psi, "roll_rad": phi, "roll_source": roll_source,
                 "vertical_m": z, "touch_vertical_m": z_touch, "rigid_vertical_m": z_rigid,
                 "rigid_roll_rad": phi_rigid, "lateral_range_m": y_lim,
                 "spin_rad_s": spin, "spin_mode": spin_mode_text(free),
                 "nominal_spin_rad_s": spin_nominal, "effective_rolling_radius_m": speed / spin},
        "wheels": wheels,
        "totals": {"force_N": total_f.tolist(), "moment_Nm": total_m.tolist(),
                   "vertical_load_N": float(total_f[2]),
                   "load_error_rel": float(total_f[2] / load - 1.0)},
    }
    return _plain(result), plot


def spin_mode_text(free):
    return ("free rolling (total longitudinal force zero)" if free else
            "nominal, v / r0 (as the vehicle model)")


def _plain(obj):
    """numpy scalars -> Python floats/ints/bools (for json)."""
    if isinstance(obj, dict):
        return {k: _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return float(obj)
    return obj


def case_text(result):
    i, pose, tot = result["inputs"], result["pose"], result["totals"]
    lines = [
        f"contact case: wheel {i['wheel']} on rail {i['rail']}, inclination {i['inclination']}, gauge "
        f"{i['gauge_m'] * 1e3:.1f} mm, back-to-back {i['back_to_back_m'] * 1e3:.1f} mm, r0 "
        f"{i['nominal_rolling_radius_m'] * 1e3:.1f} mm; model {i['model']} (normal {i['normal_model']}, "
        f"creep {i['creep_model']}{', + exact half-space patches' if i['halfspace'] else ''}), "
        f"mu {i['friction']:g}",
        f"  wheelset: lateral {pose['lateral_m'] * 1e3:.2f} mm, yaw {pose['yaw_rad'] * 1e3:.2f} mrad, roll "
        f"{pose['roll_rad'] * 1e3:.3f} mrad ({pose['roll_source']}), vertical "
        f"{pose['vertical_m'] * 1e3:.4f} mm (touch {pose['touch_vertical_m'] * 1e3:.4f} mm), speed "
        f"{i['speed_m_s'] * 3.6:g} km/h, load {i['load_N'] / 1e3:.2f} kN",
        f"  spin {pose['spin_rad_s']:.4f} rad/s, {pose['spin_mode']}; effective rolling radius "
        f"{pose['effective_rolling_radius_m'] * 1e3:.3f} mm",
    ]
    for w in result["wheels"]:
        lines.append(f"  {w['side']} wheel: Q {w['Q_N'] / 1e3:.2f} kN, P {w['P_N'] / 1e3:.2f} kN, Q/P "
                     f"{w['Q_over_P']:.3f}, {w['patch_count']} patch(es)")
        for k, p in enumerate(w["patches"]):
            cr, cf = p["creepage"], p["creep_force"]
            lines.append(
                f"    patch {k + 1}: rail y {p['rail_y_m'] * 1e3:7.2f} mm, wheel y "
                f"{p['wheel_y_m'] * 1e3:7.2f} mm, angle {math.degrees(p['contact_angle_rad']):6.2f} deg, "
                f"N {p['normal_force_N'] / 1e3:7.2f} kN, "
                f"Hertz a x b {p['hertz_a_m'] * 1e3:.2f} x {p['hertz_b_m'] * 1e3:.2f} mm, "
                f"patch {p['length_m'] * 1e3:.2f} x {p['width_m'] * 1e3:.2f} mm (length x width)")
            lines.append(
                f"             creepage x {cr['longitudinal']:+.3e}, y {cr['lateral']:+.3e}, spin "
                f"{cr['spin_1_m']:+.3f} 1/m; creep force x {cf['longitudinal_N'] / 1e3:+.3f} kN, y "
                f"{cf['lateral_N'] / 1e3:+.3f} kN")
            for key, label in (("discrete", "discrete (KP)"), ("halfspace", "half-space")):
                if key in p:
                    q = p[key]
                    lines.append(f"             {label:14s} {q['length_m'] * 1e3:.2f} x "
                                 f"{q['width_m'] * 1e3:.2f} mm, area {q['area_m2'] * 1e6:.1f} mm^2, "
                                 f"p_max {q['p_max_Pa'] / 1e6:.0f} MPa"
                                 + _separate_patches(q))
    f = tot["force_N"]
    lines.append(f"  totals on the wheelset (track axes, y left, z up): Fx {f[0] / 1e3:+.3f} kN, Fy "
                 f"{f[1] / 1e3:+.3f} kN, Fz {f[2] / 1e3:+.3f} kN (load error {tot['load_error_rel']:+.1e})")
    return "\n".join(lines)


def _separate_patches(q):
    """'; 2 separate patches: 45.8 kN at +11.2 mm, ...' when the half-space finds more than one."""
    parts = q.get("patches", ())
    if len(parts) < 2:
        return ""
    return f"; {len(parts)} separate patches: " + ", ".join(
        f"{r['normal_force_N'] / 1e3:.1f} kN at {r['centroid_offset_m'] * 1e3:+.1f} mm" for r in parts)


def plot_case(result, plot, path):
    """One panel per patch (rows: left, right wheel): Hertz ellipse, discrete outline, half-space pressure."""
    from matplotlib.patches import Ellipse
    ncol = max(1, max(len(p) for p in plot))
    fig = _new_figure(max(4.6 * ncol, 5.0), 8.0)
    axes = np.atleast_2d(fig.subplots(2, ncol, squeeze=False))
    for side, pdata in enumerate(plot):
        for k in range(ncol):
            ax = axes[side, k]
            if k >= len(pdata):
                ax.axis("off")
                ax.text(0.5, 0.5, f"{SIDES[side]} wheel: no patch" if not pdata else "", ha="center",
                        transform=ax.transAxes)
                continue
            d = pdata[k]
            lim = 0.0
            if "halfspace" in d:
                h = d["halfspace"]
                p = np.where(h["pressure"] > 0, h["pressure"], np.nan) / 1e6
                m = ax.pcolormesh((h["s"] - 0.0) * 1e3, h["x"] * 1e3, p.T, shading="nearest", cmap="viridis")
                fig.colorbar(m, ax=ax, label="half-space pressure [MPa]", shrink=0.8)
                lim = max(lim, np.max(np.abs(h["x"])) * 1e3, np.max(np.abs(h["s"])) * 1e3)
            if d["kind"] == "discrete":
                inside = d["xl"] > 0
                s_mm = np.concatenate(([d["s_edges"][0]], d["s"][inside], [d["s_edges"][1]])) * 1e3
                xl_mm = np.concatenate(([0.0], d["xl"][inside], [0.0])) * 1e3
                ax.plot(np.concatenate((s_mm, s_mm[::-1])), np.concatenate((xl_mm, -xl_mm[::-1])), "r-",
                        lw=1.2, label="discrete (KP) outline")
                lim = max(lim, np.max(np.abs(s_mm)) if len(s_mm) else 0.0, np.max(d["xl"]) * 1e3)
            ax.add_patch(Ellipse((0.0, 0.0), 2e3 * d["b"], 2e3 * d["a"], fill=False,
                                 ls="-" if d["kind"] == "hertz" else "--", color="k", lw=1.0,
                                 label="Hertz ellipse"))
            lim = 1.15 * max(lim, d["a"] * 1e3, d["b"] * 1e3)
            ax.set_xlim(-lim, lim)
            ax.set_ylim(-lim, lim)
            ax.set_aspect("equal")
            ax.set_xlabel("lateral, contact plane [mm] (+ field side)")
            ax.set_ylabel("rolling direction x [mm]")
            wp = result["wheels"][side]["patches"][k]
            ax.set_title(f"{SIDES[side]} wheel, patch {k + 1}: rail y {wp['rail_y_m'] * 1e3:.1f} mm, "
                         f"{math.degrees(wp['contact_angle_rad']):.1f} deg\n"
                         f"N {wp['normal_force_N'] / 1e3:.1f} kN, "
                         f"{wp['length_m'] * 1e3:.1f} x {wp['width_m'] * 1e3:.1f} mm", fontsize=8)
            ax.legend(fontsize=7, loc="upper right")
            ax.grid(alpha=0.3)
    i = result["inputs"]
    fig.suptitle(f"contact-case {i['wheel']} / {i['rail']}, model {i['model']}\n"
                 f"lateral {i['lateral_m'] * 1e3:g} mm, "
                 f"yaw {i['yaw_rad'] * 1e3:g} mrad, load {i['load_N'] / 1e3:.1f} kN", fontsize=9)
    write_figure(fig, path)


def case_command(parser: argparse.ArgumentParser):
    _pair_arguments(parser)
    parser.add_argument("--lateral-mm", type=float, default=0.0,
                        help="wheelset lateral shift, + left (default %(default)s mm)")
    parser.add_argument("--yaw-mrad", type=float, default=0.0,
                        help="wheelset yaw angle, + heading to the left (default %(default)s mrad)")
    parser.add_argument("--roll-mrad", type=float, default=None,
                        help="wheelset roll (default: the rigid-contact roll at this shift and yaw)")
    parser.add_argument("--load-kn", type=float, default=None,
                        help=f"vertical wheelset load (default: the CRH3 static axle load, "
                             f"{static_wheelset_load() / 1e3:.1f} kN)")
    parser.add_argument("--speed-kmh", type=float, default=300.0,
                        help="rolling speed (default %(default)s km/h)")
    parser.add_argument("--friction", type=float, default=ContactParameters.friction_coefficient,
                        help="friction coefficient (default %(default)s)")
    parser.add_argument("--youngs-gpa", type=float, default=ContactParameters.youngs_modulus / 1e9,
                        help="Young's modulus of wheel and rail (default %(default)s GPa)")
    parser.add_argument("--poisson", type=float, default=ContactParameters.poisson_ratio,
                        help="Poisson's ratio (default %(default)s)")
    parser.add_argument("--contact", choices=tuple(MODELS), default="hertz",
                        help="hertz (Hertz + SHE), fastsim (Hertz + FASTSIM), discrete (Kik-Piotrowski + "
                             "SHE), halfspace (discrete + exact half-space patches); default %(default)s")
    parser.add_argument("--spin", choices=("nominal", "free"), default="nominal",
                        help="wheelset spin: nominal = v / r0 as in the vehicle model (default), free = the "
                             "spin at which the total longitudinal force vanishes")
    parser.add_argument("--grid", type=int, default=64,
                        help="half-space grid, elements per direction (default %(default)s)")
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    parser.add_argument("--plot", metavar="FILE.png", help="draw the contact patches of both wheels")

    def run(args):
        with _one_line_errors():
            plot_path = _plot_path(args.plot)
            setup = build_setup(args.wheel, args.rail, gauge_mm=args.gauge_mm, inclination=args.inclination,
                                back_to_back_mm=args.back_to_back_mm, radius_m=args.radius_m,
                                friction=args.friction, youngs_gpa=args.youngs_gpa, poisson=args.poisson,
                                model=args.contact)
            result, plot = contact_case(setup, lateral_mm=args.lateral_mm, yaw_mrad=args.yaw_mrad,
                                        roll_mrad=args.roll_mrad, load_kn=args.load_kn,
                                        speed_kmh=args.speed_kmh, model=args.contact, grid=args.grid,
                                        spin=args.spin)
            if plot_path is not None:
                plot_case(result, plot, plot_path)
                result["plot"] = str(plot_path)
        _print_result(args, result, case_text, plot_path)
    return run


# ------------------------------------------------------------------------------------------------
# shared
# ------------------------------------------------------------------------------------------------
def _print_result(args, result, text, plot_path):
    """The command's result as JSON (--json) or as text, with where the plot went."""
    if args.json:
        print(json.dumps(result))
    else:
        print(text(result))
        if plot_path is not None:
            print(f"  plot written to {plot_path}")


def _pair_arguments(parser):
    parser.add_argument("--wheel", default="lm", metavar="NAME_OR_FILE",
                        help="wheel profile: lm, s1002 or a file (default %(default)s)")
    parser.add_argument("--rail", default="uic60", metavar="NAME_OR_FILE",
                        help="rail profile: uic60, uic60-mbench or a file (default %(default)s)")
    parser.add_argument("--gauge-mm", type=float, default=TrackParameters.gauge * 1e3,
                        help="track gauge, measured 14 mm below the rail top (default %(default)s mm)")
    parser.add_argument("--inclination", default="1/40",
                        help="rail inclination as a slope, e.g. 1/40 or 0 (default %(default)s)")
    parser.add_argument("--back-to-back-mm", type=float, default=ContactParameters.back_to_back * 1e3,
                        help="wheelset back-to-back distance; rolling circles 70 mm from the back faces "
                             "(default %(default)s mm)")
    parser.add_argument("--radius-m", type=float, default=VehicleParameters.rolling_radius,
                        help="nominal rolling radius (default %(default)s m)")


class _one_line_errors:
    """Context manager: a multi-line ValueError message becomes one line."""

    def __enter__(self):
        return self

    def __exit__(self, kind, error, tb):
        if kind is not None and issubclass(kind, ValueError) and "\n" in str(error):
            raise ValueError(" ".join(str(error).split())) from None
        return False
