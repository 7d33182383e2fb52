"""The vehicle core's outputs, bit for bit, against the golden file that commit 6be359e wrote (before the
step-cost work of issue 26, docs/performance.md): the shortcuts of the core (the stepper skipping the
frozen rail states of the rigid track, and the like) must leave every result unchanged.

Runs: the default scenario (R 1000 m, 300 km/h, Hertz, rigid smooth track), and two that use every
optional part: ERRI B176 high irregularity (seed 1), a 25 m/s crosswind and failed front yaw dampers, on
elastic and on rigid track. Each keeps its final state, its step counts and every 20th output row.
Regenerate (only for a change that is meant to alter results, saying so in its commit):
`PYTHONPATH=$PWD python tests/test_core_golden.py`.
"""
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from railderail_sim.loads.wind import Wind
from railderail_sim.parameters import TrackParameters
from railderail_sim.track.irregularity import resolve
from railderail_sim.vehicle.simulate import Simulation, scenario

GOLDEN = Path(__file__).parent / "data" / "core_golden.npz"
ROW_STRIDE = 20


def runs():
    """{name: (Scenario, simulated seconds)}."""
    default = scenario(radius=1000.0, speed_kmh=300.0)
    features = replace(default, irregularity=resolve("erri-high", 1, TrackParameters().line_length),
                       wind=Wind(speed=25.0), faults=("yaw-dampers-failed@front",))
    return {"default": (default, 1.0),
            "features_elastic": (replace(features, track_model="elastic"), 0.5),
            "features_rigid": (features, 0.5)}


def outputs(sc, duration):
    sim = Simulation(sc)
    rows = sim.advance(duration)
    return {"x": sim.x.copy(), "steps": np.array(sim.steps), "rows": rows[::ROW_STRIDE]}


@pytest.fixture(scope="module")
def golden():
    return np.load(GOLDEN)


@pytest.mark.parametrize("name", list(runs()))
def test_the_core_gives_the_golden_outputs_bit_for_bit(golden, name):
    got = outputs(*runs()[name])
    for key, value in got.items():
        want = golden[f"{name}_{key}"]
        assert value.shape == want.shape, key
        assert np.array_equal(value, want), f"{name} {key}: max difference {np.max(np.abs(value - want)):.3g}"


if __name__ == "__main__":
    data = {f"{name}_{key}": value for name, run in runs().items() for key, value in outputs(*run).items()}
    np.savez_compressed(GOLDEN, **data)
    print(f"wrote {GOLDEN} ({GOLDEN.stat().st_size} bytes)")
