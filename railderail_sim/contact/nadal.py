"""Nadal's flange-climbing limit (numba core).

Model
-----
Nadal (1908) considered a wheel in single-point flange contact at the flange angle ``delta``
(angle of the contact plane to the horizontal, i.e. of the flange face at the contact point) with
the lateral creep force *saturated* at ``mu N`` and acting so as to resist climbing (the wheel
slides down the flange relative to the rail; large positive angle of attack). Equilibrium of the
wheel's lateral force Q (toward the flange, on the rail) and vertical force P in the contact
plane gives the largest sustainable ratio

    (Q/P)_lim = (tan(delta) - mu) / (1 + mu tan(delta)).

Above this value the wheel climbs. Assumptions: quasi-static, single contact point on the flange
(tread unloaded), full saturation of the creep force in the lateral-vertical plane (the
longitudinal creep force is ignored, which makes the criterion conservative for small angles of
attack), mu the wheel-rail friction coefficient at the flange.

Values: delta = 70 deg, mu = 0.3 -> 1.342; delta = 70 deg, mu = 0.36 -> 1.200; delta = 60 deg,
mu = 0.3 -> 0.942 (the tests check these).

References
----------
Nadal, M.J. (1908) Locomotives à vapeur. Collection Encyclopédie Scientifique, Bibliothèque de
Mécanique Appliquée et Génie, vol. 186, Paris.
Iwnicki, S. (ed.) (2006) Handbook of Railway Vehicle Dynamics, CRC Press (flange-climbing
derailment, Nadal's formula). EN 14363 uses the fixed limit (Y/Q)_lim = 0.8 for acceptance tests.
"""
import math

from ..jit import core


@core
def nadal_limit(flange_angle, mu):
    """Nadal's limit (Q/P)_lim = (tan d - mu)/(1 + mu tan d); flange_angle [rad], mu [-]."""
    t = math.tan(flange_angle)
    return (t - mu) / (1.0 + mu * t)


@core
def nadal_flange_angle(q_over_p, mu):
    """Inverse: flange angle [rad] at which Nadal's limit equals q_over_p for friction mu.

    tan d = (L + mu)/(1 - mu L); returns pi/2 if mu*L >= 1 (no finite angle suffices).
    """
    den = 1.0 - mu * q_over_p
    if den <= 0.0:
        return 0.5 * math.pi
    return math.atan((q_over_p + mu) / den)


@core
def nadal_friction(q_over_p, flange_angle):
    """Inverse: friction coefficient at which Nadal's limit equals q_over_p for the flange angle."""
    t = math.tan(flange_angle)
    return (t - q_over_p) / (1.0 + q_over_p * t)
