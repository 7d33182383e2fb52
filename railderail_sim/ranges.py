"""One range check for every user-facing value (CLI options, scenario fields, node parameters).

Bad input must fail before any work starts with one sentence naming the value and the accepted range,
e.g. "curve radius 100 m is outside the accepted range [150, 20000] m"; the CLIs print it as one line
and exit with status 2.
"""
import math


def check_range(name, value, lo, hi, unit="", *, lo_open=False, hi_open=False):
    """float(value) if it is finite and within lo..hi (an end open where flagged), else ValueError."""
    v = float(value)
    if not (math.isfinite(v) and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)):
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        raise ValueError(f"{name} {v:g} {unit} is outside the accepted range {left}{lo:g}, {hi:g}{right} "
                         f"{unit}".replace("  ", " ").rstrip())
    return v
