"""Every vehicle, track, contact and material value of the model, with its unit and its source.

No value is written anywhere else. Each field carries `unit`, `source` (a key of SOURCES) and `sure`:
  V  verified in the cited source for this vehicle (Yu et al. 2022) or a standard,
  S  documented for a stand-in vehicle of the same geometry (not published for CRH3),
  A  our assumption or reconstruction (no source found), shown in the report's sensitivity table.
No value was chosen or adjusted to reproduce a published result.

Vehicle parameter sets (selectable by name, `vehicle_parameters(name)`):
  "hs19"  default. Masses and main dimensions of Yu 2022 Table 1. Suspension of the generic Chinese
          high-speed car of Math. Probl. Eng. 2019 (HS19): the only public set with the same
          17.5 m / 2.5 m geometry that gives the whole lateral suspension (primary, air springs,
          lateral and two-stage yaw dampers with series stiffness). Elements HS19 does not give (anti-roll
          bar, bump stop, absolute heights) come from one other set, the CRH380A file (A380), never
          mixing two sources inside one subsystem.
  "a380"  the CRH380A parameter file's suspension throughout (swing-arm node stiffness, nonlinear
          lateral and yaw dampers), Yu's masses and dimensions.
  "zhai"  the "high-speed passenger car" preset of Zhai's Vehicle-Track Coupled Dynamics appendix as
          republished in public code, Yu's masses and dimensions.
  "hs19-a380yaw"  hs19 with the CRH380A file's yaw damper law (damping, blow-off, series stiffness): the set
          the stability study (docs/report/stability.md) found stable beyond 1.1 x 300 km/h from sourced values.
Inertias: for each set, the set's radii of gyration applied to Yu's masses (I = m k^2): each inertia is
given as the (inertia, mass) of the set's own vehicle and scaled by the mass ratio, so that changing a
mass (`vehicle_parameters(car_body_mass=...)`) changes its inertias with it. Where a set gives no value
the HS19 radius of gyration is used and marked A.
"""
from dataclasses import dataclass, field, fields, replace
import math

from .ranges import check_range

SOURCES = {
    "Yu2022": "Yu R., Ma H., Zhang J., Niu Y., A Method of Predicting Critical Derailment Speed and "
              "Analysis of Derailment Process, Appl. Sci. 2022, 12, 11199, Tables 1-2",
    "HS19": "Numerical Investigation into the Critical Speed and Frequency of the Hunting Motion in Railway "
            "Vehicle System, Math. Probl. Eng. 2019, art. 7163732, Table 2",
    "A380": "CRH380A parameter file Par_Vehicle_CRH380A_v6 of public MATLAB vehicle-dynamics code (its "
            "header cites the SIMPACK model CRH2-380; the repository was not identified), values as read in "
            "that file",
    "Zhai": "Zhai W., Vehicle-Track Coupled Dynamics, appendix 'high-speed passenger car' preset, as "
            "republished in public vehicle-track code",
    "EN13674": "EN 13674-1 (60E1 = UIC60 rail head), EN 13715 (S1002); 1:40 rail inclination and 1435 mm "
               "gauge at 14 mm below the rail top as on Chinese lines (Ye et al., Rail. Eng. Sci. 30 (2022) "
               "96-116, Table 2)",
    "EN13803": "EN 13803 (track alignment design): cant related to 1500 mm between rail centres for "
               "standard gauge",
    "TB449": "TB/T 449 LM wheel; wheelset back-to-back 1353 mm and rolling circles 1493 mm apart "
             "(Adv. Civ. Eng. 2020, art. 4515319, Table 1)",
    "Johnson": "Johnson K.L., Contact Mechanics, Cambridge 1985 (E, nu of steel; Hertz)",
    "Iwnicki": "Iwnicki S. (ed.), Handbook of Railway Vehicle Dynamics, CRC 2006 (friction 0.3 dry rail)",
    "HuntCrossley": "Hunt K.H., Crossley F.R.E., Coefficient of restitution interpreted as damping in "
                    "vibroimpact, J. Appl. Mech. 42 (1975) 440-445",
    "Zhai2004": "Zhai W.M., Wang K.Y., Lin J.H., Modelling and experiment of railway ballast vibrations, "
                "J. Sound Vib. 270 (2004) 673-683, Table 1 (ballasted track, per rail seat), as republished "
                "in public vehicle-track code",
    "ZhaiBook": "Zhai W., Vehicle-Track Coupled Dynamics, typical ballasted-track parameters (fastening and "
                "sleeper lateral, rail torsion geometry), as republished in public vehicle-track code",
    "ACE2021": "Adv. Civ. Eng. 2021, art. 8847633, Table 2: CHN60 rail section (60.64 kg/m, I 3.217e-5 and "
               "5.24e-6 m^4, polar 3.741e-5 m^4)",
    "SV2019": "Shock Vib. 2019, art. 2015465, Table 2: the rail's torsional rigidity GK 1.9587e5 N m^2",
    "Winkler": "own reduction of the track to one co-running mass per wheel (docs/elastic-track.md): the rail "
               "on a Winkler foundation of its seats (Hetenyi, Beams on Elastic Foundation, 1946), point "
               "stiffness 2k/beta; masses and dampers by Rayleigh's method on the static deflection shape",
    "model": "modelling choice of this project, explained in docs/vehicle-model.md",
    "EN14067": "EN 14067-1 and EN 14067-6 (railway aerodynamics; cross wind assessment): reference area 10 m^2 and "
               "length 3 m of the coefficients, moments about the track centre line at rail level, the wheel "
               "unloading limit 0.90 of a running gear; as quoted in ../shared/reference/track-and-loads.md",
    "ICE3": "ICE 3 / Velaro main dimensions: car 25.7 m over the nose of an end car, 2.95 m wide, 3.89 m high "
            "(manufacturer data as quoted in encyclopedic sources)",
    "Hoerner": "Hoerner S.F., Fluid-Dynamic Drag, 1965, and Fluid-Dynamic Lift, 1985 (cross-flow drag of rounded "
               "prisms near a wall; slender-body normal force of a nose)",
    "CENgust": "the CEN extreme gust of EN 14067-6 (Bierbooms and Cheng, Wind Energy 5 (2002), the expected shape "
               "of turbulence about its extreme: the mean wind plus peak factor x turbulence intensity x the "
               "autocorrelation), in the simplified exponential form; constants not read in the standard",
}


