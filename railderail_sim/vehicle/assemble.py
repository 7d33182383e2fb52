"""Build the numba core's arrays (bodies, force elements, contact, track, speed table) from parameters.

This is where the vehicle's topology lives: which body is attached to which, where, with what law.
Nominal attachment points are given in vehicle coordinates on straight level track (x forward from the
car-body centre, y left, z up from the rail top) and converted to each body's own coordinates.
"""
from dataclasses import dataclass, field
import functools
import math

import numpy as np

from .. import profiles
from ..contact import creep, geometry, table, wheelset
from ..parameters import GRAVITY, ContactParameters, TrackParameters, VehicleParameters
from ..ranges import check_range
from ..track import alignment
from . import layout as L

WHEEL_GRID_STEP = 1.25e-4      # m; with parabolic refinement the gap minimum is right to ~1 micrometre
CREEP_MODELS = {"linear": creep.LINEAR, "she": creep.SHEN_HEDRICK_ELKINS, "polach": creep.POLACH,
                "fastsim": creep.FASTSIM}
NORMAL_MODELS = {"hertz": wheelset.NORMAL_HERTZ, "discrete": wheelset.NORMAL_DISCRETE}
CONTACT_GEOMETRIES = ("table", "online")


@dataclass
class Model:
    """Everything the numba core needs, packed once per scenario."""
    bodies: np.ndarray
    vp: np.ndarray
    bush: np.ndarray
    damp: np.ndarray
    bump: np.ndarray
    arb: np.ndarray
    track: np.ndarray
    cg: np.ndarray
    cp: np.ndarray
    vehicle: VehicleParameters
    track_parameters: TrackParameters
    contact: ContactParameters
    static_wheel_load: float = 0.0
    extra: dict = field(default_factory=dict)

    def core_args(self, speed_table):
        """Arguments of `dynamics.rhs` after (x, dx), in order, for a speed table."""
        return (self.bodies, self.vp, self.bush, self.damp, self.bump, self.arb, self.track,
                np.ascontiguousarray(speed_table, dtype=np.float64), self.cg, self.cp)


def body_table(vp: VehicleParameters):
    a = vp.bogie_semi_distance
    w = vp.wheelbase_semi
    rows = [
        (vp.car_body_mass, vp.car_body_roll_inertia, vp.car_body_pitch_inertia, vp.car_body_yaw_inertia,
         0.0, vp.car_body_cog_height, 0.0),
    ]
    for xb in (a, -a):
        rows.append((vp.bogie_frame_mass, vp.bogie_frame_roll_inertia, vp.bogie_frame_pitch_inertia,
                     vp.bogie_frame_yaw_inertia, xb, vp.bogie_frame_cog_height, 0.0))
    for xw in (a + w, a - w, -a + w, -a - w):
        rows.append((vp.wheelset_mass, vp.wheelset_roll_inertia, vp.wheelset_spin_inertia,
                     vp.wheelset_yaw_inertia, xw, vp.rolling_radius, 1.0))
    return np.array(rows, dtype=np.float64)


def _local(bodies, b, q):
    """Vehicle-coordinate point q in body b's coordinates (relative to its reference point)."""
    return (q[0] - bodies[b, L.B_STATION], q[1], q[2] - bodies[b, L.B_HEIGHT])


