"""`railderail bench --profile`: where one right-hand side of the vehicle core spends its time, and why a run
takes the steps it takes (docs/performance.md).

No Python profiler sees inside compiled numba code, so each part of `dynamics.rhs` is timed in isolation: a
numba loop calls that part's own core function n times at one state (n chosen for about TARGET_S per
run; the minimum of REPEATS runs). The state is the run's own after WINDOW_S of simulated time, with the
contact candidates its last full search left. Every time is CPU time (`time.process_time`) and the best of
REPEATS runs, the window's run as the parts' loops: integrator_us is the difference of the two, and one
run's wall time against the parts' best made it read anything from -10 to 30 us per step with the load of
the shared machine (docs/performance.md, "The stepper's share"). Parts:

    rhs_full_us, rhs_tracked_us    the whole right-hand side, with the full contact search (the step's last
                                   stage) and with the tracked one (its five inner stages)
    kinematics_us                  `dynamics.kinematics`: each body's track frame and rotation matrices
    track_frame_us                 of which the track lookups (`alignment.body_frame` per body)
    suspension_us                  `dynamics.suspension`, all elements; bushings_us, dampers_us,
                                   bump_stops_us, anti_roll_bars_us: the same with one kind of element only
    wheel_on_rail_us               the eight wheels' poses on their rails (`dynamics.wheel_on_rail`, with the
                                   irregularity lookup `rails.rail_deviation`)
    contact_tracked_us, contact_full_us   the eight `wheelset.wheel_forces` (with their poses) as the inner
                                   stages and the last stage call them
    contact_table_us               of which the contact search: the table lookup (`table.table_patches`) or
                                   the online search where the pose leaves the table
    creep_law_us                   of which the creep law (`creep.creep_law` with Kalker's coefficients from
                                   the model's table) on the loaded patches
    elastic_track_us               the eight rails' accelerations (`track.elastic.rail_accelerations`; 0 on
                                   rigid track, where they are not called)
    aerodynamics_us                `loads.aerodynamics.aerodynamic_load` (returns at once in still air)
    step_us                        CPU time per integration step of the window's run (accepted + rejected),
                                   the best of REPEATS runs
    integrator_us                  step_us less the five tracked and one full right-hand sides of a step:
                                   the stage sums, the error norm, the output rows (each with one more
                                   full right-hand side at its interpolated state) and the checks
    output_row_us                  one output row (`integrator._row_at`: its full right-hand side at the
                                   row's state, the row's fill and the derailment check)
    output_rows_us                 the output rows' share of a step: output_row_us x rows per step

Steps: accepted and rejected per simulated second over the window; the floor that the largest step
(`simulate.MAX_STEP`) sets (the steps run past the output instants: dense output); the
steps per second with the tolerances ten times looser and ten times tighter (an error-controlled run
takes 10^(1/5) = 1.58 times fewer steps for ten times looser tolerances, a stability-limited one about as
many); and the stability limit of Dormand-Prince 5(4) at the state: the largest h with |R(h lambda)| <= 1
for every eigenvalue lambda of the Jacobian (central differences of the right-hand side with the full
contact search), with the mode that sets it. Each mode is named by where its kinetic energy lies: the
velocity part of its eigenvector weighted by each velocity's mass or inertia (|v_i|^2 m_i), summed per kind
of body (car body, bogies, wheelsets, rails) and degree of freedom (a wheelset's pitch rate is its spin), as
shares of the whole; the largest raw entry of the eigenvector would name the spin rates, large numbers, for
modes whose energy lies elsewhere. The wheelsets' spin mode (the one whose largest share is the spin) gets
its own limit: its eigenvalue scales with 1 / speed, so it sets the step at low speeds.
"""
from __future__ import annotations

from dataclasses import replace
import math
import time

import numba
import numpy as np

from .. import jit
from ..contact import creep
from ..contact import geometry as geo
from ..contact import table as tab
from ..contact import wheelset as ws
from ..contact.layout import ContactConstants, Patch, Wheel
from ..loads.aerodynamics import aerodynamic_load
from ..parameters import TrackParameters
from ..track import alignment as trk
from ..track import elastic as track_elastic
from ..track.irregularity import resolve
from ..track.layout import N_RAIL_DOF, ElasticTrack, RailDof
from ..vehicle import dynamics as dyn
from ..vehicle import integrator as itg
from ..vehicle.dynamics import Kinematics
from ..vehicle.layout import BOGIES, BodyTable, Dof, N_BODY, N_DOF, N_OUT, N_STATE, State, Vector, WHEELSETS
from ..vehicle.simulate import MAX_STEP, Simulation, scenario

