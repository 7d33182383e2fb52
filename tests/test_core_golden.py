"""The vehicle core's outputs against two files.

`core_golden.npz`, bit for bit: the shortcuts of the core (the stepper skipping the frozen rail states of
the rigid track, and the like) must leave every result unchanged. Each golden entry keeps a run's final
state, its step counts and every 20th output row. Regenerate it only for a change that is meant to alter
results, saying so in its commit, after the bounds test below passes:
`PYTHONPATH=$PWD python tests/test_core_golden.py`. The file was last written by the commit that added
the Dormand-Prince dense output (docs/performance.md names it).

`core_reference_10a557a.npz`, within the tolerance study's bounds (docs/vehicle-model.md: the default
tolerances' error per output, `studies.DEFAULT_ERRORS`): every output row of the wheelsets' lateral
displacement, the wheel lift and the wheel forces Q and P as the core of commit 10a557a computed them
(before the changes of issue 26 that alter results: the dense output, the step cap, the irregularity's
spline). A change of the integration may move the results by its own error, not more. Written once, by
that commit's core: `PYTHONPATH=$PWD python tests/test_core_golden.py reference`.

Runs: the default scenario (R 1000 m, 300 km/h, Hertz, rigid smooth track), and two that use every
optional part: ERRI B176 high irregularity (seed 1), a 25 m/s crosswind and failed front yaw dampers, on
elastic and on rigid track.

Both files were first written on a CPU with numpy's AVX2 (X86_V3) loops. numpy's AVX-512 loops round
arctan, tan, arcsin, exp, log and fractional powers differently in the last bit, and the two hunting runs
with failed yaw dampers amplify such a bit in the contact tables to 22 mm by 0.5 s (found 2026-12-04 on an
AMD EPYC); the model building now calls libm one value at a time for these (`railderail_sim.scalarmath`),
so the files hold on AVX-512 CPUs as on AVX2 ones (tests/test_cpu_rounding.py builds the model under both
dispatches).
"""
from dataclasses import replace
from functools import cache
from pathlib import Path
import sys

import numpy as np
import pytest

from railderail_sim.loads.wind import Wind
from railderail_sim.parameters import TrackParameters
from railderail_sim.track.irregularity import resolve
from railderail_sim.vehicle.simulate import Simulation, output_arrays, scenario
from railderail_sim.vehicle.studies import DEFAULT_ERRORS, FILTERED, force_filter

GOLDEN = Path(__file__).parent / "data" / "core_golden.npz"
REFERENCE = Path(__file__).parent / "data" / "core_reference_10a557a.npz"
ROW_STRIDE = 20


def runs():
    """{name: (Scenario, simulated seconds)}."""
    default = scenario(radius=1000.0, speed_kmh=300.0)
    features = replace(default, irregularity=resolve("erri-high", 1, TrackParameters().line_length),
                       wind=Wind(speed=25.0), faults=("yaw-dampers-failed@front",))
    return {"default": (default, 1.0),
            "features_elastic": (replace(features, track_model="elastic"), 0.5),
            "features_rigid": (features, 0.5)}


@cache
def run(name):
    """(the Simulation after the run, all its output rows)."""
    sc, duration = runs()[name]
    sim = Simulation(sc)
    return sim, sim.advance(duration)


def golden_outputs(name):
    sim, rows = run(name)
    return {"x": sim.x.copy(), "steps": np.array(sim.steps), "rows": rows[::ROW_STRIDE]}


def reference_outputs(name):
    arrays = output_arrays(run(name)[1])
    return {output: arrays[output] for output in DEFAULT_ERRORS}


def differences(name, reference, got=None):
    """{output: the largest difference of this core's run (`got`, default: run here) to the reference}
    (forces filtered as the study)."""
    rate = runs()[name][0].output_rate
    got = reference_outputs(name) if got is None else got
    out = {}
    for output in DEFAULT_ERRORS:
        a, b = got[output], reference[f"{name}_{output}"]
        assert a.shape == b.shape, output
        if output in FILTERED:
            a, b = force_filter(a, rate), force_filter(b, rate)
        out[output] = float(np.max(np.abs(a - b)))
    return out


def all_outputs():
    """{name_key: array} of every run's golden outputs and, prefixed reference_, its reference outputs."""
    out = {f"{name}_{key}": value for name in runs() for key, value in golden_outputs(name).items()}
    out.update({f"reference_{name}_{key}": value for name in runs()
                for key, value in reference_outputs(name).items()})
    return out


@pytest.fixture(scope="module")
def outputs():
    return all_outputs()


@pytest.fixture(scope="module")
def golden():
    return np.load(GOLDEN)


@pytest.mark.parametrize("name", list(runs()))
def test_the_core_gives_the_golden_outputs_bit_for_bit(golden, outputs, name):
    got = {key: outputs[f"{name}_{key}"] for key in ("x", "steps", "rows")}
    for key, value in got.items():
        want = golden[f"{name}_{key}"]
        assert value.shape == want.shape, key
        assert np.array_equal(value, want), f"{name} {key}: max difference {np.max(np.abs(value - want)):.3g}"


@pytest.mark.parametrize("name", list(runs()))
def test_the_core_stays_within_the_tolerance_study_bounds_of_the_old_core(outputs, name):
    diff = differences(name, np.load(REFERENCE), {k: outputs[f"reference_{name}_{k}"] for k in DEFAULT_ERRORS})
    over = {k: f"{v:.3g} > {DEFAULT_ERRORS[k]:.3g}" for k, v in diff.items() if not v <= DEFAULT_ERRORS[k]}
    assert not over, f"{name}: {over}"


if __name__ == "__main__":
    if sys.argv[1:] == ["reference"]:
        data = {f"{name}_{key}": value for name in runs() for key, value in reference_outputs(name).items()}
        np.savez_compressed(REFERENCE, **data)
        print(f"wrote {REFERENCE} ({REFERENCE.stat().st_size} bytes)")
    elif sys.argv[1:] == ["differences"]:
        for name in runs():
            print(name, {k: f"{v:.3g}" for k, v in differences(name, np.load(REFERENCE)).items()})
    else:
        data = {f"{name}_{key}": value for name in runs() for key, value in golden_outputs(name).items()}
        np.savez_compressed(GOLDEN, **data)
        print(f"wrote {GOLDEN} ({GOLDEN.stat().st_size} bytes)")