def parameter(value, unit, source, sure, note=""):
    """A dataclass field of a parameter with its default `value`, `unit`, `source` (a key of SOURCES or a
    sentence), how sure it is (`sure`, the letters above) and a `note`, kept in the field's metadata for
    `parameter_rows`: every parameter table (this module's, the sensors' instruments) declares its fields
    with it."""
    return field(default=value, metadata={"unit": unit, "source": source, "sure": sure, "note": note})


_p = parameter          # the short name of the tables below


def parameter_rows(parameters):
    """Rows (name, value, unit, source, sure, note) of a parameter dataclass's fields, for reports."""
    return [(f.name, getattr(parameters, f.name), f.metadata["unit"], f.metadata["source"], f.metadata["sure"],
             f.metadata["note"]) for f in fields(parameters) if f.metadata]


@dataclass(frozen=True)
class VehicleParameters:
    """CRH3 car (body, two bogie frames, four wheelsets) with its primary and secondary suspension."""
    name: str = "hs19"
    # --- masses (Yu 2022 Table 1)
    car_body_mass: float = _p(32000.0, "kg", "Yu2022", "V")
    bogie_frame_mass: float = _p(3300.0, "kg", "Yu2022", "V")
    wheelset_mass: float = _p(1780.0, "kg", "Yu2022", "V")
    # --- inertias: each set gives (inertia, mass) of its own vehicle; the inertia of ours is that inertia
    # scaled by the mass ratio (the same radius of gyration), so a changed mass changes it too
    car_body_roll_inertia_source: tuple = _p((84560.0, 28000.0), "kg m^2, kg", "HS19", "S", "HS19 car body Ixx")
    car_body_pitch_inertia_source: tuple = _p((1102730.0, 28000.0), "kg m^2, kg", "HS19", "A",
                                              "HS19 gives no Iyy; taken equal to Izz (long slender body)")
    car_body_yaw_inertia_source: tuple = _p((1102730.0, 28000.0), "kg m^2, kg", "HS19", "S", "HS19 car body Izz")
    bogie_frame_roll_inertia_source: tuple = _p((2106.0, 3000.0), "kg m^2, kg", "HS19", "S")
    bogie_frame_pitch_inertia_source: tuple = _p((2600.0, 3000.0), "kg m^2, kg", "HS19", "A",
                                                 "HS19 gives no Iyy; taken equal to Izz")
    bogie_frame_yaw_inertia_source: tuple = _p((2600.0, 3000.0), "kg m^2, kg", "HS19", "S")
    wheelset_roll_inertia_source: tuple = _p((1029.0, 2400.0), "kg m^2, kg", "HS19", "S",
                                             "HS19 gives Izz only; roll taken equal to yaw")
    wheelset_yaw_inertia_source: tuple = _p((1029.0, 2400.0), "kg m^2, kg", "HS19", "S")
    wheelset_spin_inertia_source: tuple = _p((76.0, 1902.0), "kg m^2, kg", "A380", "S",
                                             "A380 Iyy (enters the gyroscopic terms and the spin equation only)")
    # --- main dimensions (Yu 2022 Table 1)
    bogie_semi_distance: float = _p(8.75, "m", "Yu2022", "V", "half of 17.5 m")
    wheelbase_semi: float = _p(1.25, "m", "Yu2022", "V", "half of 2.5 m")
    rolling_radius: float = _p(0.46, "m", "Yu2022", "V")
    # --- heights above the rail top
    car_body_cog_height: float = _p(1.52, "m", "A380", "S")
    bogie_frame_cog_height: float = _p(0.46 + 0.148, "m", "HS19", "S", "HS19: 0.148 m above the axle")
    secondary_height: float = _p(0.90, "m", "A380", "S", "middle of the air spring, bottom 0.80 / top 1.00")
    yaw_damper_height: float = _p(0.415, "m", "A380", "S")
    lateral_damper_height: float = _p(0.60, "m", "model", "A", "not found in any set")
    bump_stop_height: float = _p(0.60, "m", "model", "A", "not found in any set")
    # --- lateral spacings (semi-distances from the vehicle centre line)
    primary_semi_spacing: float = _p(1.0, "m", "HS19", "S")
    air_spring_semi_spacing: float = _p(1.23, "m", "HS19", "S")
    secondary_vertical_damper_semi_spacing: float = _p(1.323, "m", "HS19", "S")
    yaw_damper_semi_spacing: float = _p(1.35, "m", "HS19", "S")
    yaw_damper_length: float = _p(0.50, "m", "model", "A",
                                  "longitudinal length between end fittings; enters only through geometry")
    # --- primary suspension, per axle box
    primary_longitudinal_stiffness: float = _p(85.0e6, "N/m", "HS19", "S", "basis (per box) assumed")
    primary_lateral_stiffness: float = _p(15.0e6, "N/m", "HS19", "S", "basis (per box) assumed")
    primary_vertical_stiffness: float = _p(1.1e6, "N/m", "HS19", "S")
    primary_vertical_damping: float = _p(20.0e3, "N s/m", "HS19", "S")
    primary_lateral_damping: float = _p(10.0e3, "N s/m", "HS19", "S")
    # --- secondary suspension, per air spring (two per bogie)
    secondary_longitudinal_stiffness: float = _p(0.2e6, "N/m", "HS19", "S")
    secondary_lateral_stiffness: float = _p(0.2e6, "N/m", "HS19", "S")
    secondary_vertical_stiffness: float = _p(0.2e6, "N/m", "HS19", "S")
    secondary_vertical_damping: float = _p(10.0e3, "N s/m", "HS19", "S", "per side")
    anti_roll_stiffness: float = _p(1.0e6, "N m/rad", "A380", "S", "per bogie")
    # --- secondary lateral damper, one per bogie: force-velocity law (piecewise linear) + series spring
    lateral_damper_knee_velocity: float = _p(1.0, "m/s", "HS19", "S", "linear: knee beyond use")
    lateral_damper_damping: float = _p(30.0e3, "N s/m", "HS19", "S")
    lateral_damper_damping_after_knee: float = _p(30.0e3, "N s/m", "HS19", "S")
    lateral_damper_series_stiffness: float = _p(0.0, "N/m", "HS19", "S", "0 = rigid end fittings")
    # --- yaw dampers, one per bogie side: two-stage (blow-off) law with series stiffness
    yaw_damper_knee_velocity: float = _p(0.01, "m/s", "HS19", "S", "blow-off 3 kN at 0.01 m/s")
    yaw_damper_damping: float = _p(300.0e3, "N s/m", "HS19", "S")
    yaw_damper_damping_after_knee: float = _p(20.0e3, "N s/m", "HS19", "S")
    yaw_damper_series_stiffness: float = _p(10.0e6, "N/m", "HS19", "S")
    # --- secondary lateral bump stop (per bogie, between frame and body)
    bump_stop_clearance: float = _p(0.020, "m", "A380", "S")
    bump_stop_travel: tuple = _p((0.026, 0.032, 0.038, 0.044, 0.048), "m", "A380", "S",
                                 "deflection points of the force law (zero force at the clearance); "
                                 "beyond the last point the last slope continues")
    bump_stop_force: tuple = _p((2.0e3, 5.0e3, 11.0e3, 25.5e3, 49.0e3), "N", "A380", "S")
    # --- vertical travel limits (bump stops with a linear law beyond the clearance): no public source gives them
    # for CRH3/Velaro/CRH380 (docs/vehicle-model.md, "Suspension limits and faults"); typical engineering values
    air_spring_emergency_clearance: float = _p(0.035, "m", "model", "A",
                                               "compression of the air spring before the car body rests on the "
                                               "emergency (auxiliary rubber) spring inside it; typical 30-40 mm")
    air_spring_emergency_stiffness: float = _p(2.5e6, "N/m", "model", "A",
                                               "vertical stiffness of the emergency rubber spring, per air spring; "
                                               "typical 1-5 MN/m (layered rubber under a quarter car body)")
    air_spring_extension_clearance: float = _p(0.050, "m", "model", "A",
                                               "extension of the air spring before its height restraint (stop or "
                                               "safety cable) holds the car body")
    air_spring_extension_stiffness: float = _p(5.0e6, "N/m", "model", "A", "stiffness of the height restraint")
    primary_stop_clearance: float = _p(0.030, "m", "model", "A",
                                       "compression of the primary coil spring before the frame rests on the axle "
                                       "box's rubber stop; typical 20-40 mm (the static deflection is 43 mm)")
    primary_stop_stiffness: float = _p(5.0e6, "N/m", "model", "A",
                                       "vertical stiffness of the primary rubber stop, per axle box")

    def _scaled(self, mass, source):
        inertia, source_mass = source
        return mass * inertia / source_mass

    car_body_roll_inertia = property(lambda self: self._scaled(self.car_body_mass, self.car_body_roll_inertia_source))
    car_body_pitch_inertia = property(lambda self: self._scaled(self.car_body_mass,
                                                                self.car_body_pitch_inertia_source))
    car_body_yaw_inertia = property(lambda self: self._scaled(self.car_body_mass, self.car_body_yaw_inertia_source))
    bogie_frame_roll_inertia = property(lambda self: self._scaled(self.bogie_frame_mass,
                                                                  self.bogie_frame_roll_inertia_source))
    bogie_frame_pitch_inertia = property(lambda self: self._scaled(self.bogie_frame_mass,
                                                                   self.bogie_frame_pitch_inertia_source))
    bogie_frame_yaw_inertia = property(lambda self: self._scaled(self.bogie_frame_mass,
                                                                 self.bogie_frame_yaw_inertia_source))
    wheelset_roll_inertia = property(lambda self: self._scaled(self.wheelset_mass, self.wheelset_roll_inertia_source))
    wheelset_yaw_inertia = property(lambda self: self._scaled(self.wheelset_mass, self.wheelset_yaw_inertia_source))
    wheelset_spin_inertia = property(lambda self: self._scaled(self.wheelset_mass, self.wheelset_spin_inertia_source))

    @property
    def static_wheel_load(self):
        """Static vertical load of one wheel on level track (N): a quarter of the car body, half a bogie
        frame and the wheelset, shared by its two wheels."""
        return (0.25 * self.car_body_mass + 0.5 * self.bogie_frame_mass + self.wheelset_mass) * GRAVITY / 2.0

    def describe(self):
        """Rows (name, value, unit, source, sure, note) for reports."""
        rows = []
        for f in fields(self):
            if f.name == "name":
                continue
            m = f.metadata
            # a named set's own values carry that set's source, not the default's
            source, sure, note = SET_SOURCES.get(self.name, {}).get(f.name, (m["source"], m["sure"], m["note"]))
            rows.append((f.name, getattr(self, f.name), m["unit"], source, sure, note))
            if f.name.endswith("_inertia_source"):
                name = f.name[:-len("_source")]
                rows.append((name, getattr(self, name), "kg m^2", source, sure,
                             f"{name}_source scaled to this mass"))
        return rows


