"""The instruments' filters on a chunk's rows: every channel's cascade of second-order sections in one
compiled call, since scipy.signal.sosfilt's checks and axis moves cost about 0.2 ms per call, four calls per
row in the simulator node, where the filtering itself costs microseconds."""
from ..jit import core


@core
def filter_columns(sos, sections, y, state):
    """Each column c of y (n, channels) through its first sections[c] of sos (channels, S, 6), in place;
    state (channels, S, 2) carried. scipy.signal.sosfilt's direct form II transposed, term for term in its
    order (the same numbers to the bit)."""
    for c in range(y.shape[1]):
        for i in range(y.shape[0]):
            x = y[i, c]
            for s in range(sections[c]):
                x_new = sos[c, s, 0] * x + state[c, s, 0]
                state[c, s, 0] = sos[c, s, 1] * x - sos[c, s, 4] * x_new + state[c, s, 1]
                state[c, s, 1] = sos[c, s, 2] * x - sos[c, s, 5] * x_new
                x = x_new
            y[i, c] = x
