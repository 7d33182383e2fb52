"""Table look-up of the numba core: the interval of a strictly increasing position column that holds a point.

By hand in the core (a bisection): the rails' deviations and the wind are looked up at every evaluation of
the equations of motion, in flat arrays whose rows carry the position first, where numpy.searchsorted
would need a strided view per call.
"""
from .jit import core


@core
def interval(table, start, stride, n, s):
    """The row lo of the n rows of `stride` entries from `start` (each row's first entry its position, strictly
    increasing) with position[lo] <= s < position[lo + 1], for s between the first and the last position."""
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if table[start + mid * stride] <= s:
            lo = mid
        else:
            hi = mid
    return lo
