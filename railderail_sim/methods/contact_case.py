"""One loaded wheelset on its rails, in the spirit of CONTACT's wheelset mode (`railderail contact-case`).

Prescribed lateral shift y and yaw psi, and either
  * a roll (default: the rigid-contact roll at that y and psi) and a vertical wheelset load: the
    wheelset's vertical position is solved so that the summed vertical contact force of its two wheels
    equals the load (the elastic contact decides how the wheels share it), or
  * the vertical force of each wheel (`wheel_loads_kn`, as the Manchester contact benchmark and CONTACT's
    wheelset mode prescribe them): vertical position and roll are solved together so that each wheel
    carries its own load (the roll by bisection on the left wheel's share, the vertical position inside it).
Creepages come from the kinematics of steady rolling: centre velocity (v, 0, 0), no angular velocity
besides the spin about the axle (the pitch rate): v / r0, the free-rolling spin or a prescribed one
(`wheelset.wheel_forces` with vel = (v, 0, 0), omega = 0); no contact damping (quasi-static).
Models (`wheel_rail_pair.MODELS`):
    hertz      Hertz (equivalent ellipse from the patch curvatures) + Shen-Hedrick-Elkins
    fastsim    Hertz + FASTSIM
    discrete   Kik-Piotrowski normal + SHE on its equivalent ellipse
    halfspace  as discrete (load sharing and creep forces); each patch is in addition solved by the exact
               half-space solver at the discrete patch's normal force (`contact_patch`)
    exact      as hertz (load sharing and creep forces: the vehicle model's default laws); each patch is in
               addition solved by the exact half-space solver at its Hertz normal force and then by Kalker's
               exact steady rolling theory with its creepages (`exact_rolling`), beside the creep laws SHE,
               Polach and FASTSIM on its Hertz ellipse (`contact_patch`)
Per-patch quantities come from `contact_patch.wheel_patch_details`.

Sign conventions: totals in track axes (x forward, y left, z up), forces on the wheelset. Per wheel,
everything is in that wheel's own frame (the right wheel mirrored into the left-wheel form of
`geometry`): lateral positions, lateral creepage and lateral creep force + toward the field side of its
rail, contact angle + toward the flange, spin likewise mirrored; so a centred wheelset gives identical
left and right values. Y (+ toward the field side) and Q (+ down) are the lateral and vertical forces on the
rail (EN 14363's notation, docs/output-format.md; the JSON keys `Q_N`, `P_N`, `Q_over_P` keep the paper's letters,
Q lateral and P vertical). Yaw
psi > 0 turns the wheelset's heading to the left (toward the left rail). `force_on_rail_N` is the one
exception: the wheel's whole force on its rail in track axes (x forward, y left, z up), the way CONTACT
reports its totals, so that the two wheels can be compared with a benchmark without mirroring.
"""
from __future__ import annotations

from dataclasses import dataclass, field
import math

import numpy as np
from scipy.optimize import brentq

from ..contact import conicity
from ..contact import geometry as geo
from ..contact import wheelset as ws
from ..jsonout import NOT_WRITTEN, WRITTEN_IF_SET, plain
from ..ranges import check_range
from .contact_patch import GRID, ContactPatch, steady_rolling, wheel_patch_details
from .wheel_rail_pair import SIDES, WheelRailPair, contact_range, gap_buffers, static_wheelset_load
from ..contact.layout import W_SIZE, ContactConstants, Wheel

LOAD_KN = (0.0, 1000.0)               # (0, 1000]
WHEEL_LOAD_KN = (0.0, 500.0)          # (0, 500] per wheel
PITCH_RATE_REL = (0.8, 1.2)           # a prescribed pitch rate, in units of v / r0: longitudinal creepage <= 20 %
SPEED_KMH = (1.0, 600.0)
YAW_MRAD = (-100.0, 100.0)
ROLL_MRAD = (-50.0, 50.0)
SPIN_MODES = {"nominal": "nominal, v / r0 (as the vehicle model)",
              "free": "free rolling (total longitudinal force zero)",
              "prescribed": "prescribed pitch rate"}


