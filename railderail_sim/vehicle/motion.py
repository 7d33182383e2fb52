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

from ..jit import core
from .layout import Body, BodyMotion, Dof

ANGLES = np.array([Dof.roll, Dof.pitch, Dof.yaw])
SPECIFIC_FORCE, ANGULAR_VELOCITY, ANGULAR_ACCELERATION = (int(BodyMotion[name]) for name in (
    "specific_force", "angular_velocity", "angular_acceleration"))


def points_motion(arrays, bodies, points):
    """(specific force (n, m, 3) m/s^2, angular rate (n, m, 3) rad/s), both in each body's axes, of m points:
    `points` (m, 3) (m, body axes from the body's reference point: x forward, y left, z up) of `bodies` (m
    `layout.Body` indices)."""
    n, m = len(arrays["body_states"]), len(bodies)
    out = np.empty((n, 2 * m * 3))
    at = 3 * np.arange(m)
    points_motion_into(arrays, bodies, points, at, 3 * m + at, out)
    return out[:, :3 * m].reshape(n, m, 3), out[:, 3 * m:].reshape(n, m, 3)


def points_motion_into(arrays, bodies, points, force_at, rate_at, out):
    """`points_motion`'s readings written into the columns of out (n, ...): point k's specific force into
    out[:, force_at[k]:force_at[k] + 3], its angular rate likewise at rate_at[k] (none where it is -1). The
    sensors' channel matrix is filled so, without the arrays of each mount's reading and their concatenation
    (a row in the simulator node: the calls, not the arithmetic, cost)."""
    # each body's angles' cosines and sines once, not once per point on it (the shipped set's 17 mounts are on
    # the 7 bodies), and the motion read in place: gathered per point, (rows, points, 3 + 9) values cost
    # more than the arithmetic
    angles = np.asarray(arrays["body_states"])[:, :, ANGLES]
    _points_into(np.cos(angles), np.sin(angles), np.asarray(arrays["body_motion"]), np.asarray(bodies, dtype=np.int64),
                 np.asarray(points, dtype=float), np.asarray(force_at, dtype=np.int64),
                 np.asarray(rate_at, dtype=np.int64), out)


@core
def _points_into(cos, sin, motion, bodies, points, force_at, rate_at, out):
    """f = R^T (f_ref + alpha x r + omega x (omega x r)), r = R p, and R^T omega, R = Rz(yaw) Ry(pitch) Rx(roll)
    from the cosines and sines (n, bodies, 3) of (roll, pitch, yaw) and the motion (n, bodies, ...) of each
    point's body bodies[k]; each term in the order numpy took them when this was written with whole-array
    operations and np.cross (the same numbers to the bit)."""
    for i in range(cos.shape[0]):
        for k in range(points.shape[0]):
            q = bodies[k]
            cr, cp, cy = cos[i, q, 0], cos[i, q, 1], cos[i, q, 2]
            sr, sp, sy = sin[i, q, 0], sin[i, q, 1], sin[i, q, 2]
            r00, r01, r02 = cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr
            r10, r11, r12 = sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr
            r20, r21, r22 = -sp, cp * sr, cp * cr
            p0, p1, p2 = points[k, 0], points[k, 1], points[k, 2]
            x = r00 * p0 + r01 * p1 + r02 * p2
            y = r10 * p0 + r11 * p1 + r12 * p2
            z = r20 * p0 + r21 * p1 + r22 * p2
            w0 = motion[i, q, ANGULAR_VELOCITY]
            w1 = motion[i, q, ANGULAR_VELOCITY + 1]
            w2 = motion[i, q, ANGULAR_VELOCITY + 2]
            a0 = motion[i, q, ANGULAR_ACCELERATION]
            a1 = motion[i, q, ANGULAR_ACCELERATION + 1]
            a2 = motion[i, q, ANGULAR_ACCELERATION + 2]
            u0, u1, u2 = w1 * z - w2 * y, w2 * x - w0 * z, w0 * y - w1 * x      # omega x r
            f0 = motion[i, q, SPECIFIC_FORCE] + (a1 * z - a2 * y) + (w1 * u2 - w2 * u1)
            f1 = motion[i, q, SPECIFIC_FORCE + 1] + (a2 * x - a0 * z) + (w2 * u0 - w0 * u2)
            f2 = motion[i, q, SPECIFIC_FORCE + 2] + (a0 * y - a1 * x) + (w0 * u1 - w1 * u0)
            c = force_at[k]
            out[i, c] = r00 * f0 + r10 * f1 + r20 * f2
            out[i, c + 1] = r01 * f0 + r11 * f1 + r21 * f2
            out[i, c + 2] = r02 * f0 + r12 * f1 + r22 * f2
            c = rate_at[k]
            if c >= 0:
                out[i, c] = r00 * w0 + r10 * w1 + r20 * w2
                out[i, c + 1] = r01 * w0 + r11 * w1 + r21 * w2
                out[i, c + 2] = r02 * w0 + r12 * w1 + r22 * w2


def point_motion(arrays, body, point):
    """(specific force (n, 3) m/s^2, angular rate (n, 3) rad/s), both in the body's axes, of the point
    `point` (m, body axes from the body's reference point: x forward, y left, z up) of `body` (a
    `layout.Body` or its name)."""
    b = Body[body] if isinstance(body, str) else Body(body)
    force, rate = points_motion(arrays, [b], [point])
    return force[:, 0], rate[:, 0]
