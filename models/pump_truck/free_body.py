"""Free-body statics of a pump-truck boom on its design record: the equilibrium of every body, solved as one linear
system — the boom's static loads without building a model.

Written from scratch as **free-body equilibrium** (not virtual work as :mod:`models.pump_truck.statics`, and
nothing of the engine's multibody formulation): only mass data are read from the design statics (the section masses
:func:`~models.pump_truck.statics.mass_properties`, the cylinders :func:`~models.pump_truck.statics.design_cylinders`
/ :func:`~models.pump_truck.statics.cylinder_masses` and :func:`~models.pump_truck.statics.linkage_masses`); the pin
positions come from the record's drive kinematics, ``drive.state(q).C`` and ``.T``, nothing else of it. It has two uses:
the static loads on each section that select the flexible sections' modes
(:func:`~models.pump_truck.flexible.mpf_modes`; equal to the rigid boom's held at rest in flexlib within 4e-14 of the
largest load, tested to 1e-9), and the tests' independent reference for the machines' cylinder and hinge forces (issue
28: "independent hand statics, including cylinder housing and rod masses: cylinder forces and hinge forces within 1 %").

Bodies (planar, the boom's vertical plane, turret frame: ``x`` along the horizontal boom, ``y`` up, joint 1 at the
origin; the turret is the ground), for each joint ``n = 1 … N``:

* section ``n`` (steel box + delivery pipe at their common centre of mass; the end hose as a point mass at the tip pin
  of section ``N``), pinned to section ``n − 1`` (the turret for ``n = 1``) at joint ``n``;
* cylinder ``n`` as two bodies: the **housing** (pinned at ``H`` on section ``n − 1`` / the turret; weight at
  ``H + L_housing e``) and the **rod** (pinned at its rod-end pin ``T``; weight at ``T − L_rod e``), ``e`` the unit
  vector from ``H`` to ``T``, masses and centres as :func:`~models.pump_truck.statics.cylinder_masses` puts them.
  Between them a prismatic joint: a transverse force ``N`` and a moment ``M`` (the guide of piston and gland) and the
  hydraulic force ``F`` along ``e`` (push positive: ``+F e`` on the rod, ``−F e`` on the housing). ``F`` is what the
  chambers supply, ``p_A A_A − p_B A_B`` at rest without friction;
* for ``n ≥ 2`` the **lever** (slender bar ``P → T``, pivoted at ``P`` on section ``n − 1``, weight at its middle) and
  the **link** (slender bar ``T → C``, pinned to the lever at ``T`` and to section ``n`` at ``C``, weight at its
  middle); the rod's pin ``T`` is on the lever. For ``n = 1`` the rod is pinned directly to section 1 at ``C``.

Unknowns: every pin force (two components), ``N``, ``M`` and ``F`` of each cylinder; equations: ``ΣF = 0`` and
``ΣM = 0`` of every body (moments about the body's first pin) — a square linear system (``15 N − 6`` unknowns),
solved once (:func:`numpy.linalg.solve`). The weights ``m g`` act at the centres of mass, ``g = record.g``.

References
----------
J. L. Meriam, L. G. Kraige, *Engineering Mechanics: Statics*, 8th ed., Wiley 2015, ch. 3 (equilibrium of rigid
bodies) and ch. 6 (frames and machines: members pinned together, two-force members).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .parameters import PumpTruckParameters
from .statics import design_cylinders, linkage_masses, mass_properties

__all__ = ["free_body_statics", "total_weight"]


def _rot(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def _perp(v: np.ndarray) -> np.ndarray:
    return np.array([-v[1], v[0]])


class _System:
    """The equilibrium equations ``A x = b``: three rows per body (``ΣFx``, ``ΣFy``, ``ΣMz`` about the body's
    reference point), one column per unknown scalar."""

    def __init__(self) -> None:
        self.bodies: dict[str, tuple[int, np.ndarray]] = {}
        self.unknowns: dict[str, int] = {}
        self.rows: list[tuple[int, int, float]] = []
        self.rhs: dict[int, float] = {}

    def body(self, name: str, ref: np.ndarray) -> None:
        self.bodies[name] = (3 * len(self.bodies), np.asarray(ref, float))

    def unknown(self, name: str, size: int) -> int:
        col = len(self.unknowns)
        for i in range(size):
            self.unknowns[f"{name}.{i}" if size > 1 else name] = col + i
        return col

    def _moment_arm(self, body: str, point: np.ndarray) -> np.ndarray:
        return np.asarray(point, float) - self.bodies[body][1]

    def force(self, body: str | None, col: int, point: np.ndarray, sign: float = 1.0) -> None:
        """Unknown force vector (columns ``col``, ``col + 1``) acting on ``body`` at ``point`` (times ``sign``)."""
        if body is None:  # the ground (turret): not a body of the system
            return
        r0, d = self.bodies[body][0], self._moment_arm(body, point)
        self.rows += [(r0, col, sign), (r0 + 1, col + 1, sign), (r0 + 2, col, -sign * d[1]),
                      (r0 + 2, col + 1, sign * d[0])]

    def directed(self, body: str, col: int, point: np.ndarray, direction: np.ndarray, sign: float = 1.0) -> None:
        """Unknown scalar ``x[col]`` times the unit ``direction`` acting on ``body`` at ``point``."""
        r0, d = self.bodies[body][0], self._moment_arm(body, point)
        self.rows += [(r0, col, sign * direction[0]), (r0 + 1, col, sign * direction[1]),
                      (r0 + 2, col, sign * (d[0] * direction[1] - d[1] * direction[0]))]

    def moment(self, body: str, col: int, sign: float = 1.0) -> None:
        self.rows.append((self.bodies[body][0] + 2, col, sign))

    def weight(self, body: str, m: float, point: np.ndarray, g: float) -> None:
        """Known load ``(0, −m g)`` at ``point``: moved to the right-hand side."""
        r0, d = self.bodies[body][0], self._moment_arm(body, point)
        self.rhs[r0 + 1] = self.rhs.get(r0 + 1, 0.0) + m * g
        self.rhs[r0 + 2] = self.rhs.get(r0 + 2, 0.0) + m * g * d[0]

    def solve(self) -> tuple[np.ndarray, float]:
        n_rows, n_cols = 3 * len(self.bodies), len(self.unknowns)
        if n_rows != n_cols:
            raise ValueError(f"free_body_statics: the free-body system is not square: {n_rows} equations, "
                             f"{n_cols} unknowns")
        A, b = np.zeros((n_rows, n_cols)), np.zeros(n_rows)
        for r, c, v in self.rows:
            A[r, c] += v
        for r, v in self.rhs.items():
            b[r] = v
        x = np.linalg.solve(A, b)
        return x, float(np.linalg.norm(A @ x - b) / max(np.linalg.norm(b), 1.0))


def _equilibrium(record: PumpTruckParameters, q: np.ndarray, cyls: Sequence[dict]
                 ) -> tuple[_System, dict[str, int], list[dict], list[np.ndarray]]:
    """The free-body equations of the boom at joint angles ``q`` [rad] (module docstring): the system, the column
    of each unknown by name, each joint's pins (world) and the joint positions [m]."""
    g, n_sec = record.g, len(record.sections)
    sysm = _System()
    J, theta = [np.zeros(2)], [0.0]
    cols: dict[str, int] = {}
    geo = []
    for k, sec in enumerate(record.sections):  # bodies first (a force may act on a body of the next joint)
        n, drive = k + 1, record.drive(k + 1)
        R_prev, th = _rot(theta[-1]), theta[-1] + q[k]
        st = drive.state(float(q[k]))
        H, C, T = (J[-1] + R_prev @ np.asarray(v, float) for v in (drive.H, st.C, st.T))
        P = J[-1] + R_prev @ np.asarray(drive.P, float) if n > 1 else None
        geo.append({"J": J[-1], "H": H, "C": C, "T": T, "P": P, "theta": th})
        sysm.body(f"S{n}", J[-1])
        sysm.body(f"housing{n}", H)
        sysm.body(f"rod{n}", T)
        if n > 1:
            sysm.body(f"lever{n}", P)
            sysm.body(f"link{n}", C)
        J.append(J[-1] + _rot(th) @ np.array([sec.length, 0.0]))
        theta.append(th)
    for k in range(n_sec):
        n, gk, cyl = k + 1, geo[k], cyls[k]
        carrier = None if n == 1 else f"S{n - 1}"
        H, C, T, P = gk["H"], gk["C"], gk["T"], gk["P"]
        length = float(np.linalg.norm(T - H))
        e = (T - H) / length
        # section n: box + pipe, the hose at the tip of the last one
        mp = mass_properties(record, k)
        sysm.weight(f"S{n}", mp["m"], gk["J"] + _rot(gk["theta"]) @ mp["com"][:2], g)
        if n == n_sec:
            sysm.weight(f"S{n}", record.hose.mass, J[-1], g)
        # hinge n: section n-1 (turret) on section n
        cols[f"hinge{n}"] = c = sysm.unknown(f"hinge{n}", 2)
        sysm.force(f"S{n}", c, gk["J"])
        sysm.force(carrier, c, gk["J"], -1.0)
        # cylinder n: housing on its carrier at H, rod on its rod-end body at T, guide N, M and hydraulic F
        sysm.weight(f"housing{n}", cyl["m_housing"], H + cyl["L_housing"] * e, g)
        sysm.weight(f"rod{n}", cyl["m_rod"], T - cyl["L_rod"] * e, g)
        cols[f"H{n}"] = c = sysm.unknown(f"H{n}", 2)
        sysm.force(f"housing{n}", c, H)
        sysm.force(carrier, c, H, -1.0)
        rod_end = f"S{n}" if n == 1 else f"lever{n}"
        cols[f"R{n}"] = c = sysm.unknown(f"R{n}", 2)
        sysm.force(f"rod{n}", c, T)
        sysm.force(rod_end, c, T, -1.0)
        for name, direction in (("F", e), ("N", _perp(e))):
            cols[f"{name}{n}"] = c = sysm.unknown(f"{name}{n}", 1)
            sysm.directed(f"rod{n}", c, T, direction)
            sysm.directed(f"housing{n}", c, T, direction, -1.0)
        cols[f"M{n}"] = c = sysm.unknown(f"M{n}", 1)
        sysm.moment(f"rod{n}", c)
        sysm.moment(f"housing{n}", c, -1.0)
        if n == 1:
            continue
        # lever (P -> T) and link (T -> C): slender bars
        m_lever, m_link = linkage_masses(record, n)
        sysm.weight(f"lever{n}", m_lever, (P + T) / 2, g)
        sysm.weight(f"link{n}", m_link, (T + C) / 2, g)
        for name, body, other, point in ((f"P{n}", f"lever{n}", carrier, P), (f"L{n}", f"link{n}", f"lever{n}", T),
                                         (f"C{n}", f"S{n}", f"link{n}", C)):
            cols[name] = c = sysm.unknown(name, 2)
            sysm.force(body, c, point)
            sysm.force(other, c, point, -1.0)
    return sysm, cols, geo, J


