"""Build the numba core's arrays (bodies, force elements, contact, track, speed table) from parameters.

This is where the vehicle's topology lives: which body is attached to which, where, with what law.
Nominal attachment points are given in vehicle coordinates on straight level track (x forward from the
car-body centre, y left, z up from the rail top) and converted to each body's own coordinates.
"""
from dataclasses import dataclass, replace
import functools
import math

import numpy as np

from .. import profiles, scalarmath
from ..contact import creep, geometry, table, wheelset
from ..contact.hertz import combined_modulus, hertz_shape
from ..contact.layout import ContactConstants, GeometryHeader, Patch
from ..parameters import (FRICTION_RANGE, GRAVITY, TRACK_MODELS, ContactParameters, ElasticTrackParameters,
                          TrackParameters, VehicleParameters)
from ..ranges import check_range
from ..loads.wind import still_air
from ..track import alignment, rails
from ..track.layout import ElasticTrack
from .dynamics import ModelArrays
from .layout import (BOGIES, BUMP_POINTS, CAR_BODY, LATERAL, N_DAMPER, N_WHEELSET, VERTICAL, WHEELSETS,
                     AntiRollBar, BodyTable, BumpStop, Bushing, Damper, State, VehicleConstants)

WHEEL_GRID_STEP = 1.25e-4      # m; with parabolic refinement the gap minimum is right to ~1 micrometre
CREEP_MODELS = {"linear": creep.LINEAR, "she": creep.SHEN_HEDRICK_ELKINS, "polach": creep.POLACH,
                "fastsim": creep.FASTSIM}
NORMAL_MODELS = {"hertz": wheelset.NORMAL_HERTZ, "discrete": wheelset.NORMAL_DISCRETE}
CONTACT_GEOMETRIES = ("table", "online")
LINEAR_LAW_SPAN = 0.010        # m; a linear stop's one law point lies this far beyond its clearance

# Suspension faults, "NAME@LOCATION": each location names the elements it takes out, as (unit, side) pairs:
# the unit a bogie (0 front, 1 rear) or, for a primary spring, a wheelset (0-3 from the front); the side
# "left" or "right" (the lateral damper's mirrored halves count as its two sides). What each fault changes:
# `element_tables` and docs/vehicle-model.md ("Suspension limits and faults").
SIDES = {1.0: "left", -1.0: "right"}       # the side's sign of y (left positive)
_BOGIE_UNITS = {"front": (0,), "rear": (1,), "both": (0, 1)}


def _both_sides(units):
    return frozenset((unit, side) for unit in units for side in SIDES.values())


def _air_spring_locations():
    """front-left, front-right, front, rear-left, rear-right, rear."""
    locations = {}
    for bogie in ("front", "rear"):
        (unit,) = _BOGIE_UNITS[bogie]
        locations.update({f"{bogie}-{side}": frozenset({(unit, side)}) for side in SIDES.values()})
        locations[bogie] = _both_sides((unit,))
    return locations


FAULTS = {
    "yaw-dampers-failed": {location: _both_sides(units) for location, units in _BOGIE_UNITS.items()},
    "lateral-damper-failed": {location: _both_sides(units) for location, units in _BOGIE_UNITS.items()},
    "air-spring-deflated": _air_spring_locations(),
    "primary-spring-broken": {f"{w}-{side}": frozenset({(w, side)}) for w in range(N_WHEELSET)
                              for side in SIDES.values()},
}
FAULT_NAMES = tuple(f"{name}@{location}" for name, locations in FAULTS.items() for location in locations)


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
    rails: np.ndarray
    support: np.ndarray
    aero: np.ndarray
    cg: np.ndarray
    cp: np.ndarray
    vehicle: VehicleParameters
    track_parameters: TrackParameters
    contact: ContactParameters

    @property
    def arrays(self):
        """The arrays of the core, as `dynamics.rhs` and `integrator.advance` take them."""
        return ModelArrays(bodies=self.bodies, vp=self.vp, bush=self.bush, damp=self.damp, bump=self.bump,
                           arb=self.arb, track=self.track, rails=self.rails, support=self.support, aero=self.aero,
                           cg=self.cg,
                           cp=self.cp)

    @property
    def track_model(self):
        """"rigid" or "elastic", as the support array says."""
        return "elastic" if self.support[ElasticTrack.elastic] > 0.5 else "rigid"

    @property
    def static_wheel_load(self):
        """Static vertical load of one wheel (N), `VehicleParameters.static_wheel_load`."""
        return self.vehicle.static_wheel_load

    @property
    def flange_height(self):
        """Flange height of the wheel above its nominal rolling circle (m)."""
        return float(self.vp[VehicleConstants.flange_height])

    @property
    def flange_contact_angle(self):
        """Contact angle above which a contact is on the flange (rad)."""
        return float(self.vp[VehicleConstants.flange_contact_angle])


