"""Contact table: the exact contact search done once, ahead of the time loop, over lateral shift and roll.

Why. The exact search of `geometry.find_patches` costs about 3 us per wheel, and the Hertz shape from the
elliptic integrals (`hertz.hertz_shape`) about 0.3 us per patch; a vehicle step needs both dozens of times.
Everything they give depends on the wheel's pose only through (y, phi, psi) plus an additive z, so it can
be computed beforehand, the way Simpack's and VAMPIRE's contact tables are, without changing the model:

- The vertical displacement z of the wheelset shifts the whole gap function g(y_p) by z (`geometry._scan`:
  the wheel centre's height enters as a sum): z is exact, not tabulated.
- Lateral shift and roll are the table's grid, bilinear. Rolling the wheelset by phi about its centre
  also moves the wheel r0 phi sideways at the rail, so the lateral axis is u = y + r0 phi - lw phi^2/2
  (the nominal rolling circle's lateral position over the rail, lw its distance from the centre): at
  fixed u a change of roll only turns the profile (0.025 mm steps in u; a 2 mrad step in phi moves a
  flange point about 0.03 mm across the rail, (r - r0) phi).
- Where the contact point runs quickly across the profile (from the flange root to the flank the contact
  angle turns by 50 degrees within 0.2 mm of lateral shift) the gap's envelope bends too sharply for
  linear interpolation; a cell whose nodes' tan(contact angle) spread by more than SLOPE_SPREAD is not
  used (the interpolation error of the gap is about spread x step / 8, under a micrometre elsewhere).
- Yaw psi moves the contact point along the rail (lead) and lifts the wheel's trace line, by r(1 - cos
  theta) with sin theta ~ r' psi: second order in psi on the tread, but tens of micrometres on a flange at
  10 mrad. Each tabulated quantity q therefore keeps q(psi) = q0 + q1 psi + q2 psi^2, from the exact
  search at psi = 0 and +-PSI_FIT (the minimum searched again at each yaw, so the terms are those of the
  minimum itself, not of a fixed wheel point).

At each node the gap along the whole trace line is computed on the fine wheel grid and every local
minimum below STORE_GAP is kept (up to MAX_PATCHES, the deepest): a patch at run time wherever
g + z < 0, a candidate for the in-step search below TRACK_GAP. Each keeps its contact point, rail slope,
wheel coordinate, the Hertz shape at E* = 1 Pa (semi-axis coefficients scale as E*^(-1/3), the stiffness
as E*: exact, `hertz.hertz_shape`), and the highest gap between it and the next minimum (the ridge that
sets the share weight of `geometry._set_weights`). The wheel radius and the curvature sums A, B that the
shape comes from are not kept: the force needs only the shape, and each interpolated quantity costs.

Where the table does not apply, `table_patches` returns -1 and the wheel is searched online
(`geometry.find_patches` / `track_patches`), exactly as without a table:
- outside the grid (a wheel climbing beyond U_MAX, rolled beyond PHI_MAX) or |psi| > PSI_MAX;
- in a cell where the contact angle turns fast (SLOPE_SPREAD, above);
- where the four surrounding nodes do not have the same minima (a contact appearing or vanishing, or a
  minimum jumping across the profile between nodes), since interpolating there would blend two contacts.
`tests/test_contact_table.py` compares the two over random poses.
"""
import math

import numpy as np

from ..jit import core, core_inline
from . import geometry as geo
from .hertz import hertz_shape
from ..record import Record
from .layout import MAX_CANDIDATES, MAX_PATCHES, P_COLS, Candidates, GeometryHeader, HertzShape, Patch

# Grid (left-wheel form: the right wheel is the mirrored left one, so one table serves both rails)
U_MIN, U_MAX, DU = -0.020, 0.030, 2.5e-5       # m; lateral axis u (above), + toward the rail
PHI_MAX, DPHI = 0.030, 2.0e-3                   # rad; roll relative to the track
PSI_MAX = 0.010                                 # rad; yaw served by the second-order yaw terms
PSI_FIT = 0.008                                 # rad; yaw of the two extra searches that give them
STORE_GAP = 0.030                               # m; minima kept per node (a wheel lifted by more is far from contact)
JUMP = 24                                       # wheel grid steps (3 mm); a minimum moving more between
                                                # nodes (or between yaws) is not the same contact
SLOPE_SPREAD = 0.30                             # largest spread of tan(contact angle) over a cell's nodes