def element_tables(vp: VehicleParameters, bodies):
    """Bushings, two-point dampers, bump stops and anti-roll bars with their nominal preloads."""
    g = GRAVITY
    a = vp.bogie_semi_distance
    w = vp.wheelbase_semi
    bush, damp, bump, arb = [], [], [], []
    box_preload = (0.5 * vp.car_body_mass + vp.bogie_frame_mass) * g / 4.0
    air_preload = vp.car_body_mass * g / 4.0

    def add_bush(ba, bb, q, k, c, f0):
        bush.append((ba, bb, *_local(bodies, ba, q), *_local(bodies, bb, q), *k, *c, *f0))

    def add_damper(ba, bb, qa, qb, knee, c1, c2, ks, state):
        length = math.dist(qa, qb)
        damp.append((ba, bb, *_local(bodies, ba, qa), *_local(bodies, bb, qb), knee, c1, c2, ks, length,
                     L.I_DAMPER + state))

    state = 0
    for i, bogie in enumerate(L.BOGIES):
        xb = a if i == 0 else -a
        toward_centre = -1.0 if i == 0 else 1.0
        for j, wsx in enumerate((xb + w, xb - w)):
            wheelset_body = L.WHEELSETS[2 * i + j]
            for side in (1.0, -1.0):
                add_bush(bogie, wheelset_body, (wsx, side * vp.primary_semi_spacing, vp.rolling_radius),
                         (vp.primary_longitudinal_stiffness, vp.primary_lateral_stiffness,
                          vp.primary_vertical_stiffness),
                         (0.0, vp.primary_lateral_damping, vp.primary_vertical_damping),
                         (0.0, 0.0, -box_preload))
        for side in (1.0, -1.0):
            add_bush(bogie, L.CAR_BODY, (xb, side * vp.air_spring_semi_spacing, vp.secondary_height),
                     (vp.secondary_longitudinal_stiffness, vp.secondary_lateral_stiffness,
                      vp.secondary_vertical_stiffness), (0.0, 0.0, 0.0), (0.0, 0.0, air_preload))
            add_bush(bogie, L.CAR_BODY,
                     (xb, side * vp.secondary_vertical_damper_semi_spacing, vp.secondary_height),
                     (0.0, 0.0, 0.0), (0.0, 0.0, vp.secondary_vertical_damping), (0.0, 0.0, 0.0))
            qa = (xb, side * vp.yaw_damper_semi_spacing, vp.yaw_damper_height)
            qb = (xb + toward_centre * vp.yaw_damper_length, side * vp.yaw_damper_semi_spacing,
                  vp.yaw_damper_height)
            add_damper(bogie, L.CAR_BODY, qa, qb, vp.yaw_damper_knee_velocity, vp.yaw_damper_damping,
                       vp.yaw_damper_damping_after_knee, vp.yaw_damper_series_stiffness, state)
            state += 1
    for i, bogie in enumerate(L.BOGIES):
        xb = a if i == 0 else -a
        # the lateral damper as a mirrored pair of half dampers (brackets 0.5 m apart across the track),
        # so that the car is exactly mirror-symmetric; in parallel they act as the one damper of the set
        half = 0.25
        for side in (1.0, -1.0):
            add_damper(bogie, L.CAR_BODY, (xb, -side * half, vp.lateral_damper_height),
                       (xb, side * half, vp.lateral_damper_height), vp.lateral_damper_knee_velocity,
                       0.5 * vp.lateral_damper_damping, 0.5 * vp.lateral_damper_damping_after_knee,
                       0.5 * vp.lateral_damper_series_stiffness, state)
            state += 1
        q = (xb, 0.0, vp.bump_stop_height)
        bump.append((bogie, L.CAR_BODY, *_local(bodies, bogie, q), *_local(bodies, L.CAR_BODY, q)))
        arb.append((bogie, L.CAR_BODY, vp.anti_roll_stiffness))
    assert state == L.N_DAMPER
    return (np.array(bush, dtype=np.float64), np.array(damp, dtype=np.float64),
            np.array(bump, dtype=np.float64), np.array(arb, dtype=np.float64))


def contact_geometry(contact: ContactParameters, track: TrackParameters, rolling_radius):
    """Packed contact geometry, with the contact table appended if contact.contact_geometry is "table"."""
    if contact.contact_geometry not in CONTACT_GEOMETRIES:
        raise ValueError(f"contact geometry {contact.contact_geometry!r} is unknown; choose one of "
                         f"{', '.join(CONTACT_GEOMETRIES)}")
    wheel = profiles.resolve(contact.wheel_profile, "wheel")
    rail = profiles.resolve(track.rail_profile, "rail")
    wt = profiles.ProfileTable.from_profile(wheel, dy=WHEEL_GRID_STEP)
    rt = profiles.ProfileTable.from_profile(rail, dy=5.0e-5)
    cg = geometry.pack_contact_geometry(wt, rt, rolling_radius, contact.rolling_circle_half_distance,
                                        track.gauge, track.gauge_depth, track.rail_inclination)
    return _with_table(cg.tobytes()) if contact.contact_geometry == "table" else cg


