"""`railderail bench --profile`'s stability limit of Dormand-Prince 5(4) and its modes' names by kinetic energy
(railderail_sim/bench/profile.py)."""
from types import SimpleNamespace

import numpy as np
import pytest

from railderail_sim.bench.profile import energy_shares, kinetic_groups, shares_text, stability_limit
from railderail_sim.track.layout import ElasticTrack
from railderail_sim.vehicle.layout import BodyTable, Dof, N_BODY, N_DOF, State, WHEELSETS

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


def test_a_mode_is_named_by_its_kinetic_energy_not_its_largest_entry():
    """A wheelset's spin rate is a large number at a small inertia: a mode whose velocity part is 1 m/s of
    wheelset bounce and 20 rad/s of spin holds most of its energy in the bounce (1500 kg against 1.2 kg m^2
    x 400), although the spin's entry is the largest; positions and damper elongations carry none."""
    bodies = np.zeros((N_BODY, BodyTable.size()))
    bodies[:, BodyTable.mass] = 1500.0
    bodies[:, BodyTable.roll_inertia] = bodies[:, BodyTable.yaw_inertia] = 800.0
    bodies[:, BodyTable.pitch_inertia] = 1.2
    arrays = SimpleNamespace(bodies=bodies, support=np.zeros(ElasticTrack.size()))
    ws = WHEELSETS[1]
    bounce = State.velocities + N_DOF * ws + Dof.vertical
    spin = State.velocities + N_DOF * ws + Dof.pitch
    lift = State.positions + N_DOF * ws + Dof.vertical
    active = np.array([lift, bounce, spin, State.dampers + 0])
    masses, groups = kinetic_groups(arrays, active)
    assert list(masses) == [0.0, 1500.0, 1.2, 0.0]
    assert groups == ["", "wheelsets vertical", "wheelsets spin", ""]
    shares = energy_shares(np.array([5.0, 1.0, 20.0j, 3.0]), masses, groups)
    assert [g for g, _ in shares] == ["wheelsets vertical", "wheelsets spin"]
    assert shares[0][1] == pytest.approx(1500.0 / (1500.0 + 1.2 * 400.0))
    assert shares_text(shares) == "wheelsets vertical 76 %, wheelsets spin 24 %"