class Tabulated(Record):
    """The quantities tabulated for one minimum of the gap (at z = 0), each as yaw terms."""
    gap = "m", "vertical gap at the minimum"
    y = "m", "contact point's track-frame Y"
    x = "m", "contact point's lead"
    height = "m", "contact point's track-frame Z minus r0"
    slope = "-", "rail slope at the contact"
    wheel_y = "m", "wheel profile coordinate of the contact"
    hertz_a = "m N^(-1/3)", "Hertz shape at E* = 1 Pa: a_c"
    hertz_b = "m N^(-1/3)", "Hertz shape at E* = 1 Pa: b_c"
    hertz_stiffness = "N m^-1.5", "Hertz shape at E* = 1 Pa: C"


class YawTerms(Record):
    """q(psi) = q0 + q1 psi + q2 psi^2 of a tabulated quantity."""
    q0 = "as the quantity", "value at psi = 0"
    q1 = "per rad", "first-order yaw term"
    q2 = "per rad^2", "second-order yaw term"


class TableMinimum(Record):
    """One minimum kept at a node."""
    quantities = "-", "each Tabulated quantity's yaw terms", (Tabulated.size(),), YawTerms
    ridge = "m", "highest gap between this minimum and the next one"
    grid_index = "-", "wheel grid index of the minimum at psi = 0"


class TableNode(Record):
    """One node of the table (lateral u, roll phi)."""
    count = "-", "minima kept (-1: the node is unusable)"
    min_gap = "m", "smallest gap along the trace line"
    minima = "-", "the minima, in order across the wheel", (MAX_PATCHES,), TableMinimum


NQ = Tabulated.size()
YAW_TERMS = YawTerms.size()
M_SIZE = TableMinimum.size()
N_COLS = TableNode.size()
MAX_MINIMA = 16                                 # local minima looked at per node


def attach(cg):
    """cg with the contact table appended (a new array; the input is left as it is)."""
    ny = int(round((U_MAX - U_MIN) / DU)) + 1
    nphi = int(round(2.0 * PHI_MAX / DPHI)) + 1
    base = cg.shape[0]
    out = np.zeros(base + ny * nphi * N_COLS)
    out[:base] = cg
    H = GeometryHeader
    for field, value in ((H.table, base), (H.table_u_points, ny), (H.table_u0, U_MIN), (H.table_u_step, DU),
                         (H.table_roll_points, nphi), (H.table_roll0, -PHI_MAX), (H.table_roll_step, DPHI),
                         (H.table_yaw_max, PSI_MAX)):
        out[field] = value
    nw = int(cg[GeometryHeader.wheel_points])
    _build(out, np.zeros(nw), np.zeros(nw), np.zeros((MAX_PATCHES, P_COLS)),
           np.zeros((3, MAX_PATCHES, NQ)), np.zeros(MAX_MINIMA, dtype=np.int64))
    return out


@core
def _quantities(cg, row, q):
    """Tabulated quantities of one patch row of `geometry._fill_patch` (at z = 0) into q[:]."""
    q[Tabulated.gap] = row[Patch.gap]
    q[Tabulated.y] = row[Patch.y]
    q[Tabulated.x] = row[Patch.x]
    q[Tabulated.height] = row[Patch.z] - cg[GeometryHeader.nominal_radius]
    q[Tabulated.slope] = row[Patch.slope]
    q[Tabulated.wheel_y] = row[Patch.wheel_y]
    a, b, stiffness = hertz_shape(row[Patch.curvature_a], row[Patch.curvature_b], 1.0)
    q[Tabulated.hertz_a] = a
    q[Tabulated.hertz_b] = b
    q[Tabulated.hertz_stiffness] = stiffness


