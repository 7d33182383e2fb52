"""Wheel-climb rig (`railderail climb`): one loaded wheelset pushed sideways until a flange climbs its rail.

The rig (docs/climb.md gives the reasons for each choice):
  - one wheelset on straight, rigid track, rolling forward at the speed v; its yaw is held at the attack
    angle psi (> 0 heads the wheelset toward the left rail, the flanging one); the lateral y, vertical z and
    roll phi motion are free with the wheelset's mass and roll inertia, and so is its spin about the axle
    (its spin inertia; the contacts decide how fast it turns, as on a real axle);
  - a dead vertical load of 2 W (W the wheel load, default the CRH3 static wheel load of `parameters`; it
    includes the wheelset's weight) and a lateral force H toward the left rail act on the axle; H's line of
    action is at rail-top height (the rig takes its roll moment, as the car body and bogie do in a vehicle),
    so that H does not unload the right wheel: pushed at its centre a bare wheelset rolls over its flange at
    a wheel L/V of about lw / r0 = 1.6, before a low-friction or low-attack-angle flange climbs;
  - both wheels' forces come from `contact.wheelset.wheel_forces` (the exact online contact search, Hertz
    patches, the chosen creep law, FASTSIM by default), with the creepages from the wheelset's full motion:
    forward speed, lateral and vertical velocity, roll rate and spin. This is what bounds the climb rate: a
    wheel climbing up its flange at the rate the yawed wheel rolls up it has no creepage left to help it;
  - the contacts carry heavy Hunt-Crossley damping (RIG_CONTACT_DAMPING): the damping acts on the approach
    rate only, so that a wheel sliding steadily along its flange feels none, while the bounce that a
    contact appearing on the flange face starts dies out within a few cycles (the rigid rails have no track
    to dissipate it).

The run, in two parts:
  1. onset: H rises slowly (RAMP_PER_S x W per second) from zero until the left wheel has lifted CLIMB_LIFT
     above its lift in rigid two-point contact (tread and flange touching, `two_point_lift`): the climb has
     started. climb_lv is the wheel's L/V there. A ramp this slow leaves it at its quasi-static value (a
     test halves the rate);
  2. climb: H is held at CLIMB_OVERLOAD x its value at the onset, until the flange tip is on the rail top:
     the wheel lift (the nominal rolling circle above the rail's highest point) within TIP_ALLOWANCE of the
     flange height. The climb distance is the track travelled in this part. Holding the force is what the
     published climb-distance studies do (constant L/V, Wu & Wilson); a force still rising would set the
     distance itself: on a flange face of constant angle the wheel L/V stays at its limit while the wheel
     creeps up as fast as the force rises, so that a slower ramp gives a longer distance (docs/climb.md).

Everything is SI; the user-facing arguments carry their unit in the name (mrad, kN, km/h).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..contact import conicity
from ..contact import geometry as geo
from ..contact import wheelset as ws
from ..contact.nadal import nadal_limit
from ..jsonout import NOT_WRITTEN, plain
from ..parameters import FRICTION_RANGE, VehicleParameters
from ..ranges import check_range
from ..vehicle.assemble import CREEP_MODELS, contact_array
from ..contact.layout import W_SIZE, ContactConstants, GeometryHeader, Patch, Wheel
from .wheel_rail_pair import TREAD_ANGLE_MAX, WheelRailPair, build_pair, contact_range

# accepted ranges (user units)
ATTACK_ANGLE_MRAD = (0.0, 50.0)
SPEED_KMH = (1.0, 300.0)
WHEEL_LOAD_KN = (0.0, 500.0)          # (0, 500]
RAMP_RANGE_PER_S = (0.0, 10.0)        # (0, 10] wheel loads per second

DEFAULT_SPEED_KMH = 20.0              # flange climb is a low-speed derailment; the published rigs run slowly
DEFAULT_SWEEP_MRAD = (0.0, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0)
DEFAULT_CREEP = "fastsim"             # the flange contact spins hard (sin(delta) / r0, about 2 1/m): FASTSIM
                                      # bounds the spin's lateral force, SHE saturates it like a creepage
RAMP_PER_S = 0.5                      # dH/dt in wheel loads per second (1/s)
CLIMB_LIFT = 1.0e-3                   # m above the two-point-contact lift: the climb has started
TIP_ALLOWANCE = 0.5e-3                # m: the flange tip this close to the rail top counts as on it
CLIMB_OVERLOAD = 1.25                 # the held force of the climb part, times the force at the onset
MAX_FORCE_RATIO = 4.0                 # H/W at which the ramp gives up: above tan(75 deg), every flange's limit
MAX_CLIMB_TRAVEL = 100.0              # m of held force without reaching the rail top: the climb stalled
RIG_CONTACT_DAMPING = 20.0            # s/m, Hunt-Crossley chi: about critical for the wheelset's bounce on its
                                      # contacts (the vehicle model's 2 s/m gives about a tenth of critical)
MAX_STEP = 0.01                       # s, the integrator's largest step (the ramp changes H by 0.5 % of W)
RTOL = 1.0e-6
ATOL = (1e-8, 1e-9, 1e-8, 1e-6, 1e-6, 1e-5, 1e-4)   # y, z, phi (m, m, rad), their rates, spin (rad/s)
TRANSITION_SCAN = 5.0e-4             # m, the lateral step of the search for the first flange contact
FLANGING, OTHER = 0, 1                # the left wheel flanges (yaw and force toward the left rail)


@dataclass(frozen=True, kw_only=True)
class Climb:
    """One climb (SI). climb_lv is None when the flange did not start to climb within the ramp (up to
    MAX_FORCE_RATIO wheel loads); climb_distance_m is None when the held force did not bring the flange tip
    onto the rail top within MAX_CLIMB_TRAVEL."""
    wheel: str
    rail: str
    attack_angle_rad: float
    friction: float
    creep_law: str
    speed_m_s: float
    wheel_load_N: float
    ramp_per_s: float
    flange_height_m: float            # the flange tip above the nominal rolling circle
    two_point_lift_m: float           # the left wheel's lift in rigid tread-and-flange contact at this yaw
    climbed: bool                     # the flange tip reached the rail top
    outcome: str
    climb_lv: float | None
    climb_lateral_force_N: float | None
    climb_contact_angle_rad: float | None
    climb_position_m: float | None    # track travelled from the start of the run to the onset
    held_lateral_force_N: float | None
    peak_lv: float
    climb_distance_m: float | None
    max_contact_angle_rad: float
    nadal_limit: float                # Nadal's limit at max_contact_angle_rad and this friction
    distance_m: np.ndarray = field(metadata=NOT_WRITTEN)       # the run's samples: track travelled,
    lv: np.ndarray = field(metadata=NOT_WRITTEN)               # the left wheel's L/V,
    lift_m: np.ndarray = field(metadata=NOT_WRITTEN)           # its wheel lift,
    contact_angle_rad: np.ndarray = field(metadata=NOT_WRITTEN)  # its main patch's contact angle
    lateral_force_N: np.ndarray = field(metadata=NOT_WRITTEN)  # and the lateral force H

    def row(self) -> dict:
        """The JSON object of one attack angle."""
        return plain(self)

    def as_dict(self) -> dict:
        """The JSON object of `railderail climb --json` (one attack angle)."""
        return {"command": "climb", "rig": rig_description(), **self.row()}

    def text(self) -> str:
        """Short summary (mrad, kN, deg, km/h)."""
        head = (f"climb: attack angle {self.attack_angle_rad * 1e3:g} mrad, friction {self.friction:g}, creep law "
                f"{self.creep_law}, {self.speed_m_s * 3.6:g} km/h, wheel load {self.wheel_load_N / 1e3:.1f} kN")
        lines = [head, f"  {self.outcome}"]
        if self.climb_lv is not None:
            lines.append(f"  L/V at the climb {self.climb_lv:.3f} (lateral force "
                         f"{self.climb_lateral_force_N / 1e3:.1f} kN, contact angle "
                         f"{math.degrees(self.climb_contact_angle_rad):.2f} deg), peak L/V {self.peak_lv:.3f}")
        lines.append(f"  Nadal's limit {self.nadal_limit:.3f} at the largest contact angle reached "
                     f"{math.degrees(self.max_contact_angle_rad):.2f} deg")
        if self.climb_distance_m is not None:
            lines.append(f"  climb distance {self.climb_distance_m:.3f} m (lift {CLIMB_LIFT * 1e3:g} mm above "
                         f"two-point contact to the flange tip on the rail top, force held at "
                         f"{self.held_lateral_force_N / 1e3:.1f} kN)")
        return "\n".join(lines)


@dataclass(frozen=True, kw_only=True)
class ClimbSweep:
    """Climbs over attack angles for one or several friction coefficients."""
    wheel: str
    rail: str
    climbs: list                      # Climb, friction by friction, attack angles in the given order

    def frictions(self) -> list:
        return list(dict.fromkeys(c.friction for c in self.climbs))

    def curve(self, friction) -> list:
        return [c for c in self.climbs if c.friction == friction]

    def as_dict(self) -> dict:
        return {"command": "climb", "rig": rig_description(), "wheel": self.wheel, "rail": self.rail,
                "sweep": [c.row() for c in self.climbs]}

    def text(self) -> str:
        lines = [f"climb sweep: wheel {self.wheel} on rail {self.rail}",
                 "  friction  attack mrad  L/V climb  L/V peak  Nadal  max angle deg  climb distance m"]
        def num(value, fmt):
            return format(value, fmt) if value is not None else "-"
        for c in self.climbs:
            lines.append(f"  {c.friction:8g}  {c.attack_angle_rad * 1e3:11g}  {num(c.climb_lv, '9.3f')}  "
                         f"{c.peak_lv:8.3f}  {c.nadal_limit:5.3f}  {math.degrees(c.max_contact_angle_rad):13.2f}  "
                         f"{num(c.climb_distance_m, '16.3f')}")
        return "\n".join(lines)


def rig_description() -> dict:
    """The rig's fixed choices, as written in the JSON results."""
    return {"ramp_per_s_default": RAMP_PER_S, "climb_lift_m": CLIMB_LIFT, "tip_allowance_m": TIP_ALLOWANCE,
            "climb_overload": CLIMB_OVERLOAD, "contact_damping_s_m": RIG_CONTACT_DAMPING,
            "lateral_force_line": "rail-top height", "spin": "free (the wheelset's spin inertia)",
            "climb_start": "wheel lift climb_lift_m above its rigid two-point-contact value",
            "climb_end": "wheel lift within tip_allowance_m of the flange height (flange tip on the rail top)"}


