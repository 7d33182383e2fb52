"""The braking model: emergency deceleration by speed band, brake build-up, and the speed over distance the
simulator follows once the emergency brake is commanded (docs/supervision.md, "The braking model").

The build-up is modelled as ETCS models it (SUBSET-026 §3.13.9.3.2: the equivalent emergency brake build-up
time T_be): from the command the speed keeps its value for T_be (on level track with no traction the train
neither speeds up nor slows down), then the full deceleration of the speed's band acts at once. Within a
band the deceleration is constant, so times and distances are exact sums over the bands:
t = (v_hi - v_lo) / a and d = (v_hi^2 - v_lo^2) / (2 a) per band. The level track is assumed (no gradient).

Sureness of each value: A read in the primary text, B several secondary sources agree, C one source or
recalled.
"""
from dataclasses import dataclass
import math

import numpy as np

from ..parameters import parameter
from ..ranges import check_range

KMH = 1.0 / 3.6
ADHESIONS = ("dry", "wet")
SPEED_STEP = 0.1        # m/s between the points of the simulator's table (its chords' error is below 1 mm/s)


def _bands_ok(name, bands):
    tops = [top for top, _ in bands]
    if not bands or tops != sorted(tops) or not math.isinf(tops[-1]) or any(a <= 0.0 for _, a in bands):
        raise ValueError(f"{name} {bands!r} must be (upper speed km/h, deceleration m/s^2) pairs, upper speeds "
                         "rising to inf, decelerations positive")


