"""Contact geometry: search against brute force, mirror symmetry, rigid tables, conicity (EN 15302)."""
import math

import numpy as np
import pytest

from railderail_sim.contact import conicity as C
from railderail_sim.contact import geometry as geo
from railderail_sim.parameters import ContactParameters, TrackParameters
from railderail_sim.vehicle.assemble import contact_geometry
from railderail_sim.contact.layout import CANDIDATES_SIZE, MAX_PATCHES, P_COLS, W_SIZE, GeometryHeader, Patch


@pytest.fixture(scope="module", params=["lm", "s1002"])
def cg(request):
    return contact_geometry(ContactParameters(wheel_profile=request.param), TrackParameters(), 0.46)


@pytest.fixture(scope="module")
def cg_lm():
    return contact_geometry(ContactParameters(wheel_profile="lm"), TrackParameters(), 0.46)


def _buffers(cg):
    n = int(cg[GeometryHeader.wheel_points])
    return np.zeros(n), np.zeros(n), np.zeros((MAX_PATCHES, P_COLS)), np.zeros(CANDIDATES_SIZE)


def _brute_force(cg, y, z, phi, psi):
    """Patches on the full fine grid by the same definition: every local minimum below zero, refined by the
    parabola, with its share weight from the ridges to its neighbours (geometry._set_weights)."""
    gap, ys, _, _ = _buffers(cg)
    j0, j1 = geo.trace_gap(cg, y, z, phi, psi, gap, ys)
    g = gap[j0:j1]
    minima = [j for j in range(1, len(g) - 1) if g[j] < 0 and g[j] <= g[j - 1] and g[j] < g[j + 1]]
    weights = [1.0] * len(minima)
    for k in range(len(minima) - 1):
        a, b = minima[k], minima[k + 1]
        ridge = np.max(g[a:b + 1])
        s = k if g[a] > g[b] else k + 1
        w = (ridge - g[minima[s]]) / (geo.PROMINENCE_FULL * -g[minima[s]])
        weights[s] = min(weights[s], max(0.0, min(1.0, w)))
    out = []
    for m, w in zip(minima, weights):
        den = g[m - 1] - 2 * g[m] + g[m + 1]
        out.append((g[m] - 0.125 * (g[m - 1] - g[m + 1]) ** 2 / den if den > 0 else g[m], w))
    return out


def _significant(pairs, floor=0.05):
    """Gaps of the patches that carry a share (ripples with weight ~0 may fall between coarse samples)."""
    return sorted(g for g, w in pairs if w > floor)


def test_coarse_to_fine_search_finds_every_patch(cg):
    """Random poses (tread, flange, two-point, yaw to 0.08 rad, roll to 0.03 rad): same patches."""
    rng = np.random.default_rng(7)
    gap, ys, patches, cand = _buffers(cg)
    for _ in range(400):
        y = rng.uniform(-0.012, 0.03)
        psi = rng.uniform(-0.08, 0.08)
        phi = rng.uniform(-0.03, 0.03)
        g0, _ = geo.min_gap(cg, y, 0.0, phi, psi, gap, ys)
        z = -g0 - rng.uniform(1e-6, 3e-4)
        expected = _brute_force(cg, y, z, phi, psi)
        n, _ = geo.find_patches(cg, y, z, phi, psi, gap, ys, patches, cand)
        got = _significant(zip(patches[:n, Patch.gap], patches[:n, Patch.weight]))
        want = _significant(expected)
        assert len(got) == len(want)
        assert np.allclose(got, want, atol=1e-9)
        assert min(patches[:n, Patch.gap], default=0.0) == pytest.approx(min((g for g, _ in expected), default=0.0),
                                                                          abs=1e-9)


