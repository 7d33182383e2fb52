"""`railderail bench --only assessment`: the cost of assessing a run against the cost of simulating it.

One run on the Table 2 line (R 1000 m, 250 km/h, ERRI B176 high level, seed 1, rigid track, 200 Hz) is
simulated and timed; its output rows are repeated end to end (positions shifted by the line's length) to
20 km and that record is assessed (EN 14363 per section and the comfort indices, assessment.assess).
assess_s_per_20km is that wall time; simulation_s_per_20km the run's wall time scaled to 20 km;
assess_share_of_simulation their ratio (target < 0.10).
"""
from dataclasses import replace
import time

import numpy as np

from ..assessment import assess, signals
from ..parameters import TrackParameters
from ..track.irregularity import resolve
from ..vehicle import integrator as itg
from ..vehicle.simulate import Simulation, output_arrays, scenario

LENGTH_M = 20_000.0


def tiled(arrays, length_m):
    """The run's arrays repeated end to end until the car-body centre has covered `length_m`."""
    span = float(arrays["position"][-1] - arrays["position"][0]) + float(np.diff(arrays["position"][-2:])[0])
    duration = float(arrays["time"][-1] - arrays["time"][0]) + float(np.diff(arrays["time"][-2:])[0])
    copies = int(np.ceil(length_m / span))
    out = {}
    for name, a in arrays.items():
        out[name] = np.concatenate([a] * copies)
    n = len(arrays["time"])
    k = np.repeat(np.arange(copies), n)
    out["position"] = out["position"] + k * span
    out["time"] = out["time"] + k * duration
    return out


def run():
    sc = replace(scenario(radius=1000.0, speed_kmh=250.0),
                 irregularity=resolve("erri-high", 1, TrackParameters().line_length))
    sim = Simulation(sc)
    parts = [sim.advance(0.01)]                  # compile (or load the cache) outside the timing
    t0 = time.perf_counter()
    while sim.status == itg.RUNNING:
        parts.append(sim.advance(1.0))
    simulation_s = time.perf_counter() - t0
    arrays = output_arrays(np.concatenate(parts))
    covered = float(arrays["position"][-1] - arrays["position"][0])
    record = tiled(arrays, LENGTH_M)
    t0 = time.perf_counter()
    assess.assess(signals.from_arrays(record, sc.vehicle, "bench"))
    assess_s = time.perf_counter() - t0
    per_20km = simulation_s * LENGTH_M / covered
    return {"assess_s_per_20km": assess_s, "simulation_s_per_20km": per_20km,
            "assess_share_of_simulation": assess_s / per_20km}