REPEATS = 3
TARGET_S = 0.1
WINDOW_S = 4.0                # simulated seconds before the profiled state (the default run derails at 5.2 s)
TOLERANCE_FACTOR = 10.0


def cases():
    """The profiled runs: {name: Scenario} (those of `railderail bench --only vehicle`)."""
    irregular = replace(scenario(radius=1000.0, speed_kmh=250.0),
                        irregularity=resolve("erri-high", 1, TrackParameters().line_length))
    return {"rigid_smooth": scenario(radius=1000.0, speed_kmh=300.0),
            "rigid_irregular": irregular,
            "elastic_irregular": replace(irregular, track_model="elastic"),
            "discrete": scenario(radius=1000.0, speed_kmh=300.0, contact_model="discrete")}


# ---------------------------------------------------------------------------------------- timing kernels
_njit = numba.njit(cache=False, **jit.OPTIONS)


@_njit
def _rhs_loop(n, x, dx, model, sp, buffers, tracked):
    acc = 0.0
    for _ in range(n):
        acc += dyn.rhs(x, dx, model, sp, buffers, tracked)
    return acc


@_njit
def _row_loop(n, row, t, x, dx, model, sp, work):
    acc = 0.0
    for _ in range(n):
        acc += itg._row_at(row, t, x, dx, model, sp, work)[1]
    return acc


@_njit
def _kinematics_loop(n, x, bodies, track, sp, kin):
    acc = 0.0
    for _ in range(n):
        acc += dyn.kinematics(x, bodies, track, sp, kin)[0]
    return acc


@_njit
def _track_frame_loop(n, x, bodies, track):
    acc = 0.0
    for _ in range(n):
        for b in range(N_BODY):
            sb = x[State.s] + bodies[b, BodyTable.station]
            X, Y, heading, roll, kap, droll = trk.body_frame(track, sb)
            acc += X + Y + heading + roll + kap + droll
    return acc


@_njit
def _suspension_loop(n, x, dx, model, kin):
    for _ in range(n):
        dyn.suspension(x, dx, model, kin)
    return kin[0, Kinematics.force]


@_njit
def _wheel_motion(x, kin, bodies, b, v):
    """The wheelset's track_motion for `dynamics.wheel_on_rail`, as `dynamics.rhs` forms it."""
    ov = State.velocities + N_DOF * b
    return (kin[b, Kinematics.track_velocity + Vector.x], kin[b, Kinematics.track_velocity + Vector.y],
            kin[b, Kinematics.track_velocity + Vector.z], x[ov + Dof.roll],
            kin[b, Kinematics.track_angular_velocity + Vector.y], x[ov + Dof.yaw], x[ov + Dof.pitch], v)


@_njit
def _wheels_loop(n, x, model, kin, v, buffers, tracked, forces, search_only):
    """The eight wheels: poses (always), and the contact forces (`forces`) or the contact search alone
    (`search_only`), as in `dynamics.rhs`."""
    acc = 0.0
    bodies = model.bodies
    for _ in range(n):
        for b in WHEELSETS:
            o = State.positions + N_DOF * b
            sw = x[State.s] + bodies[b, BodyTable.station]
            for side in range(2):
                k = 2 * (b - WHEELSETS[0]) + side
                dfl = x[State.rail_deflections + k * N_RAIL_DOF:State.rail_deflections + (k + 1) * N_RAIL_DOF]
                rate = x[State.rail_rates + k * N_RAIL_DOF:State.rail_rates + (k + 1) * N_RAIL_DOF]
                pose, motion, a, c, pr, ry, rz = dyn.wheel_on_rail(x, o, bodies[b, BodyTable.height], model.rails,
                                                                   model.support, side, sw, dfl, rate,
                                                                   _wheel_motion(x, kin, bodies, b, v))
                acc += pose[0] + motion[0] + a + c + pr + ry + rz
                if forces:
                    acc += ws.wheel_forces(model.cg, model.cp, side, pose, motion, buffers.contact,
                                           buffers.cands[k], tracked, buffers.recs[k])[2]
                elif search_only:
                    m = 1.0 if side == 0 else -1.0
                    y, z, phi, psi = pose[0] * m, pose[1], pose[2] * m, pose[3] * m
                    scratch = buffers.contact
                    count, _ = tab.table_patches(model.cg, y, z, phi, psi, scratch.patches, buffers.cands[k])
                    if count < 0:                   # outside the table, or no table: the online search
                        count = geo.track_patches(model.cg, y, z, phi, psi, scratch.gap, scratch.ys,
                                                  scratch.patches, buffers.cands[k])
                    acc += count
    return acc


