"""The wind a run meets (model building): steady, or the CEN extreme gust, packed with the car body's
coefficients into the core's `aero` array (`loads.layout`).

A wind is given by its speed (the steady speed, or the gust's peak), where it comes from relative to the
track (`direction_deg`: 90 from the left, -90 from the right, 0 a head wind) and its gust. The gust is the
CEN extreme gust of EN 14067-6 in its simplified form, read as a gust standing along the track that the
train runs through (Baker's reading of the standard): the mean wind ubar = u_peak / (1 + A I) plus the hat
A I ubar exp(-|x - x_peak| / L), with A the peak factor, I the turbulence intensity and L the decay length
(`parameters.AerodynamicParameters`; their values are stand-ins, docs/loads.md). The car starts in still
air and the mean wind rises smoothly (sin^2) over the `gust_ramp` before the hat, so that the car meets the
gust settled under the mean wind, as the standard's evaluation assumes. A steady wind blows from the start.
"""
from dataclasses import dataclass
import math

import numpy as np

from .. import scalarmath
from ..parameters import AerodynamicParameters
from ..ranges import check_range
from .layout import AeroCoefficients, AeroHeader, WindPoint

GUSTS = ("none", "chinese-hat")
WIND_SPEED_RANGE = (0.0, 60.0)          # m/s; beyond 60 m/s no train runs
DIRECTION_RANGE_DEG = (-180.0, 180.0)
GUST_SPAN = 6.0                         # the hat's table reaches this many decay lengths either side (0.25 %)


@dataclass(frozen=True)
class Wind:
    """A wind: `speed` (m/s, steady or the gust's peak), `direction_deg` (where it comes from, relative to
    the direction of travel, + to the left), `gust` ("none" or "chinese-hat") and `peak_position` (m, the
    car-body centre's position along the line at the gust's peak; NaN: the middle of the circular curve)."""
    speed: float = 0.0
    direction_deg: float = 90.0
    gust: str = "none"
    peak_position: float = math.nan

    def validated(self):
        check_range("wind speed", self.speed, *WIND_SPEED_RANGE, "m/s")
        check_range("wind direction", self.direction_deg, *DIRECTION_RANGE_DEG, "deg")
        if self.gust not in GUSTS:
            raise ValueError(f"gust {self.gust!r} is unknown; choose one of {', '.join(GUSTS)}")
        return self

    @property
    def blows(self):
        """True when there is a wind to apply."""
        return self.speed > 0.0

    def history(self, parameters: AerodynamicParameters, centre_m):
        """(s, wind speed) points along the line (m, m/s); the gust centred on peak_position, else centre_m."""
        if self.gust == "none":
            return np.array([0.0]), np.array([self.speed])
        at = self.peak_at(centre_m)
        a_i = parameters.gust_peak_factor * parameters.gust_turbulence_intensity
        mean = self.speed / (1.0 + a_i)
        span = GUST_SPAN * parameters.gust_length_scale
        if not (math.isfinite(at) and at >= span + parameters.gust_ramp):
            raise ValueError(f"gust peak at {at:g} m leaves no room for its ramp and hat before it: it must be at "
                             f"least {span + parameters.gust_ramp:g} m along the line")
        ramp = np.linspace(-span - parameters.gust_ramp, -span, 61)
        x = np.linspace(-span, span, 241)
        u = np.concatenate((mean * np.sin(0.5 * np.pi * (ramp - ramp[0]) / parameters.gust_ramp) ** 2,
                            mean * (1.0 + a_i * scalarmath.exp(-np.abs(x[1:]) / parameters.gust_length_scale))))
        return at + np.concatenate((ramp, x[1:])), u

    def peak_at(self, centre_m):
        """Where the gust peaks (m): peak_position, or centre_m if that is NaN."""
        return centre_m if math.isnan(self.peak_position) else self.peak_position


def still_air():
    """The aero array without wind: the core applies no aerodynamic load."""
    return AeroHeader.pack(active=0.0)


def pack_aero(parameters: AerodynamicParameters, wind: Wind, centre_m):
    """The core's aero array (loads.layout) of a wind and the car body's coefficients; still air if the wind
    does not blow. `centre_m`: where an unplaced gust peaks (the middle of the circular curve)."""
    if wind is None or not wind.validated().blows:
        return still_air()
    table = np.array(parameters.validated().coefficients())
    s, speed = wind.history(parameters, centre_m)
    head = AeroHeader.pack(active=1.0, air_density=parameters.air_density, reference_area=parameters.reference_area,
                           reference_length=parameters.reference_length,
                           wind_direction=math.radians(wind.direction_deg), coefficient_points=len(table),
                           wind_points=len(s))
    rows = np.zeros((len(table), AeroCoefficients.size()))
    for k, name in enumerate(AeroCoefficients.names()):
        rows[:, AeroCoefficients[name]] = table[:, k]
    points = np.zeros((len(s), WindPoint.size()))
    points[:, WindPoint.s] = s
    points[:, WindPoint.speed] = speed
    return np.concatenate((head, rows.ravel(), points.ravel()))


def car_body_load(parameters: AerodynamicParameters, wind_speed, direction, train_speed):
    """(n, 7) the core's (W, beta, F_y, F_z, M_x, M_y, M_z) of `loads.aerodynamics.relative_wind_load` at n
    instants: the wind's speed (m/s) and where it comes from (rad, relative to the track, + from the left),
    measured or given, at the train's speed (m/s): the load of the simulator's coefficients, for an on-board
    estimator told the wind."""
    from .aerodynamics import relative_wind_load
    aero = pack_aero(parameters, Wind(speed=1.0), 0.0)
    w, theta, v = (np.broadcast_to(np.asarray(x, dtype=float), np.shape(train_speed))
                   for x in (wind_speed, direction, train_speed))
    return np.array([relative_wind_load(aero, *x) for x in zip(w.tolist(), theta.tolist(), v.tolist())],
                    dtype=float).reshape(-1, 7)