def test_tracking_inside_a_step_reproduces_the_full_search(cg_lm):
    gap, ys, patches, cand = _buffers(cg_lm)
    p2 = np.zeros_like(patches)
    for y, psi in [(0.0, 0.0), (0.004, 0.002), (0.0085, 0.01), (0.012, 0.03)]:
        g0, _ = geo.min_gap(cg_lm, y, 0.0, 0.0, psi, gap, ys)
        z = -g0 - 1e-4
        n, _ = geo.find_patches(cg_lm, y, z, 0.0, psi, gap, ys, patches, cand)
        # move by a typical step (0.02 mm, 1e-5 rad) and compare tracking with a new full search
        m = geo.track_patches(cg_lm, y + 2e-5, z, 1e-5, psi, gap, ys, p2, cand)
        k, _ = geo.find_patches(cg_lm, y + 2e-5, z, 1e-5, psi, gap, ys, patches, np.zeros_like(cand))
        assert m == k
        assert np.allclose(np.sort(p2[:m, Patch.gap]), np.sort(patches[:k, Patch.gap]), atol=1e-12)


def test_wheel_lifts_off_with_a_gap(cg_lm):
    gap, ys, patches, cand = _buffers(cg_lm)
    g0, _ = geo.min_gap(cg_lm, 0.0, 0.0, 0.0, 0.0, gap, ys)
    n, gmin = geo.find_patches(cg_lm, 0.0, -g0 + 1e-3, 0.0, 0.0, gap, ys, patches, cand)
    assert n == 0 and gmin == pytest.approx(1e-3, abs=2e-6)


@pytest.fixture(scope="module")
def tables():
    return {name: C.rigid_table(contact_geometry(ContactParameters(wheel_profile=name), TrackParameters(), 0.46),
                                0.012, 1e-4) for name in ("lm", "s1002")}


def test_rigid_table_mirror_symmetry(tables):
    for t in tables.values():
        i0 = len(t.y) // 2
        assert t.y[i0] == 0.0 and t.delta_r[i0] == pytest.approx(0.0, abs=1e-12)
        assert np.allclose(t.delta_r, -t.delta_r[::-1], atol=1e-9)
        assert np.allclose(t.radius_left, t.radius_right[::-1], atol=1e-9)
        assert np.allclose(t.roll, -t.roll[::-1], atol=1e-12)


def test_flange_contact_angle_reaches_the_profile_flange_angle(tables):
    lm = tables["lm"]
    assert math.degrees(lm.contact_angle_left.max()) == pytest.approx(69.4, abs=0.3)
    assert math.degrees(tables["s1002"].contact_angle_left.max()) == pytest.approx(70.0, abs=0.3)


def test_equivalent_conicity_of_a_cone_is_its_cone_angle():
    y = np.round(np.arange(-0.012, 0.012 + 5e-5, 1e-4), 12)
    zeros = np.zeros_like(y)
    for gamma in (0.025, 0.05, 0.2):
        t = C.RigidTable(y, 2 * gamma * y, *([zeros] * 14), r0=0.46, contact_half_distance=0.75)
        ge, lam = C.equivalent_conicity(t, 0.003)
        assert ge == pytest.approx(gamma, rel=1e-6)
        assert lam == pytest.approx(2 * math.pi * math.sqrt(0.75 * 0.46 / gamma), rel=1e-6)  # Klingel
        assert C.harmonic_conicity(t, 0.003) == pytest.approx(gamma, rel=1e-6)


def test_lm_conicity_against_independent_estimate(tables):
    """An EN 15302 computation on the LM.prw table itself (SIMPACK's example LM, docs/profiles.md), outside
    this code, gave 0.11 at 3 mm on UIC60 1:40."""
    ge, _ = C.equivalent_conicity(tables["lm"], 0.003)
    assert 0.10 <= ge <= 0.13


def test_bad_amplitude_is_refused(tables):
    with pytest.raises(ValueError, match="amplitude 20 mm is outside"):
        C.equivalent_conicity(tables["lm"], 0.02)


