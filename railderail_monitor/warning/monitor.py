"""The streaming monitor: every ground-truth criterion over a stream of samples (`Monitor`, what the node
and the replay run) and over a whole run fed sample by sample (`alerts_of_run`), so that batch and stream give
the same alerts by construction."""
from __future__ import annotations

import collections
import math

import numpy as np

from .alarms import Detector, nanoseconds
from .alerts import AlertRecord, describe
from .climb_distance import ClimbDistance
from .limits import BOGIE_PLACES, CRITERIA, SIDES, TIMED, Limits, debounce, default_limits
from .quantities import SlidingMean, front_attack_angle, rail_side, running_gear_unloading, unloading_ratio

# samples whose forces wait at most for the states before them (1.28 s at 200 Hz; the attack angles kept as long)
WAITING = 256


class Monitor:
    """Every criterion over a stream of samples. Feed it `on_states` (wheelset states) and
    `on_forces` (contact forces), each returning the list of AlertRecords the sample raised: an alert on
    sample i names the inner or outer rail from the track curvature (1/m, + left) that sample i's own
    message carries, so that the rail side does not depend on the order in which the topics arrive."""

    # (wheelset, side) of each channel of a criterion that is not per wheel; side '' for a wheelset
    PLACES = {"attack_angle": ((0, ""),), "running_gear_unloading": BOGIE_PLACES}

    def __init__(self, limits: Limits = None):
        limits = (limits or default_limits()).validated()
        self.limits = limits
        r, rm = limits.rearm_fraction, limits.rearm_m
        self.channels = {}
        for criterion in CRITERIA:
            count = len(self.PLACES.get(criterion, range(8)))
            held = debounce(criterion, limits)
            self.channels[criterion] = [(sev, thr, [Detector(thr, held, r, rm) for _ in range(count)])
                                        for sev, thr in limits.levels(criterion)]
        self.attack_angles = collections.deque(maxlen=WAITING)    # (sample, 4 attack angles), arrival order
        self.states_upto = -math.inf           # the latest sample whose states came
        self.climb_waiting = collections.deque()   # (t, sample, position, speed, curvature, Y/Q) for the climb
        self.qp_mean = SlidingMean(limits.sliding_mean_m, 8)
        self.climb = ClimbDistance(limits.climb_nadal_limit, limits.climb_distance_scale,
                                   limits.climb_attack_angle_scale)

    @staticmethod
    def _before(kept, sample, none):
        for s, value in reversed(kept):
            if s < sample:
                return value
        return none

    def _check(self, criterion, values, t, sample, position, speed, curvature):
        t, sample, position, speed, curvature = float(t), int(sample), float(position), float(speed), float(curvature)
        clock = nanoseconds(t) if criterion in TIMED else None
        alerts = []
        for sev, thr, detectors in self.channels[criterion]:
            for k, detector in enumerate(detectors):
                value = float(values[k])
                if detector.update(value, position, clock):
                    ws, side = self.PLACES[criterion][k] if criterion in self.PLACES else (k // 2, SIDES[k % 2])
                    rail = rail_side(side, curvature) if side else ""
                    alerts.append(AlertRecord(t, sample, criterion, sev, value, thr, ws, side, rail, position,
                                              speed, describe(criterion, sev, value, thr, ws, side, rail)))
        return alerts

    def on_states(self, t, sample, position, speed, curvature, attack_angle, wheel_lift):
        """Attack angle (4 wheelsets, rad) and wheel lift (8 wheels, m) of one sample, with its place, speed
        and track curvature (1/m, + left)."""
        self.attack_angles.append((int(sample), np.asarray(attack_angle, dtype=float)))
        self.states_upto = max(self.states_upto, int(sample))
        at = (t, sample, position, speed, curvature)
        return (self._check("attack_angle", [front_attack_angle(attack_angle)], *at)
                + self._check("wheel_lift", wheel_lift, *at) + self._climb())

    def _climb(self):
        """The climb distance of each sample whose forces wait for the states of the sample before it (its
        attack angles, `climb_distance_ratio`'s pairing), in the order the forces came: once those states
        came (each topic comes in its own order), or once WAITING samples wait (states lost: the latest
        before it, 0 if none)."""
        alerts = []
        while self.climb_waiting and (self.climb_waiting[0][1] - 1 <= self.states_upto
                                      or len(self.climb_waiting) > WAITING):
            t, sample, position, speed, curvature, qp = self.climb_waiting.popleft()
            attack = self._before(self.attack_angles, sample, np.zeros(4))
            alerts += self._check("flange_climb_distance", self.climb.update(qp, attack, position), t, sample,
                                  position, speed, curvature)
        return alerts

    def on_forces(self, t, sample, position, speed, curvature, derailment_coefficient, vertical_force):
        """Y/Q (8 wheels) and vertical forces Q (8 wheels, N) of one sample, with its place, speed and track
        curvature (1/m, + left)."""
        unloading = unloading_ratio(vertical_force, self.limits.static_wheel_load)
        at = (t, sample, position, speed, curvature)
        return (self._check("derailment_coefficient", derailment_coefficient, *at)
                + self._check("derailment_coefficient_duration", derailment_coefficient, *at)
                + self._check("derailment_coefficient_mean", self.qp_mean.update(derailment_coefficient, position), *at)
                + self._check("wheel_unloading", unloading, *at)
                + self._check("running_gear_unloading", running_gear_unloading(unloading), *at)
                + self._waiting_climb(at, derailment_coefficient))

    def _waiting_climb(self, at, derailment_coefficient):
        self.climb_waiting.append((*at, np.asarray(derailment_coefficient, dtype=float)))
        return self._climb()


def alerts_of_run(arrays, limits: Limits = None):
    """Alerts of a whole run, from the named arrays of `vehicle.simulate.Result.arrays()` or
    `vehicle.simulate.output_arrays` (or the same names from a recording): a Monitor fed sample by
    sample as the monitor node is fed, the states, then the forces of each sample, each with the sample's
    curvature, so that batch and stream give the same alerts by construction."""
    monitor = Monitor(limits)
    t, s, v = arrays["time"], arrays["position"], arrays["speed"]
    attack, lift = arrays["attack_angle"], arrays["wheel_lift"]
    qp, load, k = arrays["derailment_coefficient"], arrays["vertical_force"], arrays["curvature"]
    found = []
    for i, sample in enumerate(arrays.get("sample", range(len(t)))):
        found += monitor.on_states(t[i], sample, s[i], v[i], k[i], attack[i], lift[i])
        found += monitor.on_forces(t[i], sample, s[i], v[i], k[i], qp[i], load[i])
    return found