_A380_OVERRIDES = dict(
    name="a380",
    car_body_roll_inertia_source=(110200.0, 40840.0),
    car_body_pitch_inertia_source=(1666000.0, 40840.0),
    car_body_yaw_inertia_source=(1572200.0, 40840.0),
    bogie_frame_roll_inertia_source=(1847.0, 2280.0),
    bogie_frame_pitch_inertia_source=(1249.0, 2280.0),
    bogie_frame_yaw_inertia_source=(2280.0, 2280.0),
    wheelset_roll_inertia_source=(685.0, 1902.0),
    wheelset_yaw_inertia_source=(685.0, 1902.0),
    bogie_frame_cog_height=0.46 + (0.51 - 0.43),
    primary_semi_spacing=1.0,
    air_spring_semi_spacing=1.23,
    yaw_damper_semi_spacing=1.35,
    # swing-arm guidance: coil spring shear and arm rubber node act in parallel
    primary_longitudinal_stiffness=0.98e6 + 13.72e6,
    primary_lateral_stiffness=0.98e6 + 5.52e6,
    primary_vertical_stiffness=1.176e6,
    primary_vertical_damping=19.6e3,
    primary_lateral_damping=0.0,
    secondary_longitudinal_stiffness=0.1689e6,
    secondary_lateral_stiffness=0.1689e6,
    secondary_vertical_stiffness=0.26e6,
    secondary_vertical_damping=40.0e3,
    lateral_damper_knee_velocity=0.1,
    lateral_damper_damping=58.8e3,
    lateral_damper_damping_after_knee=24.6e3,
    lateral_damper_series_stiffness=17.15e6,
    yaw_damper_knee_velocity=0.004,
    yaw_damper_damping=2452.5e3,
    yaw_damper_damping_after_knee=49.95e3,
    yaw_damper_series_stiffness=8.82e6,
)

