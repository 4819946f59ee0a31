"""Mass properties, hand statics and cylinder sizing of the pump-truck boom (design calculation).

* Mass properties of a section: the steel box meshed by :func:`beam_mesh` (consistent mass, rotary inertia) and
  summed over its mass points, plus the delivery pipe as a slender line mass ``mu L`` along ``y_p = h/2 +
  offset`` (its own inertia ``mu L³/12`` about ``y`` and ``z``).
* Joint torques: ``tau_k = g Σ m_i (x_i − x_k)`` over the sections, pipes and hose outboard of joint ``k``
  (centres of mass ``x_i``, joint ``x_k``; the hose's weight acts at the tip pin); rockers, links and cylinders
  are not counted (≈ 3 % of the boom mass).
* Cylinder force ``F = tau / (dl/dq)`` (extending force positive: the cylinder pushes), chamber pressure
  ``F / A_piston`` when pushing, ``−F / A_annulus`` when pulling.

References
----------
J. L. Meriam, L. G. Kraige, *Engineering Mechanics: Statics*, 8th ed., Wiley 2015, ch. 3 (equilibrium of
rigid bodies) and ch. 7 (virtual work). ISO 3320:2013 (cylinder bores and rod diameters).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from flexlib.fe.beam import beam_mesh
from flexlib.fe.sections import box

from .kinematics import rot
from .parameters import CYLINDER_BORES, CYLINDER_RODS, PumpTruckParameters

__all__ = ["cylinder_forces", "joint_torques", "mass_properties", "point_masses", "sizing"]


def mass_properties(record: PumpTruckParameters, k: int, pipe: bool = True, n_elements: int = 8) -> dict:
    """Mass [kg], centre of mass [m] (section frame: root at 0, ``x`` along it) and inertia about it [kg.m2].

    Section ``k`` is 0-based; ``pipe`` adds the delivery pipe in its current state (filled or empty). Computed
    once per record and section (the record is frozen); the arrays returned are copies.
    """
    m, com, inertia = _mass_properties(record, k, pipe, n_elements)
    return {"m": m, "com": com.copy(), "I": inertia.copy()}


@lru_cache(maxsize=256)
def _mass_properties(record: PumpTruckParameters, k: int, pipe: bool, n_elements: int) -> tuple:
    sec = record.sections[k]
    L = sec.length
    fe = beam_mesh([0, 0, 0], [L, 0, 0], n_elements, box(sec.b, sec.h, sec.t(record.steel.rho)),
                   E=record.steel.E, rho=record.steel.rho, rotary_inertia=True)
    mp = fe.mass_points
    m_i, x_i = mp.masses, mp.positions
    masses, coms, inertias = [float(m_i.sum())], [m_i @ x_i / m_i.sum()], []
    d = x_i - coms[0]
    inertias.append(mp.inertias.sum(axis=0) + np.einsum("p,pij->ij", m_i, (d * d).sum(1)[:, None, None]
                                                         * np.eye(3) - d[:, :, None] * d[:, None, :]))
    if pipe:
        mu = record.pipe.mass_per_m
        masses.append(mu * L)
        coms.append(np.array([L / 2, sec.h / 2 + record.pipe.offset, 0.0]))
        inertias.append(np.diag([0.0, mu * L**3 / 12, mu * L**3 / 12]))
    m = sum(masses)
    com = sum(mi * ci for mi, ci in zip(masses, coms)) / m
    inertia = np.zeros((3, 3))
    for mi, ci, Ii in zip(masses, coms, inertias):
        r = ci - com
        inertia += Ii + mi * (r @ r * np.eye(3) - np.outer(r, r))
    return float(m), com, inertia


def point_masses(record: PumpTruckParameters, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Joint positions ``J`` (6 × 2, joint 1 … tip) [m], and the boom's lumped masses [kg] with positions [m].

    Masses: each section (box + pipe) at its centre of mass, then the hose at the tip.
    """
    q = np.asarray(q, dtype=float)
    J, m, x = [np.zeros(2)], [], []
    theta = 0.0
    for k, sec in enumerate(record.sections):
        theta += q[k]
        mp = mass_properties(record, k)
        m.append(mp["m"])
        x.append(J[-1] + rot(theta) @ mp["com"][:2])
        J.append(J[-1] + rot(theta) @ np.array([sec.length, 0.0]))
    m.append(record.hose.mass)
    x.append(J[-1])
    return np.array(J), np.array(m), np.array(x)


