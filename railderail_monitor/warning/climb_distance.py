"""The flange-climb distance criterion of TCRP Report 71 Vol. 5 (Wu and Wilson), as plain functions.

A wheel whose L/V (Q/P) has reached Nadal's limit climbs its flange, but only over a distance: a short
excursion above the limit does not derail. The report's general criterion bounds the distance over which
the limit may be exceeded, as a function of the wheelset's attack angle (AOA, mrad) and of the wheel's
maximum flange angle (Ang, deg) and flange length (Len, in., the length of the flange face at that angle):

    D < A B Len / (AOA + B Len)                           (TCRP Report 71 Vol. 5, 2005, eq. 2.4; D in ft)
    A = 100 / (-1.9128 Ang + 146.56) + 3.1 (Len - 1 / (-0.0092 Ang^2 + 1.2152 Ang - 39.031) + 1.23)
    B = 10 / (-21.157 Len + 2.1052) + 0.05 (Ang + 10 / (0.2688 Len - 0.0266) - 5)

Source and how sure: the equation and every number are from the report's page 7 (National Academies
record 13841), read only in its machine-read (OCR) text. The numbers are sure; their grouping is not,
because the OCR lost the fraction bars. This is the reading that gives the attack-angle scale B Len a few
mrad (5.0 mrad for LM), as the report's strong AOA dependence needs. A second reading, Len / (...) in place
of Len - 1 / (...) in A, gives a 37 % larger A (docs/climb.md compares both with the climb rig). Confirm
against the report's Table 2.1 before relying on the absolute distances. The formula is singular near
Ang = 76.6 deg and Len = 0.1 in, so it is accepted only inside FLANGE_ANGLE_DEG and FLANGE_LENGTH_IN.

The monitor's value is the climb-distance ratio of each wheel: the track travelled since its Q/P last rose
to Nadal's limit with mu = CLIMB_FRICTION (zero while it is below; the US rule's friction, 49 CFR 238 App. C,
since an on-board monitor does not know the friction), over D at the attack angle of its wheelset. 1 is
TCRP's limit.
The attack angle is the one of the latest wheelset-state sample before the force sample, not the force
sample's own, so that the order in which the states and the forces of one sample arrive does not matter.
"""
from __future__ import annotations

import math

import numpy as np

CLIMB_FRICTION = 0.5                  # Nadal's limit of the climb distance at this friction (49 CFR 238 App. C)
FOOT = 0.3048                         # m
INCH = 0.0254                         # m
FLANGE_ANGLE_DEG = (60.0, 75.0)       # where eq. 2.4 stays regular (A's first term is singular at 76.6 deg)
FLANGE_LENGTH_IN = (0.11, 1.0)        # B's terms are singular at 0.0995 in


def tcrp_coefficients(flange_angle, flange_length):
    """(A in m, B Len in rad) of TCRP eq. 2.4 for a flange angle (rad) and flange length (m)."""
    ang = math.degrees(float(flange_angle))
    length = float(flange_length) / INCH
    lo, hi = FLANGE_ANGLE_DEG
    if not lo <= ang <= hi:
        raise ValueError(f"flange angle {ang:.2f} deg is outside the range of TCRP eq. 2.4 used here, "
                         f"[{lo:g}, {hi:g}] deg")
    lo, hi = FLANGE_LENGTH_IN
    if not lo <= length <= hi:
        raise ValueError(f"flange length {length * INCH * 1e3:.2f} mm ({length:.3f} in) is outside the range of "
                         f"TCRP eq. 2.4 used here, [{lo * INCH * 1e3:.1f}, {hi * INCH * 1e3:.1f}] mm")
    a = 100.0 / (-1.9128 * ang + 146.56) + 3.1 * (length - 1.0 / (-0.0092 * ang**2 + 1.2152 * ang - 39.031) + 1.23)
    b = 10.0 / (-21.157 * length + 2.1052) + 0.05 * (ang + 10.0 / (0.2688 * length - 0.0266) - 5.0)
    return a * FOOT, b * length * 1e-3


def climb_distance_limit(attack_angle, distance_scale, attack_angle_scale):
    """TCRP's limiting climb distance D (m) at attack angles (rad, either sign), from `tcrp_coefficients`."""
    aoa = np.abs(np.asarray(attack_angle, dtype=float))
    return distance_scale * attack_angle_scale / (aoa + attack_angle_scale)


def climb_distance(qp, position, nadal):
    """Track travelled (m) since each wheel's Q/P last rose to `nadal`, 0 while it is below: (n, wheels)."""
    q = np.asarray(qp, dtype=float)
    step = np.diff(np.asarray(position, dtype=float), prepend=float(position[0]))
    out = np.zeros_like(q)
    for wheel in range(q.shape[1]):
        # a running sum that restarts: over each stretch at or above the limit the steps accumulated one by
        # one from 0 (np.cumsum adds in order), as the monitor's running sum does it sample by sample
        edges = np.flatnonzero(np.diff(np.concatenate(([False], q[:, wheel] >= nadal, [False])).astype(np.int8)))
        for a, b in zip(edges[::2], edges[1::2]):
            out[a:b, wheel] = np.cumsum(step[a:b])
    return out


def wheel_attack_angles(attack_angle):
    """(n, 8) from (n, 4): each wheel takes its wheelset's attack angle."""
    return np.repeat(np.asarray(attack_angle, dtype=float), 2, axis=-1)


def climb_distance_ratio(qp, attack_angle, position, nadal, distance_scale, attack_angle_scale):
    """The criterion's value of a whole run: climb distance over TCRP's limit, each wheel (n, 8), with the
    attack angle (n, 4) of the sample before each (none before the first: 0, where the distance is 0 too)."""
    aoa = np.asarray(attack_angle, dtype=float)
    before = np.concatenate((np.zeros_like(aoa[:1]), aoa[:-1]))
    limit = climb_distance_limit(wheel_attack_angles(before), distance_scale, attack_angle_scale)
    return climb_distance(qp, position, nadal) / limit


class ClimbDistance:
    """`climb_distance_ratio` sample by sample (the Monitor's running version)."""

    def __init__(self, nadal, distance_scale, attack_angle_scale):
        self.nadal = float(nadal)
        self.scales = float(distance_scale), float(attack_angle_scale)
        self.run = np.zeros(8)
        self.position = None

    def update(self, qp, attack_angle, position):
        step = 0.0 if self.position is None else float(position) - self.position
        self.position = float(position)
        self.run = np.where(np.asarray(qp, dtype=float) >= self.nadal, self.run + step, 0.0)
        return self.run / climb_distance_limit(wheel_attack_angles(attack_angle), *self.scales)
