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
"""
import numba

OPTIONS = dict(_nrt=False)     # also for the benchmarks' timing loops, so they call the core as the model does
core = numba.njit(cache=True, **OPTIONS)
# small functions on the hot path, inlined into their callers by numba: a call copies each array argument's
# descriptor (about ten words), and the contact table's interpolation costs less than its call. Only for
# scalar arguments: inlining a function that takes tuples made the vehicle's right-hand side 50 % slower
# (measured), and every call level that passes a dozen arrays costs about as much as a wheel's table
# lookup, which is why the right wheel's mirroring lives inside `wheelset.wheel_forces`, not in a wrapper.
core_inline = numba.njit(cache=True, inline="always", **OPTIONS)
