"""Root-locus method: linear critical speed from the eigenvalues of the linearised model against speed.

The full model is linearised at its centred equilibrium on straight track (`vehicle.linear`); at each
speed the eigenvalues give each mode's frequency and damping ratio zeta = -Re(lambda)/|lambda|, for the
oscillatory modes between MIN_FREQUENCY_HZ and MAX_FREQUENCY_HZ (the body and wheelset modes of running
stability; the wheelsets' bounce and roll on their Hertzian contacts, near 100-200 Hz, are left out). The
linear critical speed is the lowest speed at which the least damping ratio of the oscillatory modes
crosses zero (Yu 2022, Table 3: "the minimum damping value less than 0 represents the system
destabilization"), located by bisection between the grid speeds that bracket it. The mode that
crosses is named by its eigenvector: hunting when the wheelsets' lateral motion dominates it.
"""
from dataclasses import dataclass, field, replace

import numpy as np

from ..ranges import check_range
from ..vehicle.linear import (active_states, at_speed, damping_ratio, equilibrium, jacobian,
                              mode_participation, rhs_function)
from ..vehicle.simulate import KMH, Scenario, constant_speed, straight_track

SPEED_RANGE_KMH = (30.0, 800.0)
MIN_FREQUENCY_HZ = 0.2        # slower "modes" are the damper relaxations, not oscillations
MAX_FREQUENCY_HZ = 20.0       # the body and wheelset modes of running stability; above are contact modes
MODE_NAMES = ("car body", "front bogie", "rear bogie", "wheelset", "wheelset", "wheelset", "wheelset")


@dataclass
class RootLocus:
    speeds_kmh: np.ndarray
    eigenvalues: list                      # per speed: complex array of the oscillatory modes (Im > 0)
    least_damping: np.ndarray              # per speed: least damping ratio of the oscillatory modes
    least_mode: list                       # per speed: name of the body dominating the least-damped mode
    least_frequency_hz: np.ndarray
    linear_critical_speed_kmh: float       # nan if stable over the whole range
    critical_mode: str = ""
    critical_frequency_hz: float = float("nan")
    notes: dict = field(default_factory=dict)

    def as_json(self):
        return dict(linear_critical_speed_kmh=self.linear_critical_speed_kmh, critical_mode=self.critical_mode,
                    critical_frequency_hz=self.critical_frequency_hz,
                    speeds_kmh=self.speeds_kmh.tolist(), least_damping_ratio=self.least_damping.tolist(),
                    least_damped_mode=self.least_mode, least_damped_frequency_hz=self.least_frequency_hz.tolist())


def _modes(model, x0, idx, speed_kmh, rolling_radius):
    J = jacobian(rhs_function(model, speed_kmh), at_speed(x0, speed_kmh, rolling_radius), idx)
    lam, vec = np.linalg.eig(J)
    keep = (lam.imag > 2 * np.pi * MIN_FREQUENCY_HZ) & (lam.imag < 2 * np.pi * MAX_FREQUENCY_HZ)
    return lam[keep], vec[:, keep]


def _least(model, x0, idx, speed_kmh, rr):
    lam, vec = _modes(model, x0, idx, speed_kmh, rr)
    z = damping_ratio(lam)
    k = int(np.argmin(z))
    body = int(np.argmax(mode_participation(vec[:, k], idx)))
    return lam, z[k], MODE_NAMES[body], lam[k].imag / (2 * np.pi)


def root_locus(sc: Scenario = None, speeds_kmh=None, tolerance_kmh=0.5):
    """Eigenvalues against speed and the linear critical speed (km/h)."""
    sc = sc or Scenario(track=straight_track())
    sc = replace(sc, track=straight_track(), speed_table=constant_speed(100.0))
    speeds = np.linspace(100.0, 600.0, 101) if speeds_kmh is None else np.asarray(speeds_kmh, dtype=float)
    for v in (speeds.min(), speeds.max()):
        check_range("root-locus speed", v, *SPEED_RANGE_KMH, "km/h")
    model, x0, rr = equilibrium(sc)
    idx = active_states(model)
    eig, least, names, freq = [], [], [], []
    for v in speeds:
        lam, z, name, f = _least(model, x0, idx, v, rr)
        eig.append(lam)
        least.append(z)
        names.append(name)
        freq.append(f)
    least = np.array(least)
    vcrit = float("nan")
    mode = ""
    fcrit = float("nan")
    unstable = np.nonzero(least < 0.0)[0]
    if len(unstable):
        j = unstable[0]
        if j == 0:
            vcrit, mode, fcrit = float(speeds[0]), names[0], freq[0]
        else:
            lo, hi = speeds[j - 1], speeds[j]
            while hi - lo > tolerance_kmh:
                mid = 0.5 * (lo + hi)
                _, z, _, _ = _least(model, x0, idx, mid, rr)
                lo, hi = (mid, hi) if z >= 0.0 else (lo, mid)
            vcrit = 0.5 * (lo + hi)
            _, _, mode, fcrit = _least(model, x0, idx, vcrit, rr)
    return RootLocus(speeds_kmh=speeds, eigenvalues=eig, least_damping=least, least_mode=names,
                     least_frequency_hz=np.array(freq), linear_critical_speed_kmh=vcrit, critical_mode=mode,
                     critical_frequency_hz=fcrit,
                     notes=dict(states=len(idx), speed_unit=KMH))

