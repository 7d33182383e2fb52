"""The odometry of the measured mode: the front's position from the odometer's speed samples
(railderail_sim.sensors: the axle-end pulse generator, its radius error and pulse counting) integrated from
the last balise, and the confidence interval ETCS gives it (SUBSET-041 §5.3.1: the position within
5 m + 5 % of the distance since the last balise, the speed within V_ura), whose pessimistic end the
supervisor uses."""
from .curves import ramp


class Odometry:
    """Position (m) of the front from a balise at `balise_m` passed at `time_s`, integrated from the
    odometer's speed samples (trapezoids between samples); `limits`: the SupervisionLimits."""

    def __init__(self, limits, balise_m, time_s, speed_m_s):
        self.limits = limits
        self.balise(balise_m, time_s, speed_m_s)

    def balise(self, position_m, time_s, speed_m_s):
        """A balise read at `time_s`: the position is known again (to the balise's own accuracy, taken as 0)."""
        self.reference = self.position = position_m
        self.time, self.speed = time_s, speed_m_s

    def update(self, time_s, speed_m_s):
        """One odometer sample: its time stamp (s) and measured speed (m/s)."""
        self.position += 0.5 * (self.speed + speed_m_s) * (time_s - self.time)
        self.time, self.speed = time_s, speed_m_s

    @property
    def position_error(self):
        """Half the confidence interval of the position (m)."""
        return self.limits.position_accuracy_m + self.limits.position_accuracy_share * (self.position -
                                                                                        self.reference)

    @property
    def speed_error(self):
        """The speed measurement's accuracy V_ura (m/s) at the measured speed."""
        return ramp(self.limits.speed_accuracy_kmh, self.speed)
