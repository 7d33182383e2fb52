"""The values the ground-truth criteria compare with their levels, from the simulator's (or a recording's)
wheelset states and contact forces: the front wheelset's attack angle, the unloading ratios of a wheel and of a
running gear's side, EN 14363's sliding mean (batch and running), and which rail a wheel runs on."""
from __future__ import annotations

import collections
import math

import numpy as np

from railderail_sim.vehicle.layout import running_gear_sides


def front_attack_angle(attack_angle):
    """Magnitude of the front wheelset's attack angle (rad) from (..., 4) attack angles."""
    return np.abs(np.asarray(attack_angle, dtype=float)[..., 0])


def unloading_ratio(vertical_force, static_wheel_load):
    """Wheel unloading ratio ΔQ/Q0 = (Q0 - Q) / Q0 (dimensionless; 1 = wheel fully unloaded)."""
    if not static_wheel_load > 0.0:
        raise ValueError(f"static wheel load {static_wheel_load:g} N must be positive")
    return (static_wheel_load - np.asarray(vertical_force, dtype=float)) / static_wheel_load


def running_gear_unloading(unloading):
    """Mean unloading ratio of each bogie's two wheels on one side (EN 14067-6), (..., 4) in the order of
    BOGIE_PLACES, from the (..., 8) ratios of the wheels [wheelset 0 left, wheelset 0 right, ...]."""
    return running_gear_sides(unloading)


def sliding_mean(values, position, window):
    """The mean of each column of `values` (n, ...) over the samples of the last `window` m of track up to
    each sample (those with position > position_i - window), as EN 14363 evaluates Y/Q. From prefix sums,
    so that the monitor's running version (`SlidingMean`) gives the same numbers."""
    v = np.asarray(values, dtype=float)
    pos = np.asarray(position, dtype=float)
    sums = np.concatenate((np.zeros((1,) + v.shape[1:]), np.cumsum(v, axis=0)))
    first = np.searchsorted(pos, pos - window, side="right")
    count = (np.arange(len(pos)) + 1 - first).reshape((-1,) + (1,) * (v.ndim - 1))
    return (sums[1:] - sums[first]) / count


class SlidingMean:
    """`sliding_mean` sample by sample: the prefix sum so far and, for the samples in the window, where they
    are and the prefix sum before them."""

    def __init__(self, window, width):
        self.window = float(window)
        self.total = np.zeros(width)
        self.kept = collections.deque()

    def update(self, value, position):
        self.kept.append((float(position), self.total.copy()))
        self.total = self.total + np.asarray(value, dtype=float)
        while self.kept[0][0] <= position - self.window:
            self.kept.popleft()
        return (self.total - self.kept[0][1]) / len(self.kept)


def rail_side(wheel_side, curvature):
    """'inner' / 'outer' rail of a wheel on a curve of signed curvature (+ = curve to the left);
    '' on straight track."""
    if curvature == 0.0 or not math.isfinite(curvature):
        return ""
    inner = "left" if curvature > 0.0 else "right"
    return "inner" if wheel_side == inner else "outer"
