"""Equilibrium and linearisation of the vehicle core (for the root-locus method).

The linear model is the tangent of the full nonlinear right-hand side at the centred equilibrium on
straight track: the Jacobian by central differences of `dynamics.rhs` (contact geometry, Hertz, creep
and suspension all linearised together), without the track-position state and the wheelsets' unused
pitch states. At the centred position the contact geometry enters through its slopes there (the local
conicity of the profile pair), creep forces through Kalker's linear coefficients (the saturation law is
linear at zero creepage) and nonlinear dampers through their slope below the knee.
"""
import numpy as np

from . import dynamics as dyn
from . import integrator as itg
from .layout import N_DOF, N_STATE, WHEELSETS, Damper, Dof, State
from .simulate import Simulation, constant_speed, set_rolling

N_SPRUNG = WHEELSETS[0]         # the car body and the bogie frames come first in the state
SETTLED_RATE = 1.0e-6           # m/s and rad/s: the sprung bodies' largest velocity at rest
MAX_SETTLE_S = 30.0             # s


def rhs_function(model, speed_kmh):
    """f(x) -> dx/dt of the full model at a constant speed, with a full contact search every call."""
    sp = constant_speed(speed_kmh)
    buffers = itg.workspace(model.cg).rhs
    arrays = model.arrays

    def f(x):
        dx = np.zeros(N_STATE)
        dyn.rhs(x, dx, arrays, sp, buffers, False)
        return dx
    return f


def active_states(model):
    """Indices kept in the linear model: all but the track position, the wheelsets' unused pitch angles
    and the internal states of dampers without series stiffness or without damping (frozen, as in
    dynamics.suspension)."""
    drop = {int(State.s)}
    for b in WHEELSETS:
        drop.add(State.positions + N_DOF * b + Dof.pitch)
    for e in range(model.damp.shape[0]):
        if model.damp[e, Damper.series_stiffness] <= 0.0 or model.damp[e, Damper.damping] <= 0.0:
            drop.add(int(model.damp[e, Damper.state]))
    return np.array([i for i in range(N_STATE) if i not in drop])


def equilibrium(sc, settle_time=1.0):
    """Centred equilibrium on the scenario's (straight) track: the static state settled in time, and the
    rolling radius of the centred wheel (to set the wheelsets' spin for another speed).

    Lateral symmetry keeps every lateral state of the symmetric car exactly zero; only the vertical ones
    settle. The run goes on in pieces of settle_time until the car body and the bogie frames move slower
    than SETTLED_RATE: the healthy car after the first piece; with a fault that moves the static position
    (a deflated air spring) the car body comes down onto its emergency spring and stops bouncing first, in
    some 15 s; MAX_SETTLE_S at most.
    """
    sim = Simulation(sc)
    sim.advance(settle_time)
    while (np.max(np.abs(State.split(sim.x)["velocities"][:N_SPRUNG])) >= SETTLED_RATE
           and sim.t < MAX_SETTLE_S):
        sim.advance(settle_time)
    return sim.model, sim.x.copy(), sim.rolling_radius


def at_speed(x0, speed_kmh, rolling_radius):
    """The equilibrium state with the wheelsets spinning for another speed."""
    x = x0.copy()
    set_rolling(x, speed_kmh / 3.6, rolling_radius)
    return x


def jacobian(f, x0, idx, step=1e-7):
    """Central-difference Jacobian of f at x0 restricted to the states idx (relative+absolute step)."""
    n = len(idx)
    J = np.zeros((n, n))
    for c, i in enumerate(idx):
        h = step * max(1.0, abs(x0[i]))
        xp = x0.copy()
        xm = x0.copy()
        xp[i] += h
        xm[i] -= h
        J[:, c] = (f(xp)[idx] - f(xm)[idx]) / (2.0 * h)
    return J


def damping_ratio(lam):
    return -lam.real / np.maximum(np.abs(lam), 1e-300)


def mode_participation(vec, idx):
    """Share of each body's lateral displacement in an eigenvector (position states, angles as m at
    1 m lever arm): array (N_BODY,)."""
    pos = np.zeros(N_STATE, dtype=complex)
    pos[idx] = vec
    positions = State.split(pos)["positions"]
    lat = np.abs(positions[:, Dof.lateral])
    total = np.sqrt(np.sum(np.abs(positions) ** 2))
    return lat / total if total > 0 else lat

