"""`railderail bench --only contact`: cost of the wheel-rail contact evaluation (one core, after compilation).

One *evaluation* is what the vehicle model does per right-hand side: `wheelset.wheel_forces` for all eight
wheels of the car. The eight wheels sit at realistic poses of LM on UIC60 1:40 (gauge 1435 mm, back-to-back
1353 mm, r0 0.46 m), each wheelset loaded to the CRH3 static axle load (112.1 kN) by
`methods.contact_case.contact_case`:

    wheelset 1: centred (tread contact on both wheels)
    wheelset 2: y = 3 mm, yaw 2 mrad (tread)
    wheelset 3: y = 8.7 mm, yaw 5 mrad (left wheel at the flange root, 31 deg)
    wheelset 4: y = 9.5 mm, yaw 10 mrad (left wheel on the flange, 62 deg)

Timing: a numba loop over the eight wheels repeated n times (n chosen for ~0.1 s per run), median of
REPEATS runs, reported in microseconds per evaluation of all eight wheels. Each loop alternates between
the pose and the pose moved by a typical integration step (0.02 mm laterally, 0.01 mrad in roll and yaw),
so the tracked search has to follow the minima. Keys:

    contact_eval_us_hertz            full contact search + Hertz + Shen-Hedrick-Elkins
    contact_eval_us_hertz_tracked    the in-step tracked search (`geometry.track_patches`) + Hertz + SHE
    contact_eval_us_table            contact table lookup (`contact.table`, the vehicle model's default) +
                                     Hertz + SHE; wheelset 4's yaw is at the table's limit (10 mrad): its
                                     moved pose (10.01 mrad) is searched online, as in a simulation
    contact_eval_us_fastsim          full search + Hertz + FASTSIM (20 x 20)
    contact_eval_us_discrete         full search + Kik-Piotrowski + SHE on its equivalent ellipse
    contact_search_us_full           `geometry.find_patches` alone, eight wheels
    contact_search_us_online         `geometry.track_patches` alone, eight wheels
    contact_lookup_us_table          `table.table_patches` alone, eight wheels (-1 = online fallback counted)
    contact_table_build_s            building the contact table (`table.attach`, after compilation)
    halfspace_patch_ms_64            one exact half-space solve (`halfspace.halfspace_patch`) of the centred
                                     tread patch on a 64 x 64 grid (force control), milliseconds
    exact_rolling_ms_64              one exact steady-rolling solve (`exact_rolling.exact_rolling`) on the
                                     same patch's Hertz ellipse (`exact_rolling.hertz_grid`, 64 x 64) with its
                                     creepages at v / r0 (partial slip), milliseconds
    contact_compile_s                first call of the timing loops (numba compilation or cache load)
"""
from __future__ import annotations

import math
import time
import warnings

import numba
import numpy as np

from .. import jit
from ..contact import exact_rolling as er
from ..contact import geometry as geo
from ..contact import halfspace as hs
from ..contact import table as tab
from ..contact import wheelset as ws
from ..methods.contact_case import contact_case
from ..methods.contact_patch import gap_run, left_wheel_patches
from ..methods.wheel_rail_pair import build_pair, static_wheelset_load
from ..contact.layout import W_SIZE, Patch

REPEATS = 7
TARGET_S = 0.1
POSES = ((0.0, 0.0), (3.0, 2.0), (8.7, 5.0), (9.5, 10.0))     # (lateral mm, yaw mrad) per wheelset
STEP = (2e-5, 0.0, 1e-5, 1e-5)                                 # pose change within a step (y, z, phi, psi)


@numba.njit(cache=False, **jit.OPTIONS)
def _eval_loop(n, poses, step, cg, cp, speed, spin, tracked, scratch, cands, recs):
    acc = 0.0
    motion = (speed, 0.0, 0.0, 0.0, 0.0, 0.0, spin, speed)
    for it in range(n):
        f = 1.0 if it % 2 == 1 else 0.0
        for w in range(8):
            i = w // 2
            side = w % 2
            pose = (poses[i, 0] + f * step[0], poses[i, 1] + f * step[1], poses[i, 2] + f * step[2],
                    poses[i, 3] + f * step[3])
            fm = ws.wheel_forces(cg, cp, side, pose, motion, scratch, cands[w], tracked, recs[w])
            acc += fm[2]
    return acc


@numba.njit(cache=False, **jit.OPTIONS)
def _search_loop(n, poses, step, cg, tracked, lookup, gap, ys, patches, cands):
    count = 0
    for it in range(n):
        f = 1.0 if it % 2 == 1 else 0.0
        for w in range(8):
            i = w // 2
            m = 1.0 if w % 2 == 0 else -1.0
            y = m * (poses[i, 0] + f * step[0])
            z = poses[i, 1] + f * step[1]
            phi = m * (poses[i, 2] + f * step[2])
            psi = m * (poses[i, 3] + f * step[3])
            if tracked and lookup:
                c, _ = tab.table_patches(cg, y, z, phi, psi, patches, cands[w])
                count += c
            elif tracked:
                count += geo.track_patches(cg, y, z, phi, psi, gap, ys, patches, cands[w])
            else:
                c, _ = geo.find_patches(cg, y, z, phi, psi, gap, ys, patches, cands[w])
                count += c
    return count


