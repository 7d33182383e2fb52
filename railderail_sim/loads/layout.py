"""Layouts of the aerodynamic loads' arrays (`record.Record`), free of numba so the ROS side reads them.

The core gets one float64 array `aero` (`wind.pack_aero`): an AeroHeader, then `coefficient_points`
AeroCoefficients rows (the car body's coefficients against the yaw angle of the relative wind), then
`wind_points` WindPoint rows (the wind speed along the line).
"""
from ..record import Record


class AeroHeader(Record):
    """Header of the packed aerodynamic array."""
    active = "-", "1: aerodynamic loads on the car body; 0: none (no wind given)"
    air_density = "kg/m^3", "air density rho"
    reference_area = "m^2", "reference area A of the coefficients"
    reference_length = "m", "reference length d of the moment coefficients"
    wind_direction = ("rad", "where the wind comes from, from the direction of travel in the track plane, + to "
                      "the left (pi/2: from the left, at right angles to the track)")
    coefficient_points = "-", "number of AeroCoefficients rows"
    wind_points = "-", "number of WindPoint rows"


class AeroCoefficients(Record):
    """The car body's aerodynamic coefficients at one yaw angle, for a wind from the left (EN 14067-1 axes
    turned to ours: a wind from the right mirrors the side force and the rolling and yawing moments)."""
    yaw_angle = "rad", "yaw angle beta of the relative wind to the direction of travel, 0..pi/2"
    side_force = "-", "C_Fy, + toward the lee side"
    lift = "-", "C_Fz, + up"
    rolling_moment = "-", "C_Mx about the reference point, + rolling the car toward the lee side"
    pitching_moment = "-", "C_My about the reference point, + nose up"
    yawing_moment = "-", "C_Mz about the reference point, + nose toward the lee side"


class WindPoint(Record):
    """The wind speed where the car-body centre is at s (linear between points, constant beyond the ends)."""
    s = "m", "distance of the car-body centre along the line, strictly increasing"
    speed = "m/s", "wind speed (at the reference height), >= 0"


class AeroLoad(Record):
    """The aerodynamic load on the car body at an instant (output row), track axes, about the reference
    point: the track centre line at rail level below the car-body centre."""
    wind_speed = "m/s", "wind speed"
    yaw_angle = "rad", "yaw angle of the relative wind, + wind from the left"
    side_force = "N", "lateral force, + to the left"
    lift = "N", "vertical force, + up"
    rolling_moment = "N m", "moment about the track x axis"
    pitching_moment = "N m", "moment about the track y axis"
    yawing_moment = "N m", "moment about the track z axis"


A_HEAD = AeroHeader.size()
A_COEFF = AeroCoefficients.size()
A_WIND = WindPoint.size()
