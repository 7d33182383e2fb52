"""A wheel/rail pair placed as a wheelset on its track: the inputs of `contact_geometry` and `contact_case`.

`build_pair` checks every input (user units at this edge: mm, GPa; one-line ValueErrors naming the value
and its accepted range), reads the profiles and packs the contact geometry (`vehicle.assemble`) and the
contact parameters; it refuses a gauge / back-to-back combination whose centred wheelset does not stand
on its treads. `contact_range` is the largest lateral shift at which the rigid wheelset still touches
both rails inside its profiles.
"""
from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np

from .. import profiles
from ..contact import conicity
from ..contact import geometry as geo
from ..parameters import FRICTION_RANGE, ContactParameters, TrackParameters, VehicleParameters
from ..ranges import check_range
from ..vehicle.assemble import contact_array, contact_geometry
from ..contact.layout import H_SIZE, GeometryHeader, Patch

# accepted ranges (user units: mm, km/h, kN, GPa, mrad)
GAUGE_MM = (1000.0, 1700.0)
BACK_TO_BACK_MM = (900.0, 1700.0)
INCLINATION_MAX = 0.1                 # slope 1:10
RADIUS_M = (0.2, 0.7)
YOUNGS_GPA = (50.0, 500.0)
POISSON = (0.0, 0.5)                  # [0, 0.5)
TREAD_ANGLE_MAX = 0.5                 # rad: the centred wheelset must touch its rails below this angle
TIP_MARGIN = 5.0e-4                   # m: contact closer than this to the flange tip / profile end = lost
MODELS = {  # name: (normal model, creep model, exact half-space normal patches, exact rolling on them)
    "hertz": ("hertz", "she", False, False),
    "fastsim": ("hertz", "fastsim", False, False),
    "discrete": ("discrete", "she", False, False),
    "halfspace": ("discrete", "she", True, False),
    # the vehicle model's default laws for the load sharing, so that each exact patch checks them
    "exact": ("hertz", "she", True, True),
}
SIDES = ("left", "right")


def static_wheelset_load(vp: VehicleParameters | None = None) -> float:
    """Static vertical load of one wheelset of the CRH3 car (N): twice its static wheel load."""
    return 2.0 * (vp or VehicleParameters()).static_wheel_load


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


def read_profile(name_or_path, kind):
    """profiles.resolve with file-system errors turned into one-line ValueErrors."""
    try:
        return profiles.resolve(name_or_path, kind)
    except OSError as error:
        raise ValueError(f"{kind} profile file {str(name_or_path)!r} cannot be read "
                         f"({error.strerror or error})") from None
    except UnicodeDecodeError:
        raise ValueError(f"{kind} profile file {str(name_or_path)!r} is not a text profile "
                         "(plain text or SIMPACK .prw/.prr)") from None


@dataclass(frozen=True)
class WheelRailPair:
    """A wheel/rail pair placed as a wheelset on its track, with its contact model (one of MODELS), the
    packed contact geometry `cg` and the contact parameter array `cp` of the numba core."""
    wheel: profiles.Profile
    rail: profiles.Profile
    contact: ContactParameters
    track: TrackParameters
    radius: float
    inclination_text: str
    model: str
    cg: np.ndarray
    cp: np.ndarray

    @property
    def halfspace(self) -> bool:
        """Whether each patch is also solved by the exact half-space solver."""
        return MODELS[self.model][2]

    @property
    def exact_rolling(self) -> bool:
        """Whether each half-space patch is also solved by Kalker's exact steady rolling theory."""
        return MODELS[self.model][3]

    def inputs(self) -> dict:
        """The pair's inputs as written in the JSON results (SI)."""
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


