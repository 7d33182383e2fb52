"""The aerodynamic loads of a crosswind on the car body (numba core).

Quasi-steady aerodynamics (Baker, J. Wind Eng. Ind. Aerodyn. 98 (2010) 277-287; EN 14067-6): the load at an
instant is that of a steady flow at the relative wind of that instant,

    v_rel^2 = (v + W cos(theta))^2 + (W sin(theta))^2,   beta = atan2(W sin(theta), v + W cos(theta)),
    F = 1/2 rho v_rel^2 A C_F(beta),   M = 1/2 rho v_rel^2 A d C_M(beta),

with v the train's speed, W the wind speed at the car-body centre's position, theta where the wind comes
from (relative to the local track: the wind keeps its angle to the track through a curve, as the standard
evaluates it) and the coefficients interpolated linearly in |beta| over 0-90 deg; a relative wind from
behind (a tail wind faster than the train) is the mirror flow from the car's rear, the table read at
180 deg - |beta| with the pitching and yawing moments reversed (the leading car's coefficients stand in for
its rear). The loads act on the car body only (the bogies' share is left out, as in EN 14067-6's multibody
evaluation); the drag is left out, the speed being prescribed. Assumptions: no admittance (the gust's
shape reaches the body unfiltered), no unsteady effects of the curve, the coefficients of the leading car
for every car.
"""
import math

from ..jit import core
from ..lookup import interval
from .layout import A_COEFF, A_HEAD, A_WIND, AeroCoefficients, AeroHeader, WindPoint


@core
def wind_speed(aero, s):
    """Wind speed (m/s) with the car-body centre at s: linear between the points, constant beyond the ends.

    By hand in the core (`lookup.interval`): it runs at every evaluation of the equations of motion, where
    numpy.interp cannot be called."""
    n = int(aero[AeroHeader.wind_points])
    o = A_HEAD + int(aero[AeroHeader.coefficient_points]) * A_COEFF
    if s <= aero[o + WindPoint.s]:
        return aero[o + WindPoint.speed]
    last = o + (n - 1) * A_WIND
    if s >= aero[last + WindPoint.s]:
        return aero[last + WindPoint.speed]
    a = o + interval(aero, o + WindPoint.s, A_WIND, n, s) * A_WIND
    b = a + A_WIND
    u = (s - aero[a + WindPoint.s]) / (aero[b + WindPoint.s] - aero[a + WindPoint.s])
    return aero[a + WindPoint.speed] + u * (aero[b + WindPoint.speed] - aero[a + WindPoint.speed])


@core
def coefficients(aero, beta):
    """(C_Fy, C_Fz, C_Mx, C_My, C_Mz) at the yaw angle |beta| (rad), linear in the table, held beyond it."""
    n = int(aero[AeroHeader.coefficient_points])
    b = abs(beta)
    k = 0
    while k < n - 2 and aero[A_HEAD + (k + 1) * A_COEFF + AeroCoefficients.yaw_angle] <= b:
        k += 1
    p = A_HEAD + k * A_COEFF
    q = p + A_COEFF
    u = (b - aero[p + AeroCoefficients.yaw_angle]) / (aero[q + AeroCoefficients.yaw_angle]
                                                      - aero[p + AeroCoefficients.yaw_angle])
    u = min(max(u, 0.0), 1.0)
    return (aero[p + AeroCoefficients.side_force] + u * (aero[q + AeroCoefficients.side_force]
                                                         - aero[p + AeroCoefficients.side_force]),
            aero[p + AeroCoefficients.lift] + u * (aero[q + AeroCoefficients.lift] - aero[p + AeroCoefficients.lift]),
            aero[p + AeroCoefficients.rolling_moment] + u * (aero[q + AeroCoefficients.rolling_moment]
                                                             - aero[p + AeroCoefficients.rolling_moment]),
            aero[p + AeroCoefficients.pitching_moment] + u * (aero[q + AeroCoefficients.pitching_moment]
                                                              - aero[p + AeroCoefficients.pitching_moment]),
            aero[p + AeroCoefficients.yawing_moment] + u * (aero[q + AeroCoefficients.yawing_moment]
                                                            - aero[p + AeroCoefficients.yawing_moment]))


@core
def aerodynamic_load(aero, s, v):
    """(W, beta, F_y, F_z, M_x, M_y, M_z): the wind speed and the relative wind's yaw angle (+ from the left),
    and the load on the car body in track axes about the reference point (the track centre line at rail
    level below the car-body centre); zeros when the aerodynamics are off."""
    if aero[AeroHeader.active] < 0.5:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return relative_wind_load(aero, wind_speed(aero, s), aero[AeroHeader.wind_direction], v)


@core
def relative_wind_load(aero, w, theta, v):
    """`aerodynamic_load` of a wind of speed w (m/s) from theta (rad, relative to the track) at the train's
    speed v, the coefficients of `aero` (also what an on-board estimator given a wind computes)."""
    ux = v + w * math.cos(theta)
    uy = w * math.sin(theta)
    beta = math.atan2(uy, ux)
    q = 0.5 * aero[AeroHeader.air_density] * (ux * ux + uy * uy) * aero[AeroHeader.reference_area]
    d = aero[AeroHeader.reference_length]
    # a relative wind from behind (|beta| > 90 deg: a tail wind faster than the train) meets the car from
    # its rear: the table at 180 deg - |beta|, the pitching and yawing moments turned with the car
    behind = abs(beta) > 0.5 * math.pi
    cfy, cfz, cmx, cmy, cmz = coefficients(aero, math.pi - abs(beta) if behind else beta)
    if behind:
        cmy, cmz = -cmy, -cmz
    side = 1.0 if beta >= 0.0 else -1.0            # a wind from the left pushes to the right (-y)
    # nose up is a negative moment about y (x forward, z up); nose to the lee (the right) negative about z
    return w, beta, -side * q * cfy, q * cfz, side * q * d * cmx, -q * d * cmy, -side * q * d * cmz