@dataclass(frozen=True, kw_only=True)
class WheelsetPose:
    """The solved pose of the wheelset and its spin."""
    lateral_m: float
    yaw_rad: float
    roll_rad: float
    roll_source: str                  # "rigid contact", "input" or "wheel loads"
    vertical_m: float
    touch_vertical_m: float           # vertical position at which the first wheel touches
    rigid_vertical_m: float
    rigid_roll_rad: float
    lateral_range_m: float            # `wheel_rail_pair.contact_range` at this yaw
    spin_rad_s: float
    spin_mode: str
    nominal_spin_rad_s: float
    effective_rolling_radius_m: float


@dataclass(frozen=True, kw_only=True)
class WheelForces:
    """One wheel's force on its rail with one set of creep forces: Y (key Q_N), Q (key P_N) and Y/Q (key
    Q_over_P) in the wheel's own frame, the whole force in track axes."""
    Q_N: float
    P_N: float
    Q_over_P: float
    longitudinal_force_on_rail_N: float
    force_on_rail_N: list             # track axes (x forward, y left, z up)


@dataclass(frozen=True, kw_only=True)
class WheelContact:
    """One wheel's forces on its rail and its patches (the wheel's own frame). The totals are those of the
    pair's model: with `exact`, Kalker's exact rolling forces of its patches (`creep_forces`), the forces
    of the creep laws on the same patches in `laws`."""
    side: str
    creep_forces: str                 # what the totals' creep forces are: the creep law, or "exact rolling"
    Q_N: float
    P_N: float
    Q_over_P: float
    longitudinal_force_on_rail_N: float
    force_on_rail_N: list             # the wheel's force on its rail, track axes (x forward, y left, z up)
    wheel_lift_m: float
    min_gap_m: float
    patch_count: int
    patches: list[ContactPatch]
    laws: dict | None = field(default=None, metadata=WRITTEN_IF_SET)    # creep law -> WheelForces (exact)


@dataclass(frozen=True, kw_only=True)
class WheelsetTotals:
    """Contact force and moment on the wheelset, track axes."""
    force_N: list
    moment_Nm: list
    vertical_load_N: float
    load_error_rel: float


