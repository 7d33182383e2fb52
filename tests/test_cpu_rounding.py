"""The model building rounds the same whatever numpy's CPU dispatch (docs/performance.md, "Determinism
across CPUs").

Every array the core is fed (the contact geometry with its table, the track, the rails' irregularity and
defects, the wind, the vehicle with its faults and the contact constants) is built in child processes and
compared bit for bit:

- under numpy's default dispatch and with its AVX-512 targets disabled (NPY_DISABLE_CPU_FEATURES), the two
  kinds of CPU the golden files must hold on; on a CPU without AVX-512 the two are the same dispatch;
- under numpy's default dispatch and with numpy's arctan, tan, arcsin, arcsinh, exp, log, power and cbrt
  moved by one unit in the last place, a stand-in for another CPU's loops that this CPU can run: a model
  building that calls one of them by name on the way to the core fails here whatever CPU runs the test.
"""
import hashlib
import json
import os
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

# numpy's float64 functions whose AVX-512 loops round differently from its AVX2 ones (and their kin)
MOVED = ("arctan", "tan", "arcsin", "arcsinh", "exp", "log", "power", "cbrt")
ONE_ULP = "one-ulp"


# runs of the warning catalogue whose scenarios feed the core what the two above do not: a kink and a twist
# on the rails, failed yaw dampers, a broken spring, a measured line's curves and cant at line speed
CATALOGUE_RUNS = (("kink-45mm-5m", 101), ("twist-20mm-friction-0.4", 115), ("hunting-yaw-dampers-failed-250", 129),
                  ("primary-spring-broken-r150-30", 155), ("line-r1400-fra-6-175", 47))


def model_digests():
    """{scenario.array: sha256 of its bytes} of every array the core is fed, for the default scenario, one
    with every optional input (irregularity, crosswind gust, elastic track) and CATALOGUE_RUNS'."""
    from railderail_monitor.evaluation import catalogue
    from railderail_sim.loads.wind import Wind
    from railderail_sim.parameters import TrackParameters
    from railderail_sim.track.irregularity import resolve
    from railderail_sim.vehicle.simulate import Simulation, scenario
    default = scenario(radius=1000.0, speed_kmh=300.0)
    features = replace(default, irregularity=resolve("erri-high", 1, TrackParameters().line_length),
                       wind=Wind(speed=25.0, gust="chinese-hat"), track_model="elastic")
    entries = {e.name: e for e in catalogue.load()}
    runs = [(f"{name}:{seed}", entries[name].scenario(seed)) for name, seed in CATALOGUE_RUNS]
    out = {}
    for name, sc in (("default", default), ("features", features), *runs):
        sim = Simulation(sc)
        for key, value in sim.model.arrays._asdict().items():
            out[f"{name}.{key}"] = hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest()
        out[f"{name}.x0"] = hashlib.sha256(sim.x.tobytes()).hexdigest()
    return out


def avx512_targets():
    """numpy's AVX-512 dispatch targets this CPU has (none on an AVX2 one)."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    return [f for f in __cpu_dispatch__ if (f.startswith("AVX512") or f == "X86_V4") and __cpu_features__.get(f)]


def move_by_one_ulp():
    """Replace numpy's MOVED functions by ones whose results are one ulp higher (after numba has read
    numpy's ufuncs, which it types its own code by)."""
    import numba.np.npyimpl  # noqa: F401
    from numba.np import ufunc_db
    ufunc_db.get_ufuncs()
    for name in MOVED:
        f = getattr(np, name)
        setattr(np, name, lambda *args, _f=f, **kwargs: np.nextafter(_f(*args, **kwargs), np.inf))


def in_child(env=None, *args):
    done = subprocess.run([sys.executable, __file__, *args], check=True, timeout=600, capture_output=True,
                          text=True, env=dict(os.environ, **(env or {})))
    return json.loads(done.stdout.splitlines()[-1])


@pytest.fixture(scope="module")
def default_dispatch():
    return in_child()


def differing(a, b):
    assert a.keys() == b.keys()
    return sorted(k for k in a if a[k] != b[k])


def test_the_model_is_the_same_on_numpys_avx2_and_avx512_loops(default_dispatch):
    targets = avx512_targets()
    avx2 = in_child({"NPY_DISABLE_CPU_FEATURES": " ".join(targets)}) if targets else default_dispatch
    assert not differing(default_dispatch, avx2)


def test_the_model_does_not_depend_on_how_numpys_transcendental_functions_round(default_dispatch):
    moved = in_child(None, ONE_ULP)
    assert not differing(default_dispatch, moved)


if __name__ == "__main__":
    if sys.argv[1:] == [ONE_ULP]:
        move_by_one_ulp()
    print(json.dumps(model_digests()))
