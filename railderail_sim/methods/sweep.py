"""Sweeps of the progressive trial over radius x cant x friction x wheel profile x parameter set.

Cases run in parallel processes (concurrent.futures) with a progress bar, or on an existing Dask
distributed cluster (`scheduler` = its address). Every case is a deterministic pure function of its
inputs, so both give identical results; nothing here schedules work itself.
"""
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, replace
import itertools
import os

from ..parameters import vehicle_parameters
from ..vehicle.simulate import Scenario
from .progressive_trial import Staircase, progressive_trial

PAPER_RADII = (800.0, 1000.0, 1200.0, 1400.0, 1600.0, 1800.0)


@dataclass(frozen=True)
class Case:
    radius_m: float
    cant_mm: float = 175.0
    friction: float = 0.3
    wheel_profile: str = "lm"
    vehicle_set: str = "hs19"


def cases(radii=PAPER_RADII, cants_mm=(175.0,), frictions=(0.3,), wheels=("lm",), vehicle_sets=("hs19",)):
    return [Case(*c) for c in itertools.product(radii, cants_mm, frictions, wheels, vehicle_sets)]


def run_case(case: Case, base: Scenario, stair: Staircase, refine: bool, tolerance_kmh: float):
    """One case (a module-level function, so processes and Dask workers can run it)."""
    sc = replace(base, vehicle=vehicle_parameters(case.vehicle_set),
                 track=replace(base.track, cant_height=case.cant_mm / 1000.0),
                 contact=replace(base.contact, friction_coefficient=case.friction, wheel_profile=case.wheel_profile))
    r = progressive_trial(sc, case.radius_m, stair, refine=refine, tolerance_kmh=tolerance_kmh)
    out = dict(case.__dict__)
    out.update(r.as_json())
    return out


def _bar(total, enabled):
    if not enabled:
        return None
    from tqdm import tqdm
    return tqdm(total=total, desc="sweep", unit="case")


def sweep(case_list, base: Scenario = None, stair: Staircase = Staircase(), refine=True, tolerance_kmh=1.0,
          workers=None, scheduler=None, progress=True):
    """Run every case; results in the order of case_list."""
    base = base or Scenario()
    if not case_list:
        raise ValueError("the sweep has no cases")
    bar = _bar(len(case_list), progress)
    results = [None] * len(case_list)
    if scheduler:
        from dask.distributed import Client, as_completed as dask_completed
        with Client(scheduler) as client:
            futures = client.map(run_case, case_list, base=base, stair=stair, refine=refine,
                                 tolerance_kmh=tolerance_kmh, pure=True)
            index = {f.key: i for i, f in enumerate(futures)}
            for f in dask_completed(futures):
                results[index[f.key]] = f.result()
                if bar:
                    bar.update()
    else:
        workers = workers or min(len(case_list), os.cpu_count() or 1)
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = {pool.submit(run_case, c, base, stair, refine, tolerance_kmh): i
                       for i, c in enumerate(case_list)}
            for f in as_completed(futures):
                results[futures[f]] = f.result()
                if bar:
                    bar.update()
    if bar:
        bar.close()
    return results