@core
def _build(cg, gap, ys, patches, qs, minima):
    base = int(cg[GeometryHeader.table])
    ny = int(cg[GeometryHeader.table_u_points])
    nphi = int(cg[GeometryHeader.table_roll_points])
    h = PSI_FIT
    r0 = cg[GeometryHeader.nominal_radius]
    lw = cg[GeometryHeader.rolling_circle_distance]
    for iy in range(ny):
        u = cg[GeometryHeader.table_u0] + iy * cg[GeometryHeader.table_u_step]
        for ip in range(nphi):
            phi = cg[GeometryHeader.table_roll0] + ip * cg[GeometryHeader.table_roll_step]
            y = u - phi * (r0 - 0.5 * lw * phi)
            o = base + (iy * nphi + ip) * N_COLS
            pose = geo.pose_constants(cg, y, 0.0, phi, 0.0)
            j0, j1 = geo.wheel_range(cg, pose)
            geo._scan(cg, pose, j0, j1, 1, gap, ys)
            gmin = geo.NO_RAIL_GAP
            nmin = 0
            for j in range(j0, j1):
                gmin = min(gmin, gap[j])
                if (j > j0 and j < j1 - 1 and gap[j] < STORE_GAP and gap[j] < gap[j - 1]
                        and gap[j] <= gap[j + 1] and nmin < MAX_MINIMA):
                    minima[nmin] = j
                    nmin += 1
            # keep the MAX_PATCHES deepest, in order across the wheel
            while nmin > MAX_PATCHES:
                worst = 0
                for k in range(nmin):
                    if gap[minima[k]] > gap[minima[worst]]:
                        worst = k
                for k in range(worst, nmin - 1):
                    minima[k] = minima[k + 1]
                nmin -= 1
            cg[o + TableNode.min_gap] = gmin
            for k in range(nmin):
                s = o + TableNode.minima + k * M_SIZE
                ridge = geo.NO_RAIL_GAP
                if k + 1 < nmin:
                    ridge = gap[minima[k]]
                    for j in range(minima[k] + 1, minima[k + 1]):
                        ridge = max(ridge, gap[j])
                cg[s + TableMinimum.ridge] = ridge
                cg[s + TableMinimum.grid_index] = minima[k]
            usable = True
            for k in range(nmin):
                jm = minima[k]
                geo._fill_patch(cg, pose, jm, j0, j1, gap, patches, 0)
                _quantities(cg, patches[0], qs[0, k])
            # the same minima searched again at yaw +-h (the gap array is reused: ridges are stored)
            for side in range(2):
                psi = h if side == 0 else -h
                pose_y = geo.pose_constants(cg, y, 0.0, phi, psi)
                a0, a1 = geo.wheel_range(cg, pose_y)
                for k in range(nmin):
                    jc = int(cg[o + TableNode.minima + k * M_SIZE + TableMinimum.grid_index])
                    jm = geo.local_minimum(cg, pose_y, min(max(jc, a0), a1 - 1), a0, a1, 1, gap, ys)
                    if abs(jm - jc) > JUMP:
                        usable = False
                    geo._fill_patch(cg, pose_y, jm, a0, a1, gap, patches, 0)
                    _quantities(cg, patches[0], qs[1 + side, k])
            for k in range(nmin):
                s = o + TableNode.minima + k * M_SIZE
                for q in range(NQ):
                    q0 = qs[0, k, q]
                    qp = qs[1, k, q]
                    qm = qs[2, k, q]
                    terms = _quantity(s, q)
                    cg[terms + YawTerms.q0] = q0
                    cg[terms + YawTerms.q1] = (qp - qm) / (2.0 * h)
                    cg[terms + YawTerms.q2] = (qp + qm - 2.0 * q0) / (2.0 * h * h)
            cg[o + TableNode.count] = nmin if usable else -1


@core_inline
def _quantity(minimum, q):
    """Offset of Tabulated quantity q's yaw terms in the TableMinimum at offset `minimum`."""
    return minimum + TableMinimum.quantities + YAW_TERMS * q


@core_inline
def _at_yaw(cg, i, psi):
    """One node's yaw polynomial q0 + q1 psi + q2 psi^2 stored at cg[i:i+3] (YawTerms)."""
    return cg[i + YawTerms.q0] + psi * (cg[i + YawTerms.q1] + psi * cg[i + YawTerms.q2])


@core_inline
def _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, col, psi):
    """Bilinear interpolation over the cell's four nodes of the yaw polynomial stored at column col."""
    c0 = (w00 * cg[n00 + col + YawTerms.q0] + w01 * cg[n01 + col + YawTerms.q0] + w10 * cg[n10 + col + YawTerms.q0]
          + w11 * cg[n11 + col + YawTerms.q0])
    c1 = (w00 * cg[n00 + col + YawTerms.q1] + w01 * cg[n01 + col + YawTerms.q1] + w10 * cg[n10 + col + YawTerms.q1]
          + w11 * cg[n11 + col + YawTerms.q1])
    c2 = (w00 * cg[n00 + col + YawTerms.q2] + w01 * cg[n01 + col + YawTerms.q2] + w10 * cg[n10 + col + YawTerms.q2]
          + w11 * cg[n11 + col + YawTerms.q2])
    return c0 + psi * (c1 + psi * c2)


