"""ETCS's emergency-brake-intervention margin dV_ebi over a ceiling speed (ERA SUBSET-026 Appendix A.3.1, as
quoted in ../shared/reference/supervision.md), the one place of its constants: the survey's safe speed under a
physical limit and the supervisor's target speed and ceiling supervision both take it from here."""
from dataclasses import dataclass

from ..parameters import KMH, parameter


@dataclass(frozen=True)
class SafetyMargin:
    """dV_ebi over a ceiling speed V: dV_ebi_min up to V_ebi_min, growing linearly to dV_ebi_max at V_ebi_max,
    dV_ebi_max above."""
    dv_min: float = parameter(7.5 * KMH, "m/s", "ERA SUBSET-026 Appendix A.3.1, dV_ebi_min (7.5 km/h)", "A")
    dv_max: float = parameter(15.0 * KMH, "m/s", "ERA SUBSET-026 Appendix A.3.1, dV_ebi_max (15 km/h)", "A")
    v_min: float = parameter(110.0 * KMH, "m/s", "ERA SUBSET-026 Appendix A.3.1, V_ebi_min (110 km/h)", "A")
    v_max: float = parameter(210.0 * KMH, "m/s", "ERA SUBSET-026 Appendix A.3.1, V_ebi_max (210 km/h)", "B",
                             "the upper end of the ramp as quoted (140/210 km/h in the sources read)")

    @classmethod
    def from_kmh(cls, values):
        """The margin of (dV_min, dV_max, V_min, V_max) in km/h."""
        return cls(*(x * KMH for x in values))

    def kmh(self):
        """(dV_min, dV_max, V_min, V_max) in km/h."""
        return tuple(x / KMH for x in (self.dv_min, self.dv_max, self.v_min, self.v_max))

    def dv(self, v):
        """dV_ebi at the ceiling speed v (m/s)."""
        slope = (self.dv_max - self.dv_min) / (self.v_max - self.v_min)
        return min(self.dv_max, max(self.dv_min, self.dv_min + slope * (v - self.v_min)))

    def safe_speed(self, critical):
        """The ceiling V (m/s) with V + dV_ebi(V) = critical (m/s); 0 if the critical speed is below dV_ebi."""
        slope = (self.dv_max - self.dv_min) / (self.v_max - self.v_min)
        for v in (critical - self.dv_min, (critical - self.dv_min + slope * self.v_min) / (1.0 + slope),
                  critical - self.dv_max):
            if v >= 0.0 and abs(v + self.dv(v) - critical) < 1e-9:
                return v
        return 0.0
