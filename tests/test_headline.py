"""A guard on the headline results: the critical derailment speeds of the six radii and the linear
critical speed of the default parameter set (hs19, LM on UIC60 1:40, Hertz + Shen-Hedrick-Elkins,
friction 0.3, the contact table).

These numbers are the model's, not the paper's (docs/report/report.md sets them beside Yu et al.
2022). The test fails when a change moves any of them by 0.5 km/h or more, so that no change of the
physics goes unnoticed. When the physics changes on purpose: run `railderail sweep --json` (the
staircase and the bisection, 1 km/h) and `railderail root-locus --json`, copy the new values here,
regenerate the report (`railderail report --out docs/report`) and name the change and its reason in
the commit message.
"""
import numpy as np
import pytest

from railderail_sim.methods import root_locus as rl
from railderail_sim.methods import sweep as sw
from railderail_sim.methods.progressive_trial import Staircase
from railderail_sim.vehicle.simulate import Scenario

TOLERANCE_KMH = 0.5
# radius (m): (progressive trial's staircase, bisection over constant speeds on the Table 2 line), km/h
CRITICAL_DERAILMENT_SPEEDS_KMH = {
    800.0: (260.14, 258.125),
    1000.0: (293.35, 288.0),
    1200.0: (320.00, 315.0),
    1400.0: (345.00, 339.375),
    1600.0: (370.00, 362.5),
    1800.0: (393.21, 384.25),
}
LINEAR_CRITICAL_SPEED_KMH = 402.97


@pytest.mark.slow
@pytest.mark.timeout(900)
def test_critical_derailment_speeds_of_the_six_radii():
    results = sw.sweep(sw.cases(radii=tuple(CRITICAL_DERAILMENT_SPEEDS_KMH)), Scenario(), Staircase(),
                       refine=True, tolerance_kmh=1.0, workers=2, progress=False)
    found = {r["radius_m"]: (r["critical_derailment_speed_kmh"], r["refined_speed_kmh"]) for r in results}
    for radius, expected in CRITICAL_DERAILMENT_SPEEDS_KMH.items():
        assert found[radius] == pytest.approx(expected, abs=TOLERANCE_KMH), radius
    assert {(r["refined_wheelset"], r["refined_side"], r["refined_mechanism"]) for r in results} == \
        {(0, "inner", "wheel_unloading")}


def test_linear_critical_speed():
    locus = rl.root_locus(Scenario(), np.linspace(100.0, 600.0, 101))
    assert locus.linear_critical_speed_kmh == pytest.approx(LINEAR_CRITICAL_SPEED_KMH, abs=TOLERANCE_KMH)