def body_table(vp: VehicleParameters):
    """Rows of the body table (layout.BodyTable), in the order of layout.Body."""
    a = vp.bogie_semi_distance
    w = vp.wheelbase_semi
    rows = [BodyTable.pack(mass=vp.car_body_mass, roll_inertia=vp.car_body_roll_inertia,
                           pitch_inertia=vp.car_body_pitch_inertia, yaw_inertia=vp.car_body_yaw_inertia,
                           station=0.0, height=vp.car_body_cog_height)]
    for xb in (a, -a):
        rows.append(BodyTable.pack(mass=vp.bogie_frame_mass, roll_inertia=vp.bogie_frame_roll_inertia,
                                   pitch_inertia=vp.bogie_frame_pitch_inertia, yaw_inertia=vp.bogie_frame_yaw_inertia,
                                   station=xb, height=vp.bogie_frame_cog_height))
    for xw in (a + w, a - w, -a + w, -a - w):
        rows.append(BodyTable.pack(mass=vp.wheelset_mass, roll_inertia=vp.wheelset_roll_inertia,
                                   pitch_inertia=vp.wheelset_spin_inertia, yaw_inertia=vp.wheelset_yaw_inertia,
                                   station=xw, height=vp.rolling_radius, is_wheelset=1.0))
    return np.array(rows)


def local_point(bodies, b, q):
    """Vehicle-coordinate point q in body b's coordinates (relative to its reference point)."""
    return (q[0] - bodies[b, BodyTable.station], q[1], q[2] - bodies[b, BodyTable.height])


def failed_elements(faults):
    """The elements the faults (a sequence of FAULT_NAMES) take out, as a set of (fault name, unit, side)
    (FAULTS); a ValueError names an unknown fault or location and lists the accepted ones."""
    if isinstance(faults, str):
        raise ValueError(f"faults {faults!r} must be a sequence of fault names, not one string")
    repeated = sorted({str(f) for f in faults if list(faults).count(f) > 1})
    if repeated:
        raise ValueError(f"fault(s) {', '.join(repeated)} given more than once")
    failed = set()
    for fault in faults:
        name, _, location = str(fault).partition("@")
        if name not in FAULTS:
            raise ValueError(f"fault {fault!r} is unknown; the faults are NAME@LOCATION with NAME one of "
                             f"{', '.join(FAULTS)}")
        if location not in FAULTS[name]:
            raise ValueError(f"fault {fault!r}: location {location!r} is not one of {', '.join(FAULTS[name])}")
        failed.update((name, unit, side) for unit, side in FAULTS[name][location])
    return frozenset(failed)


def linear_law(clearance, stiffness):
    """The (travel, force) points of a bump stop of constant stiffness (N/m) beyond its clearance (m)."""
    return (clearance + LINEAR_LAW_SPAN,), (stiffness * LINEAR_LAW_SPAN,)


@dataclass(frozen=True)
class AirSpring:
    """One air spring: between bogie frame `bogie` (a layout.Body index) and the car body, at `point`
    (vehicle coordinates, the middle of the spring); its vertical stiffness and preload (both zero when
    deflated by a fault) give the bellows' force preload - stiffness * (the car body's point's rise over the
    frame's, in the frame's axes)."""
    name: str                   # air_spring_<front|rear>_<left|right>
    bogie: int
    point: tuple
    vertical_stiffness: float   # N/m
    preload: float              # N


def air_springs(vp: VehicleParameters, faults=()):
    """The four air springs, front left, front right, rear left, rear right, less what the faults take out."""
    failed = failed_elements(faults)
    springs = []
    for i, bogie in enumerate(BOGIES):
        xb = vp.bogie_semi_distance if i == 0 else -vp.bogie_semi_distance
        for side in (1.0, -1.0):
            deflated = ("air-spring-deflated", i, SIDES[side]) in failed
            springs.append(AirSpring(name=f"air_spring_{('front', 'rear')[i]}_{SIDES[side]}", bogie=bogie,
                                     point=(xb, side * vp.air_spring_semi_spacing, vp.secondary_height),
                                     vertical_stiffness=0.0 if deflated else vp.secondary_vertical_stiffness,
                                     preload=0.0 if deflated else vp.car_body_mass * GRAVITY / 4.0))
    return springs