def two_point_lift(cg, psi):
    """The left wheel's lift (m) where its rigid contact passes from the tread to the flange at yaw psi: the
    lateral shift at which the rigid contact angle crosses the tread's largest (wheel_rail_pair
    .TREAD_ANGLE_MAX), found by bisection; there tread and flange touch together."""
    def on_flange(y):
        z, phi, ok = conicity.rigid_pose(cg, y, psi)
        row, _ = conicity.deepest_patch(cg, y, z, phi, psi) if ok else (None, 0)
        return row is not None and math.atan(row[Patch.slope]) > TREAD_ANGLE_MAX

    # the first flange contact outward from the centre, in steps well below the tread's width
    shifts = np.arange(0.0, contact_range(cg, psi), TRANSITION_SCAN)
    flanging = [y for y in shifts if on_flange(y)]
    if on_flange(0.0) or not flanging:
        raise ValueError("the wheel/rail pair has no tread-to-flange transition to climb from (the centred "
                         "wheelset already flanges, or the flange is never reached)")
    hi = flanging[0]
    lo = hi - TRANSITION_SCAN
    while hi - lo > 1e-7:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if on_flange(mid) else (mid, hi)
    z, phi, _ = conicity.rigid_pose(cg, hi, psi)
    return hi, geo.wheel_lift(cg, z, phi)