_ZHAI_OVERRIDES = dict(
    name="zhai",
    car_body_roll_inertia_source=(7.506e4, 34000.0),
    car_body_pitch_inertia_source=(2.277e6, 34000.0),
    car_body_yaw_inertia_source=(2.086e6, 34000.0),
    bogie_frame_roll_inertia_source=(2260.0, 3000.0),
    bogie_frame_pitch_inertia_source=(2710.0, 3000.0),
    bogie_frame_yaw_inertia_source=(3160.0, 3000.0),
    wheelset_roll_inertia_source=(915.0, 1400.0),
    wheelset_yaw_inertia_source=(915.0, 1400.0),
    wheelset_spin_inertia_source=(140.0, 1400.0),
    primary_longitudinal_stiffness=10.0e6,
    primary_lateral_stiffness=5.0e6,
    primary_vertical_stiffness=0.55e6,
    primary_vertical_damping=6.0e3,
    primary_lateral_damping=0.0,
    secondary_longitudinal_stiffness=0.15e6,
    secondary_lateral_stiffness=0.15e6,
    secondary_vertical_stiffness=0.4e6,
    secondary_vertical_damping=80.0e3,
    lateral_damper_knee_velocity=1.0,
    lateral_damper_damping=60.0e3,
    lateral_damper_damping_after_knee=60.0e3,
    lateral_damper_series_stiffness=0.0,
    # force-velocity points 13.2 kN @ 0.01, 20.5 kN @ 0.03, 25.75 kN @ 0.2 m/s: two-stage fit through
    # the first two points' secant (knee at 0.01 m/s), then the secant to 0.2 m/s
    yaw_damper_knee_velocity=0.01,
    yaw_damper_damping=1320.0e3,
    yaw_damper_damping_after_knee=(25.75e3 - 13.2e3) / 0.19,
    yaw_damper_series_stiffness=4.0e6,
    yaw_damper_semi_spacing=1.3,
)

