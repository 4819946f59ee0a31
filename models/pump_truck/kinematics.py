"""Planar kinematics of the pump-truck boom's cylinder drives (design calculation, pure numpy).

Each joint ``k`` is described in its own joint frame: origin at the joint pin, ``x`` along section ``k−1``
(the section carrying the joint at its tip; the turret for joint 1), ``y`` upwards when that section is
horizontal. Section ``k`` is rotated by the relative joint angle ``q`` [rad] about ``z``; a point ``c`` fixed in
section ``k`` sits at ``R(q) c``.

* **Direct drive** (joint 1): the cylinder runs from the housing pin ``H`` (on the turret) to the bracket
  ``C`` on section 1: ``l(q) = |R(q) c − H|``, ``dl/dq = (R(q) c − H) · (ẑ × R(q) c) / l``.
* **Four-bar lever-and-link** (joints 2 … N, as on truck-mounted concrete pumps): a lever (rocker) of length
  ``r`` pivots at ``P`` on section ``k−1``; a link of length ``s`` joins the lever tip ``T`` to the bracket
  ``C`` on section ``k``; the cylinder pushes the lever tip from the housing ``H`` on section ``k−1``.
  ``T`` is the intersection of the circles ``|T − P| = r`` and ``|T − C(q)| = s`` on the branch ``sigma``
  (``+1``: left of ``P → C``). Velocity analysis of the two constraints,
  ``(T − P)·Ṫ = 0`` and ``(T − C)·(Ṫ − Ċ) = 0`` with ``Ċ = ẑ × C``, gives ``dT/dq`` in closed form and
  ``dl/dq = (T − H)·dT/dq / l``.

Transmission angles are measured as the deviation from collinearity (0° = dead centre, 90° = best) at the
three pins that carry the force: lever–link at ``T`` (classical four-bar transmission angle), link–arm
``O C`` at ``C`` (how the link turns section ``k``), cylinder–lever at ``T`` (how the cylinder turns the lever).

References
----------
R. L. Norton, *Design of Machinery*, 5th ed., McGraw-Hill 2012, ch. 4 (position analysis of the four-bar,
circle intersection) and §3.3 (transmission angle, keep above about 40° in fast machines, ~20° acceptable for
slow, statically loaded linkages). Putzmeister / Schwing boom drawings (lever-and-link joints 2 … N).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LinkageState", "direct_state", "fourbar_length", "fourbar_state", "rot", "transmission_deg"]


def rot(q: float) -> np.ndarray:
    """Rotation matrix about ``z`` by ``q`` [rad]."""
    c, s = np.cos(q), np.sin(q)
    return np.array([[c, -s], [s, c]])


def _perp(v: np.ndarray) -> np.ndarray:
    """``ẑ × v`` for a planar vector."""
    return np.array([-v[1], v[0]])


def transmission_deg(u: np.ndarray, v: np.ndarray) -> float:
    """Deviation of two directions from collinearity [deg], in [0, 90] (0 = dead centre)."""
    c = abs(float(np.dot(u, v))) / (np.linalg.norm(u) * np.linalg.norm(v))
    return float(np.degrees(np.arccos(min(1.0, c))))


@dataclass(frozen=True)
class LinkageState:
    """Pose of a joint's drive at one joint angle (all points in the joint frame [m]).

    Attributes
    ----------
    length : float
        Cylinder pin-to-pin length [m].
    lever_arm : float
        ``dl/dq`` [m/rad]: the cylinder's effective lever arm about the joint.
    C, T : ndarray
        Bracket on section ``k`` and lever tip (``T = C`` for a direct drive) [m].
    transmission : dict
        Transmission angles [deg] (see the module docstring).
    T_rate : ndarray or None
        ``dT/dq`` [m/rad]: velocity of the cylinder's rod pin per unit joint rate (``ẑ × C`` for a direct drive).
    """

    length: float
    lever_arm: float
    C: np.ndarray
    T: np.ndarray
    transmission: dict
    T_rate: np.ndarray | None = None


def direct_state(q: float, H: np.ndarray, c: np.ndarray) -> LinkageState:
    """Direct cylinder from ``H`` (fixed) to ``R(q) c``: length, lever arm, transmission angle."""
    C = rot(q) @ np.asarray(c, float)
    d = C - np.asarray(H, float)
    length = float(np.linalg.norm(d))
    return LinkageState(length, float(d @ _perp(C)) / length, C, C,
                        {"cylinder-arm": transmission_deg(d, C)}, _perp(C))


def _fourbar_points(q: float, P: np.ndarray, c: np.ndarray, r: float, s: float, sigma: int
                    ) -> tuple[np.ndarray, np.ndarray]:
    """The bracket ``C`` and the lever tip ``T`` of the four-bar at ``q`` (circle intersection on branch ``sigma``)."""
    C = rot(q) @ np.asarray(c, float)
    d = C - P
    dist = float(np.linalg.norm(d))
    x = (r**2 - s**2 + dist**2) / (2.0 * dist)
    h2 = r**2 - x**2
    if not (abs(r - s) < dist < r + s) or h2 <= 0.0:
        raise ValueError(f"four-bar cannot close at q = {np.degrees(q):.2f} deg: |C - P| = {dist:.4f} m, "
                         f"lever r = {r:.4f} m, link s = {s:.4f} m")
    ex = d / dist
    return C, P + x * ex + sigma * np.sqrt(h2) * _perp(ex)


def fourbar_length(q: float, P: np.ndarray, H: np.ndarray, c: np.ndarray, r: float, s: float, sigma: int) -> float:
    """The cylinder's pin-to-pin length [m] alone at ``q`` [rad] (as :func:`fourbar_state`'s, to the last bit)."""
    P = np.asarray(P, float)
    _, T = _fourbar_points(q, P, c, r, s, sigma)
    return float(np.linalg.norm(T - np.asarray(H, float)))


def fourbar_state(q: float, P: np.ndarray, H: np.ndarray, c: np.ndarray, r: float, s: float,
                  sigma: int) -> LinkageState:
    """Lever-and-link drive at joint angle ``q`` [rad] (see the module docstring).

    Raises
    ------
    ValueError
        If the loop cannot close at ``q`` (``|C − P|`` outside ``[|r − s|, r + s]``).
    """
    P, H = np.asarray(P, float), np.asarray(H, float)
    C, T = _fourbar_points(q, P, c, r, s, sigma)
    a, b = T - P, T - C
    # (T − P)·Ṫ = 0 ; (T − C)·Ṫ = (T − C)·Ċ with Ċ = ẑ × C
    Tdot = np.linalg.solve(np.array([a, b]), np.array([0.0, b @ _perp(C)]))
    e = T - H
    length = float(np.linalg.norm(e))
    tr = {"lever-link": transmission_deg(a, b), "link-arm": transmission_deg(b, C),
          "cylinder-lever": transmission_deg(e, a)}
    return LinkageState(length, float(e @ Tdot) / length, C, T, tr, Tdot)
