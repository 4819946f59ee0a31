"""The simulation model's own geometry, masses and statics: pin positions and masses in a pose, lever
and link masses, the sections as built, holding forces by virtual work, and the cylinder-length references.

The design statics of the record (:mod:`models.pump_truck.statics`) neglect levers and links; these functions work
on the model as :class:`~models.pump_truck.model.PumpTruck` builds it, so its static start and its controllers'
references agree with its own geometry.

References
----------
J. L. Meriam, L. G. Kraige, *Engineering Mechanics: Statics*, ch. 7 (virtual work).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import lru_cache
from typing import Any

import numpy as np

from .kinematics import rot
from .parameters import PumpTruckParameters
from .statics import LINK_PLATE, linkage_masses
from .statics import mass_properties as _mass_properties
from .statics import sizing as _sizing

__all__ = ["LINK_PLATE", "holding_forces", "length_reference", "linkage_masses", "mass_properties",
           "section_mass_properties", "sizing"]



@lru_cache(maxsize=64)
def mass_properties(record: PumpTruckParameters, k: int) -> dict:
    """:func:`models.pump_truck.statics.mass_properties` of section ``k`` with pipe, memoised per record (the beam
    mesh behind it costs ~50 ms; the records are frozen)."""
    return _mass_properties(record, k)


@lru_cache(maxsize=16)
def sizing(record: PumpTruckParameters) -> list[dict]:
    """:func:`models.pump_truck.statics.sizing`, memoised per record."""
    return _sizing(record)


def boom_pose(record: PumpTruckParameters, q: np.ndarray, link_plate: float = LINK_PLATE) -> dict[str, Any]:
    """Planar pose (turret frame, joint 1 at the origin) of every pin and mass of the boom at joint angles ``q``."""
    J, th = [np.zeros(2)], [0.0]
    pins: dict[str, np.ndarray] = {}
    masses: list[tuple[float, np.ndarray]] = []
    for k, sec in enumerate(record.sections):
        n = k + 1
        theta = th[-1] + q[k]
        R_prev, R = rot(th[-1]), rot(theta)
        mp = mass_properties(record, k)
        masses.append((mp["m"], J[-1] + R @ mp["com"][:2]))
        drive = record.drive(n)
        st = drive.state(float(q[k]))
        pins[f"H{n}"] = J[-1] + R_prev @ np.array(drive.H)
        pins[f"C{n}"] = J[-1] + R_prev @ st.C
        pins[f"T{n}"] = J[-1] + R_prev @ st.T
        if n > 1:
            pins[f"P{n}"] = J[-1] + R_prev @ np.array(drive.P)
            m_lever, m_link = linkage_masses(record, n, link_plate)
            masses.append((m_lever, 0.5 * (pins[f"P{n}"] + pins[f"T{n}"])))
            masses.append((m_link, 0.5 * (pins[f"T{n}"] + pins[f"C{n}"])))
        J.append(J[-1] + R @ np.array([sec.length, 0.0]))
        th.append(theta)
    masses.append((record.hose.mass, J[-1]))
    return {"J": J, "theta": th[1:], "pins": pins, "masses": masses}


def holding_forces(record: PumpTruckParameters, q: Sequence[float],
                   link_plate: float = LINK_PLATE) -> tuple[np.ndarray, np.ndarray]:
    """Cylinder forces [N] (positive pushes) holding the boom at rest at ``q`` [rad], and lengths [m].

    Virtual work on this model's geometry, ``F_k ∂l_k/∂q_k = ∂V/∂q_k`` (``V`` the potential energy of sections,
    pipe, hose, levers and links; cylinder ``k`` spans joint ``k`` only), by central differences (step 1e-6 rad,
    relative error ~1e-9).
    """
    q = np.asarray(q, dtype=float)

    def V(qq: np.ndarray) -> float:
        return record.g * sum(m * x[1] for m, x in boom_pose(record, qq, link_plate)["masses"])

    n = len(record.sections)
    F, lengths = np.zeros(n), np.zeros(n)
    h = 1e-6
    for k in range(n):
        dq = np.zeros(n)
        dq[k] = h
        dV = (V(q + dq) - V(q - dq)) / (2 * h)
        st = record.drive(k + 1).state(float(q[k]))
        F[k] = dV / st.lever_arm
        lengths[k] = st.length
    return F, lengths


def section_mass_properties(record: PumpTruckParameters, k: int) -> dict:
    """Mass [kg], centre of mass [m] (section frame) and inertia at it [kg.m2] of section ``k`` (0-based) as built:
    box and pipe (:func:`~models.pump_truck.statics.mass_properties`), plus the end hose as a point mass at the tip
    pin for the last section."""
    mp = mass_properties(record, k)
    if k < len(record.sections) - 1:
        return mp
    m_h, x_h = record.hose.mass, np.array([record.sections[k].length, 0.0, 0.0])
    m = mp["m"] + m_h
    com = (mp["m"] * mp["com"] + m_h * x_h) / m
    inertia = mp["I"].copy()
    for mi, ci in ((mp["m"], mp["com"]), (m_h, x_h)):
        d = ci - com
        inertia += mi * (d @ d * np.eye(3) - np.outer(d, d))
    return {"m": m, "com": com, "I": inertia}


def length_reference(record: PumpTruckParameters, n: int, t: np.ndarray, q_deg: np.ndarray | None,
                     q0: float, step_deg: float = 10.0) -> tuple[np.ndarray, np.ndarray]:
    """Pin-to-pin length reference [m] of cylinder ``n`` (1 … N) for the joint-angle table ``(t, q_deg)``.

    The angle table is linear between its knots; the length is not, so each interval is resampled at most
    ``step_deg`` [deg] apart and mapped through the record's closed-form kinematics
    (:meth:`~models.pump_truck.parameters.PumpTruckParameters.drive`). ``q_deg=None``: the joint holds ``q0``
    [rad]. Returns the times [s] and lengths [m] of a ``TimeTable``.
    """
    drive = record.drive(n)
    if q_deg is None:
        return np.zeros(1), np.array([drive.state(q0).length])
    t, q = np.asarray(t, dtype=float), np.radians(np.asarray(q_deg, dtype=float))
    ts, qs = [t[:1]], [q[:1]]
    for i in range(len(t) - 1):
        m = max(1, math.ceil(abs(math.degrees(q[i + 1] - q[i])) / step_deg))
        ts.append(np.linspace(t[i], t[i + 1], m + 1)[1:])
        qs.append(np.linspace(q[i], q[i + 1], m + 1)[1:])
    tt, qq = np.concatenate(ts), np.concatenate(qs)
    return tt, np.array([drive.state(float(v)).length for v in qq])