@dataclass(frozen=True, kw_only=True)
class ContactCase:
    """The result of `contact_case` (SI)."""
    pair: WheelRailPair = field(metadata=NOT_WRITTEN)
    lateral_m: float
    yaw_rad: float
    roll_input_rad: float | None      # None: the rigid-contact roll or the one the wheel loads give
    load_N: float
    wheel_loads_N: list | None        # [left, right] when each wheel's vertical force is prescribed
    speed_m_s: float
    grid: int
    pose: WheelsetPose
    wheels: list[WheelContact]
    totals: WheelsetTotals

    def as_dict(self) -> dict:
        """The JSON object of `railderail contact-case --json`."""
        c = self.pair.contact
        return {
            "command": "contact-case",
            "inputs": plain({**self.pair.inputs(), "model": self.pair.model, "normal_model": c.normal_model,
                             "creep_model": c.creep_model, "halfspace": self.pair.halfspace,
                             "exact_rolling": self.pair.exact_rolling,
                             "lateral_m": self.lateral_m, "yaw_rad": self.yaw_rad, "roll_rad": self.roll_input_rad,
                             "load_N": self.load_N, "wheel_loads_N": self.wheel_loads_N,
                             "pitch_rate_rad_s": self.pose.spin_rad_s if self.pose.spin_mode == SPIN_MODES[
                                 "prescribed"] else None, "speed_m_s": self.speed_m_s,
                             "youngs_modulus_Pa": c.youngs_modulus, "poisson_ratio": c.poisson_ratio,
                             "halfspace_grid": [self.grid, self.grid] if self.pair.halfspace else None,
                             "spin": self.pose.spin_rad_s}),   # the solved spin (rad/s), as written so far
            "pose": plain(self.pose),
            "wheels": plain(self.wheels),
            "totals": plain(self.totals),
        }

    def text(self) -> str:
        """Short human summary (mm, kN, deg, km/h)."""
        pair, pose, c = self.pair, self.pose, self.pair.contact
        lines = [
            f"contact case: wheel {pair.wheel.name} on rail {pair.rail.name}, inclination {pair.inclination_text}, "
            f"gauge {pair.track.gauge * 1e3:.1f} mm, back-to-back {c.back_to_back * 1e3:.1f} mm, r0 "
            f"{pair.radius * 1e3:.1f} mm; model {pair.model} (normal {c.normal_model}, creep {c.creep_model}"
            f"{', + exact half-space patches' if pair.halfspace else ''}"
            f"{' and exact rolling on them' if pair.exact_rolling else ''}), mu {c.friction_coefficient:g}",
            f"  wheelset: lateral {pose.lateral_m * 1e3:.2f} mm, yaw {pose.yaw_rad * 1e3:.2f} mrad, roll "
            f"{pose.roll_rad * 1e3:.3f} mrad ({pose.roll_source}), vertical {pose.vertical_m * 1e3:.4f} mm "
            f"(touch {pose.touch_vertical_m * 1e3:.4f} mm), speed {self.speed_m_s * 3.6:g} km/h, load "
            f"{self.load_N / 1e3:.2f} kN",
            f"  spin {pose.spin_rad_s:.4f} rad/s, {pose.spin_mode}; effective rolling radius "
            f"{pose.effective_rolling_radius_m * 1e3:.3f} mm",
        ]
        for w in self.wheels:
            lines.append(f"  {w.side} wheel: {_wheel_text(w)}, {w.patch_count} patch(es), creep forces "
                         f"{w.creep_forces}")
            lines += [f"    with {name:8s} {_wheel_text(law)}" for name, law in (w.laws or {}).items()]
            for k, p in enumerate(w.patches):
                cr, cf = p.creepage, p.creep_force
                lines.append(
                    f"    patch {k + 1}: rail y {p.rail_y_m * 1e3:7.2f} mm, wheel y {p.wheel_y_m * 1e3:7.2f} mm, "
                    f"angle {math.degrees(p.contact_angle_rad):6.2f} deg, N {p.normal_force_N / 1e3:7.2f} kN, "
                    f"Hertz a x b {p.hertz_a_m * 1e3:.2f} x {p.hertz_b_m * 1e3:.2f} mm, "
                    f"patch {p.length_m * 1e3:.2f} x {p.width_m * 1e3:.2f} mm (length x width)")
                lines.append(
                    f"             creepage x {cr.longitudinal:+.3e}, y {cr.lateral:+.3e}, spin "
                    f"{cr.spin_1_m:+.3f} 1/m; creep force x {cf.longitudinal_N / 1e3:+.3f} kN, y "
                    f"{cf.lateral_N / 1e3:+.3f} kN")
                for q, label in ((p.discrete, "discrete (KP)"), (p.halfspace, "half-space")):
                    if q is not None:
                        lines.append(f"             {label:14s} {q.length_m * 1e3:.2f} x {q.width_m * 1e3:.2f} mm, "
                                     f"area {q.area_m2 * 1e6:.1f} mm^2, p_max {q.p_max_Pa / 1e6:.0f} MPa"
                                     + _separate_patches(q))
                if p.exact_rolling is not None:
                    lines.extend(_rolling_lines(p.exact_rolling))
        f, t = self.totals.force_N, self.totals
        lines.append(f"  totals on the wheelset (track axes, y left, z up): Fx {f[0] / 1e3:+.3f} kN, Fy "
                     f"{f[1] / 1e3:+.3f} kN, Fz {f[2] / 1e3:+.3f} kN (load error {t.load_error_rel:+.1e})")
        return "\n".join(lines)


def _wheel_text(w):
    return (f"Y {w.Q_N / 1e3:.2f} kN, Q {w.P_N / 1e3:.2f} kN, Y/Q {w.Q_over_P:.3f}, longitudinal "
            f"{w.longitudinal_force_on_rail_N / 1e3:+.3f} kN")