def element_tables(vp: VehicleParameters, bodies, faults=()):
    """Bushings, two-point dampers, bump stops and anti-roll bars with their nominal preloads, less what the
    faults (FAULT_NAMES) take out:

    - yaw-dampers-failed@front|rear|both: the bogie's two yaw dampers (both: all four) lose their damping and
      carry no force (a damper without damping has no series spring either, dynamics.suspension);
    - lateral-damper-failed@front|rear|both: the same for the bogie's lateral damper (both halves);
    - air-spring-deflated@front-left|front-right|front|rear-left|rear-right|rear: the air spring's vertical
      stiffness and its preload are gone; the car body comes down onto the emergency spring (its bump stop
      after air_spring_emergency_clearance), which carries the load. The horizontal stiffness stays: the
      bellows' shear is taken to pass to the emergency spring's rubber layers (an assumption, A);
    - primary-spring-broken@W-left|W-right (W the wheelset, 0-3): the coil spring's vertical stiffness and
      preload at that axle box are gone (guidance stiffness and damper stay); the frame corner comes down
      onto the primary stop, which carries the load.

    Bump stops: the lateral one per bogie (the bump_stop_* law, both sides), and vertical ones in body a's
    axes: at each air spring the emergency spring (compression) and the height restraint (extension), at each
    axle box the primary stop (compression); the vertical ones have linear laws (`linear_law`)."""
    failed = failed_elements(faults)
    g = GRAVITY
    a = vp.bogie_semi_distance
    w = vp.wheelbase_semi
    bush, damp, bump, arb = [], [], [], []
    box_preload = (0.5 * vp.car_body_mass + vp.bogie_frame_mass) * g / 4.0
    springs = iter(air_springs(vp, faults))

    def add_bush(ba, bb, q, k, c, f0):
        bush.append(Bushing.pack(body_a=ba, body_b=bb, point_a=local_point(bodies, ba, q), point_b=local_point(bodies, bb, q),
                                 stiffness=k, damping=c, preload=f0))

    def add_damper(ba, bb, qa, qb, knee, c1, c2, ks, state, fault):
        if fault in failed:
            c1 = c2 = 0.0
        damp.append(Damper.pack(body_a=ba, body_b=bb, point_a=local_point(bodies, ba, qa), point_b=local_point(bodies, bb, qb),
                                knee_velocity=knee, damping=c1, damping_after_knee=c2, series_stiffness=ks,
                                length=math.dist(qa, qb), state=State.dampers + state))

    def add_stop(ba, bb, q, axis, clearance_negative, clearance_positive, law):
        travel, force = law
        n = len(travel)
        if not 1 <= n <= BUMP_POINTS or len(force) != n:
            raise ValueError(f"a bump-stop law needs 1 to {BUMP_POINTS} (travel, force) points of equal count, "
                             f"not {n} travels and {len(force)} forces")
        points = np.zeros((2, BUMP_POINTS))
        points[0, :n] = travel
        points[1, :n] = force
        bump.append(BumpStop.pack(body_a=ba, body_b=bb, point_a=local_point(bodies, ba, q), point_b=local_point(bodies, bb, q),
                                  axis=axis, clearance_negative=clearance_negative,
                                  clearance_positive=clearance_positive, points=n, travel=points[0],
                                  force=points[1]))

    state = 0
    for i, bogie in enumerate(BOGIES):
        xb = a if i == 0 else -a
        toward_centre = -1.0 if i == 0 else 1.0
        for j, wsx in enumerate((xb + w, xb - w)):
            wheelset = 2 * i + j
            for side in (1.0, -1.0):
                q = (wsx, side * vp.primary_semi_spacing, vp.rolling_radius)
                broken = ("primary-spring-broken", wheelset, SIDES[side]) in failed
                add_bush(bogie, WHEELSETS[wheelset], q,
                         (vp.primary_longitudinal_stiffness, vp.primary_lateral_stiffness,
                          0.0 if broken else vp.primary_vertical_stiffness),
                         (0.0, vp.primary_lateral_damping, vp.primary_vertical_damping),
                         (0.0, 0.0, 0.0 if broken else -box_preload))
                # the wheelset rises toward the frame when the spring is compressed
                add_stop(bogie, WHEELSETS[wheelset], q, VERTICAL, math.inf, vp.primary_stop_clearance,
                         linear_law(vp.primary_stop_clearance, vp.primary_stop_stiffness))
        for side in (1.0, -1.0):
            spring = next(springs)
            q = spring.point
            add_bush(bogie, CAR_BODY, q,
                     (vp.secondary_longitudinal_stiffness, vp.secondary_lateral_stiffness, spring.vertical_stiffness),
                     (0.0, 0.0, 0.0), (0.0, 0.0, spring.preload))
            # the car body comes down onto the emergency spring, or up against the height restraint
            add_stop(bogie, CAR_BODY, q, VERTICAL, vp.air_spring_emergency_clearance, math.inf,
                     linear_law(vp.air_spring_emergency_clearance, vp.air_spring_emergency_stiffness))
            add_stop(bogie, CAR_BODY, q, VERTICAL, math.inf, vp.air_spring_extension_clearance,
                     linear_law(vp.air_spring_extension_clearance, vp.air_spring_extension_stiffness))
            add_bush(bogie, CAR_BODY,
                     (xb, side * vp.secondary_vertical_damper_semi_spacing, vp.secondary_height),
                     (0.0, 0.0, 0.0), (0.0, 0.0, vp.secondary_vertical_damping), (0.0, 0.0, 0.0))
            qa = (xb, side * vp.yaw_damper_semi_spacing, vp.yaw_damper_height)
            qb = (xb + toward_centre * vp.yaw_damper_length, side * vp.yaw_damper_semi_spacing,
                  vp.yaw_damper_height)
            add_damper(bogie, CAR_BODY, qa, qb, vp.yaw_damper_knee_velocity, vp.yaw_damper_damping,
                       vp.yaw_damper_damping_after_knee, vp.yaw_damper_series_stiffness, state,
                       ("yaw-dampers-failed", i, SIDES[side]))
            state += 1
    for i, bogie in enumerate(BOGIES):
        xb = a if i == 0 else -a
        # the lateral damper as a mirrored pair of half dampers (brackets 0.5 m apart across the track),
        # so that the car is exactly mirror-symmetric; in parallel they act as the one damper of the set
        half = 0.25
        for side in (1.0, -1.0):
            add_damper(bogie, CAR_BODY, (xb, -side * half, vp.lateral_damper_height),
                       (xb, side * half, vp.lateral_damper_height), vp.lateral_damper_knee_velocity,
                       0.5 * vp.lateral_damper_damping, 0.5 * vp.lateral_damper_damping_after_knee,
                       0.5 * vp.lateral_damper_series_stiffness, state, ("lateral-damper-failed", i, SIDES[side]))
            state += 1
        add_stop(bogie, CAR_BODY, (xb, 0.0, vp.bump_stop_height), LATERAL, vp.bump_stop_clearance,
                 vp.bump_stop_clearance, (vp.bump_stop_travel, vp.bump_stop_force))
        arb.append(AntiRollBar.pack(body_a=bogie, body_b=CAR_BODY, stiffness=vp.anti_roll_stiffness))
    assert state == N_DAMPER
    return np.array(bush), np.array(damp), np.array(bump), np.array(arb)


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
    check_range("friction coefficient", contact.friction_coefficient, *FRICTION_RANGE, lo_open=True)
    E, nu = contact.youngs_modulus, contact.poisson_ratio
    estar = combined_modulus(E, nu, E, nu)
    return ContactConstants.pack(youngs_modulus=E, combined_modulus=estar, combined_modulus_cbrt=estar ** (1.0 / 3.0),
                                 shear_modulus=contact.shear_modulus, poisson_ratio=nu,
                                 friction=contact.friction_coefficient, contact_damping=contact.contact_damping,
                                 normal_model=NORMAL_MODELS[contact.normal_model],
                                 creep_model=CREEP_MODELS[contact.creep_model],
                                 qp_min_load=contact.derailment_coefficient_min_load * static_wheel_load,
                                 kalker=creep.kalker_table(nu))


