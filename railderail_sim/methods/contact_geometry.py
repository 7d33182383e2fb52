"""Rigid contact geometry of a wheel/rail pair (`railderail contact-geometry`).

Over the wheelset's lateral shift y (no yaw): rolling-radius difference Delta r(y), wheelset roll,
contact angles, rolling radii, contact positions on wheel and rail, two-point flags, wheel lift
(`conicity.rigid_table`); equivalent conicity by EN 15302 Annex B (`conicity.equivalent_conicity`,
harmonic value beside it) over amplitudes 1..8 mm; flange height, maximum contact angle, Nadal's limit
there, rail head width.
"""
from __future__ import annotations

from dataclasses import dataclass, field
import math

import numpy as np

from ..contact import conicity
from ..contact import geometry as geo
from ..contact.nadal import nadal_limit
from ..jsonout import NOT_WRITTEN
from ..ranges import check_range
from .wheel_rail_pair import WheelRailPair
from ..contact.layout import H_SIZE, GeometryHeader

Y_MAX_MM = (1.0, 40.0)
STEP_MM = (0.01, 1.0)
MAX_ROWS_HALF = 4000                  # table rows on each side of the centre
CONICITY_AMPLITUDES_MM = (1, 2, 3, 4, 5, 6, 7, 8)
CONICITY_METHOD = "EN 15302:2008+A1:2010 Annex B (integration of the kinematic wheelset motion)"
NADAL_FORMULA = ("(tan d - mu) / (1 + mu tan d) at d = max_contact_angle_rad (the table's largest contact "
                 "angle refined between its neighbouring rows)")
TABLE_KEYS = {  # JSON key: conicity.RigidTable field
    "y_m": "y", "delta_r_m": "delta_r", "roll_rad": "roll", "vertical_m": "z",
    "contact_angle_left_rad": "contact_angle_left", "contact_angle_right_rad": "contact_angle_right",
    "rolling_radius_left_m": "radius_left", "rolling_radius_right_m": "radius_right",
    "wheel_contact_y_left_m": "contact_y_left", "wheel_contact_y_right_m": "contact_y_right",
    "rail_contact_y_left_m": "rail_y_left", "rail_contact_y_right_m": "rail_y_right",
    "two_point_left": "two_point_left", "two_point_right": "two_point_right",
    "wheel_lift_left_m": "lift_left", "wheel_lift_right_m": "lift_right",
}


@dataclass(frozen=True)
class ConicityAtAmplitude:
    amplitude_m: float
    equivalent_conicity: float
    harmonic_conicity: float
    wavelength_m: float


@dataclass(frozen=True)
class ProfileSection:
    """The left wheel over its rail at the centred rigid pose, and the contact points of the table's
    shifts (m, lateral from the rail head axis, + field side; heights in the track frame)."""
    rail_y: np.ndarray
    rail_z: np.ndarray
    wheel_y: np.ndarray
    wheel_z: np.ndarray
    shift: np.ndarray                 # wheelset lateral shift of each contact (m)
    wheel_points: np.ndarray          # (n, 2): contact point on the wheel, drawn at its centred height
    rail_points: np.ndarray           # (n, 2): contact point on the rail