@core
def table_patches(cg, y, z, phi, psi, patches, cand):
    """Patches of the left wheel from the contact table: (count, smallest gap), count -1 where the table
    does not apply (the caller then searches online).

    Fills the patch columns of `geometry.find_patches` (contact point, gap, slope, wheel coordinate, grid
    index, share weight; the wheel radius and A, B are NaN) plus the Hertz shape at E* = 1 (Patch.hertz_shape),
    and lists the minima below TRACK_GAP in `cand` for the in-step search, should a later stage leave the
    table.
    """
    base = int(cg[GeometryHeader.table])
    if base == 0 or abs(psi) > cg[GeometryHeader.table_yaw_max]:
        return -1, 0.0
    r0 = cg[GeometryHeader.nominal_radius]
    lw = cg[GeometryHeader.rolling_circle_distance]
    u = (y + phi * (r0 - 0.5 * lw * phi) - cg[GeometryHeader.table_u0]) / cg[GeometryHeader.table_u_step]
    v = (phi - cg[GeometryHeader.table_roll0]) / cg[GeometryHeader.table_roll_step]
    ny = int(cg[GeometryHeader.table_u_points])
    nphi = int(cg[GeometryHeader.table_roll_points])
    if not (u >= 0.0 and u < ny - 1 and v >= 0.0 and v < nphi - 1):
        return -1, 0.0
    i = int(u)
    k = int(v)
    ty = u - i
    tp = v - k
    n00 = base + (i * nphi + k) * N_COLS
    n01 = n00 + N_COLS
    n10 = n00 + nphi * N_COLS
    n11 = n10 + N_COLS
    count = cg[n00 + TableNode.count]
    if (count < 0 or cg[n01 + TableNode.count] != count or cg[n10 + TableNode.count] != count
            or cg[n11 + TableNode.count] != count):
        return -1, 0.0
    nmin = int(count)
    for s in range(nmin):
        col = TableNode.minima + s * M_SIZE + TableMinimum.grid_index
        j = cg[n00 + col]
        lo = min(j, cg[n01 + col], cg[n10 + col], cg[n11 + col])
        hi = max(j, cg[n01 + col], cg[n10 + col], cg[n11 + col])
        if hi - lo > JUMP:
            return -1, 0.0
        col = _quantity(TableNode.minima + s * M_SIZE, Tabulated.slope)
        s00 = _at_yaw(cg, n00 + col, psi)
        s01 = _at_yaw(cg, n01 + col, psi)
        s10 = _at_yaw(cg, n10 + col, psi)
        s11 = _at_yaw(cg, n11 + col, psi)
        if max(s00, s01, s10, s11) - min(s00, s01, s10, s11) > SLOPE_SPREAD:
            return -1, 0.0
    w00 = (1.0 - ty) * (1.0 - tp)
    w01 = (1.0 - ty) * tp
    w10 = ty * (1.0 - tp)
    w11 = ty * tp
    gmin = (w00 * cg[n00 + TableNode.min_gap] + w01 * cg[n01 + TableNode.min_gap] + w10 * cg[n10 + TableNode.min_gap]
            + w11 * cg[n11 + TableNode.min_gap] + z)
    r0z = r0 + z
    count = 0
    ncand = 0
    ridge = -geo.NO_RAIL_GAP               # highest gap since the last patch
    for s in range(nmin):
        o = TableNode.minima + s * M_SIZE
        g = _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.gap), psi) + z
        gmin = min(gmin, g)
        yp = _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.wheel_y), psi)
        jm = int(round((yp - cg[GeometryHeader.wheel_y0]) / cg[GeometryHeader.wheel_step]))
        if g < geo.TRACK_GAP and ncand < MAX_CANDIDATES:
            cand[Candidates.indices + ncand] = jm
            ncand += 1
        if g < 0.0 and count < MAX_PATCHES:
            row = patches[count]
            row[Patch.gap] = g
            row[Patch.y] = _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.y), psi)
            row[Patch.x] = _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.x), psi)
            row[Patch.z] = r0z + _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.height), psi)
            row[Patch.slope] = _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.slope), psi)
            row[Patch.wheel_y] = yp
            # not tabulated: the wheel's contact needs only the Hertz shape below (a stale value from an
            # online search would pass silently)
            row[Patch.radius] = math.nan
            row[Patch.curvature_a] = math.nan
            row[Patch.curvature_b] = math.nan
            shape = Patch.hertz_shape
            row[shape + HertzShape.a_coefficient] = _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.hertz_a), psi)
            row[shape + HertzShape.b_coefficient] = _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.hertz_b), psi)
            row[shape + HertzShape.stiffness] = _value(cg, n00, n01, n10, n11, w00, w01, w10, w11, _quantity(o, Tabulated.hertz_stiffness),
                                                       psi)
            row[Patch.grid_index] = jm
            row[Patch.weight] = 1.0
            if count > 0:                  # share weights as in geometry._set_weights, the ridge from the table
                geo.share_weight(patches, count - 1, count, ridge + z)
            count += 1
            ridge = -geo.NO_RAIL_GAP
        ridge = max(ridge, w00 * cg[n00 + o + TableMinimum.ridge] + w01 * cg[n01 + o + TableMinimum.ridge]
                    + w10 * cg[n10 + o + TableMinimum.ridge] + w11 * cg[n11 + o + TableMinimum.ridge])
    cand[Candidates.count] = ncand
    return count, gmin