def vehicle_array(vp: VehicleParameters, cg, lift_tolerance):
    """The vehicle constants (layout.VehicleConstants)."""
    H = GeometryHeader
    # the flange face: the steepest part of the wheel between the rolling circle and the flange tip
    _, wheel_slope, _ = geometry.wheel_table(cg)
    i0 = int(round(-cg[H.wheel_y0] / cg[H.wheel_step]))
    tip = int(round((cg[H.flange_tip_y] - cg[H.wheel_y0]) / cg[H.wheel_step]))
    flange_angle = float(np.max(scalarmath.arctan(np.abs(wheel_slope[min(i0, tip):max(i0, tip) + 1]))))
    return VehicleConstants.pack(gravity=GRAVITY, rolling_radius=vp.rolling_radius,
                                 spin_inertia=vp.wheelset_spin_inertia, flange_height=cg[H.flange_height],
                                 flange_contact_angle=0.5 * flange_angle,
                                 lift_tolerance=lift_tolerance)


def static_contact(cg, cp, load):
    """The centred wheelset with `load` (N) on each wheel, rigid rails: its vertical displacement (the rigid
    contact less the Hertz approach, m), the centred wheel's rolling radius (m) and the Hertz contact's
    stiffness dN/dd = 1.5 N / d at that load (N/m)."""
    scratch = wheelset.contact_scratch(cg)
    z_rigid, _, _, _ = geometry.rigid_contact(cg, 0.0, 0.0, scratch.gap, scratch.ys)
    patches = scratch.patches
    n, _ = geometry.find_patches(cg, 0.0, z_rigid - 1e-7, 0.0, 0.0, scratch.gap, scratch.ys, patches,
                                 wheelset.candidates()[0])
    k = int(np.argmin(patches[:n, Patch.gap]))
    _, _, coefficient = hertz_shape(patches[k, Patch.curvature_a], patches[k, Patch.curvature_b],
                                    cp[ContactConstants.combined_modulus])
    slope = patches[k, Patch.slope]
    approach = (load / coefficient) ** (2.0 / 3.0)
    return z_rigid - approach * math.sqrt(1.0 + slope * slope), float(patches[k, Patch.radius]), 1.5 * load / approach