def _rolling_lines(q):
    """The exact rolling solution of a patch and the creep laws beside it (kN, N m)."""
    def forces(f):
        return (f"Fx {f.longitudinal_N / 1e3:+.3f} kN, Fy {f.lateral_N / 1e3:+.3f} kN, Mz "
                f"{f.spin_moment_Nm:+.2f} N m")
    lines = [f"             exact rolling  {forces(q.creep_force)}; stick {100.0 * q.stick_fraction:.0f} % of "
             f"the patch{'' if q.converged else f' (not converged, residual {q.residual:.1e})'}"]
    lines += [f"             {name:14s} {forces(f)}" for name, f in q.laws.items()]
    return lines


def _separate_patches(q):
    """'; 2 separate patches: 45.8 kN at +11.2 mm, ...' when the half-space finds more than one."""
    parts = getattr(q, "patches", ())
    if len(parts) < 2:
        return ""
    return f"; {len(parts)} separate patches: " + ", ".join(
        f"{r.normal_force_N / 1e3:.1f} kN at {r.centroid_offset_m * 1e3:+.1f} mm" for r in parts)


def _wheel_forces(patches, creep, side, cp):
    """The wheel's `WheelForces` and its force and moment on the wheelset (track axes) from its patches'
    normal forces and the creep forces `creep` (a `CreepForce` per patch), as `wheelset.wheel_forces` sums
    them."""
    load = np.zeros(6)
    for p, c in zip(patches, creep):
        sd, cd = math.sin(p.contact_angle_rad), math.cos(p.contact_angle_rad)
        load += ws.patch_load(-sd, cd, *p.lever_arm_m, p.normal_force_N, c.longitudinal_N, c.lateral_N,
                              c.spin_moment_Nm)
    fx, fy, fz, mx, my, mz = load
    mirror = 1.0 if side == 0 else -1.0
    f, m = np.array([fx, mirror * fy, fz]), np.array([mirror * mx, my, mirror * mz])
    loaded = fz > cp[ContactConstants.qp_min_load]
    own = WheelForces(Q_N=-fy, P_N=fz, Q_over_P=-fy / fz if loaded else 0.0, longitudinal_force_on_rail_N=-fx,
                      force_on_rail_N=(-f).tolist())
    return own, f, m


def _mirror(pose, side):
    y, z, phi, psi = pose
    return (y, z, phi, psi) if side == 0 else (-y, z, -phi, -psi)


def steady_wheel_forces(cg, cp, side, pose, speed, spin):
    """`wheelset.wheel_forces` in steady rolling: (force, moment, wheel record W_*), track axes."""
    rec = np.zeros(W_SIZE)
    fm = ws.wheel_forces(cg, cp, side, pose, steady_rolling(speed, spin), ws.contact_scratch(cg), ws.candidates()[0],
                         False, rec)
    return np.array(fm[:3]), np.array(fm[3:]), rec


def _vertical_force(cg, cp, pose, speed, spin):
    return sum(steady_wheel_forces(cg, cp, side, pose, speed, spin)[0][2] for side in (0, 1))


def _free_spin(cg, cp, pose, speed, spin0):
    """Spin (rad/s) at which the wheelset's total longitudinal contact force vanishes (free rolling)."""
    def fx(spin):
        return sum(steady_wheel_forces(cg, cp, side, pose, speed, spin)[0][0] for side in (0, 1))

    lo, hi = spin0 * 0.995, spin0 * 1.005
    f_lo, f_hi = fx(lo), fx(hi)
    while f_lo * f_hi > 0.0 and hi - lo < 0.2 * spin0:
        lo, hi = lo - 0.005 * spin0, hi + 0.005 * spin0
        f_lo, f_hi = fx(lo), fx(hi)
    if f_lo * f_hi > 0.0:
        return spin0 if abs(fx(spin0)) < 1e-6 else float("nan")
    return brentq(fx, lo, hi, xtol=1e-12 * spin0, rtol=1e-14)