@_njit
def _creep_loop(n, rows, cp, model_id, mu, shear):
    """The creep law on the patch rows as `wheelset.wheel_forces` calls it (Kalker's coefficients from cp's table)."""
    acc = 0.0
    for _ in range(n):
        for r in range(rows.shape[0]):
            a, b = rows[r, 3], rows[r, 4]
            C11, C22, C23, C33 = creep.tabulated_coefficients(cp, a, b)
            fx, fy, mz = creep.creep_law(model_id, rows[r, 0], rows[r, 1], rows[r, 2], a, b, rows[r, 5], mu, shear,
                                         C11, C22, C23, C33)
            acc += fx + fy + mz
    return acc


@_njit
def _elastic_loop(n, x, support):
    acc = 0.0
    for _ in range(n):
        for k in range(8):
            dfl = x[State.rail_deflections + k * N_RAIL_DOF:State.rail_deflections + (k + 1) * N_RAIL_DOF]
            rate = x[State.rail_rates + k * N_RAIL_DOF:State.rail_rates + (k + 1) * N_RAIL_DOF]
            ay, az, ar = track_elastic.rail_accelerations(support, dfl, rate, 1.0e4, 5.0e4, 1.0e3)
            acc += ay + az + ar
    return acc


@_njit
def _aero_loop(n, aero, s, v):
    acc = 0.0
    for _ in range(n):
        acc += aerodynamic_load(aero, s, v)[2]
    return acc


def min_us(fn):
    """Minimum over REPEATS of fn(n) / n in microseconds of CPU time, n chosen for about TARGET_S per run."""
    fn(1)
    t0 = time.process_time()
    fn(10)
    dt = max(time.process_time() - t0, 1e-7) / 10
    n = max(10, int(math.ceil(TARGET_S / dt)))
    times = []
    for _ in range(REPEATS):
        t0 = time.process_time()
        fn(n)
        times.append((time.process_time() - t0) / n)
    return min(times) * 1e6


# ---------------------------------------------------------------------------------------- the profile
def _window(sc, window_s):
    """A Simulation run for window_s (or to its end): (simulation, wall s, CPU s, simulated s, accepted,
    rejected)."""
    sim = Simulation(sc)
    sim.advance(0.01)                                       # compile or load the cache outside the timing
    t_start = sim.t
    steps0 = sim.steps
    t0, c0 = time.perf_counter(), time.process_time()
    while sim.status == itg.RUNNING and sim.t < window_s - 1e-9:
        sim.advance(min(1.0, window_s - sim.t))
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    accepted, rejected = (a - b for a, b in zip(sim.steps, steps0))
    return sim, wall, cpu, sim.t - t_start, accepted, rejected


def _steps_per_s(sc, window_s):
    _, _, _, simulated, accepted, rejected = _window(sc, window_s)
    return (accepted + rejected) / simulated


def dopri_stability(z):
    """|R(z)| of Dormand-Prince 5(4) (the 5th-order solution): R = sum z^k / k!, k <= 5, + z^6 / 600."""
    return np.abs(1 + z + z ** 2 / 2 + z ** 3 / 6 + z ** 4 / 24 + z ** 5 / 120 + z ** 6 / 600)


def stability_limit(eigenvalues):
    """The largest h (s) with |R(h lambda)| <= 1 for all eigenvalues with a negative real part, and the index
    of the eigenvalue that sets it."""
    best, which = math.inf, -1
    for i, lam in enumerate(eigenvalues):
        if lam.real >= 0.0 or abs(lam) == 0.0:
            continue
        hi = 10.0 / abs(lam)              # |R| > 1 there for any lambda of the left half-plane (|z| = 10)
        lo = 0.0
        for _ in range(60):               # the first exit from the stable region, on a fine scan then bisection
            mid = 0.5 * (lo + hi)
            if np.all(dopri_stability(np.linspace(0.0, mid, 64)[1:] * lam) <= 1.0 + 1e-12):
                lo = mid
            else:
                hi = mid
        if lo < best:
            best, which = lo, i
    return best, which


