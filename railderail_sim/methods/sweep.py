"""Sweeps of the progressive trial over radius x cant x friction x wheel profile x parameter set.

Cases run in parallel processes or on a Dask cluster (`parallel.run_all`).
"""
from dataclasses import dataclass, replace
import functools
import itertools

from ..parameters import vehicle_parameters
from ..vehicle.simulate import Scenario
from .parallel import run_all
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


def sweep(case_list, base: Scenario = None, stair: Staircase = Staircase(), refine=True, tolerance_kmh=1.0,
          workers=None, scheduler=None, progress=True):
    """Run every case; results in the order of case_list."""
    if not case_list:
        raise ValueError("the sweep has no cases")
    one = functools.partial(run_case, base=base or Scenario(), stair=stair, refine=refine,
                            tolerance_kmh=tolerance_kmh)
    return run_all(one, case_list, workers=workers, scheduler=scheduler, progress=progress, desc="sweep",
                   unit="case")
