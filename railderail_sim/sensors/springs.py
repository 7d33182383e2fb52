"""The air springs' rise, row by row through the core's kinematics: one compiled loop (`jit.core`), since a
Python loop calling `dynamics.kinematics` per output row cost as much as all the other sensors together."""
from ..jit import core
from ..vehicle.dynamics import _point, _to_body_axes, kinematics
from ..vehicle.layout import CAR_BODY, N_BODY, N_DOF, State


@core
def spring_rise(states, positions, bodies, track, sp, bogies, local, x, kin, out):
    """out[i, k] = the rise (m) of the car body's point of spring k over its frame's (`bogies[k]`), in the
    frame's axes, at output row i: `states` (n, N_BODY * N_DOF) the rows' body states, `positions` (n,) the
    car-body centre's distance along the line; `local` (2, springs, 3) the spring's point in the frame's and
    in the car body's coordinates; x (the state vector) and kin (the kinematics) scratch buffers."""
    for i in range(states.shape[0]):
        for j in range(N_BODY * N_DOF):
            x[State.positions + j] = states[i, j]
        x[State.s] = positions[i]
        kinematics(x, bodies, track, sp, kin)
        for k in range(bogies.shape[0]):
            b = bogies[k]
            pax, pay, paz, _, _, _, _, _, _ = _point(kin, b, local[0, k, 0], local[0, k, 1], local[0, k, 2])
            pbx, pby, pbz, _, _, _, _, _, _ = _point(kin, CAR_BODY, local[1, k, 0], local[1, k, 1], local[1, k, 2])
            out[i, k] = _to_body_axes(kin, b, pbx - pax, pby - pay, pbz - paz)[2]
