"""Shield 5 of the POLYCRANK fragment as a flexible body: a beam-frame FE model from the beam mesher, reduced by
Craig–Bampton (SI units).

Seed 002 (§4.1) made the shield of body 5 flexible: the composite shield meshed with SOLID186 elements in ANSYS,
joined to the discs by "spider webs" of light, stiff beam elements. Here the shield is a beam frame in its body
axes (origin at the bearing axis ``A1``, ``x`` towards ``A2``, ``z`` along the joint axes; the rigid shield's
``frame_a``):

* the shell: a Timoshenko beam of the CFRP box section (``h_shield`` in the plane of motion, ``b_shield`` along
  the joint axes, wall ``t_shield``) from ``A1`` to ``A2`` in ``shield_elements`` elements. The shell is short and
  deep (``L5 / h_shield`` ≈ 2), so its shear flexibility counts: Timoshenko, shear area of the two webs;
* the spider: six spokes from ``A1`` to the outer parallelogram's pins on the pin circle ``r_o`` (seed 002's
  spider webs), light and stiff (``E_spider``, ``rho_spider``): they carry the pin loads to the bearing as a thick
  flange would, whose own compliance a beam model does not resolve;
* the bearing housings and flange: point masses at ``A1`` and ``A2``.

The shell's density and the two point masses are solved (three linear equations) so that the FE model has the
rigid shield's mass ``m_shield5``, centre of mass ``(L5/2, 0, 0)`` and moment of inertia ``I_shield5`` about ``z``
(the plane of motion) — the shell carries the shield's mass smeared along it, as the pull rods' density carries
their heads; the housings' rotary inertias about ``x`` and ``y`` (half at each) make up the out-of-plane moments,
so that the whole inertia tensor is the rigid shield's ``I_shield5 · 1``.

Interface nodes (the flexible body's frames, in this order): ``A1`` (``frame_a``, the reference node, pinned: the
shield sits on the free bearing ``j5``), ``A2`` (``frame_b``: the grip discs' bearings and the load), the six pins
(``frame_c`` … ``frame_h``: pin ``k`` at the angle ``2πk/6`` on the pin circle, as in the rigid fragment).

References
----------
- Seed 002, §4.1 (flexible shield of body 5, spider webs of beam elements).
- I. M. Daniel, O. Ishai, *Engineering Mechanics of Composite Materials*, 2nd ed., Oxford University Press 2006
  (stiffness of quasi-isotropic carbon/epoxy laminates, about 50 GPa).
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np

import flexlib as fl
from flexlib.fe import beam_mesh, box, join_models, modal_data_from_fe, rectangle

if TYPE_CHECKING:
    from flexlib.fe import FEModel, MassPoints

    from .polycrank import PolycrankParameters

__all__ = ["SHIELD_FRAMES", "shield_fe", "shield_modal_data", "shield_shell_section"]

#: What the flexible shield's frames carry, in order (``frame_a``, ``frame_b``, ``frame_c`` … ``frame_h``).
SHIELD_FRAMES = ("A1", "A2", "pin1", "pin2", "pin3", "pin4", "pin5", "pin6")


def shield_shell_section(par: PolycrankParameters) -> Any:
    """The shell's box section (:func:`~flexlib.fe.box`: ``b_shield`` along ``z``, ``h_shield`` along ``y``)."""
    return box(par.b_shield, par.h_shield, par.t_shield)