# HS19 throughout but its yaw dampers, which take the CRH380A file's law whole (one source per subsystem): HS19's
# blow-off at 3 kN is a third or less of the other two public high-speed laws' (A380 9.8 kN, Zhai 13.2 kN), and
# the yaw damper alone moves the nonlinear critical speed most of all inputs (docs/report/stability.md)
_HS19_A380YAW_OVERRIDES = dict(
    name="hs19-a380yaw",
    yaw_damper_knee_velocity=0.004,
    yaw_damper_damping=2452.5e3,
    yaw_damper_damping_after_knee=49.95e3,
    yaw_damper_series_stiffness=8.82e6,
)

_SET_OVERRIDES = {"a380": _A380_OVERRIDES, "zhai": _ZHAI_OVERRIDES, "hs19-a380yaw": _HS19_A380YAW_OVERRIDES}
_A380_YAW_NOTE = "the CRH380A file's yaw damper, one per bogie side as in that file (the CRH3's count is not known)"
SET_SOURCES = {     # set: {field: (source, sure, note)} of the values a set changes
    "a380": {k: ("A380", "S", "") for k in _A380_OVERRIDES if k != "name"},
    "zhai": {k: ("Zhai", "S", "") for k in _ZHAI_OVERRIDES if k != "name"},
    "hs19-a380yaw": {
        "yaw_damper_knee_velocity": ("A380", "S", "blow-off 9.81 kN at 0.004 m/s; " + _A380_YAW_NOTE),
        "yaw_damper_damping": ("A380", "S", _A380_YAW_NOTE),
        "yaw_damper_damping_after_knee": ("A380", "S", _A380_YAW_NOTE),
        "yaw_damper_series_stiffness": ("A380", "S", _A380_YAW_NOTE),
    },
}

VEHICLE_SETS = ("hs19", "a380", "zhai", "hs19-a380yaw")


def vehicle_parameters(name="hs19", **changes):
    """The named parameter set, with optional field changes (for sensitivity studies)."""
    if name not in VEHICLE_SETS:
        raise ValueError(f"vehicle parameter set {name!r} is unknown; choose one of {', '.join(VEHICLE_SETS)}")
    base = VehicleParameters()
    if name in _SET_OVERRIDES:
        base = replace(base, **_SET_OVERRIDES[name])
    unknown = set(changes) - {f.name for f in fields(VehicleParameters)}
    if unknown:
        raise ValueError(f"unknown vehicle parameter(s): {', '.join(sorted(unknown))}")
    return replace(base, **changes)


@dataclass(frozen=True)
class TrackParameters:
    """Ideal track (Yu 2022 Table 2) and the rail placement."""
    straight_in: float = _p(200.0, "m", "Yu2022", "V")
    transition_in: float = _p(200.0, "m", "Yu2022", "V")
    curve_length: float = _p(1000.0, "m", "Yu2022", "V")
    transition_out: float = _p(200.0, "m", "Yu2022", "V")
    straight_out: float = _p(200.0, "m", "Yu2022", "V")
    radius: float = _p(1000.0, "m", "Yu2022", "V", "800-1800 m in the paper")
    cant_height: float = _p(0.175, "m", "Yu2022", "V")
    direction: int = _p(1, "-", "model", "A", "+1 curve to the left, -1 to the right")
    rail_spacing: float = _p(1.500, "m", "EN13803", "V", "distance between rail centres for the cant angle")
    gauge: float = _p(1.435, "m", "EN13674", "V")
    gauge_depth: float = _p(0.014, "m", "EN13674", "V", "gauge measured 14 mm below the rail top")
    rail_inclination: float = _p(math.atan(1.0 / 40.0), "rad", "EN13674", "V", "1:40")
    rail_profile: str = _p("uic60", "-", "Yu2022", "V")

    @property
    def line_length(self):
        """Length of the line from s = 0 to the end of the last straight (m)."""
        return self.straight_in + self.transition_in + self.curve_length + self.transition_out + self.straight_out

    def with_line_length(self, line_length):
        """This track with its circular curve made longer so that the whole line is `line_length` (m) long
        (on straight track the same: the middle part is straight); at least the line it is."""
        check_range("line length", line_length, self.line_length, 1.0e6, "m")
        return replace(self, curve_length=self.curve_length + line_length - self.line_length)

    @property
    def cant_angle(self):
        """Angle of the canted track plane on the circular curve (rad, magnitude)."""
        return math.asin(self.cant_height / self.rail_spacing)

    def uncompensated_acceleration(self, speed):
        """Uncompensated lateral acceleration in the track plane on the circular curve (m/s^2, + toward
        the outside) at speed (m/s): v^2/R cos(theta) - g sin(theta), as the core's output row has it."""
        if math.isinf(self.radius):
            return -GRAVITY * math.sin(self.cant_angle)
        theta = self.cant_angle
        return speed * speed / self.radius * math.cos(theta) - GRAVITY * math.sin(theta)

    def speed_at_uncompensated_acceleration(self, acceleration):
        """Speed (m/s) on the circular curve at which the uncompensated lateral acceleration is
        `acceleration` (m/s^2); 0 for the balance speed."""
        theta = self.cant_angle
        return math.sqrt(self.radius * (acceleration + GRAVITY * math.sin(theta)) / math.cos(theta))

    def radius_at_uncompensated_acceleration(self, speed, acceleration):
        """Radius (m) of the circular curve on this cant at which `speed` (m/s) gives the uncompensated
        lateral acceleration `acceleration` (m/s^2): the inverse of `uncompensated_acceleration`."""
        theta = self.cant_angle
        return speed * speed * math.cos(theta) / (acceleration + GRAVITY * math.sin(theta))

    def speed_at_cant_deficiency(self, deficiency):
        """Speed (m/s) on the circular curve at a cant deficiency (m): the uncompensated acceleration
        g D / e of the deficiency D on the rail spacing e (EN 13803); 0 gives the balance speed."""
        return self.speed_at_uncompensated_acceleration(GRAVITY * deficiency / self.rail_spacing)


