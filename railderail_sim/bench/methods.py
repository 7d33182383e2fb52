"""`railderail bench --only methods`: wall time of each method (after compilation).

root_locus_s: 100 speeds 100-600 km/h; limit_cycle_s: the default scan (200-600 km/h by 50) and
bisection to 1 km/h; sweep_s: the progressive trial (staircase, no refinement) on the paper's six radii
in parallel processes on this machine's cores; sweep_refined_s: the same with the bisection over
constant speeds; cwc_s: the default characteristic wind curves (`railderail cwc`: 9 speeds 200-360 km/h,
straight track and a_q = 1 m/s^2, bisection to 0.25 m/s) in parallel processes on this machine's cores;
survey_case_cpu_s: the process time (CPU seconds, not wall: a survey's cost on a shared machine) of one case of
`railderail survey table2` at every default (hs19 at friction 0.3: the top run, the staircase and its bisection,
the margins' search), survey_case_runs its runs.
"""
import os
import time

import numpy as np

from ..line.file import load_line
from ..methods import cwc
from ..methods import survey as sv
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
    t = time.process_time()
    case = sv.curve_case(load_line("table2"), 0, Scenario(), sv.Settings(), "hs19", 0.3)
    out["survey_case_cpu_s"] = time.process_time() - t
    out["survey_case_runs"] = case["runs"]
    return out
