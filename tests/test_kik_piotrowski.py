"""Kik-Piotrowski non-elliptic normal contact and strip FASTSIM (railderail_sim/contact)."""
import math

import numpy as np
import pytest

from railderail_sim.contact import creep as cr
from railderail_sim.contact import hertz as hz
from railderail_sim.contact import kik_piotrowski as kp

E = 2.1e11
NU = 0.28
G = E / (2.0 * (1.0 + NU))
E_STAR = E / (2.0 * (1.0 - NU * NU))
MU = 0.3
N = 5.0e4
A_WHEEL = 1.0 / (2.0 * 0.43)   # longitudinal curvature sum/2: 0.43 m wheel on a straight rail


def _hertz_gap(ratio, n=801, half_width_factor=3.0):
    """gap(y) = B y^2 with R_long = 1/(2A): the KP input of a Hertzian contact."""
    A = A_WHEEL
    B = ratio * A
    a, b, d, p0 = hz.hertz_patch(A, B, E_STAR, N)
    s = np.linspace(-half_width_factor * b, half_width_factor * b, n)
    return A, B, (a, b, d, p0), s, B * s * s, np.full(n, 1.0 / (2.0 * A))


def test_sphere_with_eps_half_is_hertz():
    # eps = 0.5 makes the virtual interpenetration circle the Hertz circle, and the KP pressure
    # Hertz's: the method is then exact up to the strip discretisation
    _, _, (a, b, d, p0), s, gap, R = _hertz_gap(1.0)
    xl, pid, P, _ = kp.kp_patches(s, gap, R, d, E, NU, eps=0.5)
    assert len(P) == 1
    p = P[0]
    assert p["normal_force"] == pytest.approx(N, rel=1e-4)
    assert p["length"] / 2 == pytest.approx(a, rel=1e-4)
    assert p["width"] / 2 == pytest.approx(b, rel=1e-4)
    assert p["area"] == pytest.approx(math.pi * a * b, rel=1e-3)
    assert p["p_max"] == pytest.approx(p0, rel=1e-4)
    assert p["y_centroid"] == pytest.approx(0.0, abs=1e-9)


def test_grid_convergence_second_order():
    errs = []
    for n in (201, 401, 801):
        _, _, (a, b, d, p0), s, gap, R = _hertz_gap(1.0, n=n)
        errs.append(abs(kp.kp_normal_force(s, gap, R, d, E, NU, 0.5) / N - 1.0))
    assert errs[2] < errs[1] < errs[0]
    assert errs[0] / errs[2] > 10.0            # ~ 4x per halving


@pytest.mark.parametrize("ratio", (0.5, 0.7, 1.0, 1.5, 2.0))
def test_eps_055_close_to_hertz(ratio):
    # B/A in [0.5, 2] gives Hertz a/b in [0.63, 1.59]. KP's overlap ellipse has a/b = sqrt(B/A)
    # while Hertz has about (B/A)^0.64, so the semi-axes differ by up to ~10 % at the ends of
    # this range (values in docs/contact-models.md).
    _, _, (a, b, d, p0), s, gap, R = _hertz_gap(ratio)
    dk = kp.kp_delta_for_force(s, gap, R, N, E, NU, kp.EPS_DEFAULT)
    xl, pid, P, _ = kp.kp_patches(s, gap, R, dk, E, NU, kp.EPS_DEFAULT)
    p = P[0]
    assert p["length"] / 2 == pytest.approx(a, rel=0.10)
    assert p["width"] / 2 == pytest.approx(b, rel=0.10)
    assert p["area"] == pytest.approx(math.pi * a * b, rel=0.08)
    assert p["p_max"] == pytest.approx(p0, rel=0.08)
    assert dk == pytest.approx(d, rel=0.035)
    assert kp.kp_normal_force(s, gap, R, d, E, NU, kp.EPS_DEFAULT) == pytest.approx(N, rel=0.05)