class _Rig:
    """The wheelset's equations of motion on the rig; state (y, z, phi, y', z', phi', spin)."""

    def __init__(self, pair, cp, psi, speed, wheel_load, vp):
        self.cg, self.cp, self.psi, self.speed, self.load = pair.cg, cp, psi, speed, wheel_load
        self.mass = vp.wheelset_mass
        self.roll_inertia = vp.wheelset_roll_inertia
        self.spin_inertia = vp.wheelset_spin_inertia
        self.radius = self.cg[GeometryHeader.nominal_radius]
        self.scratch = ws.contact_scratch(self.cg)
        self.cand = ws.candidates()[0]
        self.recs = np.zeros((2, W_SIZE))
        self.roll_axis = np.array([math.cos(psi), math.sin(psi), 0.0])

    def contact(self, s):
        """Force and moment of both wheels on the wheelset (track axes); fills the wheel records."""
        y, z, phi, vy, vz, roll_rate, spin = s
        pose = (y, z, phi, self.psi)
        ox, oy, oz = roll_rate * self.roll_axis
        motion = (self.speed, vy, vz, ox, oy, oz, spin, self.speed)
        total = np.zeros(6)
        for side in (FLANGING, OTHER):
            total += ws.wheel_forces(self.cg, self.cp, side, pose, motion, self.scratch, self.cand, False,
                                     self.recs[side])
        return total

    def rates(self, s, lateral_force):
        y, z, phi, vy, vz, roll_rate, spin = s
        f = self.contact(s)
        # the lateral force acts along a line at rail-top height, r0 + z below the centre: its moment there
        moment = f[3:] + np.array([(self.radius + z) * lateral_force, 0.0, 0.0])
        axle = np.array([-math.sin(self.psi) * math.cos(phi), math.cos(self.psi) * math.cos(phi), math.sin(phi)])
        # yaw held: roll about the yawed x axis and spin about the axle (both perpendicular, the wheelset
        # axisymmetric); the gyroscopic moment is about the third axis, which the rig's yaw restraint takes
        return (vy, vz, roll_rate, (f[1] + lateral_force) / self.mass, (f[2] - 2.0 * self.load) / self.mass,
                float(moment @ self.roll_axis) / self.roll_inertia, float(moment @ axle) / self.spin_inertia)

    def wheel(self):
        """(L/V, lift, contact angle) of the flanging wheel from the last evaluation."""
        r = self.recs[FLANGING]
        p = r[Wheel.vertical_force]
        lv = r[Wheel.lateral_force] / p if p > 0.0 else 0.0
        return lv, r[Wheel.wheel_lift], r[Wheel.contact_angle]

    def start(self, y):
        """Rest at lateral shift y on the tread: the rigid pose pressed in until the wheels carry 2 W."""
        z_rigid, phi, _ = conicity.rigid_pose(self.cg, y, self.psi)
        spin = self.speed / self.radius

        def excess(z):
            return self.contact((y, z, phi, 0.0, 0.0, 0.0, spin))[2] - 2.0 * self.load

        z = brentq(excess, z_rigid - 2e-3, z_rigid, xtol=1e-12)
        return np.array([y, z, phi, 0.0, 0.0, 0.0, spin])