def elastic_contact_damping(elastic: ElasticTrackParameters, contact_stiffness, load):
    """Hunt-Crossley chi (s/m) on elastic track, set from the track: the contact, a spring in series with
    the track's, damped in the same ratio as the track's vertical mode, c = c_v sqrt(k_contact / k_v); at
    the static load chi = c / load (docs/elastic-track.md)."""
    _, k_v, c_v = elastic.vertical
    return c_v * math.sqrt(contact_stiffness / k_v) / load


def support_array(track_model, elastic: ElasticTrackParameters, cg):
    """The track's constants (track.elastic.ElasticTrack) for track_model "rigid" or "elastic"."""
    if track_model == "rigid":
        return ElasticTrack.pack(roll_centre_lateral=cg[GeometryHeader.rail_axis_y])
    (my, ky, cy), (mz, kz, cz), (ir, kr, cr) = elastic.lateral, elastic.vertical, elastic.roll
    return ElasticTrack.pack(elastic=1.0, lateral_mass=my, vertical_mass=mz, roll_inertia=ir, lateral_stiffness=ky,
                             vertical_stiffness=kz, roll_stiffness=kr, lateral_damping=cy, vertical_damping=cz,
                             roll_damping=cr, roll_centre_depth=elastic.roll_centre_depth,
                             roll_centre_lateral=cg[GeometryHeader.rail_axis_y])


def build_model(vehicle: VehicleParameters, track: TrackParameters, contact: ContactParameters,
                lift_tolerance=1.0e-3, irregularity=None, track_model="rigid", elastic=ElasticTrackParameters(),
                aero=None, faults=()):
    """Pack a scenario's parameters into a Model; `irregularity`: a `track.irregularity.Irregularity`, or
    None for ideal rails; `track_model` "rigid" or "elastic" (the co-running rails of `elastic`; the contact
    damping then comes from the track, `elastic_contact_damping`); `aero` the packed wind and aerodynamic
    coefficients (`loads.wind.pack_aero`), None for still air; `faults`: the suspension faults
    (FAULT_NAMES, `element_tables`)."""
    if track_model not in TRACK_MODELS:
        raise ValueError(f"track model {track_model!r} is unknown; choose one of {', '.join(TRACK_MODELS)}")
    bodies = body_table(vehicle)
    bush, damp, bump, arb = element_tables(vehicle, bodies, faults)
    cg = contact_geometry(contact, track, vehicle.rolling_radius)
    if track_model == "elastic":
        load = vehicle.static_wheel_load
        _, _, stiffness = static_contact(cg, contact_array(contact), load)
        contact = replace(contact, contact_damping=elastic_contact_damping(elastic, stiffness, load))
    trk = alignment.pack_track(track.straight_in, track.transition_in, track.curve_length,
                               track.transition_out, track.straight_out, track.radius, track.cant_height,
                               track.direction, track.rail_spacing)
    return Model(bodies=bodies, vp=vehicle_array(vehicle, cg, lift_tolerance), bush=bush, damp=damp,
                 bump=bump, arb=arb, track=trk, rails=rails.pack_rails() if irregularity is None
                 else irregularity.pack(),
                 support=support_array(track_model, elastic, cg), aero=still_air() if aero is None else aero, cg=cg,
                 cp=contact_array(contact, vehicle.static_wheel_load), vehicle=vehicle, track_parameters=track,
                 contact=contact)