def jacobian(sim):
    """Central-difference Jacobian of the right-hand side (full contact search) at the simulation's state,
    over the states the error control counts, and their indices."""
    active = np.flatnonzero(np.isfinite(sim.control.atol))
    active = active[active != State.s]
    sp, arrays = sim.speed_table, sim.model.arrays
    buffers = itg.workspace(sim.model.cg).rhs
    x0 = sim.x.copy()
    J = np.zeros((len(active), len(active)))
    dp, dm = np.zeros(N_STATE), np.zeros(N_STATE)
    for j, i in enumerate(active):
        step = 1e-7 * max(1.0, abs(x0[i])) if i >= State.velocities and i < State.dampers else 1e-8
        xp, xm = x0.copy(), x0.copy()
        xp[i] += step
        xm[i] -= step
        dyn.rhs(xp, dp, arrays, sp, buffers, False)
        dyn.rhs(xm, dm, arrays, sp, buffers, False)
        J[:, j] = (dp[active] - dm[active]) / (2.0 * step)
    return J, active


_INERTIA = {Dof.lateral: BodyTable.mass, Dof.vertical: BodyTable.mass, Dof.roll: BodyTable.roll_inertia,
            Dof.pitch: BodyTable.pitch_inertia, Dof.yaw: BodyTable.yaw_inertia}
_RAIL_INERTIA = {RailDof.lateral: ElasticTrack.lateral_mass, RailDof.vertical: ElasticTrack.vertical_mass,
                 RailDof.roll: ElasticTrack.roll_inertia}


def _body_kind(b):
    return "wheelsets" if b in WHEELSETS else "bogies" if b in BOGIES else "car body"


def kinetic_groups(arrays, active):
    """For each of the `active` states: the mass or inertia of its velocity (0 for positions, damper
    elongations and the track position, which carry no kinetic energy) and the name of its group, '<kind of
    body> <dof>' (a wheelset's pitch rate: 'wheelsets spin'; a rail's: 'rails <dof>')."""
    masses, groups = np.zeros(len(active)), []
    for j, i in enumerate(active):
        group = ""
        if State.velocities <= i < State.velocities.stop:
            b, d = divmod(int(i - State.velocities), N_DOF)
            masses[j] = arrays.bodies[b, _INERTIA[Dof(d)]]
            group = f"{_body_kind(b)} {'spin' if b in WHEELSETS and d == Dof.pitch else Dof(d).name}"
        elif State.rail_rates <= i < State.rail_rates.stop:
            d = RailDof(int(i - State.rail_rates) % N_RAIL_DOF)
            masses[j] = arrays.support[_RAIL_INERTIA[d]]
            group = f"rails {d.name}"
        groups.append(group)
    return masses, groups


def energy_shares(vector, masses, groups):
    """A mode's kinetic energy per group, as shares of the whole, largest first: [(group, share)]."""
    energy = masses * np.abs(vector) ** 2
    total = energy.sum()
    per = {}
    for e, g in zip(energy, groups):
        if g:
            per[g] = per.get(g, 0.0) + e / total
    return sorted(per.items(), key=lambda kv: -kv[1])


def shares_text(shares, floor=0.05):
    """'wheelsets vertical 45 %, wheelsets roll 37 %, ...' for the shares of at least `floor`."""
    return ", ".join(f"{g} {100.0 * v:.0f} %" for g, v in shares if v >= floor)


def limiting_modes(eigenvalues, vectors, masses, groups):
    """Every oscillatory or decaying mode (one of each conjugate pair), ordered by the Dormand-Prince
    stability limit it alone sets: [(limit s, frequency Hz, damping ratio, energy shares, eigenvalue)]."""
    modes = []
    for i, lam in enumerate(eigenvalues):
        if lam.imag < 0.0:
            continue
        h, which = stability_limit(np.array([lam]))
        if which < 0:
            continue
        modes.append((h, abs(lam.imag) / (2.0 * math.pi), -lam.real / abs(lam),
                      energy_shares(vectors[:, i], masses, groups), lam))
    return sorted(modes, key=lambda m: m[0])


