"""`railderail bench --profile`'s stability limit of Dormand-Prince 5(4) (railderail_sim/bench/profile.py)."""
import numpy as np
import pytest

from railderail_sim.bench.profile import stability_limit

# R(z) of Dormand-Prince 5(4), highest power first: z^6/600 + z^5/120 + z^4/24 + z^3/6 + z^2/2 + z + 1
R = np.array([1 / 600, 1 / 120, 1 / 24, 1 / 6, 1 / 2, 1.0, 1.0])


def test_the_real_axis_limit_is_where_the_stability_function_leaves_the_unit_disc():
    """On the negative real axis the limit is the first z < 0 with |R(z)| = 1, a root of R - 1 or R + 1
    (about -3.31, Hairer & Wanner's figure of the DOPRI5 stability domain); for lambda it scales as 1/|lambda|."""
    roots = np.concatenate([np.roots(R - np.eye(7)[-1]), np.roots(R + np.eye(7)[-1])])
    real = roots[(abs(roots.imag) < 1e-9) & (roots.real < -1e-9)].real
    edge = -real.max()
    assert 3.30 < edge < 3.31
    h, which = stability_limit(np.array([-1.0 + 0j]))
    assert h == pytest.approx(edge, rel=1e-9) and which == 0
    h, which = stability_limit(np.array([-10.0 + 5j, -1000.0 + 0j, 3.0 + 0j]))
    assert h == pytest.approx(edge / 1000.0, rel=1e-9) and which == 1


def test_a_lightly_damped_mode_is_limited_near_the_imaginary_axis_radius():
    """A 200 Hz mode with damping 0.036 (the wheelset spin of docs/performance.md): h |lambda| at the limit
    lies between the imaginary-axis extent and the real-axis one, and |R| is 1 there."""
    lam = 2 * np.pi * 200 * (-0.036 + 1j * np.sqrt(1 - 0.036 ** 2))
    h, _ = stability_limit(np.array([lam]))
    assert abs(np.polyval(R, h * lam)) == pytest.approx(1.0, abs=1e-6)
    assert 2.0 < h * abs(lam) < 3.31
