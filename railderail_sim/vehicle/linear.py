"""Equilibrium and linearisation of the vehicle core (for the root-locus method).

The linear model is the tangent of the full nonlinear right-hand side at the centred equilibrium on
straight track: the Jacobian by central differences of `dynamics.rhs` (contact geometry, Hertz, creep
and suspension all linearised together), without the track-position state and the wheelsets' unused
pitch states. At the centred position the contact geometry enters through its slopes there (the local
conicity of the profile pair), creep forces through Kalker's linear coefficients (the saturation law is
linear at zero creepage) and nonlinear dampers through their slope below the knee.
"""
import numpy as np

from . import integrator as itg
from . import layout as L
from .simulate import Simulation, constant_speed, set_rolling


def rhs_function(model, speed_kmh):
    """f(x) -> dx/dt of the full model at a constant speed, with a full contact search every call."""
    sp = constant_speed(speed_kmh)
    w = itg.workspace(model.cg)

    def f(x):
        dx = np.zeros(L.N_STATE)
        itg._rhs(x, dx, model.bodies, model.vp, model.bush, model.damp, model.bump, model.arb, model.track,
                 sp, model.cg, model.cp, w["kin"], w["gap"], w["ys"], w["patches"], w["cands"], False,
                 w["kpbuf"], w["kpid"], w["kprow"], w["recs"])
        return dx
    return f


def active_states(model):
    """Indices kept in the linear model: all but the track position, the wheelsets' unused pitch angles
    and the internal states of dampers without series stiffness."""
    drop = {L.I_S}
    for b in L.WHEELSETS:
        drop.add(L.N_DOF * b + 3)
    for e in range(model.damp.shape[0]):
        if model.damp[e, L.D_KS] <= 0.0:
            drop.add(int(model.damp[e, L.D_STATE]))
    return np.array([i for i in range(L.N_STATE) if i not in drop])


def equilibrium(sc, settle_time=1.0):
    """Centred equilibrium on the scenario's (straight) track: the static state settled in time, and the
    rolling radius of the centred wheel (to set the wheelsets' spin for another speed).

    Lateral symmetry keeps every lateral state exactly zero; only the vertical ones settle.
    """
    sim = Simulation(sc)
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
    pos = np.zeros(L.N_STATE, dtype=complex)
    pos[idx] = vec
    lat = np.array([abs(pos[L.N_DOF * b]) for b in range(L.N_BODY)])
    total = np.sqrt(sum(abs(pos[i]) ** 2 for i in range(L.I_VEL)))
    return lat / total if total > 0 else lat

