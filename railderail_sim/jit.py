"""The decorator of the numba core: compiled, cached, and without numba's reference-counting runtime.

Why. The core functions work on arrays their callers allocate (the state, the contact geometry and
its table, scratch buffers); none allocates an array of its own. Numba's runtime (NRT) nevertheless
counts the references to every array a compiled function receives, with an atomic operation on entry
and another on each way out, and its pruning pass cannot remove them across the calls and branches of
the contact code. One wheel's contact evaluation passes about ten arrays down three calls, and the
counting cost a third of it (`railderail bench --only contact`: eight wheels through the contact table
9.7 -> 5.8 us; the vehicle model's real-time factor 15 -> 24). `core` compiles without the runtime.

Safety. Without the runtime an array cannot be allocated: a `core` function that calls np.zeros (or
returns a new array) fails to compile with a typing error at that line, so a leak cannot slip in: the
Python layer allocates every buffer (`table.attach` the table's scratch arrays, `integrator.workspace`
the time loop's) and constant arrays live at module level. Views and slices of argument arrays are fine:
the caller holds the memory.
`_nrt` is numba's own option (`numba.core.options.DefaultOptions`), marked private by its underscore:
setup.py bounds numba to the releases it is checked on.

The on-disk cache. numba checks a cached function against its own source file's time stamp only, not
against the callees it compiled in from other modules nor the record layouts it took as constants: after
an edit of `creep.py`, `dynamics.rhs` kept running the old creep law from its cache. So the cache lives in
a folder of its own per version of the core's sources (`sources_key`: every module the compiled code is
made of or takes constants from), under the user's cache folder (`~/.cache/railderail/numba/<key>`, about
10 MB each; older ones may be deleted), unless NUMBA_CACHE_DIR says where.
"""
import hashlib
import os
from pathlib import Path

import numba

# the packages and modules of railderail_sim that the compiled core is made of or takes constants from (the
# layers above it, cli, ros, methods and the like, hold no compiled function)
CORE_SOURCES = ("contact", "loads", "sensors", "track", "vehicle")


def sources_key():
    """16 hex digits of SHA-256 over the core's sources (CORE_SOURCES and the package's own modules)."""
    here = Path(__file__).parent
    digest = hashlib.sha256()
    for path in sorted(here.glob("*.py")) + [p for d in CORE_SOURCES for p in sorted((here / d).rglob("*.py"))]:
        digest.update(path.relative_to(here).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


if not os.environ.get("NUMBA_CACHE_DIR"):
    numba.config.CACHE_DIR = str(Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
                                 / "railderail" / "numba" / sources_key())

# error_model "numpy": a float division needs no test of its divisor for zero (numba's default, "python", raises
# ZeroDivisionError there, a branch at every division). The divisions the runs reach are guarded (with the
# default model an unguarded one raised); were one not, it would give inf or nan, which in the state's rates the
# error control turns into a step below h_min, a clear DIVERGED. The same rows bit for bit, about 3 % less
# process time on irregular track (docs/performance.md). Also for the benchmarks' timing loops, so they call the
# core as the model does
OPTIONS = dict(_nrt=False, error_model="numpy")
core = numba.njit(cache=True, **OPTIONS)
# small functions on the hot path, inlined into their callers by numba: a call copies each array argument's
# descriptor (about ten words), and the contact table's interpolation costs less than its call. Only for
# scalar arguments: inlining a function that takes tuples made the vehicle's right-hand side 50 % slower
# (measured), and every call level that passes a dozen arrays costs about as much as a wheel's table
# lookup, which is why the right wheel's mirroring lives inside `wheelset.wheel_forces`, not in a wrapper.
core_inline = numba.njit(cache=True, inline="always", **OPTIONS)


def compiled_entry(dispatcher, args):
    """The compiled entry point of `dispatcher` (a `core` function) for the types of `args`, or None if it has not
    been compiled (nor loaded from the cache) for them yet: calling it skips numba's dispatch, which resolves
    the type of every argument on each call (for `integrator.advance` and its 45 arrays in nested namedtuples,
    8.9 us of its 10 us per call: docs/performance.md, "The stepper's share"). The entry point does not check
    its arguments' types: a caller must call it only with arguments of the same types (same objects, or
    scalars converted as they were), else through the dispatcher.

    numba API: `numba.typeof` (public, an argument's type as the dispatcher types it), and the dispatcher's
    `signatures` (the compiled argument types) and `get_overload(signature)` (the entry point), public
    methods of numba's `Dispatcher` since before 0.60 and unchanged up to 0.68 (setup.py's bounds).
    """
    signature = tuple(numba.typeof(a) for a in args)
    if signature not in dispatcher.signatures:
        return None
    return dispatcher.get_overload(signature)