def joint_torques(record: PumpTruckParameters, q: np.ndarray) -> np.ndarray:
    """Gravity torque about each joint of the masses outboard of it, ``tau_k = g Σ m_i (x_i − x_k)`` [N.m].

    Positive: gravity tends to decrease ``q_k`` (fold the boom down); the drive must supply ``+tau_k``.
    """
    J, m, x = point_masses(record, q)
    # masses 0..4 are sections 1..5 (outboard of joints 1..k+1), mass 5 the hose (outboard of all)
    return np.array([record.g * sum(m[i] * (x[i, 0] - J[k, 0]) for i in range(k, 6)) for k in range(5)])


def cylinder_forces(record: PumpTruckParameters, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Holding force of each cylinder ``F = tau / (dl/dq)`` [N] (positive pushes) and the lever arms [m/rad]."""
    tau = joint_torques(record, q)
    arm = np.array([record.drive(k + 1).state(float(q[k])).lever_arm for k in range(5)])
    return tau / arm, arm


def _pressure(F: float, bore: float, rod: float) -> float:
    area = math.pi / 4 * bore**2 if F >= 0 else math.pi / 4 * (bore**2 - rod**2)
    return abs(F) / area


def sizing(record: PumpTruckParameters, n_sweep: int = 91) -> list[dict]:
    """Size each cylinder from ISO 3320 bores and rods (rod the largest ≤ 0.7 bore).

    The bore is the smallest that holds every pose of the sweep (joint ``k`` over its range, all other joints
    extended: ``q = 0``; fully extended horizontal included) at ``p_hold_fraction * p_system``.

    Returns
    -------
    list of dict
        Per joint: ``bore``, ``rod`` [m], ``l_min``, ``l_max``, ``stroke`` [m], ``min_transmission_deg``,
        extended-horizontal ``lever_arm`` [m], ``F`` [N], ``p`` [Pa], the worst pose ``q_worst`` [rad] with
        its pressure ``p_worst`` [Pa], and the largest holding pressure on each side over the sweep, ``p_worst_A``
        (cap side, the cylinder pushes) and ``p_worst_B`` (rod side, it pulls) [Pa]; 0 for a side that never holds.
    """
    p_max = record.p_hold_fraction * record.p_system
    rows = []
    for k in range(5):
        drive = record.drive(k + 1)
        qs = np.unique(np.append(np.linspace(drive.q_min, drive.q_max, n_sweep), 0.0))
        forces, lengths, trans = [], [], []
        for qk in qs:
            q = np.zeros(5)
            q[k] = qk
            F, _ = cylinder_forces(record, q)
            st = drive.state(float(qk))
            forces.append(F[k])
            lengths.append(st.length)
            trans.append(min(st.transmission.values()))
        chosen = None
        for bore in CYLINDER_BORES:
            rod = max(r for r in CYLINDER_RODS if r <= 0.7 * bore)
            if max(_pressure(F, bore, rod) for F in forces) <= p_max:
                chosen = (bore, rod)
                break
        if chosen is None:
            bore, rod = CYLINDER_BORES[-1], max(r for r in CYLINDER_RODS if r <= 0.7 * CYLINDER_BORES[-1])
        else:
            bore, rod = chosen
        pressures = [_pressure(F, bore, rod) for F in forces]
        i_ext, i_worst = int(np.argmin(np.abs(qs))), int(np.argmax(pressures))
        side = {c: max([p for F, p in zip(forces, pressures, strict=True) if (F >= 0) == (c == "A")], default=0.0)
                for c in ("A", "B")}
        rows.append({"joint": k + 1, "bore": bore, "rod": rod, "l_min": min(lengths), "l_max": max(lengths),
                     "stroke": max(lengths) - min(lengths), "min_transmission_deg": min(trans),
                     "lever_arm": drive.state(0.0).lever_arm, "F": forces[i_ext], "p": pressures[i_ext],
                     "q_worst": float(qs[i_worst]), "p_worst": pressures[i_worst], "p_worst_A": side["A"],
                     "p_worst_B": side["B"], "sized": chosen is not None})
    return rows