def _creep_rows(sim):
    """The loaded patches of the eight wheels at the state: (xi_x, xi_y, phi, a, b, N) per patch."""
    rows = []
    arrays, x = sim.model.arrays, sim.x
    buffers = itg.workspace(sim.model.cg).rhs
    dx = np.zeros(N_STATE)
    v = dyn.rhs(x, dx, arrays, sim.speed_table, buffers, False)
    scratch = ws.contact_scratch(sim.model.cg)
    for b in WHEELSETS:
        o = State.positions + N_DOF * b
        sw = x[State.s] + arrays.bodies[b, BodyTable.station]
        for side in range(2):
            k = 2 * (b - WHEELSETS[0]) + side
            dfl = x[State.rail_deflections + k * N_RAIL_DOF:State.rail_deflections + (k + 1) * N_RAIL_DOF]
            rate = x[State.rail_rates + k * N_RAIL_DOF:State.rail_rates + (k + 1) * N_RAIL_DOF]
            pose, motion, *_ = dyn.wheel_on_rail(x, o, arrays.bodies[b, BodyTable.height], arrays.rails,
                                                 arrays.support, side, sw, dfl, rate,
                                                 _wheel_motion(x, buffers.kin, arrays.bodies, b, v))
            rec = np.zeros(buffers.recs.shape[1])
            ws.wheel_forces(arrays.cg, arrays.cp, side, pose, motion, scratch, ws.candidates()[0], False, rec)
            for q in range(int(rec[Wheel.contact_count])):
                p = Patch.split(scratch.patches[q])
                if p["normal_force"] > 0.0:
                    rows.append([p["creepage_x"], p["creepage_y"], p["spin_creepage"], p["creep_a"],
                                 p["creep_b"], p["normal_force"]])
    return np.array(rows).reshape(-1, 6)


