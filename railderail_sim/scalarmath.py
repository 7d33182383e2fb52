"""Elementwise transcendental functions for model building that round the same whatever numpy's CPU dispatch.

numpy (2.4) sends float64 arctan, tan, arcsin, arcsinh, exp, log and fractional powers to AVX-512 loops where
the CPU has them, and these round differently in the last bit from its AVX2 loops; the contact tables built
with them then differ between CPUs and a hunting run amplifies the last bit to millimetres
(docs/performance.md, "Determinism across CPUs"). These functions call C's libm one value at a time (Python's
`math`), the library the numba core calls too. glibc picks its libm variants by the CPU's FMA and AVX2
(measured with GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA: 2 to 249 of 200 000 values differ per
function), so the results are the same on every x86-64 CPU with AVX2 and FMA (x86-64-v3, AVX-512 ones
included), not on older ones. Arrays of any shape (or scalars, which give floats); the model building's
arrays are small (tens of thousands of values), so the Python loop costs milliseconds.
"""
import math

import numpy as np


def _elementwise(fn, x):
    a = np.asarray(x, dtype=np.float64)
    out = np.fromiter(map(fn, a.ravel().tolist()), dtype=np.float64, count=a.size).reshape(a.shape)
    return float(out) if out.ndim == 0 else out


def arctan(x):
    return _elementwise(math.atan, x)


def tan(x):
    return _elementwise(math.tan, x)


def arcsin(x):
    return _elementwise(math.asin, x)


def sin(x):
    return _elementwise(math.sin, x)


def cos(x):
    return _elementwise(math.cos, x)


def exp(x):
    return _elementwise(math.exp, x)


def power(x, p):
    """x ** p, the exponent p a scalar or an array that broadcasts with x."""
    a, b = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(p, dtype=np.float64))
    out = np.fromiter(map(math.pow, a.ravel().tolist(), b.ravel().tolist()), dtype=np.float64,
                      count=a.size).reshape(a.shape)
    return float(out) if out.ndim == 0 else out
