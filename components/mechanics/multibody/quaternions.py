"""Unit quaternions for frame orientations (MSL ``MultiBody.Frames.Quaternions``), and the floating frame.

A quaternion ``Q = (e·sin(φ/2), cos(φ/2))`` describes the rotation by φ about the unit axis ``e``; it has
no singular orientation, and its norm constraint ``|Q| = 1`` is kept exactly by index reduction (the
constraint stays in the system, so there is no drift). Shared by every component that owns the
orientation of a free-floating frame: :class:`~.body.Body` (the root of an orientation tree without a
World or Fixed), :class:`~.free_motion.FreeMotion` (relative orientation), and the flexible body's
reference frame.

References
----------
Modelica Standard Library 4.0, ``MultiBody.Frames.Quaternions`` (``from_T``, ``to_T``,
``angularVelocity2``); Shabana, *Dynamics of Multibody Systems*, 4th ed., §7.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import der, eq

__all__ = ["floating_frame_equations", "quaternion_from_T", "quaternion_to_T", "quaternion_w"]


def quaternion_from_T(T: np.ndarray) -> np.ndarray:
    """Unit quaternion ``(e·sin(φ/2), cos(φ/2))`` of a numeric transformation matrix (MSL ``from_T``)."""
    T = np.asarray(T, dtype=float)
    c1, c2, c3, c4 = 1 + T[0, 0] - T[1, 1] - T[2, 2], 1 + T[1, 1] - T[0, 0] - T[2, 2], \
        1 + T[2, 2] - T[0, 0] - T[1, 1], 1 + T[0, 0] + T[1, 1] + T[2, 2]
    k = int(np.argmax([c1, c2, c3, c4]))
    if k == 3:
        q4 = np.sqrt(c4) / 2
        q = [(T[1, 2] - T[2, 1]) / (4 * q4), (T[2, 0] - T[0, 2]) / (4 * q4), (T[0, 1] - T[1, 0]) / (4 * q4), q4]
    elif k == 0:
        q1 = np.sqrt(c1) / 2
        q = [q1, (T[0, 1] + T[1, 0]) / (4 * q1), (T[0, 2] + T[2, 0]) / (4 * q1), (T[1, 2] - T[2, 1]) / (4 * q1)]
    elif k == 1:
        q2 = np.sqrt(c2) / 2
        q = [(T[0, 1] + T[1, 0]) / (4 * q2), q2, (T[1, 2] + T[2, 1]) / (4 * q2), (T[2, 0] - T[0, 2]) / (4 * q2)]
    else:
        q3 = np.sqrt(c3) / 2
        q = [(T[0, 2] + T[2, 0]) / (4 * q3), (T[1, 2] + T[2, 1]) / (4 * q3), q3, (T[0, 1] - T[1, 0]) / (4 * q3)]
    return np.array(q)


def quaternion_to_T(Q: Any) -> ca.SX:
    """Transformation matrix world → frame of the unit quaternion ``Q = (e·sin(φ/2), cos(φ/2))``."""
    q1, q2, q3, q4 = Q[0], Q[1], Q[2], Q[3]
    return ca.vertcat(
        ca.horzcat(2 * (q1**2 + q4**2) - 1, 2 * (q1 * q2 + q3 * q4), 2 * (q1 * q3 - q2 * q4)),
        ca.horzcat(2 * (q2 * q1 - q3 * q4), 2 * (q2**2 + q4**2) - 1, 2 * (q2 * q3 + q1 * q4)),
        ca.horzcat(2 * (q3 * q1 + q2 * q4), 2 * (q3 * q2 - q1 * q4), 2 * (q3**2 + q4**2) - 1),
    )


def quaternion_w(Q: Any, dQ: Any) -> ca.SX:
    """Angular velocity [rad/s] resolved in the frame, from a quaternion and its derivative (MSL angularVelocity2)."""
    q1, q2, q3, q4 = Q[0], Q[1], Q[2], Q[3]
    M = ca.vertcat(ca.horzcat(q4, q3, -q2, -q1), ca.horzcat(-q3, q4, q1, -q2), ca.horzcat(q2, -q1, q4, -q3))
    return 2 * ca.mtimes(M, dQ)


def floating_frame_equations(frame: Any, Q: Any) -> list:
    """Equations of a frame whose orientation is owned by the quaternion ``Q`` (the root of an orientation tree).

    ``T = T(Q)``, ``w = 2·W(Q)·der(Q)`` (resolved in the frame) and ``Q·Q = 1``: the orientation matrix is
    exactly orthogonal for every ``Q`` satisfying the norm constraint, so the engine's frame rule
    ``der(T) = −[w×]·T`` holds exactly.

    Parameters
    ----------
    frame : Frame
        The frame connector whose ``T`` [1] and ``w`` [rad/s] are defined.
    Q : array_like (4,)
        The quaternion variable [1] of the owning component (state_select ``prefer``).
    """
    return [eq(frame.T, quaternion_to_T(Q)), eq(frame.w, quaternion_w(Q, der(Q))),
            eq(ca.dot(Q, Q), 1.0, label="quaternion norm")]
