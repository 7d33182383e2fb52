"""The flange-climb distance criterion (TCRP Report 71 Vol. 5 eq. 2.4) and its alerts."""
import math

import numpy as np
import pytest

from railderail_monitor.warning import climb_distance as CD
from railderail_monitor.warning.monitor import Monitor
from railderail_monitor.warning.limits import default_limits
from railderail_sim import profiles


def test_eq_2_4_at_the_lm_flange_by_hand():
    """LM: largest flange angle 69.36 deg over 3.64 mm of flange face (0.1434 in). By hand with the constants:
    A = 100 / 13.89 + 3.1 (0.1434 - 1 / 0.9958 + 1.23) = 8.35 ft, B Len = 4.92 mrad, so D = 2.54 m at zero
    attack angle, half that at 4.92 mrad, and a tenth of it at 44 mrad."""
    wheel = profiles.resolve("lm", "wheel")
    assert math.degrees(wheel.max_flange_angle()) == pytest.approx(69.36, abs=0.01)
    assert wheel.flange_length() == pytest.approx(3.64e-3, abs=0.01e-3)
    distance, angle = CD.tcrp_coefficients(wheel.max_flange_angle(), wheel.flange_length())
    assert distance == pytest.approx(8.35 * 0.3048, rel=2e-3)
    assert angle == pytest.approx(4.92e-3, rel=2e-3)
    d = CD.climb_distance_limit(np.array([0.0, angle, -angle, 9.0 * angle]), distance, angle)
    assert d == pytest.approx([distance, distance / 2, distance / 2, distance / 10])


def test_the_shipped_monitor_file_carries_the_lm_scales():
    limits = default_limits()
    # Nadal at LM/UIC60's 69.54 deg with mu 0.5: (2.676 - 0.5) / (1 + 0.5 x 2.676) = 0.931
    assert limits.climb_nadal_limit == pytest.approx(0.931, abs=1e-3)
    wheel = profiles.resolve("lm", "wheel")
    assert (limits.climb_distance_scale, limits.climb_attack_angle_scale) == pytest.approx(
        CD.tcrp_coefficients(wheel.max_flange_angle(), wheel.flange_length()))


@pytest.mark.parametrize("angle_deg, length_mm, message", [(77.0, 3.6, "flange angle 77.00 deg"),
                                                           (69.0, 2.0, "flange length 2.00 mm")])
def test_outside_the_formula_s_regular_range_is_refused(angle_deg, length_mm, message):
    with pytest.raises(ValueError, match=message):
        CD.tcrp_coefficients(math.radians(angle_deg), length_mm * 1e-3)


def test_the_distance_runs_only_while_q_p_is_at_nadal_s_limit():
    position = np.arange(8) * 0.5
    qp = np.array([[1.0], [1.4], [1.4], [1.2], [1.4], [1.4], [1.4], [1.3]])
    assert CD.climb_distance(qp, position, 1.3)[:, 0].tolist() == [0.0, 0.5, 1.0, 0.0, 0.5, 1.0, 1.5, 2.0]


def test_the_monitor_raises_it_where_the_batch_does_and_from_the_attack_angle_before_the_sample():
    """A wheel at 1.5 x Nadal from 1 m on, its wheelset at 10 mrad from sample 20: the running ratio equals
    the whole run's, bit for bit, and the alerts at 0.5 and 1 fall where the distance is half and all of
    TCRP's limit at 10 mrad. Feeding each sample's forces before its states changes nothing."""
    limits = default_limits()
    n, ds = 400, 0.02
    position = np.arange(n) * ds
    qp = np.zeros((n, 8))
    qp[position >= 1.0, 2] = 1.5 * limits.climb_nadal_limit       # wheelset 1, left
    aoa = np.zeros((n, 4))
    aoa[20:, 1] = 0.010
    batch = CD.climb_distance_ratio(qp, aoa, position, limits.climb_nadal_limit,
                                    limits.climb_distance_scale, limits.climb_attack_angle_scale)
    monitor = Monitor(limits)
    running, alerts = [], []
    for i in range(n):
        alerts += monitor.on_forces(i * 0.001, i, position[i], 20.0, 0.0, qp[i], np.full(8, limits.static_wheel_load))
        running.append(monitor.climb.run / CD.climb_distance_limit(CD.wheel_attack_angles(aoa[i - 1] if i else
                                                                                          np.zeros(4)),
                                                                   limits.climb_distance_scale,
                                                                   limits.climb_attack_angle_scale))
        alerts += monitor.on_states(i * 0.001, i, position[i], 20.0, 0.0, aoa[i], np.zeros(8))
    assert np.array_equal(np.array(running), batch)
    climb = [a for a in alerts if a.criterion == "flange_climb_distance"]
    limit = CD.climb_distance_limit(0.010, limits.climb_distance_scale, limits.climb_attack_angle_scale)
    assert [(a.severity, a.wheelset, a.wheel_side) for a in climb] == [(1, 1, "left"), (2, 1, "left")]
    assert climb[0].track_position - 1.0 == pytest.approx(0.5 * limit, abs=ds)
    assert climb[1].track_position - 1.0 == pytest.approx(limit, abs=ds)
