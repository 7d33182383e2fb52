"""The groups of `railderail bench` (`cli/bench.py`): contact, vehicle, methods; each `run()` returns its
figures. They time the library and the numba core; they are never tests."""