def _median_us(fn, per_call):
    """Median over REPEATS of fn(n) / n in microseconds, n chosen for about TARGET_S per run."""
    fn(1)
    t0 = time.perf_counter()
    fn(per_call)
    dt = max(time.perf_counter() - t0, 1e-7)
    n = max(2, int(math.ceil(per_call * TARGET_S / dt)))
    n += n % 2                                                # whole pairs (pose, moved pose)
    times = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        fn(n)
        times.append((time.perf_counter() - t0) / n)
    return float(np.median(times)) * 1e6


def _loaded_poses(model):
    """The wheel/rail pair with `model` and the four wheelsets' poses (y, z, phi, psi) under load."""
    pair = build_pair(model=model)
    rows = []
    for lateral, yaw in POSES:
        p = contact_case(pair, lateral_mm=lateral, yaw_mrad=yaw).pose
        rows.append((p.lateral_m, p.vertical_m, p.roll_rad, p.yaw_rad))
    return pair, np.array(rows)


def run() -> dict:
    figures = {}
    compile_s = 0.0
    for model in ("hertz", "fastsim", "discrete"):
        pair, poses = _loaded_poses(model)
        cg, cp = pair.cg, pair.cp
        speed = 300.0 / 3.6
        spin = speed / pair.radius
        scratch = ws.contact_scratch(cg)
        cands = ws.candidates(8)
        recs = np.zeros((8, W_SIZE))
        step = np.array(STEP)

        def evaluate(n, tracked=False, geometry=cg):
            return _eval_loop(n, poses, step, geometry, cp, speed, spin, tracked, scratch, cands, recs)

        t0 = time.perf_counter()
        evaluate(1)
        compile_s += time.perf_counter() - t0
        figures[f"contact_eval_us_{model}"] = _median_us(evaluate, 1)
        if model == "hertz":
            evaluate(1)                                  # full search at the pose: fills the candidates
            figures["contact_eval_us_hertz_tracked"] = _median_us(lambda n: evaluate(n, True), 1)

            def search(n, tracked=False, lookup=False, geometry=cg):
                return _search_loop(n, poses, step, geometry, tracked, lookup, scratch.gap, scratch.ys,
                                    scratch.patches, cands)

            t0 = time.perf_counter()
            search(1)
            search(1, True)
            table_cg = tab.attach(cg)
            evaluate(1, geometry=table_cg)
            search(1, True, True, table_cg)
            compile_s += time.perf_counter() - t0
            figures["contact_search_us_full"] = _median_us(search, 1)
            search(1)
            figures["contact_search_us_online"] = _median_us(lambda n: search(n, True), 1)
            figures["contact_lookup_us_table"] = _median_us(lambda n: search(n, True, True, table_cg), 1)
            figures["contact_eval_us_table"] = _median_us(lambda n: evaluate(n, True, table_cg), 1)
            t0 = time.perf_counter()
            tab.attach(cg)
            figures["contact_table_build_s"] = time.perf_counter() - t0
            hertz_pair, hertz_poses = pair, poses

    # one 64 x 64 half-space solve of the centred tread patch at the static wheel load
    pose = (0.0, float(hertz_poses[0, 1]), 0.0, 0.0)
    scratch = ws.contact_scratch(cg)
    patches = scratch.patches
    n_p, _ = geo.find_patches(cg, *pose, scratch.gap, scratch.ys, patches, ws.candidates()[0])
    k = int(np.argmin(patches[:n_p, Patch.gap]))
    cd = 1.0 / math.sqrt(1.0 + patches[k, Patch.slope] ** 2)
    s, g, R, _, _ = gap_run(cg, pose, int(patches[k, Patch.grid_index]), patches[k, Patch.gap], cd,
                            margin=3)
    su = np.linspace(s[0], s[-1], 64)
    x_half = 1.05 * math.sqrt(2.0 * R.max() * (-patches[k, Patch.gap] * cd))
    h, x, dx, dy = hs.wheelrail_gap(su, np.interp(su, s, g), np.interp(su, s, R), x_half, 64)
    load = 0.5 * static_wheelset_load()
    E, nu = pair.contact.youngs_modulus, pair.contact.poisson_ratio
    times = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        hs.halfspace_patch(h, dx, dy, E, nu, N=load, x=x, y=su)          # kernel FFT cached per grid
        for _ in range(5):
            t0 = time.perf_counter()
            hs.halfspace_patch(h, dx, dy, E, nu, N=load, x=x, y=su)
            times.append(time.perf_counter() - t0)
    figures["halfspace_patch_ms_64"] = float(np.median(times)) * 1e3

    # one 64 x 64 steady-rolling solve on the same patch's Hertz ellipse, with its creepages
    rows = left_wheel_patches(hertz_pair.cg, hertz_pair.cp, pose, speed, spin)
    row = Patch.split(rows[int(np.argmax(rows[:, Patch.normal_force]))])
    p_n, x, y, dx, dy = er.hertz_grid(float(row["hertz_a"]), float(row["hertz_b"]), float(row["normal_force"]),
                                      64, 64)
    creepage = (float(row["creepage_x"]), float(row["creepage_y"]), float(row["spin_creepage"]))
    mu = hertz_pair.contact.friction_coefficient
    er.exact_rolling(*creepage, p_n, dx, dy, E, nu, mu, x=x, y=y)      # compiles / loads the sweep, caches
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        er.exact_rolling(*creepage, p_n, dx, dy, E, nu, mu, x=x, y=y)
        times.append(time.perf_counter() - t0)
    figures["exact_rolling_ms_64"] = float(np.median(times)) * 1e3
    figures["contact_compile_s"] = compile_s
    return figures