def test_force_scales_with_delta_to_the_1_5():
    _, _, (a, b, d, p0), s, gap, R = _hertz_gap(2.0, half_width_factor=6.0, n=1601)
    d1, d2 = 0.5 * d, 2.0 * d
    N1 = kp.kp_normal_force(s, gap, R, d1, E, NU, kp.EPS_DEFAULT)
    N2 = kp.kp_normal_force(s, gap, R, d2, E, NU, kp.EPS_DEFAULT)
    assert math.log(N2 / N1) / math.log(d2 / d1) == pytest.approx(1.5, abs=0.005)
    assert kp.kp_normal_force(s, gap, R, 0.0, E, NU, kp.EPS_DEFAULT) == 0.0


def test_inverse_is_consistent():
    _, _, (a, b, d, p0), s, gap, R = _hertz_gap(3.0)
    for Nt in (1.0e3, 3.0e4, 1.2e5):
        dk = kp.kp_delta_for_force(s, gap, R, Nt, E, NU, kp.EPS_DEFAULT)
        Nk = kp.kp_normal_force(s, gap, R, dk, E, NU, kp.EPS_DEFAULT)
        assert Nk == pytest.approx(Nt, rel=1e-9)
    assert kp.kp_delta_for_force(s, gap, R, 0.0, E, NU, kp.EPS_DEFAULT) == 0.0


def test_two_lobe_gap_gives_two_patches():
    B = 2.0 * A_WHEEL
    s = np.linspace(-0.03, 0.03, 1201)
    y1, y2, g2 = -0.012, 0.012, 2.0e-5
    gap = np.minimum(B * (s - y1) ** 2, B * (s - y2) ** 2 + g2)
    R = np.full(s.size, 0.43)
    delta = 1.0e-4
    xl, pid, P, arr = kp.kp_patches(s, gap, R, delta, E, NU, kp.EPS_DEFAULT)
    assert len(P) == 2
    assert P[0]["y_max"] < 0.0 < P[1]["y_min"]
    assert P[0]["y0"] == pytest.approx(y1, abs=1e-4) and P[1]["y0"] == pytest.approx(y2, abs=1e-4)
    assert P[0]["approach"] == pytest.approx(delta, rel=1e-12)
    assert P[1]["approach"] == pytest.approx(delta - g2, rel=1e-9)
    # each patch is the single-lobe patch at its own approach (no elastic interaction)
    for k, (yc, dl) in enumerate(((y1, delta), (y2, delta - g2))):
        single = B * (s - yc) ** 2
        Nk = kp.kp_normal_force(s, single, R, dl, E, NU, kp.EPS_DEFAULT)
        assert P[k]["normal_force"] == pytest.approx(Nk, rel=1e-9)
    assert P[0]["normal_force"] > P[1]["normal_force"] > 0
    assert kp.kp_normal_force(s, gap, R, delta, E, NU, kp.EPS_DEFAULT) == pytest.approx(
        P[0]["normal_force"] + P[1]["normal_force"], rel=1e-12)
    assert set(np.unique(pid)) == {-1, 0, 1}
    assert np.all(xl[pid == -1] == 0.0) and np.all(xl[pid >= 0] > 0.0)
    # when the separating hump is not crossed the lobes are one patch only if gap < delta between
    xl, pid, P, _ = kp.kp_patches(s, gap, R, 1.0e-5, E, NU, kp.EPS_DEFAULT)
    assert len(P) == 1                          # second lobe (gap 2e-5) not reached


def test_conformal_gap_gives_long_narrow_non_elliptic_patch():
    # very flat (quartic) lateral gap, as in a worn, conformal tread contact
    s = np.linspace(-0.04, 0.04, 1601)
    gap = 2.0e2 * s ** 4
    R = np.full(s.size, 0.43)
    dk = kp.kp_delta_for_force(s, gap, R, N, E, NU, kp.EPS_DEFAULT)
    xl, pid, P, _ = kp.kp_patches(s, gap, R, dk, E, NU, kp.EPS_DEFAULT)
    p = P[0]
    assert p["width"] / p["length"] > 3.0
    # an ellipse with the same length and width would have area pi/4 L W; a flat-sided patch more
    assert p["area"] / (math.pi / 4 * p["length"] * p["width"]) > 1.05
    # and the equivalent Hertz ellipse from the local curvature at the deepest point is useless:
    # B = 0 there (guarded), while the KP patch is finite
    assert np.isfinite(p["normal_force"]) and p["p_max"] > 0


