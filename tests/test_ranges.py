"""The one range check of user-facing values (railderail_sim.ranges)."""
import math

import pytest

from railderail_sim.ranges import check_range


def test_ends_are_closed_unless_flagged_open():
    assert check_range("speed", 30, 30.0, 800.0, "km/h") == 30.0
    assert check_range("speed", "800", 30.0, 800.0, "km/h") == 800.0
    with pytest.raises(ValueError, match=r"friction coefficient 0 is outside the accepted range \(0, 1\]$"):
        check_range("friction coefficient", 0.0, 0.0, 1.0, lo_open=True)
    with pytest.raises(ValueError, match=r"Poisson's ratio 0.5 is outside the accepted range \[0, 0.5\)$"):
        check_range("Poisson's ratio", 0.5, 0.0, 0.5, hi_open=True)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, 1e6])
def test_bad_values_name_the_value_and_the_range(value):
    with pytest.raises(ValueError, match=r"^curve radius .* m is outside the accepted range \[300, 20000\] m$"):
        check_range("curve radius", value, 300.0, 20000.0, "m")