def _touch_height(cg, y, phi, psi):
    """Vertical position (m) at which the first wheel touches its rail, or inf if a wheel has no rail."""
    gap, ys = gap_buffers(cg)
    gl0, _ = geo.min_gap(cg, y, 0.0, phi, psi, gap, ys)
    gr0, _ = geo.min_gap(cg, -y, 0.0, -phi, -psi, gap, ys)
    return -min(gl0, gr0) if max(gl0, gr0) < geo.NO_RAIL_GAP else math.inf


def _wheel_loads(wheel_loads_kn, load_kn, roll_mrad):
    """The prescribed vertical force of each wheel [left, right] (N), or None; refuses what contradicts it."""
    if wheel_loads_kn is None:
        return None
    if load_kn is not None:
        raise ValueError("give either the wheelset load (--load-kn) or the load of each wheel (--wheel-loads-kn), "
                         "not both")
    if roll_mrad is not None:
        raise ValueError("with the load of each wheel (--wheel-loads-kn) prescribed the roll follows from them; "
                         "leave out --roll-mrad")
    loads = list(wheel_loads_kn)
    if len(loads) != 2:
        raise ValueError(f"--wheel-loads-kn takes two loads, LEFT,RIGHT (kN); got {len(loads)}: {wheel_loads_kn!r}")
    return [check_range(f"{side} wheel load --wheel-loads-kn", value, *WHEEL_LOAD_KN, "kN", lo_open=True) * 1e3
            for side, value in zip(SIDES, loads)]


def _spin_rule(spin, pitch_rate_rad_s, cg, cp, speed, spin_nominal):
    """The spin mode and a function pose -> spin (rad/s)."""
    if pitch_rate_rad_s is not None:
        if spin == "free":
            raise ValueError("--spin free solves the pitch rate; leave out --pitch-rate-rad-s (or use --spin "
                             "nominal)")
        lo, hi = (k * spin_nominal for k in PITCH_RATE_REL)
        rate = float(pitch_rate_rad_s)
        if not (math.isfinite(rate) and lo <= rate <= hi):
            raise ValueError(f"pitch rate --pitch-rate-rad-s {rate:g} rad/s is outside the accepted range "
                             f"[{lo:.4f}, {hi:.4f}] rad/s ({PITCH_RATE_REL[0]:g}..{PITCH_RATE_REL[1]:g} times "
                             f"v / r0 = {spin_nominal:.4f} rad/s at this speed and rolling radius)")
        return "prescribed", lambda pose: rate
    if spin not in ("nominal", "free"):
        raise ValueError(f"spin {spin!r} is unknown; choose nominal or free")
    if spin == "free":
        return spin, lambda pose: _free_spin(cg, cp, pose, speed, spin_nominal)
    return spin, lambda pose: spin_nominal


def _vertical_position(cg, cp, y, phi, psi, speed, spin_at, z_touch, load, load_text):
    """Vertical position (m) at which the two wheels together carry `load` (N) at roll phi."""
    def excess(zz):
        pose = (y, zz, phi, psi)
        return _vertical_force(cg, cp, pose, speed, spin_at(pose)) - load

    step = 1e-4
    z_lo = z_touch - step
    while excess(z_lo) <= 0.0:
        step *= 2.0
        z_lo = z_touch - step
        if step > 0.02:
            raise ValueError(f"{load_text} is not reached within 20 mm of interpenetration")
    return brentq(excess, z_lo, z_touch, xtol=1e-14, rtol=1e-13, maxiter=200)


def _wheel_loads_text(loads):
    return (f"wheel loads {loads[0] / 1e3:g},{loads[1] / 1e3:g} kN (--wheel-loads-kn; accepted range per wheel "
            f"(0, {WHEEL_LOAD_KN[1]:g}] kN)")