@dataclass(frozen=True)
class ContactParameters:
    """Wheel profile, wheelset placement, materials, friction and the contact models."""
    wheel_profile: str = _p("lm", "-", "Yu2022", "V")
    back_to_back: float = _p(1.353, "m", "TB449", "S")
    rolling_circle_from_back: float = _p(0.070, "m", "TB449", "S")
    youngs_modulus: float = _p(2.1e11, "Pa", "Johnson", "V", "steel, wheel and rail")
    poisson_ratio: float = _p(0.28, "-", "Johnson", "V")
    friction_coefficient: float = _p(0.3, "-", "Iwnicki", "S", "dry rail")
    contact_damping: float = _p(2.0, "s/m", "HuntCrossley", "A",
                                "N = C d^1.5 (1 + chi d'); chi gives about 5 % damping of the wheelset "
                                "bounce on the rigid track, standing in for the dissipation of the track")
    derailment_coefficient_min_load: float = _p(0.1, "-", "model", "A",
                                                "Q/P is evaluated only above this fraction of the static "
                                                "wheel load; an unloaded wheel's ratio is meaningless")
    normal_model: str = _p("hertz", "-", "model", "A", "hertz | discrete")
    creep_model: str = _p("she", "-", "model", "A", "she (Shen-Hedrick-Elkins) | polach | fastsim | linear")
    contact_geometry: str = _p("table", "-", "model", "A",
                               "table (precomputed over lateral shift and roll, online search outside it; "
                               "contact.table) | online (the exact search at every evaluation)")

    @property
    def rolling_circle_half_distance(self):
        """Lateral distance from the wheelset centre to each nominal rolling circle (m)."""
        return 0.5 * self.back_to_back + self.rolling_circle_from_back

    @property
    def shear_modulus(self):
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))


GRAVITY = 9.81  # m/s^2, standard value used throughout
# EN 14067-6 (SOURCES["EN14067"], S): the wheel unloading dQ/Q0 of the most unloaded running gear at which a
# characteristic wind speed is read, and the monitor's default level of the same criterion
RUNNING_GEAR_UNLOADING_LIMIT = 0.90
# Hz; the low-pass of dQ/Q0 before its peak is read: the standard's filter as quoted second hand, not read in
# the standard (A)
RUNNING_GEAR_UNLOADING_FILTER_HZ = 2.0
KMH = 1.0 / 3.6                 # m/s per km/h
RADIUS_RANGE = (150.0, 20000.0)  # accepted curve radii (m)
SPEED_RANGE_KMH = (30.0, 800.0)  # accepted speeds (km/h): the creepage normalisation and tolerances are set for this range
FRICTION_RANGE = (0.0, 1.0)     # accepted wheel-rail friction coefficients, (0, 1]
CANT_RANGE_MM = (0.0, 200.0)    # accepted cant heights (mm); EN 13803 allows up to 180 mm (200 mm on ballastless track)


TRACK_MODELS = ("rigid", "elastic")