def _samples(rig, t, states, force, t0):
    """Rows (distance, L/V, lift, contact angle, H) at the solver's steps."""
    rows = []
    for tk, sk in zip(t, states.T):
        rig.contact(sk)
        rows.append((rig.speed * (t0 + tk), *rig.wheel(), force(tk)))
    return np.array(rows).reshape(-1, 5)


def _event(rig, target):
    def crossing(t, s):
        rig.contact(s)
        return rig.wheel()[1] - target
    crossing.terminal = True
    crossing.direction = 1.0
    return crossing


def climb(wheel="lm", rail="uic60", *, attack_angle_mrad=10.0, friction=0.3, speed_kmh=DEFAULT_SPEED_KMH,
          creep=DEFAULT_CREEP, wheel_load_kn=None, ramp_per_s=RAMP_PER_S, pair: WheelRailPair | None = None) -> Climb:
    """Run the rig once (module docstring); user units in, SI out. `pair` (from `build_pair(wheel, rail)`)
    may be given to share the packed geometry between runs."""
    psi = check_range("attack angle --attack-angle-mrad", attack_angle_mrad, *ATTACK_ANGLE_MRAD, "mrad") * 1e-3
    mu = check_range("friction coefficient --friction", friction, *FRICTION_RANGE)
    speed = check_range("speed --speed-kmh", speed_kmh, *SPEED_KMH, "km/h") / 3.6
    ramp = check_range("lateral force ramp", ramp_per_s, *RAMP_RANGE_PER_S, "wheel loads per s", lo_open=True)
    if creep not in CREEP_MODELS:
        raise ValueError(f"creep law --creep {creep!r} is unknown; choose one of {', '.join(CREEP_MODELS)}")
    if creep == "linear" and mu == 0.0:
        raise ValueError("creep law --creep linear has no friction limit, so friction 0 means nothing to it; "
                         "use a saturating law (she, polach, fastsim) for a frictionless flange")
    vp = VehicleParameters()
    if wheel_load_kn is None:
        wheel_load_kn = vp.static_wheel_load / 1e3
    load = check_range("wheel load --wheel-load-kn", wheel_load_kn, *WHEEL_LOAD_KN, "kN", lo_open=True) * 1e3
    pair = pair or build_pair(wheel, rail)
    contact = replace(pair.contact, creep_model=creep, contact_damping=RIG_CONTACT_DAMPING)
    cp = contact_array(contact, load)
    # contact_array refuses friction 0 (a vehicle without friction is a slip of the pen); the rig's
    # frictionless flange is one of its checks: the creep laws then give no tangential force
    cp[ContactConstants.friction] = mu
    rig = _Rig(pair, cp, psi, speed, load, vp)
    y_two_point, h0 = two_point_lift(pair.cg, psi)
    state = rig.start(y_two_point - 0.5e-3)
    flange_height = pair.cg[GeometryHeader.flange_height]
    inputs = dict(wheel=pair.wheel.name, rail=pair.rail.name, attack_angle_rad=psi, friction=mu, creep_law=creep,
                  speed_m_s=speed, wheel_load_N=load,
                  ramp_per_s=ramp, flange_height_m=flange_height, two_point_lift_m=h0)

    def ramp_force(t):
        return ramp * load * t

    onset = solve_ivp(lambda t, s: rig.rates(s, ramp_force(t)), (0.0, MAX_FORCE_RATIO / ramp), state,
                      method="RK45", max_step=MAX_STEP, rtol=RTOL, atol=ATOL, events=_event(rig, h0 + CLIMB_LIFT))
    rows = _samples(rig, onset.t, onset.y, ramp_force, 0.0)
    if onset.status != 1:
        return _result(inputs, rows, mu, climbed=False, outcome=f"no climb: the ramp reached {MAX_FORCE_RATIO:g} "
                       "wheel loads of lateral force without the flange starting to climb")
    t_onset = onset.t_events[0][0]
    rig.contact(onset.y_events[0][0])
    lv_onset, _, angle_onset = rig.wheel()
    held = CLIMB_OVERLOAD * ramp_force(t_onset)
    at_onset = dict(climb_lv=lv_onset, climb_lateral_force_N=ramp_force(t_onset), climb_contact_angle_rad=angle_onset,
                    climb_position_m=speed * t_onset, held_lateral_force_N=held)
    run = solve_ivp(lambda t, s: rig.rates(s, held), (0.0, MAX_CLIMB_TRAVEL / speed), onset.y_events[0][0],
                    method="RK45", max_step=MAX_STEP, rtol=RTOL, atol=ATOL,
                    events=_event(rig, flange_height - TIP_ALLOWANCE))
    rows = np.vstack([rows, _samples(rig, run.t, run.y, lambda t: held, t_onset)])
    if run.status != 1:
        return _result(inputs, rows, mu, climbed=False, **at_onset,
                       outcome=f"climb stalled: the flange started to climb but did not reach the rail top within "
                               f"{MAX_CLIMB_TRAVEL:g} m of held force")
    return _result(inputs, rows, mu, climbed=True, **at_onset, climb_distance_m=speed * run.t_events[0][0],
                   outcome="the flange climbed onto the rail top")