def _roll_for_wheel_loads(cg, cp, y, psi, speed, spin_at, loads, phi_rigid):
    """Roll (rad) at which each wheel carries its own load.

    A positive roll lifts the left wheel, so the left wheel's shortfall (its load minus the vertical force
    it carries, with both together carrying the sum) rises with the roll: it is bracketed by steps that
    double outward from the rigid-contact roll, then bisected."""
    total = sum(loads)
    text = _wheel_loads_text(loads)

    def shortfall(phi):
        z_touch = _touch_height(cg, y, phi, psi)
        if not math.isfinite(z_touch):
            raise ValueError(f"{text}: the roll that shares them so ({phi * 1e3:.2f} mrad) leaves a wheel without "
                             "rail under it")
        z = _vertical_position(cg, cp, y, phi, psi, speed, spin_at, z_touch, total, text)
        pose = (y, z, phi, psi)
        return loads[0] - steady_wheel_forces(cg, cp, 0, pose, speed, spin_at(pose))[0][2]

    inner, f_inner = phi_rigid, shortfall(phi_rigid)
    direction = 1.0 if f_inner < 0.0 else -1.0
    step = 1e-6
    outer, f_outer = inner, f_inner
    while f_outer * direction < 0.0:
        if step > ROLL_MRAD[1] * 1e-3:
            raise ValueError(f"{text}: no roll within {ROLL_MRAD[1]:g} mrad of the rigid-contact roll "
                             f"({phi_rigid * 1e3:.2f} mrad) shares the load so")
        inner, f_inner = outer, f_outer
        outer = phi_rigid + direction * step
        f_outer = shortfall(outer)
        step *= 2.0
    return outer if f_outer == 0.0 else brentq(shortfall, min(inner, outer), max(inner, outer), xtol=1e-14,
                                               rtol=1e-12, maxiter=200)