def test_variable_rolling_radius_shapes_the_patch():
    # larger longitudinal radius on one side -> longer strips there, centroid shifted
    _, _, (a, b, d, p0), s, gap, R = _hertz_gap(1.0)
    R2 = R * (1.0 + 20.0 * s)
    xl, pid, P, _ = kp.kp_patches(s, gap, R2, d, E, NU, kp.EPS_DEFAULT)
    assert P[0]["y_centroid"] > 0.0
    assert xl[s > 0.5 * b][:5].sum() > xl[s < -0.5 * b][-5:].sum()


def test_creep_forces_linear_limit_and_saturation():
    for ratio in (0.5, 1.0, 3.0):
        _, _, (a, b, d, p0), s, gap, R = _hertz_gap(ratio)
        dk = kp.kp_delta_for_force(s, gap, R, N, E, NU, kp.EPS_DEFAULT)
        xl, pid, P, arr = kp.kp_patches(s, gap, R, dk, E, NU, kp.EPS_DEFAULT)
        ae, be = P[0]["a_eq"], P[0]["b_eq"]
        for xi in ((1e-5, 0.0, 0.0), (0.0, 1e-5, 0.0), (0.0, 0.0, 1e-4)):
            Fx, Fy = kp.kp_creep_forces(s, xl, arr, 0, *xi, MU, G, NU, 20)
            lin = cr.creep_forces(cr.LINEAR, *xi, ae, be, N, MU, G, NU)
            i = 0 if xi[0] else 1
            assert (Fx, Fy)[i] == pytest.approx(lin[i], rel=0.01)
        for xi in ((0.05, 0.0, 0.0), (0.0, 0.05, 0.0), (0.03, -0.03, 0.5)):
            Fx, Fy = kp.kp_creep_forces(s, xl, arr, 0, *xi, MU, G, NU, 20)
            assert math.hypot(Fx, Fy) == pytest.approx(MU * P[0]["normal_force"], rel=2e-3)
        f1 = np.array(kp.kp_creep_forces(s, xl, arr, 0, 1e-3, -5e-4, 0.2, MU, G, NU, 20))
        f2 = np.array(kp.kp_creep_forces(s, xl, arr, 0, -1e-3, 5e-4, -0.2, MU, G, NU, 20))
        assert np.allclose(f1, -f2, rtol=1e-12)


def test_no_contact_and_bad_input():
    s = np.linspace(-0.01, 0.01, 101)
    gap = 5.0 * s * s
    R = np.full(101, 0.43)
    xl = np.zeros(101)
    pid = np.zeros(101, dtype=np.int64)
    patches = np.zeros((3, kp.NPROP))
    assert kp.kp_normal(s, gap, R, 0.0, E, NU, 0.55, xl, pid, patches) == 0
    assert np.all(pid == -1) and np.all(xl == 0.0)
    assert kp.kp_creep_forces(s, xl, patches, 0, 1e-3, 0.0, 0.0, MU, G, NU, 20) == (0.0, 0.0)
    with pytest.raises(ValueError):
        kp.kp_normal_force(s, gap, R[:50], 1e-4, E, NU, 0.55)
    with pytest.raises(ValueError):
        kp.kp_normal_force(s, gap, R, 1e-4, E, NU, 1.5)


# ---------------------------------------------------------------------------------------- the vehicle core's strips
STRIP_FORCE_TOLERANCE = 6e-4       # docs/contact-models.md: 5.1e-4 at B/A 3 with 16 strips, 1.3e-4 for the sphere
STRIP_AREA_TOLERANCE = 1e-4        # 4.2e-5