@dataclass(frozen=True, kw_only=True)
class ContactGeometry:
    """The result of `contact_geometry` (SI); `table` holds the rigid-contact rows."""
    pair: WheelRailPair = field(metadata=NOT_WRITTEN)
    y_max_m: float
    step_m: float
    equivalent_conicity: float
    equivalent_conicity_amplitude_m: float
    harmonic_conicity: float
    kinematic_wavelength_m: float
    equivalent_conicity_by_amplitude: list[ConicityAtAmplitude]
    flange_height_m: float
    flange_tip_y_m: float
    max_flange_angle_rad: float
    max_contact_angle_rad: float
    max_contact_angle_at_y_m: float
    max_contact_angle_table_rad: float
    flange_contact_shift_m: float | None      # first shift with the left contact on the flange
    nadal_limit: float
    rail_head_width_m: float
    table: conicity.RigidTable

    @property
    def friction(self) -> float:
        return self.pair.contact.friction_coefficient

    def as_dict(self) -> dict:
        """The JSON object of `railderail contact-geometry --json`."""
        t = self.table
        return {
            "command": "contact-geometry",
            "inputs": {**self.pair.inputs(), "y_max_m": self.y_max_m, "step_m": self.step_m,
                       "amplitude_m": self.equivalent_conicity_amplitude_m},
            "equivalent_conicity": self.equivalent_conicity,
            "equivalent_conicity_method": CONICITY_METHOD,
            "equivalent_conicity_amplitude_m": self.equivalent_conicity_amplitude_m,
            "harmonic_conicity": self.harmonic_conicity,
            "kinematic_wavelength_m": self.kinematic_wavelength_m,
            "equivalent_conicity_by_amplitude": [vars(row) for row in self.equivalent_conicity_by_amplitude],
            "contact_half_distance_m": t.contact_half_distance,
            "flange_height_m": self.flange_height_m,
            "flange_tip_y_m": self.flange_tip_y_m,
            "max_flange_angle_rad": self.max_flange_angle_rad,
            "max_contact_angle_rad": self.max_contact_angle_rad,
            "max_contact_angle_at_y_m": self.max_contact_angle_at_y_m,
            "max_contact_angle_table_rad": self.max_contact_angle_table_rad,
            "flange_contact_shift_m": self.flange_contact_shift_m,
            "friction": self.friction,
            "nadal_limit": self.nadal_limit,
            "nadal_formula": NADAL_FORMULA,
            "rail_head_width_m": self.rail_head_width_m,
            "rail_head_width_depth_m": self.pair.track.gauge_depth,
            "tables": {key: getattr(t, name).tolist() for key, name in TABLE_KEYS.items()},
        }

    def text(self) -> str:
        """Short human summary (mm, deg)."""
        p = self.pair
        lines = [
            f"contact geometry: wheel {p.wheel.name} on rail {p.rail.name}, inclination {p.inclination_text}, "
            f"gauge {p.track.gauge * 1e3:.1f} mm (at {p.track.gauge_depth * 1e3:g} mm), back-to-back "
            f"{p.contact.back_to_back * 1e3:.1f} mm, rolling circles "
            f"{p.contact.rolling_circle_half_distance * 2e3:.1f} mm apart, r0 {p.radius * 1e3:.1f} mm",
            f"  flange height                 {self.flange_height_m * 1e3:.2f} mm",
            f"  max flange angle (profile)    {math.degrees(self.max_flange_angle_rad):.2f} deg",
            f"  max contact angle             {math.degrees(self.max_contact_angle_rad):.2f} deg "
            f"(at y = {self.max_contact_angle_at_y_m * 1e3:.1f} mm)",
        ]
        if self.flange_contact_shift_m is not None:
            lines.append(f"  flange contact from           y = {self.flange_contact_shift_m * 1e3:.1f} mm")
        else:
            lines.append("  flange contact                not reached within the table (increase --y-max-mm)")
        lines += [
            f"  Nadal limit Y/Q               {self.nadal_limit:.3f} (mu {self.friction:g}, at the max "
            "contact angle)",
            f"  rail head width               {self.rail_head_width_m * 1e3:.2f} mm "
            f"(at {p.track.gauge_depth * 1e3:g} mm)",
            f"  equivalent conicity           {self.equivalent_conicity:.4f} (EN 15302 Annex B, amplitude "
            f"{self.equivalent_conicity_amplitude_m * 1e3:g} mm; harmonic "
            f"{self.harmonic_conicity:.4f}; wavelength {self.kinematic_wavelength_m:.2f} m)",
            "  amplitude mm   EN 15302   harmonic   wavelength m",
        ]
        for row in self.equivalent_conicity_by_amplitude:
            lines.append(f"  {row.amplitude_m * 1e3:12g}   {row.equivalent_conicity:8.4f}   "
                         f"{row.harmonic_conicity:8.4f}   {row.wavelength_m:12.2f}")
        return "\n".join(lines)

    def profile_section(self, every=0.5e-3, samples=1500) -> ProfileSection:
        """The left wheel and rail profiles at the centred pose, and the contact points every `every`
        metres of lateral shift (for the contact-point figure)."""
        pair, t = self.pair, self.table
        cg = pair.cg
        h = GeometryHeader.split(cg[:H_SIZE])
        axis_y = h["rail_axis_y"]
        ry = np.linspace(h["rail_y0"], h["rail_y0"] + (h["rail_points"] - 2) * h["rail_step"], samples)
        z0 = t.z[len(t.y) // 2]
        w = pair.wheel
        w0 = float(w.eval(0.0))
        rows = np.arange(0, len(t.y), max(1, int(round(every / (t.y[1] - t.y[0])))))
        rail_y = t.rail_y_left[rows] + axis_y
        wheel_y = t.contact_y_left[rows]
        return ProfileSection(
            rail_y=ry - axis_y, rail_z=_rail_heights(cg, ry), wheel_y=h["rolling_circle_distance"] + w.y - axis_y,
            wheel_z=z0 - (w.z - w0), shift=t.y[rows],
            wheel_points=np.column_stack((h["rolling_circle_distance"] + wheel_y - axis_y,
                                          [z0 - (float(w.eval(v)) - w0) for v in wheel_y])),
            rail_points=np.column_stack((rail_y - axis_y, _rail_heights(cg, rail_y))))


def _rail_heights(cg, ys):
    """Left-rail surface height (m) at track-frame lateral positions ys."""
    return np.array([geo.rail_height(cg, v)[0] for v in ys])


def contact_geometry(pair: WheelRailPair, *, y_max_mm=12.0, step_mm=0.1, amplitude_mm=3.0) -> ContactGeometry:
    """Rigid contact tables, conicity, flange data and Nadal's limit of a wheel/rail pair (user units
    in, SI out)."""
    y_max = check_range("table range --y-max-mm", y_max_mm, *Y_MAX_MM, "mm") * 1e-3
    step = check_range("table step --step-mm", step_mm, *STEP_MM, "mm") * 1e-3
    if y_max / step > MAX_ROWS_HALF:
        raise ValueError(f"table step {step_mm:g} mm over +-{y_max_mm:g} mm gives more than "
                         f"{2 * MAX_ROWS_HALF} rows; use a step of at least {y_max_mm / MAX_ROWS_HALF:g} mm")
    amp = check_range("conicity amplitude --amplitude-mm", amplitude_mm, 0.0, y_max_mm, "mm", lo_open=True) * 1e-3
    cg = pair.cg
    table = conicity.rigid_table(cg, y_max, step)
    ge, wavelength = conicity.equivalent_conicity(table, amp)
    by_amp = []
    for a_mm in CONICITY_AMPLITUDES_MM:
        a = a_mm * 1e-3
        if a > table.y[-1] + 1e-12:
            break
        g, lam = conicity.equivalent_conicity(table, a)
        by_amp.append(ConicityAtAmplitude(a, g, float(conicity.harmonic_conicity(table, a)), lam))
    angles = np.maximum(table.contact_angle_left, table.contact_angle_right)
    max_angle, y_peak = conicity.max_contact_angle(cg, table)
    flange_angle = pair.wheel.max_flange_angle()
    on_flange = np.nonzero((table.y >= 0.0) & (table.contact_angle_left > 0.6 * flange_angle))[0]
    return ContactGeometry(
        pair=pair, y_max_m=y_max, step_m=step, equivalent_conicity=ge, equivalent_conicity_amplitude_m=amp,
        harmonic_conicity=float(conicity.harmonic_conicity(table, amp)), kinematic_wavelength_m=wavelength,
        equivalent_conicity_by_amplitude=by_amp, flange_height_m=float(cg[GeometryHeader.flange_height]),
        flange_tip_y_m=float(cg[GeometryHeader.flange_tip_y]), max_flange_angle_rad=flange_angle,
        max_contact_angle_rad=max_angle, max_contact_angle_at_y_m=y_peak,
        max_contact_angle_table_rad=float(angles[int(np.argmax(angles))]),
        flange_contact_shift_m=float(table.y[on_flange[0]]) if len(on_flange) else None,
        nadal_limit=float(nadal_limit(max_angle, pair.contact.friction_coefficient)),
        rail_head_width_m=float(cg[GeometryHeader.rail_head_width]), table=table)