def contact_case(pair: WheelRailPair, *, lateral_mm=0.0, yaw_mrad=0.0, roll_mrad=None, load_kn=None,
                 wheel_loads_kn=None, speed_kmh=300.0, grid=64, spin="nominal",
                 pitch_rate_rad_s=None) -> ContactCase:
    """Solve one wheelset contact case with the pair's contact model (user units in, SI out).

    spin: "nominal" = v / r0 (as the vehicle model), "free" = the spin at which the total longitudinal
    contact force of the wheelset vanishes (solved together with the vertical position); a
    `pitch_rate_rad_s` (+ rolling forward) prescribes it instead. `wheel_loads_kn` = (left, right)
    prescribes each wheel's vertical force in place of `load_kn` and `roll_mrad`."""
    cg, cp = pair.cg, pair.cp
    psi = check_range("yaw --yaw-mrad", yaw_mrad, *YAW_MRAD, "mrad") * 1e-3
    speed = check_range("speed --speed-kmh", speed_kmh, *SPEED_KMH, "km/h") / 3.6
    wheel_loads = _wheel_loads(wheel_loads_kn, load_kn, roll_mrad)
    if wheel_loads is None:
        if load_kn is None:
            load_kn = static_wheelset_load() / 1e3
        load = check_range("vertical wheelset load --load-kn", load_kn, *LOAD_KN, "kN", lo_open=True) * 1e3
    else:
        load = sum(wheel_loads)
    spin_nominal = speed / pair.radius
    spin_mode, spin_at = _spin_rule(spin, pitch_rate_rad_s, cg, cp, speed, spin_nominal)
    grid = int(check_range("half-space grid --grid", grid, *GRID, "elements"))
    y = float(lateral_mm) * 1e-3
    if not math.isfinite(y):
        raise ValueError(f"lateral shift {lateral_mm!r} mm is not a number")
    y_lim = contact_range(cg, psi)
    if abs(y) > y_lim:
        raise ValueError(f"lateral shift {lateral_mm:g} mm (--lateral-mm) is beyond what {pair.wheel.name} "
                         f"on {pair.rail.name} can contact at yaw {yaw_mrad:g} mrad; accepted range "
                         f"{-y_lim * 1e3:.1f}..{y_lim * 1e3:.1f} mm (beyond it a contact passes the flange "
                         "tip or the end of the wheel profile)")
    z_rigid, phi_rigid, _ = conicity.rigid_pose(cg, y, psi)
    if wheel_loads is not None:
        phi = _roll_for_wheel_loads(cg, cp, y, psi, speed, spin_at, wheel_loads, phi_rigid)
        roll_input, roll_source, load_text = None, "wheel loads", _wheel_loads_text(wheel_loads)
    else:
        if roll_mrad is None:
            phi, roll_input, roll_source = phi_rigid, None, "rigid contact"
        else:
            phi = roll_input = check_range("roll --roll-mrad", roll_mrad, *ROLL_MRAD, "mrad") * 1e-3
            roll_source = "input"
        load_text = f"vertical wheelset load {load / 1e3:g} kN (accepted range (0, {LOAD_KN[1]:g}] kN)"
    z_touch = _touch_height(cg, y, phi, psi)
    if not math.isfinite(z_touch):          # the roll search keeps to rolls with both rails under the wheels
        raise ValueError(f"roll {phi * 1e3:g} mrad at lateral shift {lateral_mm:g} mm leaves a wheel without "
                         "rail under it; use a roll nearer the rigid-contact roll "
                         f"{phi_rigid * 1e3:.2f} mrad")
    z = _vertical_position(cg, cp, y, phi, psi, speed, spin_at, z_touch, load, load_text)
    pose = (y, z, phi, psi)
    spin_rate = spin_at(pose)
    if not math.isfinite(spin_rate):
        raise ValueError("spin free: no spin within +-10 % of v / r0 balances the longitudinal forces; "
                         "use --spin nominal")
    wheels = []
    total_f, total_m = np.zeros(3), np.zeros(3)
    for side in (0, 1):
        f, m, rec = steady_wheel_forces(cg, cp, side, pose, speed, spin_rate)
        patches = wheel_patch_details(pair, _mirror(pose, side), speed, spin_rate, grid)
        r = Wheel.split(rec)
        own = WheelForces(Q_N=r["lateral_force"], P_N=r["vertical_force"], Q_over_P=r["derailment_coefficient"],
                          longitudinal_force_on_rail_N=r["longitudinal_force"], force_on_rail_N=(-f).tolist())
        laws = None
        if pair.exact_rolling:
            # the exact rolling forces of the patches replace the law's in the totals; the normal forces
            # stay those of the load sharing (docs/contact-report.md)
            laws = {name: _wheel_forces(patches, [p.exact_rolling.laws[name] for p in patches], side, cp)[0]
                    for name in patches[0].exact_rolling.laws} if patches else {}
            own, f, m = _wheel_forces(patches, [p.exact_rolling.creep_force for p in patches], side, cp)
        total_f += f
        total_m += m
        wheels.append(WheelContact(side=SIDES[side],
                                   creep_forces="exact rolling" if pair.exact_rolling else pair.contact.creep_model,
                                   **vars(own), wheel_lift_m=r["wheel_lift"], min_gap_m=r["min_gap"],
                                   patch_count=len(patches), patches=patches, laws=laws))
    pose_out = WheelsetPose(lateral_m=y, yaw_rad=psi, roll_rad=phi, roll_source=roll_source, vertical_m=z,
                            touch_vertical_m=z_touch, rigid_vertical_m=z_rigid, rigid_roll_rad=phi_rigid,
                            lateral_range_m=y_lim, spin_rad_s=spin_rate, spin_mode=SPIN_MODES[spin_mode],
                            nominal_spin_rad_s=spin_nominal, effective_rolling_radius_m=speed / spin_rate)
    totals = WheelsetTotals(force_N=total_f.tolist(), moment_Nm=total_m.tolist(),
                            vertical_load_N=float(total_f[2]), load_error_rel=float(total_f[2] / load - 1.0))
    return ContactCase(pair=pair, lateral_m=y, yaw_rad=psi, roll_input_rad=roll_input, load_N=load,
                       wheel_loads_N=wheel_loads, speed_m_s=speed, grid=grid, pose=pose_out, wheels=wheels,
                       totals=totals)
