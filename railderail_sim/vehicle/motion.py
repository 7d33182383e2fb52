"""What ideal inertial sensors fixed to a body read: the specific force and the angular rate at any point of
a body, in the body's own axes, from a run's output arrays (`simulate.output_arrays`).

The core writes each body's `BodyMotion` at its reference point in the track axes at its station (the
specific force F/m, the absolute angular velocity and angular acceleration). A point P fixed to the body,
at p from the reference point in body axes, reads, as a rigid body and gravity uniform over it,

    f_P = f_ref + alpha x r + omega x (omega x r),   r = R p,     in track axes,

turned into the body's axes by R^T, where R = Rz(yaw) Ry(pitch) Rx(roll) is the body's rotation relative
to the track (its `body_states` angles; a wheelset's pitch position is unused and zero, so an axle box
turns with the wheelset's roll and yaw and not with its spin). Axes: x forward, y left, z up; an
accelerometer at rest on level track reads +g along z.
"""
import numpy as np

from .layout import Body, BodyMotion, Dof


def relative_rotation(angles):
    """(..., 3, 3) rotations track <- body from (..., 5) body states (roll, pitch, yaw of `layout.Dof`)."""
    roll, pitch, yaw = (np.asarray(angles[..., d], dtype=float) for d in (Dof.roll, Dof.pitch, Dof.yaw))
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    return np.stack([np.stack([cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr], -1),
                     np.stack([sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr], -1),
                     np.stack([-sp, cp * sr, cp * cr], -1)], -2)


def points_motion(arrays, bodies, points):
    """(specific force (n, m, 3) m/s^2, angular rate (n, m, 3) rad/s), both in each body's axes, of m points:
    `points` (m, 3) (m, body axes from the body's reference point: x forward, y left, z up) of `bodies` (m
    `layout.Body` indices)."""
    b = np.asarray(bodies, dtype=int)
    motion = BodyMotion.split(np.asarray(arrays["body_motion"])[:, b])
    rotation = relative_rotation(np.asarray(arrays["body_states"])[:, b])
    p = np.asarray(points, dtype=float)
    r = rotation[..., 0] * p[:, None, 0] + rotation[..., 1] * p[:, None, 1] + rotation[..., 2] * p[:, None, 2]
    omega, alpha = motion["angular_velocity"], motion["angular_acceleration"]
    force = motion["specific_force"] + _cross(alpha, r) + _cross(omega, _cross(omega, r))
    return _to_body(rotation, force), _to_body(rotation, omega)


# Written out component by component, each term in the order np.cross and np.sum take them (the same
# numbers to the bit): numpy's general functions cost more in their calls than in their arithmetic on the
# small arrays of a sensor chunk (one row in the simulator node).

def _cross(a, b):
    """a x b over the last axis."""
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1], a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], -1)


def _to_body(rotation, v):
    """R^T v: track axes (..., 3) into the body's."""
    return (rotation[..., 0, :] * v[..., 0, None] + rotation[..., 1, :] * v[..., 1, None]
            + rotation[..., 2, :] * v[..., 2, None])


def point_motion(arrays, body, point):
    """(specific force (n, 3) m/s^2, angular rate (n, 3) rad/s), both in the body's axes, of the point
    `point` (m, body axes from the body's reference point: x forward, y left, z up) of `body` (a
    `layout.Body` or its name)."""
    b = Body[body] if isinstance(body, str) else Body(body)
    force, rate = points_motion(arrays, [b], [point])
    return force[:, 0], rate[:, 0]
