"""Frames: ours (NED world, FRD body, ZYX roll-pitch-yaw; lcmtypes/nav_state_t.lcm)
and ROS's (REP-103/105: ENU world, FLU body, quaternions). docs/ros2.md.

    p_enu = A p_ned,    A = [[0,1,0],[1,0,0],[0,0,-1]]   (swap x/y, negate z)
    v_flu = F v_frd,    F = diag(1,-1,-1)
    R_enu_flu = A R_ned_frd F,   R_ned_frd = Rz(yaw) Ry(pitch) Rx(roll)

Positions convert exactly (a swap and a sign). Orientations go through a
rotation matrix and a quaternion, so they come back to within a few 1e-16 rad.
"""

import math

A = ((0.0, 1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, -1.0))
F = ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0))


def matmul(a, b):
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))


def transpose(a):
    return tuple(tuple(a[j][i] for j in range(3)) for i in range(3))


def matvec(a, v):
    return tuple(sum(a[i][k] * v[k] for k in range(3)) for i in range(3))


def ned_to_enu(p):
    return (p[1], p[0], -p[2])


def enu_to_ned(p):
    return (p[1], p[0], -p[2])


def rot_ned_frd(roll, pitch, yaw):
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return ((cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
            (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
            (-sp, cp * sr, cp * cr))


def rpy_of(r):
    """ZYX roll, pitch, yaw of a rotation matrix (pitch in [-pi/2, pi/2])."""
    roll = math.atan2(r[2][1], r[2][2])
    pitch = math.asin(max(-1.0, min(1.0, -r[2][0])))
    yaw = math.atan2(r[1][0], r[0][0])
    return roll, pitch, yaw


def quat_of(r):
    """Unit quaternion (x, y, z, w), w >= 0, of a rotation matrix (Shepperd)."""
    t = r[0][0] + r[1][1] + r[2][2]
    if t > 0.0:
        s = 2.0 * math.sqrt(1.0 + t)
        w, x, y, z = 0.25 * s, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s
    elif r[0][0] > r[1][1] and r[0][0] > r[2][2]:
        s = 2.0 * math.sqrt(1.0 + r[0][0] - r[1][1] - r[2][2])
        w, x, y, z = (r[2][1] - r[1][2]) / s, 0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s
    elif r[1][1] > r[2][2]:
        s = 2.0 * math.sqrt(1.0 + r[1][1] - r[0][0] - r[2][2])
        w, x, y, z = (r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s
    else:
        s = 2.0 * math.sqrt(1.0 + r[2][2] - r[0][0] - r[1][1])
        w, x, y, z = (r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s
    if w < 0.0:
        w, x, y, z = -w, -x, -y, -z
    return x, y, z, w


def rot_of_quat(x, y, z, w):
    n = math.sqrt(x * x + y * y + z * z + w * w)
    if not (n > 1e-9) or not math.isfinite(n):
        raise ValueError("orientation quaternion of zero or non-finite norm")
    x, y, z, w = x / n, y / n, z / n, w / n
    return ((1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
            (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
            (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)))


def ned_frd_to_enu_flu(position_ned, rpy, velocity_ned):
    """(position_enu, quaternion_xyzw of FLU in ENU, linear velocity in FLU body
    axes, as nav_msgs/Odometry's twist is in its child frame)."""
    r = rot_ned_frd(*rpy)
    q = quat_of(matmul(matmul(A, r), F))
    v_flu = matvec(F, matvec(transpose(r), velocity_ned))
    return ned_to_enu(position_ned), q, v_flu


def enu_flu_to_ned_frd(position_enu, quat_xyzw, velocity_flu=(0.0, 0.0, 0.0)):
    """(position_ned, (roll, pitch, yaw) of FRD in NED, velocity_ned)."""
    m = rot_of_quat(*quat_xyzw)
    r = matmul(matmul(A, m), F)  # A and F are their own inverses
    v_ned = matvec(r, matvec(F, velocity_flu))
    return enu_to_ned(position_enu), rpy_of(r), v_ned