@dataclass(frozen=True)
class BrakingModel:
    """The car's emergency and service brake (level track). `adhesion` picks the emergency bands: dry rail
    or the degraded-adhesion (wet rail) variant."""
    emergency_bands: tuple = parameter(
        ((170.0, 1.2), (230.0, 1.05), (300.0, 0.9), (math.inf, 0.85)), "km/h, m/s^2",
        "TSI HS RST 2008/232/EC, minimum mean emergency deceleration by speed band, its Case A (level track, "
        "normal mode, dry rail), as recalled (reference sheet, section 5): the TSI's table was not reached. ETCS "
        "takes Case A of 2008/232/EC as a high-speed train's nominal emergency deceleration (SUBSET-040 "
        "4.4.1.2.1.1, A); with the TSI's 3 s equivalent response time the bands give 3651, 2431 and 1504 m from "
        "300, 250 and 200 km/h, the stopping distances recalled from TSI LOC&PAS 1302/2014 4.2.4.5.2 (3650, 2430, "
        "1500 m); the CRH380A's 3760 m from 300 km/h agrees", "C",
        "deceleration below each upper speed, dry rail")
    wet_bands: tuple = parameter(
        ((170.0, 0.9), (230.0, 0.8), (300.0, 0.7), (math.inf, 0.65)), "km/h, m/s^2",
        "TSI HS RST 2008/232/EC, its Case B row as recalled (its conditions, wet rail and/or a brake unit "
        "isolated, unverified; the table was not reached); ETCS lowers its safe deceleration on wet rail by a "
        "train's K_wet (SUBSET-026 3.13.6.2.1; SUBSET-040 4.4.1.5 measures it by EN 15595's low-adhesion tests, "
        "A); the rows are the dry bands times 0.75-0.78, a K_wet within the 0.7-0.9 of ETCS example values "
        "(C): used as the wet-rail case", "C",
        "deceleration below each upper speed, degraded adhesion (wet rail)")
    adhesion: str = parameter("dry", "-", "the run's choice", "-", "which emergency bands apply: dry or wet")
    buildup_s: float = parameter(2.0, "s", "EMU electro-pneumatic brakes 1.5-3 s (reference sheet, section 5); "
                                 "ETCS's T_be", "C", "equivalent emergency brake build-up time")
    service_buildup_s: float = parameter(2.0, "s", "EMU electro-pneumatic brakes 1.5-3 s (reference sheet); "
                                         "ETCS's T_bs", "C", "equivalent service brake build-up time")
    service_deceleration: float = parameter(0.7, "m/s^2", "a modelling choice: the full service brake below the "
                                            "emergency brake's 0.85-1.2 m/s^2 (no CRH3 figure found)", "C",
                                            "full service brake deceleration (not used to brake in the loop)")
    reaction_s: float = parameter(1.0, "s", "an automatic command; a driver needs 1-2 s for an expected alarm "
                                  "(reference sheet, section 5)", "C",
                                  "from a warning to the emergency brake command")

    def validated(self):
        _bands_ok("emergency_bands", self.emergency_bands)
        _bands_ok("wet_bands", self.wet_bands)
        if self.adhesion not in ADHESIONS:
            raise ValueError(f"adhesion {self.adhesion!r} is not one of {', '.join(ADHESIONS)}")
        check_range("brake build-up time", self.buildup_s, 0.0, 30.0, "s")
        check_range("service brake build-up time", self.service_buildup_s, 0.0, 30.0, "s")
        check_range("service brake deceleration", self.service_deceleration, 0.0, 3.0, "m/s^2", lo_open=True)
        check_range("reaction time", self.reaction_s, 0.0, 30.0, "s")
        return self

    @property
    def bands(self):
        """The emergency bands of the chosen adhesion: (upper speed km/h, deceleration m/s^2) pairs."""
        return self.emergency_bands if self.adhesion == "dry" else self.wet_bands

    def edges(self):
        """The bands' finite upper speeds (m/s), rising."""
        return sorted(top / 3.6 for top, _ in self.bands if math.isfinite(top))

    def deceleration(self, v):
        """Emergency deceleration (m/s^2) at speed v (m/s)."""
        kmh = v * 3.6
        return next(a for top, a in self.bands if kmh < top)

    def _pieces(self, v0, v1):
        """(upper, lower, deceleration) of each piece of a braking from v0 down to v1 (m/s), band by band."""
        edges, v, out = self.edges(), v0, []
        while v > v1 + 1e-12:
            low = max([e for e in edges if e < v - 1e-12] + [v1])
            out.append((v, low, self.deceleration(v - 1e-9)))
            v = low
        return out

    def deceleration_time(self, v0, v1):
        """Time (s) the full emergency deceleration takes from v0 down to v1 (m/s), band by band, without
        the build-up."""
        t = 0.0
        for hi, lo, a in self._pieces(v0, v1):
            t += (hi - lo) / a
        return t

    def deceleration_distance(self, v0, v1):
        """Distance (m) the full emergency deceleration takes from v0 down to v1 (m/s), without the build-up."""
        d = 0.0
        for hi, lo, a in self._pieces(v0, v1):
            d += (hi * hi - lo * lo) / (2.0 * a)
        return d

    def braking_time(self, v0, v1):
        """Time (s) from the emergency brake command at v0 to the speed v1 (m/s): build-up, then braking."""
        return self.buildup_s + self.deceleration_time(v0, v1)

    def braking_distance(self, v0, v1):
        """Distance (m) from the emergency brake command at v0 to the speed v1 (m/s): v0 held over the
        build-up, then braking."""
        return v0 * self.buildup_s + self.deceleration_distance(v0, v1)

    def speed_after(self, v0, distance):
        """Speed (m/s) `distance` m after the emergency brake command at v0 (m/s); 0 once stopped."""
        rest = distance - v0 * self.buildup_s
        if rest <= 0.0:
            return v0
        for hi, lo, a in self._pieces(v0, 0.0):
            piece = (hi * hi - lo * lo) / (2.0 * a)
            if rest <= piece:
                return math.sqrt(max(hi * hi - 2.0 * a * rest, 0.0))
            rest -= piece
        return 0.0

    def speed_table(self, s0, v0, v1):
        """The simulator's speed table (rows s m, v m/s) from an emergency brake command at s0 and v0 down to
        v1, held after: v0 over the build-up, then the braking curve at points SPEED_STEP apart in speed
        and at every band edge (the core interpolates linearly between them)."""
        check_range("release speed", v1, 0.0, v0, "m/s", hi_open=True)
        start = s0 + v0 * self.buildup_s
        # the grid and the edges strictly below v0 (an edge may differ from v0 in its last bit only)
        inner = np.concatenate([np.arange(v1, v0, SPEED_STEP), [e for e in self.edges() if v1 < e]])
        speeds = np.concatenate([[v0], np.unique(inner[inner < v0 - 1e-9])[::-1]])
        s = [start + self.deceleration_distance(v0, v) for v in speeds]
        return np.array([[s0, v0]] + list(zip(s, speeds)) + [[s[-1] + 1.0, v1]])