def _result(inputs, rows, mu, *, climbed, outcome, climb_lv=None, climb_lateral_force_N=None,
            climb_contact_angle_rad=None, climb_position_m=None, held_lateral_force_N=None, climb_distance_m=None):
    distance, lv, lift, angle, force = rows.T
    max_angle = float(angle.max())
    return Climb(**inputs, climbed=climbed, outcome=outcome, climb_lv=climb_lv,
                 climb_lateral_force_N=climb_lateral_force_N, climb_contact_angle_rad=climb_contact_angle_rad,
                 climb_position_m=climb_position_m, held_lateral_force_N=held_lateral_force_N,
                 peak_lv=float(lv.max()), climb_distance_m=climb_distance_m, max_contact_angle_rad=max_angle,
                 nadal_limit=float(nadal_limit(max_angle, mu)), distance_m=distance, lv=lv, lift_m=lift,
                 contact_angle_rad=angle, lateral_force_N=force)


def climb_sweep(attack_angles_mrad=DEFAULT_SWEEP_MRAD, frictions=(0.3,), *, wheel="lm", rail="uic60",
                **options) -> ClimbSweep:
    """`climb` at every attack angle for every friction coefficient (one packed geometry for all)."""
    if not attack_angles_mrad or not frictions:
        raise ValueError("a climb sweep needs at least one attack angle and one friction coefficient")
    pair = build_pair(wheel, rail)
    runs = [climb(attack_angle_mrad=a, friction=mu, pair=pair, **options) for mu in frictions
            for a in attack_angles_mrad]
    return ClimbSweep(wheel=pair.wheel.name, rail=pair.rail.name, climbs=runs)