def _strip_patch(ratio, m, eps, delta=1e-4):
    """kp_strip_force on gap = B y^2 (R_long = 1/(2A)), m strips across the extent of f = eps delta - gap > 0:
    (N, area, length)."""
    B = ratio * A_WHEEL
    w = math.sqrt(eps * delta / B)
    ds = 2.0 * w / m
    y = (np.arange(m) + 0.5) * ds
    f = eps * delta - B * (y - w) ** 2
    N_, IS, xlmax, area = kp.kp_strip_force(f, np.full(m, 1.0 / (2.0 * A_WHEEL)), m, ds, w, (0.0, 0.0), eps * delta,
                                            delta, E_STAR, np.zeros(m))
    return N_, area, 2.0 * xlmax


def test_the_vehicle_cores_strips_give_the_converged_kp_patch():
    """`wheelset.KP_STRIPS` strips at fixed fractions of the patch (`kp_strip_force`): the normal force of a Hertzian
    gap within STRIP_FORCE_TOLERANCE of Hertz's closed form (eps = 0.5, sphere) and of KP over 8001 grid strips
    (eps = 0.55, B/A 0.3-3); the area within STRIP_AREA_TOLERANCE, the length exact."""
    from railderail_sim.contact.wheelset import KP_STRIPS
    d = 1e-4
    R = 1.0 / (2.0 * A_WHEEL)
    a = math.sqrt(R * d)
    assert _strip_patch(1.0, KP_STRIPS, 0.5, d)[0] == pytest.approx(4.0 / 3.0 * E_STAR * a ** 3 / R,
                                                                    rel=STRIP_FORCE_TOLERANCE)
    for ratio in (0.3, 0.5, 1.0, 2.0, 3.0):
        B = ratio * A_WHEEL
        s = np.linspace(-1.05, 1.05, 8001) * math.sqrt(d / B)
        _, _, P, _ = kp.kp_patches(s, B * s * s, np.full(s.size, R), d, E, NU, kp.EPS_DEFAULT)
        N_, area, length = _strip_patch(ratio, KP_STRIPS, kp.EPS_DEFAULT, d)
        assert N_ == pytest.approx(P[0]["normal_force"], rel=STRIP_FORCE_TOLERANCE), ratio
        assert area == pytest.approx(P[0]["area"], rel=STRIP_AREA_TOLERANCE), ratio
        assert length == pytest.approx(P[0]["length"], rel=1e-9), ratio


@pytest.mark.parametrize("y, psi", [(0.0, 0.0), (0.003, 0.0), (0.0065, 0.0), (0.008, 0.005)])
def test_the_vehicle_cores_kp_force_is_smooth_in_the_approach(y, psi):
    """The wheel pushed down in 0.05 um steps from 20 to 120 um (tread, flange root, flange with yaw): no jump
    in the KP normal force, |N_i - (N_i-1 + N_i+1) / 2| / N_i below 2e-5 (measured at most 9.5e-6; the curvature
    alone gives 2e-7). The strips of the grid's cells with at least 24 across a patch gave 2.6e-5 on the tread
    and 2.5e-3 on the flange, where the patch's samples jumped with its extent."""
    from railderail_sim.contact import geometry as geo
    from railderail_sim.contact import wheelset as ws
    from railderail_sim.contact.layout import W_SIZE
    from railderail_sim.parameters import ContactParameters, TrackParameters
    from railderail_sim.vehicle.assemble import contact_array, contact_geometry
    c = ContactParameters(normal_model="discrete", contact_damping=0.0)
    cg = contact_geometry(c, TrackParameters(), 0.46)
    cp = contact_array(c)
    scratch = ws.contact_scratch(cg)
    z0, phi, _, _ = geo.rigid_contact(cg, y, psi, scratch.gap, scratch.ys)
    forces = []
    for dz in np.arange(20e-6, 120e-6, 0.05e-6):
        f = ws.wheel_forces(cg, cp, 0, (y, z0 - dz, phi, psi), (83.3, 0.0, 0.0, 0.0, 0.0, 0.0, 181.0, 83.3), scratch,
                            ws.candidates()[0], False, np.zeros(W_SIZE))
        forces.append(math.hypot(f[1], f[2]))
    N_ = np.array(forces)
    assert np.all(np.diff(N_) > 0.0)
    assert np.max(np.abs(N_[1:-1] - 0.5 * (N_[:-2] + N_[2:])) / N_[1:-1]) < 2e-5
