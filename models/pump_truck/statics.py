"""Mass properties, hand statics and cylinder sizing of the pump-truck boom (design calculation).

* Mass properties of a section: the steel box meshed by :func:`beam_mesh` (consistent mass, rotary inertia) and
  summed over its mass points, plus the delivery pipe as a slender line mass ``mu L`` along ``y_p = h/2 +
  offset`` (its own inertia ``mu L³/12`` about ``y`` and ``z``).
* Joint torques by virtual work, ``tau_k = ∂V/∂q_k`` with ``V = g Σ m_i y_i``: ``g Σ m_i (x_i − x_k)`` over the
  sections, pipes and hose outboard of joint ``k`` (centres of mass ``x_i``, joint ``x_k``; the hose's weight acts at
  the tip pin), plus each cylinder's housing and rod (steel, :func:`cylinder_masses`: 0.6–0.9 t for the 220–250 mm
  cylinders, 2.7 t in all, a third of the 7.5 t of sections, filled pipe and hose) and the levers and links of joints
  2… (slender steel bars moving with their joint, :func:`linkage_masses`: 0.2 t in all): the cylinders raise the
  gravity torque of the extended boom by 16 % at joint 1, 10 % at joint 2, 5 % at joint 3 and 3 % at joint 4 (the
  sizing table's ``cyl. share``).
* Cylinder force ``F = tau / (dl/dq)`` (extending force positive: the cylinder pushes), chamber pressure
  ``F / A_piston`` when pushing, ``−F / A_annulus`` when pulling.

References
----------
J. L. Meriam, L. G. Kraige, *Engineering Mechanics: Statics*, 8th ed., Wiley 2015, ch. 3 (equilibrium of
rigid bodies) and ch. 7 (virtual work). ISO 3320:2013 (cylinder bores and rod diameters).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from dataclasses import asdict, replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from flexlib.fe.beam import beam_mesh
from flexlib.fe.sections import box

from .kinematics import rot
from .parameters import CYLINDER_BORES, CYLINDER_RODS, PumpTruckParameters

__all__ = ["DESIGN_JOINT_SPEED", "LINK_PLATE", "cylinder_forces", "cylinder_masses", "dead_length", "design_cylinders",
           "design_sizing", "joint_torques", "linkage_masses", "mass_properties", "point_masses", "sizing",
           "worst_case"]

LINK_PLATE = 2 * 0.025 * 0.12  # lever/link cross-section at joint scale 3.0: two 25 x 120 mm plates [m2]


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


#: Cylinder construction (engineering estimates, see :func:`cylinder_masses`): tube steel E355 (EN 10305-1 honed
#: tube, yield 355 MPa) at Re/1.5 under the ISO 10100 proof pressure 1.5 × p_system; dead length (retracted pin-to-pin
#: length minus stroke: base, eye, piston, gland) ``DEAD_BORES`` bores + ``DEAD_EYES`` [m].
TUBE_YIELD = 355e6
PROOF_FACTOR = 1.5
DEAD_BORES = 1.5
DEAD_EYES = 0.2
#: Joint speed at full valve command [rad/s] for the flow column (``models.pump_truck.model.W_MAX``).
DESIGN_JOINT_SPEED = 0.03


def linkage_masses(record: PumpTruckParameters, k: int, link_plate: float = LINK_PLATE) -> tuple[float, float]:
    """Masses [kg] of lever and link of joint ``k`` (2 … N): steel bars of cross-section ``link_plate`` [m2] at joint
    scale 3, scaled by (scale/3)²."""
    fb = record.drive(k)
    scale = fb.r / 0.48
    area = link_plate * (scale / 3.0) ** 2
    return record.steel.rho * area * fb.r, record.steel.rho * area * fb.s


def dead_length(bore: float) -> float:
    """Smallest retracted length minus stroke of a cylinder of ``bore`` [m]: ``DEAD_BORES·bore + DEAD_EYES`` [m]."""
    return DEAD_BORES * bore + DEAD_EYES


def cylinder_masses(record: PumpTruckParameters, bore: float, rod: float, stroke: float) -> dict:
    """Housing and rod of a steel cylinder [kg], and where their centres sit [m] (``LineForceWithTwoMasses``).

    Tube wall ``t = PROOF_FACTOR p_system bore / (2 TUBE_YIELD / 1.5)`` (Barlow); housing = tube of length
    ``stroke + bore`` plus base and gland (one bore length of solid ``(bore + 2t)`` round), centre ``L_housing =
    (stroke + bore)/2 + DEAD_EYES/2`` from the housing pin; rod = bar ``rod`` × ``(stroke + bore)`` plus piston
    (half a bore of solid ``bore`` round), centre ``L_rod`` the same distance from the rod pin.
    """
    rho = record.steel.rho
    t = PROOF_FACTOR * record.p_system * bore / (2.0 * TUBE_YIELD / 1.5)
    length = stroke + bore
    outer = math.pi / 4 * (bore + 2 * t) ** 2
    m_housing = rho * ((outer - math.pi / 4 * bore**2) * length + outer * bore)
    m_rod = rho * (math.pi / 4 * rod**2 * length + math.pi / 4 * bore**2 * 0.5 * bore)
    reach = length / 2 + DEAD_EYES / 2
    return {"bore": bore, "rod": rod, "stroke": stroke, "wall": t, "m_housing": m_housing, "L_housing": reach,
            "m_rod": m_rod, "L_rod": reach}


def _masses(record: PumpTruckParameters, q: np.ndarray, cylinders, states=None) -> tuple[list, list]:
    """Joint positions and the lumped masses ``(m, x, rigid_to, own)``: ``x`` [m] in the turret frame, rigid with
    joints ``0 … rigid_to − 1``; ``own = (k, dx/dq_k)`` for a cylinder point that moves with its own joint ``k``
    through the drive's kinematics (``None`` for a point rigid on a section). ``states``: the drives' states at
    ``q`` if the caller has them (``record.drive(k + 1).state(q[k])``)."""
    J, theta, masses = [np.zeros(2)], [0.0], []
    for k, sec in enumerate(record.sections):
        th = theta[-1] + q[k]
        mp = mass_properties(record, k)
        masses.append((mp["m"], J[-1] + rot(th) @ mp["com"][:2], k + 1, None))
        st = states[k] if states is not None else record.drive(k + 1).state(float(q[k]))
        if cylinders is not None:
            cyl = cylinders[k]
            R = rot(theta[-1])
            H = np.array(record.drive(k + 1).H)
            e = (st.T - H) / st.length
            de = (st.T_rate - e * (e @ st.T_rate)) / st.length
            masses.append((cyl["m_housing"], J[-1] + R @ (H + cyl["L_housing"] * e), k,
                           (k, R @ (cyl["L_housing"] * de))))
            masses.append((cyl["m_rod"], J[-1] + R @ (st.T - cyl["L_rod"] * e), k,
                           (k, R @ (st.T_rate - cyl["L_rod"] * de))))
        if k > 0:  # the lever (P → T) and link (T → C) of a lever-and-link drive, slender bars moving with joint k
            R = rot(theta[-1])
            P = np.array(record.drive(k + 1).P)
            C_rate = np.array([-st.C[1], st.C[0]])  # the bracket turns with section k about the joint: ẑ × C
            m_lever, m_link = linkage_masses(record, k + 1)
            masses.append((m_lever, J[-1] + R @ ((P + st.T) / 2), k, (k, R @ (st.T_rate / 2))))
            masses.append((m_link, J[-1] + R @ ((st.T + st.C) / 2), k, (k, R @ ((st.T_rate + C_rate) / 2))))
        J.append(J[-1] + rot(th) @ np.array([sec.length, 0.0]))
        theta.append(th)
    masses.append((record.hose.mass, J[-1], len(record.sections), None))
    return J, masses


def point_masses(record: PumpTruckParameters, q: np.ndarray, cylinders=None) -> tuple[np.ndarray, np.ndarray,
                                                                                       np.ndarray]:
    """Joint positions ``J`` ((N + 1) × 2, joint 1 … tip) [m], and the boom's lumped masses [kg] with positions [m].

    Masses: each section (box + pipe) at its centre of mass, each cylinder's housing and rod (after its section's
    inboard joint; ``cylinders`` as :func:`design_cylinders`, default the record's own), then the hose at the tip.
    """
    q = np.asarray(q, dtype=float)
    J, masses = _masses(record, q, design_cylinders(record) if cylinders is None else cylinders)
    return np.array(J), np.array([m[0] for m in masses]), np.array([m[1] for m in masses])


def joint_torques(record: PumpTruckParameters, q: np.ndarray, cylinders=None, states=None) -> np.ndarray:
    """Gravity torque about each joint, ``tau_k = ∂V/∂q_k`` with ``V = g Σ m_i y_i`` [N.m].

    A point rigid with joint ``k`` contributes ``g m_i (x_i − x_k)``; a cylinder point of drive ``k`` contributes
    ``g m_i ∂y_i/∂q_k`` from the drive's kinematics (:attr:`LinkageState.T_rate`). ``cylinders``: as
    :func:`point_masses`; ``False`` leaves the cylinders out; ``states`` as :func:`_masses`. Positive: gravity tends
    to decrease ``q_k`` (fold the boom down); the drive must supply ``+tau_k``.
    """
    q = np.asarray(q, dtype=float)
    cyl = None if cylinders is False else (design_cylinders(record) if cylinders is None else cylinders)
    J, masses = _masses(record, q, cyl, states)
    tau = np.zeros(len(record.sections))
    for m, x, rigid_to, own in masses:
        for k in range(rigid_to):
            tau[k] += m * (x[0] - J[k][0])
        if own is not None:
            tau[own[0]] += m * own[1][1]
    return record.g * tau


def cylinder_forces(record: PumpTruckParameters, q: np.ndarray, cylinders=None,
                    states=None) -> tuple[np.ndarray, np.ndarray]:
    """Holding force of each cylinder ``F = tau / (dl/dq)`` [N] (positive pushes) and the lever arms [m/rad];
    ``states`` as :func:`_masses`."""
    if states is None:
        states = [record.drive(k + 1).state(float(q[k])) for k in range(len(record.sections))]
    tau = joint_torques(record, q, cylinders, states)
    arm = np.array([st.lever_arm for st in states])
    return tau / arm, arm


def _pressure(F: float, bore: float, rod: float) -> float:
    area = math.pi / 4 * bore**2 if F >= 0 else math.pi / 4 * (bore**2 - rod**2)
    return abs(F) / area


def worst_case(record: PumpTruckParameters) -> PumpTruckParameters:
    """The record the machine is designed for: the same machine with its pipe filled (the heaviest load)."""
    return record if record.pipe.filled else replace(record, pipe=replace(record.pipe, filled=True))


def design_sizing(record: PumpTruckParameters) -> tuple[dict, ...]:
    """The machine's cylinders, one :func:`sizing` row per joint, sized once on its worst case: every pipe state of
    the record gives the same rows (and the same objects: do not change them)."""
    return _design_sizing(worst_case(record))


@lru_cache(maxsize=16)
def _design_sizing(design: PumpTruckParameters) -> tuple[dict, ...]:
    return tuple(_stored_sizing(design))


def _stored_sizing(design: PumpTruckParameters) -> list[dict]:
    """:func:`sizing` of ``design``, kept on disk (``$FLEXLIB_CACHE_DIR/pump_truck/sizing-*.json``, written atomically)
    under a key of the record and of the sources it is computed from (this package and ``flexlib/fe``): every process
    that builds the machine would otherwise repeat the sweep (0.5 s). A file that cannot be read is made again; the
    values read back are the computed ones to the last bit (JSON keeps a float's shortest exact representation)."""
    from flexlib.compile.cache import cache_dir
    from flexlib.fe import beam

    h = hashlib.sha256(json.dumps(asdict(design), sort_keys=True, default=str).encode())
    for root in (Path(__file__).resolve().parent, Path(beam.__file__).resolve().parent):
        for path in sorted(root.glob("*.py")):
            h.update(path.name.encode())
            h.update(path.read_bytes())
    path = Path(os.environ.get("FLEXLIB_CACHE_DIR") or cache_dir()) / "pump_truck" / f"sizing-{h.hexdigest()[:24]}.json"
    try:
        return json.loads(path.read_text())["rows"]
    except (OSError, ValueError, KeyError, TypeError):
        pass  # absent or damaged: size again and replace it
    rows = [{k: v.item() if isinstance(v, np.generic) else v for k, v in row.items()} for row in sizing(design)]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{os.getpid()}.part")
        tmp.write_text(json.dumps({"rows": rows}))
        os.replace(tmp, path)
    except OSError:  # a read-only cache: the sizing is still right, only not kept
        pass
    return rows


@lru_cache(maxsize=64)
def design_cylinders(record: PumpTruckParameters) -> tuple[dict, ...]:
    """The cylinders of the machine, one per boom joint (:func:`cylinder_masses` of the :func:`design_sizing` bores),
    sized on its worst case whatever ``record.pipe.filled`` says."""
    return tuple(cylinder_masses(record, row["bore"], row["rod"], row["stroke"]) for row in design_sizing(record))


def _sweep(record: PumpTruckParameters, k: int, n_sweep: int) -> np.ndarray:
    drive = record.drive(k + 1)
    return np.unique(np.append(np.linspace(drive.q_min, drive.q_max, n_sweep), 0.0))


def _choose(forces: list[float], p_max: float) -> tuple[float, float, bool]:
    for bore in CYLINDER_BORES:
        rod = max(r for r in CYLINDER_RODS if r <= 0.7 * bore)
        if max(_pressure(F, bore, rod) for F in forces) <= p_max:
            return bore, rod, True
    return CYLINDER_BORES[-1], max(r for r in CYLINDER_RODS if r <= 0.7 * CYLINDER_BORES[-1]), False


def sizing(record: PumpTruckParameters, n_sweep: int = 91) -> list[dict]:
    """Size each cylinder from ISO 3320 bores and rods (rod the largest ≤ 0.7 bore), once per machine.

    The machine is sized on its worst case (:func:`worst_case`: pipe filled, whatever ``record.pipe.filled``): the
    bore is the smallest that holds every pose of the sweep (joint ``k`` over its range, all other joints extended:
    ``q = 0``; fully extended horizontal included) at ``p_hold_fraction * p_system``, with the weight of every
    cylinder (:func:`cylinder_masses`) in the load. The cylinders' masses depend on their bores, so the sizing
    repeats until no bore changes (two or three rounds).

    Returns
    -------
    list of dict
        Per joint: ``bore``, ``rod`` [m], ``l_min``, ``l_max``, ``stroke`` [m], ``dead`` (smallest dead length,
        :func:`dead_length`) [m] and ``fits`` (``l_min >= stroke + dead``), ``min_transmission_deg``,
        extended-horizontal ``lever_arm`` [m], ``F`` [N], ``p`` [Pa], the worst pose ``q_worst`` [rad] with its
        pressure ``p_worst`` [Pa], the largest holding pressure on each side over the sweep, ``p_worst_A`` (cap side,
        the cylinder pushes) and ``p_worst_B`` (rod side, it pulls) [Pa] (0 for a side that never holds), ``flow``
        [m3/s] at ``DESIGN_JOINT_SPEED`` and the largest lever arm, the cylinder's ``m_housing`` and ``m_rod``
        [kg], and ``cylinder_share``: the cylinders' share of the joint's gravity torque, extended horizontal [1].
    """
    design = worst_case(record)
    p_max = design.p_hold_fraction * design.p_system
    n = len(design.sections)
    sweeps = [_sweep(design, k, n_sweep) for k in range(n)]
    states = [[design.drive(k + 1).state(float(qk)) for qk in sweeps[k]] for k in range(n)]
    strokes = [max(s.length for s in st) - min(s.length for s in st) for st in states]
    chosen = [(CYLINDER_BORES[0], CYLINDER_RODS[0], True)] * n
    extended = [design.drive(k + 1).state(0.0) for k in range(n)]
    for _ in range(20):
        cyls = tuple(cylinder_masses(design, b, r, s) for (b, r, _), s in zip(chosen, strokes, strict=True))
        forces = []
        for k in range(n):
            fk = []
            for qk, stk in zip(sweeps[k], states[k], strict=True):
                q = np.zeros(n)
                q[k] = qk
                pose = [*extended[:k], stk, *extended[k + 1:]]
                fk.append(float(cylinder_forces(design, q, cyls, pose)[0][k]))
            forces.append(fk)
        new = [_choose(f, p_max) for f in forces]
        if new == chosen:
            break
        chosen = new
    tau_bare = joint_torques(design, np.zeros(n), False)
    tau_full = joint_torques(design, np.zeros(n), cyls)
    rows = []
    for k in range(n):
        bore, rod, ok = chosen[k]
        qs, fk, st = sweeps[k], forces[k], states[k]
        lengths = [s.length for s in st]
        pressures = [_pressure(F, bore, rod) for F in fk]
        i_ext, i_worst = int(np.argmin(np.abs(qs))), int(np.argmax(pressures))
        side = {c: max([p for F, p in zip(fk, pressures, strict=True) if (F >= 0) == (c == "A")], default=0.0)
                for c in ("A", "B")}
        arm_max = max(abs(s.lever_arm) for s in st)
        rows.append({"joint": k + 1, "bore": bore, "rod": rod, "l_min": min(lengths), "l_max": max(lengths),
                     "stroke": strokes[k], "dead": dead_length(bore),
                     "fits": min(lengths) >= strokes[k] + dead_length(bore),
                     "min_transmission_deg": min(min(s.transmission.values()) for s in st),
                     "lever_arm": st[i_ext].lever_arm, "F": fk[i_ext], "p": pressures[i_ext],
                     "q_worst": float(qs[i_worst]), "p_worst": pressures[i_worst], "p_worst_A": side["A"],
                     "p_worst_B": side["B"], "sized": ok, "flow": math.pi / 4 * bore**2 * arm_max * DESIGN_JOINT_SPEED,
                     "m_housing": cyls[k]["m_housing"], "m_rod": cyls[k]["m_rod"],
                     "cylinder_share": 1.0 - tau_bare[k] / tau_full[k]})
    return rows