@functools.lru_cache(maxsize=4)
def _with_table(packed):
    """The packed geometry (as bytes: the cache key is the geometry itself) with its contact table.

    Built once per process and geometry (about 1 s and 44 MB): the runs of a progressive trial or of a
    sweep's radius share one wheel, rail and wheelset, and building the table was half of a trial's time.
    The core never writes into the geometry, so the models share the array.
    """
    return table.attach(np.frombuffer(packed, dtype=np.float64))


def contact_array(contact: ContactParameters, static_wheel_load=0.0):
    """Contact parameter array; Q/P is evaluated above derailment_coefficient_min_load x static_wheel_load."""
    if contact.normal_model not in NORMAL_MODELS:
        raise ValueError(f"normal contact model {contact.normal_model!r} is unknown; choose one of "
                         f"{', '.join(NORMAL_MODELS)}")
    if contact.creep_model not in CREEP_MODELS:
        raise ValueError(f"creep model {contact.creep_model!r} is unknown; choose one of "
                         f"{', '.join(CREEP_MODELS)}")
    check_range("friction coefficient", contact.friction_coefficient, 0.0, 1.0, lo_open=True)
    E, nu = contact.youngs_modulus, contact.poisson_ratio
    cp = np.zeros(wheelset.C_SIZE)
    cp[wheelset.C_ESTAR] = E / (2.0 * (1.0 - nu * nu))
    cp[wheelset.C_ESTAR_CBRT] = cp[wheelset.C_ESTAR] ** (1.0 / 3.0)
    cp[wheelset.C_G] = contact.shear_modulus
    cp[wheelset.C_NU] = nu
    cp[wheelset.C_MU] = contact.friction_coefficient
    cp[wheelset.C_CHI] = contact.contact_damping
    cp[wheelset.C_NORMAL] = NORMAL_MODELS[contact.normal_model]
    cp[wheelset.C_CREEP] = CREEP_MODELS[contact.creep_model]
    cp[wheelset.C_QP_MIN_LOAD] = contact.derailment_coefficient_min_load * static_wheel_load
    return cp


def vehicle_array(vp: VehicleParameters, cg, lift_tolerance):
    v = np.zeros(L.V_SIZE)
    v[L.V_G] = GRAVITY
    v[L.V_R0] = vp.rolling_radius
    v[L.V_SPIN_INERTIA] = vp.wheelset_spin_inertia
    v[L.V_BUMP_CLEARANCE] = vp.bump_stop_clearance
    n = len(vp.bump_stop_travel)
    if n > 8 or len(vp.bump_stop_force) != n:
        raise ValueError("bump-stop law needs 1 to 8 (travel, force) points of equal count")
    v[L.V_BUMP_N] = n
    v[L.V_BUMP_TRAVEL:L.V_BUMP_TRAVEL + n] = vp.bump_stop_travel
    v[L.V_BUMP_FORCE:L.V_BUMP_FORCE + n] = vp.bump_stop_force
    v[L.V_FLANGE_HEIGHT] = cg[geometry.H_FLANGE_HEIGHT]
    # flange tip above the rail's highest point
    v[L.V_CLIMB_DISPLACEMENT] = cg[geometry.H_RAIL_TOP_Y] - (cg[geometry.H_LW] + cg[geometry.H_FLANGE_TIP_YP])
    v[L.V_LIFT_TOLERANCE] = lift_tolerance
    return v


def build_model(vehicle: VehicleParameters, track: TrackParameters, contact: ContactParameters,
                lift_tolerance=1.0e-3):
    """Pack a scenario's parameters into a Model."""
    bodies = body_table(vehicle)
    bush, damp, bump, arb = element_tables(vehicle, bodies)
    cg = contact_geometry(contact, track, vehicle.rolling_radius)
    trk = alignment.pack_track(track.straight_in, track.transition_in, track.curve_length,
                               track.transition_out, track.straight_out, track.radius, track.cant_height,
                               track.direction, track.rail_spacing,
                               (track.excitation_start, track.excitation_length, track.excitation_amplitude))
    static = vehicle.static_wheel_load
    return Model(bodies=bodies, vp=vehicle_array(vehicle, cg, lift_tolerance), bush=bush, damp=damp,
                 bump=bump, arb=arb, track=trk, cg=cg, cp=contact_array(contact, static), vehicle=vehicle,
                 track_parameters=track, contact=contact, static_wheel_load=static)
