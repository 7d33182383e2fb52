"""The elastic track under each wheel: a co-running rail mass on springs and dampers to ground (numba core).

Model (the "moving track" of GENSYS and of Simpack's rail bodies; Knothe & Grassie, Vehicle System
Dynamics 22 (1993) 209-262, on why one mass per wheel is enough below about 300 Hz): each wheel has its
own piece of rail that travels with the wheelset, rigid, with three degrees of freedom relative to its
unloaded place (`RailDof`: lateral, vertical and roll about a roll centre below the rail top), each on a
spring and a viscous damper to ground. The rail's own weight is carried at zero deflection, so the states
are the deflections under the wheel. Assumptions: the rail does not move along the track; the pieces
under different wheels are independent (no beam coupling between the axles, 2.5 m apart, beyond a
Winkler beam's 2 m reach); the rail's profile, inclination and gauge move rigidly with it; no centripetal
or gravity term acts on the rail mass (it does not travel with the train, only its deflection does).

What the wheel sees (`vehicle.dynamics.rhs`): the rail frame is the track frame moved by the rail's
irregularity and by its deflection (translation of the roll centre, roll about it); the wheelset's pose
and velocities are taken relative to that moving frame (so the creepages see the rail's velocity), the
wheel's force and moment are turned back, and the rail takes the reaction. On rigid track (`elastic` 0)
the rail states are frozen at zero, their rates are zero and the error control does not count them.
"""
from ..jit import core
from .layout import ElasticTrack, RailDof


@core
def rail_accelerations(support, deflection, rate, fy, fz, mx):
    """Accelerations (lateral, vertical, roll) of a co-running rail with the wheel's reaction: the wheel's
    contact force (fy, fz; N, track axes) and its moment about the rail's roll centre (mx, N m) act on the
    rail with the opposite sign. `deflection`, `rate`: the rail's (lateral, vertical, roll) and their rates."""
    E = ElasticTrack
    ay = -(fy + support[E.lateral_stiffness] * deflection[0] + support[E.lateral_damping] * rate[0]) \
        / support[E.lateral_mass]
    az = -(fz + support[E.vertical_stiffness] * deflection[1] + support[E.vertical_damping] * rate[1]) \
        / support[E.vertical_mass]
    ar = -(mx + support[E.roll_stiffness] * deflection[2] + support[E.roll_damping] * rate[2]) \
        / support[E.roll_inertia]
    return ay, az, ar


@core
def head_shift(support, x, o):
    """Lateral shift (m, + left) of the rail top above the roll centre, of the rail whose deflection
    (`RailDof`) is at x[o:]: the roll centre's lateral deflection less the roll times the depth."""
    return x[o + RailDof.lateral] - support[ElasticTrack.roll_centre_depth] * x[o + RailDof.roll]
