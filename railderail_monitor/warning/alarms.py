"""The alarm mechanics: one alert per event on one channel (debounce over track or time, hysteresis before the
channel re-arms), sample by sample (`Detector`, what the monitor runs) and over a whole series at once
(`alarm_intervals`, what a threshold sweep of the evaluation runs), with the same decisions; and the integer
nanosecond clock of the timed rules (a ROS stamp's resolution)."""
from __future__ import annotations

import numpy as np

NANOSECOND = 1e-9                                 # s: the clock of the timed rules (a ROS stamp's resolution)


def nanoseconds(seconds):
    """Integer nanoseconds of a time (s) or an array of times, as a ROS stamp holds it
    (`ros.interface.set_time`): exact for times below 10^6 s, whether they come from the simulator's clock
    or from a stamp's sec + 1e-9 nanosec."""
    ns = np.round(np.asarray(seconds, dtype=float) / NANOSECOND)
    return ns.astype(np.int64) if ns.ndim else int(ns)


class Detector:
    """One alert per event on one channel: the value must stay >= threshold over `debounce` (m of
    track, or integer nanoseconds of time for a duration rule) to raise the alert; the channel re-arms once the value has
    stayed below rearm_fraction x threshold over `rearm_m` of track. `update` returns True on the
    sample that raises the alert."""

    __slots__ = ("threshold", "rearm_level", "debounce", "rearm_m", "armed", "start")

    def __init__(self, threshold, debounce=2.0, rearm_fraction=0.9, rearm_m=50.0):
        self.threshold = float(threshold)
        self.rearm_level = float(rearm_fraction) * self.threshold
        self.debounce = debounce                   # m, or integer ns of a timed rule
        self.rearm_m = float(rearm_m)
        self.armed = True
        self.start = None      # where (or when) the value crossed (the level, or the re-arm level)

    def update(self, value, position, clock=None):
        """`clock`: what the debounce is measured on, the track position by default (a duration rule
        passes the time in integer nanoseconds); the re-arm is always measured on the track."""
        if not self.armed:
            if value < self.rearm_level:
                if self.start is None:
                    self.start = position
                if position - self.start >= self.rearm_m:
                    self.armed = True
                    self.start = None
            else:
                self.start = None
            return False
        at = position if clock is None else clock
        if value >= self.threshold:
            if self.start is None:
                self.start = at
            if at - self.start >= self.debounce:
                self.armed = False
                self.start = None
                return True
        else:
            self.start = None
        return False


def alarm_intervals(values, position, threshold, debounce=2.0, rearm_fraction=0.9, rearm_m=50.0, clock=None):
    """[(alert, rearm)] of a Detector fed (values[i], position[i], clock[i]): the sample that raises each
    alert and the one at which the channel re-arms (len(values) if it never does), so the channel is in
    alarm over alert <= i < rearm. Found over the runs of samples above the level and below the re-arm level
    instead of sample by sample, with the same decisions (the same comparisons of the same differences), so
    that a threshold sweep over long runs (`over_catalogue`) is what the monitor would have said at each
    threshold. Positions (and the clock) must not decrease."""
    v = np.asarray(values, dtype=float)
    pos = np.asarray(position, dtype=float)
    at = pos if clock is None else np.asarray(clock)
    above = np.flatnonzero(v >= float(threshold))
    not_above = np.flatnonzero(~(v >= float(threshold)))
    rearm_level = float(rearm_fraction) * float(threshold)
    below = np.flatnonzero(v < rearm_level)
    not_below = np.flatnonzero(~(v < rearm_level))
    n = len(v)

    def first_after(indices, i):
        k = indices.searchsorted(i)
        return int(indices[k]) if k < len(indices) else n

    def held(coordinate, start, end, length):
        """The first sample in [start, end) whose coordinate is `length` past the start's, else end."""
        k = int(coordinate[start:end].searchsorted(coordinate[start] + length)) + start
        k = max(k - 1, start)                  # the exact comparison decides, not the sum's rounding
        while k < end and not coordinate[k] - coordinate[start] >= length:
            k += 1
        return k

    intervals, i, armed = [], 0, True
    while i < n:
        if armed:
            start = first_after(above, i)
            if start >= n:
                break
            end = first_after(not_above, start)
            k = held(at, start, end, debounce)
            if k < end:
                intervals.append([k, n])
                armed = False
            i = k + 1 if k < end else end
        else:
            start = first_after(below, i)
            if start >= n:
                break
            end = first_after(not_below, start)
            k = held(pos, start, end, float(rearm_m))
            if k < end:
                intervals[-1][1] = k
                armed = True
            i = k + 1 if k < end else end
    return [tuple(x) for x in intervals]


def alert_indices(values, position, threshold, debounce=2.0, rearm_fraction=0.9, rearm_m=50.0, clock=None):
    """The samples at which a Detector fed (values[i], position[i], clock[i]) raises its alerts
    (`alarm_intervals`' first samples)."""
    return [a for a, _ in alarm_intervals(values, position, threshold, debounce, rearm_fraction, rearm_m, clock)]

