"""The braking model (railderail_sim/supervision/braking.py): distances and times against the closed form
v^2 / (2 a) within a band and summed across bands, the build-up, speed over distance and the simulator's
speed table."""
import math

import numpy as np
import pytest

from railderail_sim.supervision.braking import BrakingModel

KMH = 1.0 / 3.6
MODEL = BrakingModel().validated()


def test_within_one_band_the_closed_form():
    v0 = 160 * KMH                      # the 1.2 m/s^2 band runs from 0 to 170 km/h
    assert MODEL.deceleration_distance(v0, 0.0) == pytest.approx(v0 ** 2 / (2 * 1.2), rel=1e-12)
    assert MODEL.deceleration_time(v0, 0.0) == pytest.approx(v0 / 1.2, rel=1e-12)
    assert MODEL.deceleration_distance(v0, 60 * KMH) == pytest.approx((v0 ** 2 - (60 * KMH) ** 2) / 2.4, rel=1e-12)


def test_across_bands_the_sum_of_the_closed_forms():
    e = [v * KMH for v in (320, 300, 230, 170, 100)]
    a = (0.85, 0.9, 1.05, 1.2)
    distance = sum((hi ** 2 - lo ** 2) / (2 * acc) for hi, lo, acc in zip(e, e[1:], a))
    duration = sum((hi - lo) / acc for hi, lo, acc in zip(e, e[1:], a))
    assert MODEL.deceleration_distance(e[0], e[-1]) == pytest.approx(distance, rel=1e-12)
    assert MODEL.deceleration_time(e[0], e[-1]) == pytest.approx(duration, rel=1e-12)
    # the build-up: the speed kept for T_be, as ETCS models it
    assert MODEL.braking_distance(e[0], e[-1]) == pytest.approx(e[0] * 2.0 + distance, rel=1e-12)
    assert MODEL.braking_time(e[0], e[-1]) == pytest.approx(2.0 + duration, rel=1e-12)


def test_the_deceleration_of_each_band_and_the_wet_rail():
    assert [MODEL.deceleration(v * KMH) for v in (100, 169.9, 170.1, 250, 310)] == [1.2, 1.2, 1.05, 0.9, 0.85]
    wet = BrakingModel(adhesion="wet").validated()
    assert wet.deceleration(250 * KMH) == 0.7
    assert wet.braking_distance(300 * KMH, 0.0) > MODEL.braking_distance(300 * KMH, 0.0) * 1.2
    with pytest.raises(ValueError, match="adhesion 'icy'"):
        BrakingModel(adhesion="icy").validated()
    with pytest.raises(ValueError, match="emergency_bands"):
        BrakingModel(emergency_bands=((300.0, 0.9), (200.0, 1.0), (math.inf, 0.8))).validated()


def test_speed_after_a_distance_inverts_the_braking_distance():
    v0 = 330 * KMH
    assert MODEL.speed_after(v0, v0 * 2.0 - 1e-6) == v0            # still in the build-up
    for v1 in (310, 300, 250, 171, 120, 30):
        d = MODEL.braking_distance(v0, v1 * KMH)
        assert MODEL.speed_after(v0, d) == pytest.approx(v1 * KMH, abs=1e-9)
    assert MODEL.speed_after(v0, 1e6) == 0.0


def test_the_simulators_table_follows_the_curve_to_a_millimetre_per_second():
    s0, v0, v1 = 500.0, 300 * KMH, 40 * KMH
    table = MODEL.speed_table(s0, v0, v1)
    assert table[0].tolist() == [s0, v0] and table[1].tolist() == [s0 + 2.0 * v0, v0]
    assert table[-1, 1] == table[-2, 1] == pytest.approx(v1) and np.all(np.diff(table[:, 0]) > 0)
    s = np.linspace(s0, table[-2, 0], 20001)
    exact = np.array([MODEL.speed_after(v0, x - s0) for x in s])
    assert np.max(np.abs(np.interp(s, table[:, 0], table[:, 1]) - exact)) < 1e-3
    with pytest.raises(ValueError, match="release speed"):
        MODEL.speed_table(s0, v0, v0 + 1.0)
