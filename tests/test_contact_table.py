"""Contact table (contact.table) against the exact online search it stands in for."""
import numpy as np
import pytest

from railderail_sim.contact import geometry as geo
from railderail_sim.contact import table as tab
from railderail_sim.contact import wheelset as ws
from railderail_sim.parameters import ContactParameters, TrackParameters
from railderail_sim.vehicle.assemble import contact_array, contact_geometry
from railderail_sim.contact.layout import CANDIDATES_SIZE, MAX_PATCHES, P_COLS, W_SIZE, GeometryHeader, Patch


@pytest.fixture(scope="module")
def geometries():
    """(exact, tabulated) packed geometry of LM on UIC60 1:40."""
    exact = contact_geometry(ContactParameters(contact_geometry="online"), TrackParameters(), 0.46)
    return exact, tab.attach(exact)


def _buffers(cg):
    n = int(cg[GeometryHeader.wheel_points])
    return (np.zeros(n), np.zeros(n), np.zeros((MAX_PATCHES, P_COLS)), np.zeros((MAX_PATCHES, P_COLS)),
            np.zeros(CANDIDATES_SIZE))


def _random_poses(exact, n, seed=7):
    """Poses across the table (tread to flange, rolled and yawed) pressed 0-150 um into the rail."""
    rng = np.random.default_rng(seed)
    gap, ys, _, _, _ = _buffers(exact)
    poses = []
    for _ in range(n):
        y = rng.uniform(-0.015, 0.025)
        phi = rng.uniform(-0.02, 0.02)
        psi = rng.uniform(-tab.PSI_MAX, tab.PSI_MAX)
        g0, _ = geo.min_gap(exact, y, 0.0, phi, psi, gap, ys)
        poses.append((y, -g0 + rng.uniform(-150e-6, 0.0), phi, psi))
    return poses


def test_table_matches_the_online_search(geometries):
    exact, table = geometries
    gap, ys, online, tabulated, cand = _buffers(exact)
    errors, angles, fallback, unmatched = [], [], 0, 0
    poses = _random_poses(exact, 1500)
    for y, z, phi, psi in poses:
        n_online, _ = geo.find_patches(exact, y, z, phi, psi, gap, ys, online, cand)
        n_table, _ = tab.table_patches(table, y, z, phi, psi, tabulated, cand)
        if n_table < 0:
            fallback += 1
            continue
        if n_table != n_online:
            # only a contact just touching may be counted by one and not the other
            shallow = min(online[:n_online, Patch.gap].min(initial=0.0), tabulated[:n_table, Patch.gap].min(initial=0.0))
            assert shallow > -3e-6, (y, z, phi, psi)
            unmatched += 1
            continue
        for k in range(n_online):
            errors.append(tabulated[k, Patch.gap] - online[k, Patch.gap])
            angles.append(np.arctan(tabulated[k, Patch.slope]) - np.arctan(online[k, Patch.slope]))
    errors = np.abs(errors)
    assert fallback < 0.10 * len(poses) and unmatched < 0.01 * len(poses)
    # penetrations are 0-150 um: the gap (hence the Hertz force, ~ gap^1.5) agrees to about a micrometre
    assert np.percentile(errors, 50) < 0.3e-6
    assert np.percentile(errors, 99) < 1.0e-6
    assert errors.max() < 5e-6
    assert np.percentile(np.abs(angles), 99) < 0.01


def test_vertical_displacement_is_exact(geometries):
    """z shifts the gap function as a whole: the tabulated gap moves by exactly dz."""
    exact, table = geometries
    gap, ys, _, rows, cand = _buffers(table)
    g0, _ = geo.min_gap(exact, 0.004, 0.0, 0.003, 0.002, gap, ys)
    n1, _ = tab.table_patches(table, 0.004, -g0 - 1e-4, 0.003, 0.002, rows, cand)
    g1 = rows[0, Patch.gap]
    n2, _ = tab.table_patches(table, 0.004, -g0 - 5e-5, 0.003, 0.002, rows, cand)
    assert n1 == n2 == 1
    assert rows[0, Patch.gap] - g1 == pytest.approx(5e-5, abs=1e-15)


def test_tread_forces_agree_with_the_exact_search(geometries):
    """Normal and creep forces of a loaded wheel, table vs online, on the tread and at the flange root."""
    exact, table = geometries
    cp = contact_array(ContactParameters())
    nw = int(exact[GeometryHeader.wheel_points])
    gap, ys = np.zeros(nw), np.zeros(nw)
    for y, psi in ((0.0, 0.0), (0.003, 0.002), (0.0087, 0.005)):
        forces = []
        for cg in (exact, table):
            g0, _ = geo.min_gap(exact, y, 0.0, 0.0, psi, gap, ys)
            rec = np.zeros(W_SIZE)
            f = ws.wheel_forces(cg, cp, 0, (y, -g0 - 80e-6, 0.0, psi), (83.3, 0.0, 0.0, 0.0, 0.0, 0.0, 83.3 / 0.46, 83.3),
                                ws.contact_scratch(cg), ws.candidates()[0], False, rec)
            forces.append(np.array(f[:3]))
        normal = np.linalg.norm(forces[0])
        assert normal > 20e3
        assert np.linalg.norm(forces[1] - forces[0]) < 0.03 * normal, (y, psi, forces)


def test_outside_the_table_it_says_so(geometries):
    _, table = geometries
    _, _, _, rows, cand = _buffers(table)
    assert tab.table_patches(table, 0.0, 0.0, 0.0, 1.5 * tab.PSI_MAX, rows, cand)[0] == -1
    assert tab.table_patches(table, tab.U_MAX + 0.001, 0.0, 0.0, 0.0, rows, cand)[0] == -1
    assert tab.table_patches(table, 0.0, 0.0, tab.PHI_MAX + 0.001, 0.0, rows, cand)[0] == -1
    exact, _ = geometries
    assert tab.table_patches(exact, 0.0, 0.0, 0.0, 0.0, rows, cand)[0] == -1      # no table attached


def test_unknown_contact_geometry_is_refused():
    with pytest.raises(ValueError, match="'exact'.*table, online"):
        contact_geometry(ContactParameters(contact_geometry="exact"), TrackParameters(), 0.46)


def test_models_of_one_geometry_share_one_table(geometries):
    """The table is built once per geometry and process, and is the table a fresh build gives."""
    exact, table = geometries
    first = contact_geometry(ContactParameters(), TrackParameters(), 0.46)
    assert contact_geometry(ContactParameters(), TrackParameters(), 0.46) is first
    assert np.array_equal(first, table)
    other = contact_geometry(ContactParameters(), TrackParameters(), 0.45)       # another wheelset radius
    assert other is not first and other[GeometryHeader.nominal_radius] == 0.45
