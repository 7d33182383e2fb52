"""`railderail bench --only methods`: wall time of each method (after compilation).

root_locus_s: 100 speeds 100-600 km/h; limit_cycle_s: the default scan (200-600 km/h by 50) and
bisection to 1 km/h; sweep_s: the progressive trial (staircase, no refinement) on the paper's six radii
in parallel processes on this machine's cores; sweep_refined_s: the same with the bisection over
constant speeds; cwc_s: the default characteristic wind curves (`railderail cwc`: 9 speeds 200-360 km/h,
straight track and a_q = 1 m/s^2, bisection to 0.25 m/s) in parallel processes on this machine's cores.
"""
import os
import time

import numpy as np

from ..methods import cwc
from ..methods import limit_cycle as lc
from ..methods import root_locus as rl
from ..methods import sweep as sw
from ..vehicle.simulate import Scenario


def run():
    out = {}
    rl.root_locus(Scenario(), np.linspace(100.0, 600.0, 3))         # compile
    t = time.perf_counter()
    res = rl.root_locus(Scenario(), np.linspace(100.0, 600.0, 100))
    out["root_locus_s"] = time.perf_counter() - t
    out["linear_critical_speed_kmh"] = res.linear_critical_speed_kmh
    t = time.perf_counter()
    cyc = lc.limit_cycle(Scenario())
    out["limit_cycle_s"] = time.perf_counter() - t
    out["nonlinear_critical_speed_kmh"] = cyc.nonlinear_critical_speed_kmh
    out["cores"] = os.cpu_count()
    t = time.perf_counter()
    sw.sweep(sw.cases(), refine=False, progress=False)
    out["sweep_s"] = time.perf_counter() - t
    t = time.perf_counter()
    sw.sweep(sw.cases(), refine=True, progress=False)
    out["sweep_refined_s"] = time.perf_counter() - t
    t = time.perf_counter()
    curves = cwc.cwc(progress=False)
    out["cwc_s"] = time.perf_counter() - t
    out["cwc_runs"] = sum(p["runs"] for p in curves.points)
    return out