def build_pair(wheel="lm", rail="uic60", *, gauge_mm=1435.0, inclination="1/40", back_to_back_mm=1353.0,
               radius_m=0.46, friction=0.3, youngs_gpa=210.0, poisson=0.28, model="hertz") -> WheelRailPair:
    """Check the inputs, read the profiles and pack the contact geometry (SI inside)."""
    gauge = check_range("gauge", gauge_mm, *GAUGE_MM, "mm") * 1e-3
    b2b = check_range("back-to-back distance", back_to_back_mm, *BACK_TO_BACK_MM, "mm") * 1e-3
    radius = check_range("nominal rolling radius", radius_m, *RADIUS_M, "m")
    mu = check_range("friction coefficient", friction, *FRICTION_RANGE, "", lo_open=True)
    E = check_range("Young's modulus", youngs_gpa, *YOUNGS_GPA, "GPa") * 1e9
    nu = check_range("Poisson's ratio", poisson, *POISSON, "", hi_open=True)
    if model not in MODELS:
        raise ValueError(f"contact model {model!r} is unknown; choose one of {', '.join(MODELS)}")
    incl = parse_inclination(inclination)
    w = read_profile(wheel, "wheel")
    r = read_profile(rail, "rail")
    normal, creep = MODELS[model][:2]
    # the contact calculator answers with the exact search (the contact table is the time loop's shortcut)
    contact = ContactParameters(wheel_profile=w, back_to_back=b2b, youngs_modulus=E, poisson_ratio=nu,
                                friction_coefficient=mu, contact_damping=0.0, normal_model=normal,
                                creep_model=creep, contact_geometry="online")
    track = TrackParameters(gauge=gauge, rail_inclination=incl, rail_profile=r)
    pair = WheelRailPair(wheel=w, rail=r, contact=contact, track=track, radius=radius,
                         inclination_text=str(inclination).strip(), model=model,
                         cg=contact_geometry(contact, track, radius), cp=contact_array(contact))
    _check_centred_fit(pair, gauge_mm, back_to_back_mm)
    return pair


def gap_buffers(cg):
    """Work arrays (gap, track-frame y) of the core's gap functions, one entry per wheel grid point."""
    nw = int(cg[GeometryHeader.wheel_points])
    return np.zeros(nw), np.zeros(nw)


def _check_centred_fit(pair, gauge_mm, back_to_back_mm):
    cg = pair.cg
    z, phi, ok = conicity.rigid_pose(cg, 0.0, 0.0)
    row = conicity.deepest_patch(cg, 0.0, z, phi, 0.0)[0] if ok else None
    angle = math.atan(row[Patch.slope]) if row is not None else float("nan")
    # the flange face: steepest point between the flange tip and the rolling circle
    wheel_z, slope, _ = geo.wheel_table(cg)
    tip = int(np.argmax(wheel_z))
    y0, dy = cg[GeometryHeader.wheel_y0], cg[GeometryHeader.wheel_step]
    j0 = int(round(-y0 / dy))
    y_face = y0 + (tip + int(np.argmin(slope[tip:j0 + 1]))) * dy
    on_tread = row is not None and row[Patch.wheel_y] > y_face
    if not (ok and abs(angle) < TREAD_ANGLE_MAX and on_tread):
        what = ("finds no rail under its wheels" if not math.isfinite(angle) else
                f"touches its rails at a contact angle of {math.degrees(angle):.1f} deg" if on_tread else
                f"touches its rails with the flange ({row[Patch.wheel_y] * 1e3:.1f} mm from the rolling circle, "
                f"beyond the flange face at {y_face * 1e3:.1f} mm)")
        raise ValueError(f"gauge {gauge_mm:g} mm with back-to-back {back_to_back_mm:g} mm does not fit "
                         f"{pair.wheel.name} on {pair.rail.name}: the centred wheelset {what}; the "
                         f"tread must carry it (contact angle below {math.degrees(TREAD_ANGLE_MAX):.0f} "
                         "deg), e.g. 1435 / 1353 mm")


def contact_range(cg, psi=0.0, y_hi=0.1, tol=1e-5):
    """Largest lateral shift (m) for which the rigid wheelset still touches both rails with the
    climbing wheel's contact short of its flange tip and the other wheel's contact inside its profile
    (the same for -y by mirror symmetry)."""
    h = GeometryHeader.split(cg[:H_SIZE])
    tip = h["flange_tip_y"]
    y_end = h["wheel_y0"] + (h["wheel_points"] - 1) * h["wheel_step"]

    def fits(y):
        z, phi, ok = conicity.rigid_pose(cg, y, psi)
        if not ok:
            return False
        for yy, pp, ss in ((y, phi, psi), (-y, -phi, -psi)):
            row, _ = conicity.deepest_patch(cg, yy, z, pp, ss)
            if row is None or not (tip + TIP_MARGIN < row[Patch.wheel_y] < y_end - TIP_MARGIN):
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