@dataclass(frozen=True)
class ElasticTrackParameters:
    """The elastic track (`track.elastic`): one co-running rail per wheel, reduced from the rail and the
    rail seats of a ballasted high-speed track (docs/elastic-track.md). The fields are the published
    values of the rail and of one rail seat; the co-running rail's mass, stiffness and damping under a
    wheel (`vertical`, `lateral`, `roll`) are their Winkler-beam reduction (source "Winkler", A)."""
    rail_mass: float = _p(60.64, "kg/m", "ACE2021", "V", "60 kg/m rail (CHN60; 60E1 60.2 kg/m)")
    rail_density: float = _p(7850.0, "kg/m^3", "Johnson", "V", "steel")
    youngs_modulus: float = _p(2.059e11, "Pa", "Zhai2004", "S")
    vertical_second_moment: float = _p(3.217e-5, "m^4", "ACE2021", "V", "bending in the vertical plane")
    lateral_second_moment: float = _p(5.24e-6, "m^4", "ACE2021", "V", "bending in the track plane")
    polar_second_moment: float = _p(3.741e-5, "m^4", "ACE2021", "V", "gives the rail's roll inertia per metre")
    torsional_rigidity: float = _p(1.9587e5, "N m^2", "SV2019", "V", "GK of the CHN60 rail")
    sleeper_spacing: float = _p(0.60, "m", "Zhai2004", "S")
    half_sleeper_mass: float = _p(125.5, "kg", "Zhai2004", "S", "between the pad and the ballast")
    ballast_mass: float = _p(531.4, "kg", "Zhai2004", "S", "per rail seat, between the ballast and the subgrade")
    pad_vertical_stiffness: float = _p(6.5e7, "N/m", "Zhai2004", "S", "per rail seat")
    pad_vertical_damping: float = _p(7.5e4, "N s/m", "Zhai2004", "S")
    ballast_vertical_stiffness: float = _p(1.3775e8, "N/m", "Zhai2004", "S", "per rail seat")
    ballast_vertical_damping: float = _p(5.88e4, "N s/m", "Zhai2004", "S")
    subgrade_vertical_stiffness: float = _p(7.75e7, "N/m", "Zhai2004", "S", "per rail seat")
    subgrade_vertical_damping: float = _p(3.115e4, "N s/m", "Zhai2004", "S")
    pad_lateral_stiffness: float = _p(3.0e7, "N/m", "ZhaiBook", "S", "fastening, per rail seat")
    pad_lateral_damping: float = _p(5.0e4, "N s/m", "ZhaiBook", "S")
    sleeper_lateral_stiffness: float = _p(5.0e7, "N/m", "ZhaiBook", "S", "sleeper in the ballast, per sleeper "
                                                                             "(half of it under each rail)")
    sleeper_lateral_damping: float = _p(4.0e4, "N s/m", "ZhaiBook", "S", "per sleeper")
    pad_half_width: float = _p(0.075, "m", "ZhaiBook", "S", "half the distance of the pad's vertical reactions")
    lateral_reaction_arm: float = _p(0.082, "m", "ZhaiBook", "S", "the pad's lateral reaction below the roll centre")
    roll_centre_depth: float = _p(0.0945, "m", "ZhaiBook", "S", "the rail's torsion centre below the rail top")
    roll_inertia_scale: float = _p(10.0, "-", "model", "A",
                                   "numerical mass scaling of the rail's roll inertia: its roll mode, overdamped "
                                   "by the creep forces, would need steps below 0.3 ms (docs/elastic-track.md "
                                   "shows the results unchanged)")

    def _series(self, *layers):
        """(stiffness, damping) of spring-damper layers (k_i, c_i) in series: 1/k = sum 1/k_i, and each
        damper dissipating at its spring's share of the deflection, c = k^2 sum c_i / k_i^2."""
        k = 1.0 / sum(1.0 / ki for ki, _ in layers)
        return k, k * k * sum(c / (ki * ki) for ki, c in layers)

    def _co_running(self, seat, mass_per_metre, second_moment):
        """(mass, stiffness, damping) under a wheel of a rail on seats (k, c) every sleeper_spacing: the
        point stiffness 2k'/beta of the Winkler beam (k' = k / spacing, beta = (k' / 4EI)^(1/4)); the mass
        and the damping of the static deflection shape, whose square integrates to 3/(2 beta)."""
        k, c = seat[0] / self.sleeper_spacing, seat[1] / self.sleeper_spacing
        beta = (k / (4.0 * self.youngs_modulus * second_moment)) ** 0.25
        return 1.5 * mass_per_metre / beta, 2.0 * k / beta, 1.5 * c / beta

    @property
    def vertical(self):
        """(mass kg, stiffness N/m, damping N s/m) of the co-running rail vertically: the rail, and the
        sleeper and the ballast at the square of their share of the rail's deflection."""
        pad = (self.pad_vertical_stiffness, self.pad_vertical_damping)
        ballast = (self.ballast_vertical_stiffness, self.ballast_vertical_damping)
        subgrade = (self.subgrade_vertical_stiffness, self.subgrade_vertical_damping)
        seat = self._series(pad, ballast, subgrade)
        sleeper_share = seat[0] / self._series(ballast, subgrade)[0]
        ballast_share = seat[0] / subgrade[0]
        mass = self.rail_mass + (sleeper_share ** 2 * self.half_sleeper_mass
                                 + ballast_share ** 2 * self.ballast_mass) / self.sleeper_spacing
        return self._co_running(seat, mass, self.vertical_second_moment)

    @property
    def lateral(self):
        """(mass, stiffness, damping) laterally: the fastening in series with half the sleeper's lateral
        support; the rail, and the half sleeper at the square of its share."""
        pad = (self.pad_lateral_stiffness, self.pad_lateral_damping)
        sleeper = (0.5 * self.sleeper_lateral_stiffness, 0.5 * self.sleeper_lateral_damping)
        seat = self._series(pad, sleeper)
        mass = self.rail_mass + (seat[0] / sleeper[0]) ** 2 * self.half_sleeper_mass / self.sleeper_spacing
        return self._co_running(seat, mass, self.lateral_second_moment)

    @property
    def roll(self):
        """(inertia kg m^2, stiffness N m/rad, damping N m s/rad) in roll about the torsion centre: the
        seat's restraint (its vertical pad reactions at +-pad_half_width, its lateral one at the arm below
        the centre) on the rail's torsion (decay rate lambda = sqrt(k' / GK)): point stiffness 2 GK lambda,
        inertia and damping of the shape exp(-lambda |x|), 1/lambda times their per-metre values (the inertia
        times roll_inertia_scale)."""
        b2, a2 = self.pad_half_width ** 2, self.lateral_reaction_arm ** 2
        k = (self.pad_vertical_stiffness * b2 + self.pad_lateral_stiffness * a2) / self.sleeper_spacing
        c = (self.pad_vertical_damping * b2 + self.pad_lateral_damping * a2) / self.sleeper_spacing
        lam = math.sqrt(k / self.torsional_rigidity)
        inertia = self.roll_inertia_scale * self.rail_density * self.polar_second_moment / lam
        return inertia, 2.0 * self.torsional_rigidity * lam, c / lam

    def describe(self):
        """Rows (name, value, unit, source, sure, note) for reports, with the co-running values."""
        rows = parameter_rows(self)
        for name, units in (("vertical", ("kg", "N/m", "N s/m")), ("lateral", ("kg", "N/m", "N s/m")),
                            ("roll", ("kg m^2", "N m/rad", "N m s/rad"))):
            what = ("inertia" if name == "roll" else "mass", "stiffness", "damping")
            for w, value, unit in zip(what, getattr(self, name), units):
                rows.append((f"co_running_{name}_{w}", value, unit, "Winkler", "A", "per wheel, derived"))
        return rows


