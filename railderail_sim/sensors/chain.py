"""The instruments' arithmetic on a chunk's channel matrix in one compiled call: the bias, the white noise
and the bias's random walk added, the sensing element's saturation, the filters, the clipping and the
quantisation. In numpy and scipy.signal.sosfilt these were some twenty calls per chunk, about 0.4 ms of call
overhead on the one row a period of the simulator node brings, where the arithmetic costs microseconds.
Each element goes through the operations the numpy code applied, in its order (the same numbers to the bit)."""
import numpy as np

from ..jit import core


@core
def instrument_chain(y, bias, draws, first, width, white, walk_step, walk, low, high, sos, sections, settled,
                     state, settle, lsb, top):
    """The readings of the ideal values y (n, channels), in place, channel c's parameters at [c]:

    y + bias + draw * white + the walk (walk[c] + the running sum of draw * walk_step), clipped to [low,
    high]; through the first sections[c] second-order sections of sos (channels, S, 6) with state (channels,
    S, 2) carried (scipy.signal.sosfilt's direct form II transposed; with `settle`, the state first set to
    settled times the first row, the filter's steady state); clipped again and, where lsb > 0, rounded to
    lsb over low, between 0 and top codes. walk keeps each channel's walk at the last row.

    draws: the chunk's standard normal draws, unit after unit, each unit's (n, 2 w) row by row, a row its w
    white noise draws then its w walk steps (a unit's generator fills its block in one call); first[c] and
    width[c]: the first channel and the width w of channel c's unit."""
    n = y.shape[0]
    for c in range(y.shape[1]):
        w = width[c]
        at = 2 * n * first[c] + c - first[c]
        running = walk[c]
        for i in range(n):
            v = y[i, c] + bias[c]
            v = v + draws[at + 2 * w * i] * white[c]
            running = running + draws[at + 2 * w * i + w] * walk_step[c]
            v = v + running
            v = low[c] if v < low[c] else v          # as np.maximum and np.minimum, a NaN passes through
            v = high[c] if v > high[c] else v
            if settle and i == 0:
                for s in range(sections[c]):
                    state[c, s, 0] = settled[c, s, 0] * v
                    state[c, s, 1] = settled[c, s, 1] * v
            for s in range(sections[c]):
                v_new = sos[c, s, 0] * v + state[c, s, 0]
                state[c, s, 0] = sos[c, s, 1] * v - sos[c, s, 4] * v_new + state[c, s, 1]
                state[c, s, 1] = sos[c, s, 2] * v - sos[c, s, 5] * v_new
                v = v_new
            v = low[c] if v < low[c] else v
            v = high[c] if v > high[c] else v
            if lsb[c] > 0.0:
                code = np.rint((v - low[c]) / lsb[c])
                code = 0.0 if code < 0.0 else code
                code = top[c] if code > top[c] else code
                v = code * lsb[c] + low[c]
            y[i, c] = v
        walk[c] = running