@pytest.mark.parametrize("model", ["hertz", "discrete"])
def test_two_point_contact_force_is_continuous(model):
    """S1002 (back-to-back 1360 mm) at 5 mm touches tread and flange root at once: pushing the wheel down
    must raise its normal force smoothly, with no jump where the ridge between the two lobes sinks below
    zero gap or toward the minima (a multi-patch model that merged or dropped one lobe would jump)."""
    from railderail_sim.contact import wheelset as ws
    from railderail_sim.vehicle.assemble import contact_array
    c = ContactParameters(wheel_profile="s1002", back_to_back=1.360, normal_model=model, contact_damping=0.0)
    cg = contact_geometry(c, TrackParameters(), 0.46)
    cp = contact_array(c)
    scratch = ws.contact_scratch(cg)
    z0, phi, _, _ = geo.rigid_contact(cg, 0.005, 0.0, scratch.gap, scratch.ys)
    forces = []
    for dz in np.arange(20e-6, 160e-6, 2e-6):
        fm = ws.wheel_forces(cg, cp, 0, (0.005, z0 - dz, phi, 0.0), (83.3, 0.0, 0.0, 0.0, 0.0, 0.0, 181.0, 83.3),
                             scratch, ws.candidates()[0], False, np.zeros(W_SIZE))
        forces.append(fm[2])
    steps = np.diff(forces)
    assert np.all(steps > 0.0)                          # monotonic
    assert np.max(steps) < 2.5 * np.median(steps)       # no jump


@pytest.mark.parametrize("y, phi, psi", [(0.0, 0.0, 0.03), (0.006, 0.002, 0.05), (0.0095, 0.004, 0.08),
                                         (0.0095, -0.004, -0.06)])
def test_trace_line_gap_is_the_wheel_surfaces_lowest_point_at_large_yaw(cg_lm, y, phi, psi):
    """Sharp curves bring attack angles of tens of mrad: the trace line's closed form (module docstring of
    contact.geometry) against a brute-force search over the whole wheel surface, a body of revolution
    rotated by roll and yaw, above the rail extruded along the track."""
    gap, ys, _, _ = _buffers(cg_lm)
    g_trace, _ = geo.min_gap(cg_lm, y, 0.0, phi, psi, gap, ys)
    wz, _, _ = geo.wheel_table(cg_lm)
    rz, _, _ = geo.rail_table(cg_lm)
    H = GeometryHeader
    yp = cg_lm[H.wheel_y0] + cg_lm[H.wheel_step] * np.arange(len(wz))
    rail_y = cg_lm[H.rail_y0] + cg_lm[H.rail_step] * np.arange(len(rz))
    r = cg_lm[H.nominal_radius] + wz
    eta = cg_lm[H.rolling_circle_distance] + yp
    theta = np.linspace(-0.25, 0.25, 5001)[:, None]                 # from the lowest point of each circle
    px, pz = r * np.sin(theta), -r * np.cos(theta)
    qy = eta * math.cos(phi) - pz * math.sin(phi)                   # roll about x, then yaw about z
    qz = eta * math.sin(phi) + pz * math.cos(phi)
    Y = y + math.sin(psi) * px + math.cos(psi) * qy
    Z = cg_lm[H.nominal_radius] + qz
    inside = (Y > rail_y[0]) & (Y < rail_y[-1])
    g_brute = np.min(np.where(inside, Z - np.interp(Y, rail_y, rz), np.inf))
    assert g_trace == pytest.approx(g_brute, abs=1e-6)


def test_small_angle_sin_cos_within_an_ulp_of_libm():
    """`wheelset.sin_cos` (the wheel's roll and yaw): its Taylor polynomials within one rounding of libm's
    sin and cos up to SMALL_ANGLE, libm's own values beyond."""
    from railderail_sim.contact import wheelset as ws
    rng = np.random.default_rng(5)
    xs = np.concatenate([np.linspace(-ws.SMALL_ANGLE, ws.SMALL_ANGLE, 20001), rng.uniform(-0.05, 0.05, 20000),
                         [0.0, -0.0, 1e-300, 1e-9, ws.SMALL_ANGLE, -ws.SMALL_ANGLE]])
    for x in xs:
        s, c = ws.sin_cos(float(x))
        assert abs(s - math.sin(x)) <= np.spacing(abs(math.sin(x))) and abs(c - math.cos(x)) <= np.spacing(1.0) / 2
    for x in (0.0500001, -0.07, 0.3, -1.2, 3.0):
        assert ws.sin_cos(x) == (math.sin(x), math.cos(x))