@dataclass(frozen=True)
class AerodynamicParameters:
    """The car body's aerodynamics (`loads.aerodynamics`) and the wind's gust (`loads.wind`).

    No table of the ICE 3 / Velaro leading car's coefficients against yaw angle was found in a public
    source (../shared/reference/track-and-loads.md; EN 14067-6 gives the reference train's coefficients to
    its purchasers only). The coefficients are therefore a stand-in built from the car's size by the
    cross-flow and slender-body model (Hoerner): side force C_Fy = (c_c S sin^2 beta + F sin 2 beta cos(beta/2)) / A
    with S the side area, F the frontal area and c_c the cross-flow drag coefficient; the cross-flow part
    acts at the side area's centroid (centre_of_pressure_height above the rail, no yawing arm), the
    slender-body part at the nose (nose_arm ahead of the car-body centre); lift C_Fz = c_l P sin^2 beta / A with
    P the plan area. docs/loads.md gives the table and the sensitivity of the results to it."""
    air_density: float = _p(1.225, "kg/m^3", "EN14067", "V", "standard atmosphere at sea level, 15 C")
    reference_area: float = _p(10.0, "m^2", "EN14067", "S")
    reference_length: float = _p(3.0, "m", "EN14067", "S")
    side_area: float = _p(82.0, "m^2", "ICE3", "A", "25.7 m x 3.6 m (body above 0.3 m clearance) less the nose's taper")
    frontal_area: float = _p(10.9, "m^2", "ICE3", "A", "2.95 m x 3.89 m less the rounded corners")
    plan_area: float = _p(70.0, "m^2", "ICE3", "A", "25.7 m x 2.95 m less the nose's taper")
    cross_flow_drag: float = _p(0.55, "-", "Hoerner", "A", "rounded box on the ground, flow across it")
    cross_flow_lift: float = _p(0.35, "-", "Hoerner", "A", "the same, lift from the flow over the roof")
    centre_of_pressure_height: float = _p(2.05, "m", "ICE3", "A", "middle of the side area above the rail")
    nose_arm: float = _p(10.0, "m", "ICE3", "A", "the nose's normal force ahead of the car-body centre")
    gust_peak_factor: float = _p(2.84, "-", "CENgust", "A", "not read in the standard")
    gust_turbulence_intensity: float = _p(0.10, "-", "CENgust", "A", "open flat ground; not read in the standard")
    gust_length_scale: float = _p(50.0, "m", "CENgust", "A",
                                  "the hat's exponential decay length along the track; not read in the standard")
    gust_ramp: float = _p(300.0, "m", "model", "A",
                          "the mean wind rises from still air over this length before the gust's hat (the car "
                          "meets the gust settled; the standard starts from the mean wind)")
    yaw_angle_step_deg: float = _p(5.0, "deg", "model", "A", "step of the coefficient table over 0-90 deg; "
                                   "a divisor of 90")

    def validated(self):
        """self if every value is positive (the step a divisor of 90 deg), else ValueError naming it."""
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in ("centre_of_pressure_height", "nose_arm", "cross_flow_lift", "gust_turbulence_intensity"):
                check_range(f.name, value, 0.0, 1.0e3, f.metadata["unit"])
            else:
                check_range(f.name, value, 0.0, 1.0e4, f.metadata["unit"], lo_open=True)
        steps = 90.0 / self.yaw_angle_step_deg
        if abs(steps - round(steps)) > 1e-9:
            raise ValueError(f"yaw_angle_step_deg {self.yaw_angle_step_deg:g} deg does not divide 90 deg")
        return self

    def coefficients(self):
        """The coefficient table: rows (beta rad, C_Fy, C_Fz, C_Mx, C_My, C_Mz) over 0-90 deg, the moments
        about the reference point (the track centre line at rail level below the car-body centre)."""
        rows = []
        n = int(round(90.0 / self.yaw_angle_step_deg))
        for k in range(n + 1):
            beta = math.radians(90.0 * k / n)
            cross = self.cross_flow_drag * self.side_area * math.sin(beta) ** 2 / self.reference_area
            nose = self.frontal_area * math.sin(2.0 * beta) * math.cos(0.5 * beta) / self.reference_area
            lift = self.cross_flow_lift * self.plan_area * math.sin(beta) ** 2 / self.reference_area
            side = cross + nose
            d = self.reference_length
            rows.append((beta, side, lift, side * self.centre_of_pressure_height / d, 0.0, nose * self.nose_arm / d))
        return rows

    def describe(self):
        """Rows (name, value, unit, source, sure, note) for reports."""
        return parameter_rows(self)