def free_body_statics(record: PumpTruckParameters, q: Sequence[float] | np.ndarray,
                      cylinders: Sequence[dict] | None = None) -> dict:
    """Pin forces of the boom held at rest at joint angles ``q`` [rad] (``N`` values, relative, as the record's).

    Parameters
    ----------
    record : PumpTruckParameters
        The machine (any ``N`` = 4 … 6 sections). Its pipe state (filled or empty) is the load.
    q : sequence of float
        Joint angles ``q1 … qN`` [rad].
    cylinders : sequence of dict, optional
        The cylinders (:func:`~models.pump_truck.statics.cylinder_masses` dicts: ``m_housing``, ``L_housing``,
        ``m_rod``, ``L_rod``); default the machine's own, :func:`~models.pump_truck.statics.design_cylinders`.

    Returns
    -------
    dict
        ``F_cyl`` (N,) [N]: hydraulic force of each cylinder along its axis, **push positive** (``+F e`` on the rod,
        ``e`` from housing pin to rod pin); ``F_hinge`` (N, 2) [N]: the force **section n − 1 (the turret for n = 1)
        exerts on section n** through the hinge pin of joint ``n``, world (turret-frame) ``x``/``y`` components
        (``y`` up); ``F_hinge_abs`` (N,) its magnitude; ``F_hinge_section`` (N, 2) the same force resolved in
        section ``n``'s frame (``x`` along section ``n``); ``pins``: every pin force by name, world, each the
        force on the first-named body — ``H{n}`` on housing ``n`` from its carrier at ``H``, ``R{n}`` on rod ``n``
        from the lever (``n ≥ 2``) or section 1 (``n = 1``) at ``T``, ``P{n}`` on lever ``n`` from section ``n − 1``,
        ``L{n}`` on link ``n`` from lever ``n`` at ``T``, ``C{n}`` on section ``n`` from link ``n``; ``N``, ``M``
        (N,) the cylinder guides' transverse force [N] (on the rod, along ``ẑ × e``, at ``T``) and moment [N.m];
        ``turret_force`` (2,) [N] the force the turret exerts on the boom (``F_hinge[0] + pins['H1']``) and
        ``turret_moment`` [N.m] its moment about joint 1; ``points`` the pins ``H{n}``, ``C{n}``, ``T{n}``,
        ``P{n}`` (world) [m]; ``J`` ((N + 1), 2) the joint and tip positions [m],
        ``theta`` (N,) the sections' absolute angles [rad], ``residual`` the relative residual of the solve.

    Notes
    -----
    A simulation's hinge force compares as follows (flexlib/MSL cut forces act *on the component*, resolved in the
    connector's frame): for a revolute ``joint{n}`` with ``frame_a`` on section ``n − 1`` and ``frame_b`` on section
    ``n``, ``F_hinge[n−1] = R_a · joint{n}.frame_a.f = −R_b · joint{n}.frame_b.f`` (``R`` the frame's rotation
    to the turret frame, ``R = Tᵀ`` in MSL's ``T``). With ``frame_b`` on section ``n``'s root frame (``x`` along the
    section, ``y`` up when it is horizontal), simply ``F_hinge_section[n−1] = −joint{n}.frame_b.f[:2]`` (the slew
    angle drops out; ``frame_b.f[2]`` is 0 in the boom's plane). A cylinder's ``F_cyl`` is its chamber force
    ``p_A A_A − p_B A_B`` at rest (seal friction aside), not the force on its pins: its own weight puts a transverse
    component on them.
    """
    q = np.asarray(q, dtype=float)
    n_sec = len(record.sections)
    if q.shape != (n_sec,):
        raise ValueError(f"free_body_statics: q needs {n_sec} joint angles [rad], got shape {q.shape}")
    sysm, cols, geo, J = _equilibrium(record, q, design_cylinders(record) if cylinders is None else cylinders)
    x, residual = sysm.solve()
    pins = {name: x[c:c + 2].copy() for name, c in cols.items() if name[0] in "HRPLC" or name.startswith("hinge")}
    F_hinge = np.array([pins[f"hinge{n}"] for n in range(1, n_sec + 1)])
    turret_force = F_hinge[0] + pins["H1"]
    H1 = geo[0]["H"]
    return {
        "F_cyl": np.array([x[cols[f"F{n}"]] for n in range(1, n_sec + 1)]),
        "F_hinge": F_hinge,
        "F_hinge_abs": np.linalg.norm(F_hinge, axis=1),
        "F_hinge_section": np.array([_rot(geo[k]["theta"]).T @ F_hinge[k] for k in range(n_sec)]),
        "N": np.array([x[cols[f"N{n}"]] for n in range(1, n_sec + 1)]),
        "M": np.array([x[cols[f"M{n}"]] for n in range(1, n_sec + 1)]),
        "pins": pins,
        "turret_force": turret_force,
        "turret_moment": float(H1[0] * pins["H1"][1] - H1[1] * pins["H1"][0]),
        "points": {f"{name}{k + 1}": gk[name].copy() for k, gk in enumerate(geo) for name in "HCTP"
                   if gk[name] is not None},
        "J": np.array(J),
        "theta": np.array([gk["theta"] for gk in geo]),
        "residual": residual,
    }


def total_weight(record: PumpTruckParameters, cylinders: Sequence[dict] | None = None) -> float:
    """Weight [N] of everything above joint 1, in closed form: boxes (``SectionSpec.mass``), delivery pipe
    (``mass_per_m × length``), end hose, cylinder housings and rods, levers and links."""
    cyls = design_cylinders(record) if cylinders is None else cylinders
    m = sum(s.mass + record.pipe.mass_per_m * s.length for s in record.sections) + record.hose.mass
    m += sum(c["m_housing"] + c["m_rod"] for c in cyls)
    m += sum(sum(linkage_masses(record, n)) for n in range(2, len(record.sections) + 1))
    return record.g * m
