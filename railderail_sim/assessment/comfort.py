"""Ride comfort at the car-body floor: EN 12299's mean comfort N_MV (simplified method) and Sperling's
ride index W_z, lateral and vertical.

N_MV (EN 12299, floor, C for the formula's coefficient): each axis weighted (Wd for x and y, Wb for z,
`filters.weighting`), its r.m.s. over consecutive 5 s windows, the 95th percentile of those over a 5 min
block (60 windows; a shorter run is one block of the windows it has), N_MV = 6 sqrt(a_x95^2 + a_y95^2 +
a_z95^2). Comfort classes (C): < 1 very comfortable, 1-2 comfortable, 2-4 medium, 4-5 uncomfortable,
>= 5 very uncomfortable; EN 12299 sets no acceptance limit.

W_z (GB 5599 / UIC 513's predecessor): the acceleration weighted with B(f) over 0.5-40 Hz
(`filters.sperling_weighting`), per 5 s window (GB/T 5599-2019's window, A) W_z = (2 a_w,rms^2)^0.15 with
a in cm/s^2, which for a sine of amplitude A is (B(f) A)^0.3, the spectral form of 0.896 (A^3 F(f)/f)^0.1;
the run's value is its largest window's (C). Limit 3.0, GB 5599's "acceptable" bound for passenger cars
(< 2.5 excellent, 2.5-2.75 good, 2.75-3.0 acceptable; C).
"""
from __future__ import annotations

import math

import numpy as np

from . import filters

WINDOW_S = 5.0                       # B: EN 12299's 5 s r.m.s.; A: GB/T 5599-2019's 5 s window
BLOCK_WINDOWS = 60                   # a 5 min block (B)
PERCENTILE = 95.0
N_MV_FACTOR = 6.0                    # C
WZ_LIMIT = 3.0                       # C
COMFORT_CLASSES = ((1.0, "very comfortable"), (2.0, "comfortable"), (4.0, "medium"), (5.0, "uncomfortable"),
                   (math.inf, "very uncomfortable"))


def comfort_class(n_mv):
    return next(name for top, name in COMFORT_CLASSES if n_mv < top)


def window_rms(x, rate):
    """r.m.s. of x (axis 0 time) over consecutive whole WINDOW_S windows, (windows, ...); ValueError if the
    record is shorter than one window."""
    per = int(round(WINDOW_S * rate))
    count = len(x) // per
    if count < 1:
        raise ValueError(f"comfort needs at least one {WINDOW_S:g} s window; the record lasts "
                         f"{len(x) / rate:.2f} s")
    x = np.asarray(x[:count * per])
    return np.sqrt(np.mean(x.reshape((count, per) + x.shape[1:]) ** 2, axis=1))


def n_mv(floor, rate):
    """[(first window, last window + 1, N_MV)] per 5 min block of a floor acceleration (n, 3) in body axes
    (x, y, z; m/s^2)."""
    wd, wb = filters.weighting("Wd"), filters.weighting("Wb")
    weighted = np.stack([wd.apply(floor[:, 0], rate), wd.apply(floor[:, 1], rate), wb.apply(floor[:, 2], rate)], -1)
    rms = window_rms(weighted, rate)
    out = []
    for first in range(0, len(rms), BLOCK_WINDOWS):
        block = rms[first:first + BLOCK_WINDOWS]
        a95 = np.percentile(block, PERCENTILE, axis=0)
        out.append((first, first + len(block), float(N_MV_FACTOR * math.sqrt(float(np.sum(a95 ** 2))))))
    return out


def sperling(acceleration, rate, direction):
    """W_z of each 5 s window of one direction's acceleration (n,) m/s^2."""
    weighted = filters.sperling_weighting(direction).apply(acceleration, rate) * 100.0   # cm/s^2
    rms = window_rms(weighted, rate)
    return (2.0 * rms ** 2) ** 0.15