def profile_case(sc, window_s=WINDOW_S):
    """The profile of one run (module docstring): {key: value}."""
    # the window's run timed as the parts are: the best of REPEATS (the runs are the same, step for step)
    runs = [_window(sc, window_s) for _ in range(REPEATS)]
    sim, _, _, simulated, accepted, rejected = runs[-1]
    wall, cpu = min(r[1] for r in runs), min(r[2] for r in runs)
    out = {"simulated_s": simulated, "wall_s": wall, "real_time_factor": simulated / wall, "cpu_s": cpu,
           "real_time_factor_cpu": simulated / cpu,
           "accepted_per_s": accepted / simulated, "rejected_per_s": rejected / simulated,
           "step_floor_per_s": 1.0 / MAX_STEP,
           "mean_step_ms": 1e3 * simulated / accepted}
    model, arrays, x, sp = sim.model, sim.model.arrays, sim.x.copy(), sim.speed_table
    buffers = sim.work.rhs
    dx = np.zeros(N_STATE)
    v = dyn.rhs(x, dx, arrays, sp, buffers, False)                    # the candidates of a full search
    t = {}
    t["rhs_full_us"] = min_us(lambda n: _rhs_loop(n, x, dx, arrays, sp, buffers, False))
    dyn.rhs(x, dx, arrays, sp, buffers, False)
    t["rhs_tracked_us"] = min_us(lambda n: _rhs_loop(n, x, dx, arrays, sp, buffers, True))
    kin = buffers.kin
    t["kinematics_us"] = min_us(lambda n: _kinematics_loop(n, x, arrays.bodies, arrays.track, sp, kin))
    t["track_frame_us"] = min_us(lambda n: _track_frame_loop(n, x, arrays.bodies, arrays.track))
    t["suspension_us"] = min_us(lambda n: _suspension_loop(n, x, dx, arrays, kin))
    kinds = ("bush", "damp", "bump", "arb")
    for kind, key in zip(kinds, ("bushings_us", "dampers_us", "bump_stops_us", "anti_roll_bars_us")):
        only = arrays._replace(**{k: getattr(arrays, k)[:0] for k in kinds if k != kind})
        t[key] = min_us(lambda n, only=only: _suspension_loop(n, x, dx, only, kin))
    dyn.kinematics(x, arrays.bodies, arrays.track, sp, kin)
    t["wheel_on_rail_us"] = min_us(lambda n: _wheels_loop(n, x, arrays, kin, v, buffers, True, False, False))
    dyn.rhs(x, dx, arrays, sp, buffers, False)
    t["contact_tracked_us"] = min_us(lambda n: _wheels_loop(n, x, arrays, kin, v, buffers, True, True, False))
    t["contact_full_us"] = min_us(lambda n: _wheels_loop(n, x, arrays, kin, v, buffers, False, True, False))
    t["contact_table_us"] = min_us(lambda n: _wheels_loop(n, x, arrays, kin, v, buffers, True, False, True)) \
        - t["wheel_on_rail_us"]
    rows = _creep_rows(sim)
    cp = arrays.cp
    law = (int(cp[ContactConstants.creep_model]), cp[ContactConstants.friction], cp[ContactConstants.shear_modulus])
    t["creep_law_us"] = min_us(lambda n: _creep_loop(n, rows, cp, *law))
    out["loaded_patches"] = len(rows)
    elastic = arrays.support[ElasticTrack.elastic] > 0.5            # rigid track: not called
    t["elastic_track_us"] = min_us(lambda n: _elastic_loop(n, x, arrays.support)) if elastic else 0.0
    t["aerodynamics_us"] = min_us(lambda n: _aero_loop(n, arrays.aero, x[State.s], v))
    work = itg.workspace(arrays.cg)                       # the row's own buffers: the run's stay untouched
    work.out_contact[:] = sim.work.last_contact
    row = np.zeros(N_OUT)
    t["output_row_us"] = min_us(lambda n: _row_loop(n, row, sim.t, x, dx, arrays, sp, work))
    t["step_us"] = 1e6 * cpu / (accepted + rejected)
    t["integrator_us"] = t["step_us"] - 5.0 * t["rhs_tracked_us"] - t["rhs_full_us"]
    t["output_rows_us"] = t["output_row_us"] * sc.output_rate * simulated / (accepted + rejected)
    out.update(t)
    # why this many steps
    looser = replace(sc, atol=sc.atol * TOLERANCE_FACTOR, rtol=sc.rtol * TOLERANCE_FACTOR)
    tighter = replace(sc, atol=sc.atol / TOLERANCE_FACTOR, rtol=sc.rtol / TOLERANCE_FACTOR)
    out["steps_per_s"] = (accepted + rejected) / simulated
    out["steps_per_s_tolerance_x10"] = _steps_per_s(looser, window_s)
    out["steps_per_s_tolerance_div10"] = _steps_per_s(tighter, window_s)
    J, active = jacobian(sim)
    lam, vec = np.linalg.eig(J)
    masses, groups = kinetic_groups(arrays, active)
    modes = limiting_modes(lam, vec, masses, groups)
    h_stab, hz, damping, shares, _ = modes[0]
    out["stability_limit_ms"] = 1e3 * h_stab
    out["stiffest_mode_hz"] = hz
    out["stiffest_mode_damping"] = damping
    out["stiffest_mode"] = shares[0][0]
    out["stiffest_mode_energy"] = shares_text(shares)
    spin = next((m for m in modes if m[3][0][0] == "wheelsets spin"), None)
    out["spin_mode_limit_ms"] = 1e3 * spin[0] if spin else math.nan
    out["spin_mode_energy"] = shares_text(spin[3]) if spin else ""
    out["fastest_eigenvalue_1_s"] = float(np.max(np.abs(lam)))
    return out


def profile(names=None, window_s=WINDOW_S):
    """{case: profile_case(...)} for the named cases (default: all of `cases()`)."""
    all_cases = cases()
    names = names or list(all_cases)
    unknown = [n for n in names if n not in all_cases]
    if unknown:
        raise ValueError(f"unknown profile case(s) {', '.join(unknown)}; choose from {', '.join(all_cases)}")
    return {name: profile_case(all_cases[name], window_s) for name in names}


def text(result):
    """The profile as a table, one column per case, then the modes' energy shares, one line per case."""
    names = list(result)
    keys = list(result[names[0]])
    lines = [f"{'':30s}" + "".join(f"{n:>20s}" for n in names)]
    for key in keys:
        if isinstance(result[names[0]][key], str) and key.endswith("_energy"):
            continue
        cells = []
        for n in names:
            value = result[n][key]
            cells.append(f"{value:>20s}" if isinstance(value, str) else f"{value:>20.4g}")
        lines.append(f"{key:30s}" + "".join(cells))
    for key in (k for k in keys if k.endswith("_energy")):
        lines.append(f"{key} (kinetic energy shares of 5 % or more):")
        lines.extend(f"  {n:20s}{result[n][key]}" for n in names)
    return "\n".join(lines)
