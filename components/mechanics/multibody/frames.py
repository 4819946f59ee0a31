"""Orientation algebra for 3D frames (after MSL ``Modelica.Mechanics.MultiBody.Frames``).

An orientation is the pair ``(T, w)``: ``T`` transforms a vector resolved in the world frame
into the same vector resolved in the frame (``v_frame = T @ v_world``), ``w`` is the angular
velocity of the frame with respect to the world, resolved in the frame. All functions work on
CasADi SX and on NumPy arrays.
"""

from __future__ import annotations

from typing import Any

import casadi as ca

__all__ = ["absolute_rotation", "equality_constraint", "planar_rotation", "resolve1", "resolve2", "skew"]


def skew(v: Any) -> ca.SX:
    """Skew-symmetric matrix with ``skew(a) @ b = a × b``."""
    return ca.vertcat(ca.horzcat(0, -v[2], v[1]), ca.horzcat(v[2], 0, -v[0]), ca.horzcat(-v[1], v[0], 0))


def resolve1(T: Any, v2: Any) -> ca.SX:
    """A vector resolved in the frame (``v2``) resolved in the world frame: ``Tᵀ v2``."""
    return ca.mtimes(T.T, v2)


def resolve2(T: Any, v1: Any) -> ca.SX:
    """A vector resolved in the world frame (``v1``) resolved in the frame: ``T v1``."""
    return ca.mtimes(T, v1)


def planar_rotation(e: Any, angle: Any) -> ca.SX:
    """Transformation matrix of a rotation by ``angle`` about the unit axis ``e`` (fixed in both frames).

    ``T = e eᵀ + (I − e eᵀ) cos(angle) − skew(e) sin(angle)`` (MSL ``Frames.planarRotation``).
    """
    e = ca.SX(e) if not isinstance(e, ca.SX) else e
    eet = ca.mtimes(e, e.T)
    return eet + (ca.SX.eye(3) - eet) * ca.cos(angle) - skew(e) * ca.sin(angle)


def absolute_rotation(T1: Any, T_rel: Any) -> ca.SX:
    """Orientation of frame 2 from frame 1 and the relative rotation 1→2: ``T2 = T_rel T1``."""
    return ca.mtimes(T_rel, T1)


def equality_constraint(T1: Any, T2: Any) -> ca.SX:
    """Three residues that vanish when ``T1`` and ``T2`` are the same orientation.

    With ``T_rel = T2 T1ᵀ`` (identity when equal), the residue is the rotation vector's sine part,
    ``vee((T_rel − T_relᵀ)/2)``: its Jacobian with respect to a small relative rotation is the
    identity, so it closes kinematic loops with three independent equations (MSL
    ``Frames.Orientation.equalityConstraint`` serves the same purpose).
    """
    T_rel = ca.mtimes(T2, T1.T)
    return 0.5 * ca.vertcat(T_rel[1, 2] - T_rel[2, 1], T_rel[2, 0] - T_rel[0, 2], T_rel[0, 1] - T_rel[1, 0])