def _mass_properties(points: MassPoints, centre: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass [kg], first moment about the body origin [kg.m] and inertia tensor about ``centre`` [kg.m2] of a mass
    description."""
    m = points.masses
    p = points.positions - centre
    inertia = np.einsum("p,pij->ij", m, np.einsum("pi,pi->p", p, p)[:, None, None] * np.eye(3)
                        - np.einsum("pi,pj->pij", p, p)) + points.inertias.sum(axis=0)
    return float(m.sum()), m @ points.positions, inertia


def _parts(par: PolycrankParameters, rho_shell: float, theory: str) -> list[FEModel]:
    """The shell (first) and the six spokes, each a beam mesh in the shield's body axes."""
    nu = par.nu_shield
    shell = beam_mesh((0.0, 0.0, 0.0), (par.L5, 0.0, 0.0), par.shield_elements, shield_shell_section(par),
                      E=par.E_shield, nu=nu, rho=rho_shell, theory=theory)
    spokes = []
    for k in range(par.n_links):
        a = 2 * math.pi * k / par.n_links
        e = np.array([math.cos(a), math.sin(a), 0.0])
        spokes.append(beam_mesh((0.0, 0.0, 0.0), par.r_o * e, 2, rectangle(par.b_spider, par.h_spider, nu),
                                E=par.E_spider, nu=nu, rho=par.rho_spider, theory=theory, y_axis=(-e[1], e[0], 0.0)))
    return [shell, *spokes]


def shield_fe(par: PolycrankParameters, theory: str = "timoshenko") -> tuple[FEModel, list[int]]:
    """The shield's FE model (module docstring) and its interface node ids in the order of :data:`SHIELD_FRAMES`;
    the fitted shell density [kg/m3], housing masses [kg] and rotary inertias about x and y [kg.m2] are in
    ``info["shield_fit"]``.

    Parameters
    ----------
    par : PolycrankParameters
        The numbers (shell section and material, spider, element count, the rigid shield's mass and inertia).
    theory : {"timoshenko", "euler-bernoulli"}
        Beam theory of the shell and spokes (the fragment uses Timoshenko; Euler–Bernoulli for checks against its
        closed forms). The masses are fitted for either.

    Raises
    ------
    ParameterError
        The shield's mass and inertia cannot be met with non-negative housing masses and inertias (the spider or
        the shell's section carries too much inertia for ``I_shield5``).
    """
    unit = _parts(par, 1.0, theory)  # the shell's mass description scales with its density
    centre = np.array([par.L5 / 2, 0.0, 0.0])
    m_s, S_s, I_s = _mass_properties(unit[0].mass_points, centre)
    spider = [_mass_properties(p.mass_points, centre) for p in unit[1:]]
    m_w = sum(s[0] for s in spider)
    S_w = sum(s[1] for s in spider)
    I_w = sum(s[2] for s in spider)
    # unknowns: shell density, housing masses at A1 (x = 0) and A2 (x = L5); mass, x moment, Izz about the centre
    A = np.array([[m_s, 1.0, 1.0], [S_s[0], 0.0, par.L5], [I_s[2, 2], centre[0] ** 2, (par.L5 - centre[0]) ** 2]])
    b = np.array([par.m_shield5 - m_w, par.m_shield5 * centre[0] - S_w[0], par.I_shield5 - I_w[2, 2]])
    rho, m1, m2 = np.linalg.solve(A, b)
    fe = join_models(_parts(par, float(rho), theory))
    nodes = fe.nodes
    ids = [int(np.argmin(np.linalg.norm(nodes - x, axis=1))) for x in
           [np.zeros(3), np.array([par.L5, 0.0, 0.0])]
           + [par.r_o * np.array([math.cos(a), math.sin(a), 0.0])
              for a in 2 * np.pi * np.arange(par.n_links) / par.n_links]]
    _, _, inertia = _mass_properties(fe.mass_points, centre)
    housing_x2 = m1 * centre[0] ** 2 + m2 * (par.L5 - centre[0]) ** 2  # the housings' share of Iyy (and Izz)
    missing = np.array([par.I_shield5 - inertia[0, 0], par.I_shield5 - inertia[1, 1] - housing_x2])
    if min(rho, m1, m2) < 0 or missing.min() < -1e-12 * par.I_shield5:
        raise fl.ParameterError(
            f"shield_fe: the flexible shield cannot have the rigid shield's mass {par.m_shield5} kg and inertia "
            f"{par.I_shield5} kg.m2 with this shell and spider (shell density {rho:.4g} kg/m3, housings {m1:.4g} and "
            f"{m2:.4g} kg, out-of-plane inertia to add {missing.tolist()} kg.m2): make the spider lighter, the "
            "shell's section shallower or I_shield5 larger")
    J = np.diag([*np.maximum(missing, 0.0) / 2, 0.0])
    fe = fe.with_point_masses([ids[0], ids[1]], [m1, m2], inertias=[J, J])
    fit = {"rho_shell_kg_m3": float(rho), "m_A1_kg": float(m1), "m_A2_kg": float(m2),
           "J_housing_kg_m2": [float(J[0, 0]), float(J[1, 1])]}
    return replace(fe, info={**fe.info, "shield_fit": fit}), ids


@lru_cache(maxsize=8)
def shield_modal_data(par: PolycrankParameters) -> Any:
    """Craig–Bampton data of the flexible shield (:func:`shield_fe`, Timoshenko): the eight interface nodes of
    :data:`SHIELD_FRAMES`, ``shield_cb_modes`` fixed-interface modes, reference frame pinned at ``A1`` (the shield
    on its free bearing ``j5``: the basis of a body on a hinge). The fragment keeps the ``shield_modes`` lowest
    in-plane modes (``FlexibleBody(plane="xy")``)."""
    fe, ids = shield_fe(par)
    return modal_data_from_fe(fe, ids, par.shield_cb_modes, reference_node=ids[0], attachment="pinned",
                              title=f"POLYCRANK shield 5, {par.L5} m, CFRP box {par.h_shield} x {par.b_shield} x "
                                    f"{par.t_shield} m")
