"""Built-in 3D beam FE mesher: Euler–Bernoulli and Timoshenko frame elements, straight or tapered.

Each two-node element has 12 DOFs ``(ux, uy, uz, rx, ry, rz)`` per node (translations [m], small rotations
[rad]). The element stiffness is obtained by the flexibility (unit-load) method: the 6 x 6 flexibility of the
element clamped at node 1 is the integral of the section compliances ``1/EA, 1/(G Asy), 1/(G Asz), 1/GJ,
1/(E Iy), 1/(E Iz)`` weighted by the exact statically determinate force distribution, and the 12 x 12
stiffness follows by equilibrium (Przemieniecki 1968, §5.6 uniform and §5.7 tapered elements). For a uniform
element this *is* the classical Przemieniecki frame element (with the shear parameters
``Phi = 12 E I / (G As L^2)`` for Timoshenko, ``Phi = 0`` for Euler–Bernoulli); for a tapered one it is the
exact static stiffness of the element, so static nodal displacements under nodal loads are exact for any
section variation. Sections may vary along the beam (``section`` as a function of the position fraction).

The consistent mass integrates ``rho A`` (translation), ``rho Ip`` (torsion) and, with rotary inertia,
``rho Iy, rho Iz`` (section rotation) over the element with the interdependent interpolation shape functions
of Friedman & Kosmatka (1993), which reduce to the cubic Hermite functions for ``Phi = 0``; Gauss–Legendre
quadrature of 6 points per element (exact for cubic shapes and a cubic ``rho A(x)``). The lumped mass is the
HRZ diagonal scaling of the consistent one (Hinton, Rock & Zienkiewicz 1976; Cook et al. §11.3).

References
----------
- J. S. Przemieniecki, *Theory of Matrix Structural Analysis*, McGraw-Hill 1968, ch. 5 (§5.6 eq. 5.116 stiffness
  of the space frame element with shear deformation; §5.7 tapered elements) and ch. 11 (consistent mass).
- Z. Friedman, J. B. Kosmatka, "An improved two-node Timoshenko beam finite element", *Computers & Structures*
  47 (1993) 473-481 (interdependent interpolation shape functions).
- E. Hinton, T. Rock, O. C. Zienkiewicz, "A note on mass lumping and related processes in the finite element
  method", *Earthquake Eng. Struct. Dyn.* 4 (1976) 245-249.
- R. D. Cook, D. S. Malkus, M. E. Plesha, R. J. Witt, *Concepts and Applications of Finite Element Analysis*,
  4th ed., Wiley 2002, §2.4 (beam element), §11.3 (mass matrices).
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Callable, Sequence
from typing import Any, Literal

import numpy as np
import scipy.sparse as sp

from flexlib.errors import RunArgumentError

from .fe_model import BeamElements, FEModel, MassPoints, check_fields
from .sections import Section

__all__ = ["beam_mesh", "beam_stress_modes", "element_matrices", "section_force_modes"]

SectionLike = Section | Callable[[float], Section]
_GAUSS_STIFFNESS = 8  # points for the flexibility integrals (exact for compliance polynomials of degree 13)
_GAUSS_MASS = 6
#: Peak memory [bytes] per element of the mesher (element stiffness, Gauss points, interpolation, assembly;
#: a consistent mass), to refuse a mesh that cannot fit before allocating it.
_BYTES_PER_ELEMENT = 24_000


def _memory() -> float:
    """Physical memory of the machine [bytes] (0 if unknown)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE")) * float(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):
        return 0.0


def _section_at(section: SectionLike, s: float) -> Section:
    if isinstance(section, Section):
        return section
    try:
        sec = section(s)
    except RunArgumentError as exc:
        raise RunArgumentError(f"beam_mesh: argument 'section' at position fraction s = {s:.6g}: {exc}") from None
    except (ValueError, TypeError, ZeroDivisionError, ArithmeticError) as exc:
        raise RunArgumentError(f"beam_mesh: argument 'section' (a function) fails at position fraction s = {s:.6g}: "
                               f"{type(exc).__name__}: {exc}") from None
    if not isinstance(sec, Section):
        raise SectionTypeError(f"beam_mesh: argument 'section' (a function of the position fraction s in [0, 1]): the "
                               f"section at position fraction {s:.6g} must be a Section, got {type(sec).__name__} "
                               f"{sec!r:.60}")
    return sec


class SectionTypeError(RunArgumentError, TypeError):
    """A ``section`` function of :func:`beam_mesh` returned something that is not a Section (a
    :class:`~flexlib.errors.RunArgumentError` and a ``TypeError``)."""


def _real(name: str, value: Any, accepted: str) -> float:
    """A real number argument (not a bool or a string), as float; finite."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real) or not math.isfinite(float(value)):
        raise RunArgumentError(f"beam_mesh: {name} must be {accepted}, got {type(value).__name__} {value!r}")
    return float(value)


def _point(name: str, value: Any, *, nonzero: bool = False) -> np.ndarray:
    """Three finite coordinates [m] (or direction components)."""
    if isinstance(value, str | bytes):
        raise RunArgumentError(f"beam_mesh: argument {name!r} must be three numbers (x, y, z), got {value!r}")
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise RunArgumentError(f"beam_mesh: argument {name!r} must be three numbers (x, y, z), got {value!r}") from None
    if a.shape != (3,):
        raise RunArgumentError(f"beam_mesh: argument {name!r} must be three numbers (x, y, z), got shape {a.shape}: "
                               f"{value!r}")
    if not np.all(np.isfinite(a)):
        raise RunArgumentError(f"beam_mesh: argument {name!r} has a non-finite coordinate: {a.tolist()}")
    if nonzero and not np.any(a):
        raise RunArgumentError(f"beam_mesh: argument {name!r} must be a nonzero direction, got {a.tolist()}")
    return a


def _shape(xi: float, L: float, phi_y: float, phi_z: float) -> tuple[np.ndarray, np.ndarray]:
    """Local translation ``Nt`` (3 x 12) and rotation ``Nr`` (3 x 12) shape functions at ``xi = x/L``."""
    Nt = np.zeros((3, 12))
    Nr = np.zeros((3, 12))
    Nt[0, 0], Nt[0, 6] = 1.0 - xi, xi
    Nr[0, 3], Nr[0, 9] = 1.0 - xi, xi

    def bending(phi: float) -> tuple[np.ndarray, np.ndarray]:
        c = 1.0 / (1.0 + phi)
        v = c * np.array([2 * xi**3 - 3 * xi**2 - phi * xi + 1 + phi,
                          L * (xi**3 - (2 + phi / 2) * xi**2 + (1 + phi / 2) * xi),
                          -2 * xi**3 + 3 * xi**2 + phi * xi,
                          L * (xi**3 - (1 - phi / 2) * xi**2 - phi / 2 * xi)])
        th = c * np.array([(6 * xi**2 - 6 * xi) / L, 3 * xi**2 - (4 + phi) * xi + 1 + phi,
                           (-6 * xi**2 + 6 * xi) / L, 3 * xi**2 - (2 - phi) * xi])
        return v, th

    v, th = bending(phi_y)  # x-y plane: (uy, rz)
    Nt[1, [1, 5, 7, 11]] = v
    Nr[2, [1, 5, 7, 11]] = th
    w, ps = bending(phi_z)  # x-z plane: (uz, -ry)
    Nt[2, [2, 4, 8, 10]] = w * np.array([1, -1, 1, -1])
    Nr[1, [2, 4, 8, 10]] = ps * np.array([-1, 1, -1, 1])
    return Nt, Nr


def element_matrices(L: float, section: Callable[[float], Section], E: float, G: float, rho: float, *,
                     timoshenko: bool, rotary_inertia: bool, lumped: bool) -> tuple[np.ndarray, np.ndarray]:
    """Local 12 x 12 stiffness [N/m, N, N m] and mass [kg, kg m, kg m2] of one element of length ``L`` [m].

    Parameters
    ----------
    L : float
        Element length [m].
    section : callable
        Section at the element-local fraction ``xi`` in [0, 1].
    E, G : float
        Young's and shear modulus [Pa].
    rho : float
        Density [kg/m3].
    timoshenko : bool
        Include shear flexibility (Timoshenko) or not (Euler–Bernoulli).
    rotary_inertia : bool
        Include the rotary inertia ``rho Iy, rho Iz`` of the section in bending.
    lumped : bool
        HRZ-lumped (diagonal) instead of consistent mass.
    """
    if isinstance(L, bool | np.bool_) or not isinstance(L, numbers.Real) or not (math.isfinite(L) and L > 0):
        raise RunArgumentError(f"element_matrices: the element length L must be a positive finite number [m], got "
                               f"{L!r}")
    if not callable(section):
        raise RunArgumentError(f"element_matrices: argument 'section' must be a function of the element fraction "
                               f"returning a Section, got {type(section).__name__}")
    # flexibility of the element clamped at node 1, loaded at node 2 (local axes)
    xg, wg = np.polynomial.legendre.leggauss(_GAUSS_STIFFNESS)
    xg, wg = (xg + 1) / 2, wg / 2
    F = np.zeros((6, 6))
    for xi, w in zip(xg, wg):
        sec = section(xi)
        shear_y = 1.0 / (G * sec.Asy) if timoshenko else 0.0
        shear_z = 1.0 / (G * sec.Asz) if timoshenko else 0.0
        C = np.diag([1 / (E * sec.A), shear_y, shear_z, 1 / (G * sec.J), 1 / (E * sec.Iy), 1 / (E * sec.Iz)])
        B = np.eye(6)  # section forces (N, Vy, Vz, T, My, Mz) from the end forces (Fx..Mz) at node 2
        B[4, 2] = -(1 - xi) * L
        B[5, 1] = (1 - xi) * L
        F += w * L * B.T @ C @ B
    k22 = np.linalg.inv(F)
    k22 = (k22 + k22.T) / 2
    Gam = np.eye(6)  # node-1 forces = -Gam @ node-2 forces (equilibrium); rigid motion d2 = Gam^T d1
    Gam[3:, :3] = np.array([[0, 0, 0], [0, 0, -L], [0, L, 0]])  # [r x] with r = (L, 0, 0)
    K = np.block([[Gam @ k22 @ Gam.T, -Gam @ k22], [-k22 @ Gam.T, k22]])

    mid = section(0.5)
    phi_y = 12 * E * mid.Iz / (G * mid.Asy * L**2) if timoshenko else 0.0
    phi_z = 12 * E * mid.Iy / (G * mid.Asz * L**2) if timoshenko else 0.0
    xg, wg = np.polynomial.legendre.leggauss(_GAUSS_MASS)
    M = np.zeros((12, 12))
    for xi, w in zip((xg + 1) / 2, wg / 2):
        sec = section(xi)
        Nt, Nr = _shape(xi, L, phi_y, phi_z)
        r = 1.0 if rotary_inertia else 0.0
        D = rho * np.diag([sec.Ip, r * sec.Iy, r * sec.Iz])
        M += w * L * (rho * sec.A * Nt.T @ Nt + Nr.T @ D @ Nr)
    if lumped:
        M = _hrz(M)
    return K, M


def _hrz(M: np.ndarray) -> np.ndarray:
    """HRZ lumping: keep the diagonal, scale each direction's translational and associated rotational terms so
    that the translational terms sum to the element mass (torsion with the axial direction)."""
    m_total = M[0, 0] + M[0, 6] + M[6, 0] + M[6, 6]  # axial block of the consistent mass integrates rho A
    d = np.diag(M).copy()
    for trans, rots in (([0, 6], [3, 9]), ([1, 7], [5, 11]), ([2, 8], [4, 10])):
        s = m_total / d[trans].sum()
        d[trans] *= s
        d[rots] *= s
    return np.diag(d)


def _frame(axis: np.ndarray, y_axis: Sequence[float] | None) -> np.ndarray:
    """Rotation matrix whose rows are the element's local x, y, z axes in the body frame."""
    ex = axis / np.linalg.norm(axis)
    hint = np.array([0.0, 1.0, 0.0]) if y_axis is None else np.asarray(y_axis, dtype=float)
    if y_axis is None and abs(ex @ hint) > 0.99:
        hint = np.array([0.0, 0.0, 1.0])
    ez = np.cross(ex, hint)
    if np.linalg.norm(ez) < 1e-9 * np.linalg.norm(hint):
        raise RunArgumentError(f"beam_mesh: y_axis {hint.tolist()} is parallel to the beam axis {ex.tolist()}: it "
                               "must give the section's y direction across the beam")
    ez /= np.linalg.norm(ez)
    return np.vstack([ex, np.cross(ez, ex), ez])


def _stations(length: float, n_elements: int, nodes_at: Sequence[float]) -> np.ndarray:
    """Node positions as fractions of ``length``: equal elements, or split at ``nodes_at`` [m] with the elements
    shared out by part length (largest remainders; at least one per part)."""
    if isinstance(nodes_at, str | bytes | numbers.Number) or not isinstance(nodes_at, Sequence | np.ndarray | range):
        raise RunArgumentError(f"beam_mesh: argument 'nodes_at' must be a sequence of distances [m] from start, got "
                               f"{nodes_at!r}" + (f" (for one node: [{nodes_at}])" if isinstance(nodes_at, numbers.Real)
                                                  else ""))
    items = list(nodes_at.ravel()) if isinstance(nodes_at, np.ndarray) else list(nodes_at)
    if not all(isinstance(v, numbers.Real) and not isinstance(v, bool | np.bool_) for v in items):
        raise RunArgumentError(f"beam_mesh: argument 'nodes_at' must be numbers (distances [m] from start), got "
                               f"{items!r}")
    at = np.asarray(items, dtype=float).ravel()
    if at.size and (not np.all(np.isfinite(at)) or at.min() < 0 or at.max() > length * (1 + 1e-12)):
        raise RunArgumentError(f"beam_mesh: nodes_at must lie on the axis, 0 .. {length:g} m, got {at.tolist()}")
    cuts = np.unique(np.concatenate([[0.0, 1.0], np.clip(at / length, 0.0, 1.0)]))
    cuts = cuts[np.concatenate([[True], np.diff(cuts) > 1e-9])]
    cuts[-1] = 1.0
    parts = np.diff(cuts)
    if parts.size > n_elements:
        raise RunArgumentError(f"beam_mesh: {parts.size} parts between the nodes_at positions need at least as many "
                         f"elements, got n_elements={n_elements}")
    share = parts * n_elements
    count = np.maximum(np.floor(share).astype(int), 1)
    while count.sum() < n_elements:
        count[np.argmax(share - count)] += 1
    while count.sum() > n_elements:
        count[np.argmax(np.where(count > 1, count - share, -np.inf))] -= 1
    return np.concatenate([np.linspace(a, b, c, endpoint=False) for a, b, c in zip(cuts[:-1], cuts[1:], count,
                                                                                    strict=True)] + [[1.0]])


def beam_mesh(start: Sequence[float], end: Sequence[float], n_elements: int, section: SectionLike, *,
              E: float, rho: float, G: float | None = None, nu: float = 0.3,
              theory: Literal["euler-bernoulli", "timoshenko"] = "euler-bernoulli",
              mass: Literal["consistent", "lumped"] = "consistent", rotary_inertia: bool | None = None,
              y_axis: Sequence[float] | None = None, nodes_at: Sequence[float] = ()) -> FEModel:
    """Mesh a straight (optionally tapered) beam from ``start`` to ``end`` into equal 3D frame elements.

    Parameters
    ----------
    start, end : sequence of 3 floats
        End points of the beam axis in the body frame [m]; nodes are numbered 0 (at ``start``) to
        ``n_elements`` (at ``end``).
    n_elements : int
        Number of elements (>= 1).
    section : Section or callable
        Cross-section, or a function of the position fraction ``s`` in [0, 1] from ``start`` to ``end``
        returning the section there (tapered beams, e.g. ``lambda s: rectangle(0.02, 0.04 * (1 - s / 2))``).
    E : float
        Young's modulus [Pa].
    rho : float
        Density [kg/m3].
    G : float, optional
        Shear modulus [Pa]; default ``E / (2 (1 + nu))``.
    nu : float
        Poisson's ratio [1], ``-1 < nu <= 0.5``, used only for the default ``G``.
    theory : {"euler-bernoulli", "timoshenko"}
        Beam theory: Timoshenko adds shear flexibility (shear areas of the section) and, by default, rotary
        inertia.
    mass : {"consistent", "lumped"}
        Consistent mass, or HRZ-lumped mass (nodal, block-diagonal).
    rotary_inertia : bool, optional
        Include the section's rotary inertia in bending; default: True for Timoshenko, False for
        Euler–Bernoulli (the classical beams of the closed-form frequencies).
    y_axis : sequence of 3 floats, optional
        Direction in the local ``x``-``y`` plane (section axis ``y``) [1]; default the body y axis (z for a
        beam along y).
    nodes_at : sequence of float
        Distances from ``start`` along the axis [m] where a node must lie (joint pins, brackets: the frames of a
        flexible body). The beam is split there and each part gets equal elements, ``n_elements`` in all
        (distributed by length, at least one per part).

    Returns
    -------
    FEModel
        ``M``, ``K``, nodes, six DOFs per node, element connectivity, and the mass points (Gauss points for a
        consistent mass, nodes for a lumped one) from which the inertia invariants are computed.

    Raises
    ------
    RunArgumentError
        An argument that is not what is accepted, named: ``start``/``end`` not three finite numbers or
        coinciding, ``E``, ``rho``, ``G`` not positive finite numbers (strings and bools are refused), ``nu``
        outside ``(-1, 0.5]``, ``n_elements`` not a whole number >= 1, ``section`` not a Section (or a function
        that fails or returns something else at a position), ``theory``/``mass`` not one of their choices,
        ``rotary_inertia`` not a bool, ``y_axis`` zero, non-finite or along the beam, ``nodes_at`` off the axis.

    References
    ----------
    Przemieniecki 1968 ch. 5 and 11; Friedman & Kosmatka 1993; Cook et al. 2002 §11.3 (see the module).
    """
    p0, p1, E, rho, G = _checked_arguments(n_elements, start, end, E, rho, G, nu, theory, mass, rotary_inertia,
                                           section)
    timoshenko = theory == "timoshenko"
    rotary = timoshenko if rotary_inertia is None else bool(rotary_inertia)
    axis, length, R, fractions = _axis_and_stations(p0, p1, y_axis, int(n_elements), nodes_at)
    mesh = _BeamAssembly(section, fractions, length, bool(len(nodes_at)), p0, axis, R)
    mesh.assemble(E, G, rho, timoshenko, rotary, mass)
    info = {"producer": "flexlib beam_mesh", "theory": theory, "mass": mass, "rotary_inertia": rotary,
            "n_elements": int(mesh.n_elements), "length_m": length, "E_Pa": float(E), "G_Pa": float(G),
            "rho_kg_m3": float(rho), "section_start": _section_at(section, 0.0).name,
            "section_end": _section_at(section, 1.0).name}
    return mesh.model(info, mass)


def _checked_arguments(n_elements: Any, start: Any, end: Any, E: Any, rho: Any, G: Any, nu: Any, theory: Any,
                       mass: Any, rotary_inertia: Any, section: Any) -> tuple[np.ndarray, np.ndarray, float, float,
                                                                             float]:
    """The arguments of :func:`beam_mesh` checked: the end points, ``E``, ``rho`` and ``G`` (default from ``nu``)."""
    if isinstance(n_elements, bool | np.bool_) or not isinstance(n_elements, numbers.Integral) or n_elements < 1:
        raise RunArgumentError(f"beam_mesh: n_elements must be a positive integer (a whole number >= 1), got "
                               f"{n_elements!r}")
    need = _BYTES_PER_ELEMENT * float(n_elements)
    have = _memory()
    if have and need > have:
        raise RunArgumentError(f"beam_mesh: n_elements={n_elements} needs about {need / 2**30:.3g} GiB for the element "
                               f"arrays, more than the {have / 2**30:.3g} GiB of this machine; a modal body needs far "
                               "fewer elements (its modes converge with tens to hundreds)")
    p0, p1 = _point("start", start), _point("end", end)
    E = _real("E", E, "a positive finite number [Pa]")
    rho = _real("rho", rho, "a positive finite number [kg/m3]")
    for name, value in (("E", E), ("rho", rho)):
        if value <= 0:
            raise RunArgumentError(f"beam_mesh: {name} must be a positive finite number "
                                   f"[{'Pa' if name == 'E' else 'kg/m3'}], got {value!r}")
    if theory not in ("euler-bernoulli", "timoshenko"):
        raise RunArgumentError(f"beam_mesh: theory must be 'euler-bernoulli' or 'timoshenko', got {theory!r}")
    if mass not in ("consistent", "lumped"):
        raise RunArgumentError(f"beam_mesh: mass must be 'consistent' or 'lumped', got {mass!r}")
    if rotary_inertia is not None and not isinstance(rotary_inertia, bool | np.bool_):
        raise RunArgumentError(f"beam_mesh: rotary_inertia must be True, False or None (default by theory), got "
                               f"{rotary_inertia!r}")
    if not isinstance(section, Section) and not callable(section):
        raise RunArgumentError(f"beam_mesh: argument 'section' must be a Section (rectangle(), circle(), tube(), "
                               f"box(), i_section() or Section(...)) or a function of the position fraction "
                               f"returning one, got {type(section).__name__} {section!r:.60}")
    if G is None:
        nu = _real("nu", nu, "Poisson's ratio, a number in (-1, 0.5]")
        if not -1.0 < nu <= 0.5:
            raise RunArgumentError(f"beam_mesh: Poisson's ratio nu must be in (-1, 0.5] (an isotropic material: "
                                   f"G = E / (2 (1 + nu)) > 0 and bulk modulus > 0), got {nu!r}")
        G = E / (2 * (1 + nu))
    else:
        G = _real("G", G, "a positive finite number [Pa]")
    if G <= 0:
        raise RunArgumentError(f"beam_mesh: G must be a positive finite number [Pa], got {G!r}")
    return p0, p1, E, rho, G


def _axis_and_stations(p0: np.ndarray, p1: np.ndarray, y_axis: Any, n_elements: int,
                       nodes_at: Sequence[float]) -> tuple[np.ndarray, float, np.ndarray, np.ndarray]:
    """The beam axis ``p1 - p0`` [m], its length [m], the element frame (rows: local x, y, z) and the node
    stations as fractions of the length."""
    axis = p1 - p0
    length = float(np.linalg.norm(axis))
    if length == 0 or not math.isfinite(length):
        raise RunArgumentError(f"beam_mesh: start and end coincide ({p0.tolist()}): the beam has no length"
                               if length == 0 else f"beam_mesh: the beam from {p0.tolist()} to {p1.tolist()} is "
                               "too long to represent")
    if y_axis is not None:
        y_axis = _point("y_axis", y_axis, nonzero=True)
    R = _frame(axis, y_axis)
    return axis, length, R, _stations(length, n_elements, nodes_at)


class _BeamAssembly:
    """The global matrices, frame-element data and consistent mass points of a straight beam mesh, element by
    element (:func:`beam_mesh`)."""

    def __init__(self, section: SectionLike, fractions: np.ndarray, length: float, split: bool, p0: np.ndarray,
                 axis: np.ndarray, R: np.ndarray) -> None:
        self.section, self.fractions, self.length, self.split = section, fractions, length, split
        self.p0, self.axis, self.R = p0, axis, R
        self.T = np.kron(np.eye(4), R)
        self.n_elements = fractions.size - 1
        n_nodes = self.n_elements + 1
        self.nodes = p0 + fractions[:, None] * axis
        self.dof_map = np.arange(6 * n_nodes).reshape(n_nodes, 6)
        self.n = 6 * n_nodes
        self.rows: list[np.ndarray] = []
        self.cols: list[np.ndarray] = []
        self.kvals: list[np.ndarray] = []
        self.mvals: list[np.ndarray] = []
        P = self.n_elements * _GAUSS_MASS
        self.positions, self.masses, self.inertias = np.zeros((P, 3)), np.zeros(P), np.zeros((P, 3, 3))
        self.nt_rows: list[np.ndarray] = []
        self.nt_cols: list[np.ndarray] = []
        self.nt_vals: list[np.ndarray] = []
        self.nr_vals: list[np.ndarray] = []
        self.k_local = np.zeros((self.n_elements, 12, 12))
        self.ends = np.zeros((3, self.n_elements, 2))  # A, Iy, Iz at the two ends
        self.shapes: dict[tuple[int, float, float], tuple[np.ndarray, np.ndarray]] = {}
        xg, wg = np.polynomial.legendre.leggauss(_GAUSS_MASS)
        self.gauss = (xg + 1) / 2, wg / 2  # points and weights on [0, 1]

    def assemble(self, E: float, G: float, rho: float, timoshenko: bool, rotary: bool, mass: str) -> None:
        """Add every element's matrices [N/m, kg] (equal elements computed once) and, for a consistent mass, its
        Gauss points."""
        T = self.T
        uniform: tuple | None = None
        for e in range(self.n_elements):
            s0, s1 = float(self.fractions[e]), float(self.fractions[e + 1])
            L = self.length * (s1 - s0) if self.split else self.length / self.n_elements

            def local(xi: float, s0: float = s0, s1: float = s1) -> Section:
                return _section_at(self.section, s0 + xi * (s1 - s0))

            if uniform is None or callable(self.section) or abs(uniform[0] - L) > 1e-12 * L:  # equal elements
                Ke, Me = element_matrices(L, local, E, G, rho, timoshenko=timoshenko, rotary_inertia=rotary,
                                          lumped=mass == "lumped")
                uniform = (L, Ke, Me, T.T @ Ke @ T, T.T @ Me @ T)
            Ke, Me, Kg, Mg = uniform[1:]
            self.k_local[e] = Ke
            for end, xi in enumerate((0.0, 1.0)):
                sec = local(xi)
                self.ends[:, e, end] = sec.A, sec.Iy, sec.Iz
            idx = np.arange(6 * e, 6 * e + 12)
            self.rows.append(np.repeat(idx, 12))
            self.cols.append(np.tile(idx, 12))
            self.kvals.append(Kg.ravel())
            self.mvals.append(Mg.ravel())
            if mass == "consistent":
                mid = local(0.5)
                phi_y = 12 * E * mid.Iz / (G * mid.Asy * L**2) if timoshenko else 0.0
                phi_z = 12 * E * mid.Iy / (G * mid.Asz * L**2) if timoshenko else 0.0
                self._gauss_points(e, idx, local, (s0, s1, L), rho, rotary, (phi_y, phi_z))

    def _gauss_points(self, e: int, idx: np.ndarray, local: Callable[[float], Section],
                      span: tuple[float, float, float], rho: float, rotary: bool,
                      phi: tuple[float, float]) -> None:
        """Element ``e``'s mass points: position [m], mass [kg], rotary inertia [kg m2] and shape functions at its
        Gauss points (``span``: start and end fractions and length [m]; ``phi``: shear parameters)."""
        s0, s1, L = span
        R, T = self.R, self.T
        for g, (xi, w) in enumerate(zip(*self.gauss)):
            p = e * _GAUSS_MASS + g
            sec = local(xi)
            key = (g, *phi)
            if key not in self.shapes:
                Nt, Nr = _shape(xi, L, *phi)
                self.shapes[key] = ((R.T @ Nt @ T).ravel(), (R.T @ Nr @ T).ravel())
            self.positions[p] = self.p0 + (s0 + xi * (s1 - s0)) * self.axis
            self.masses[p] = rho * sec.A * w * L
            r = 1.0 if rotary else 0.0
            self.inertias[p] = R.T @ (rho * w * L * np.diag([sec.Ip, r * sec.Iy, r * sec.Iz])) @ R
            self.nt_rows.append(np.repeat(np.arange(3 * p, 3 * p + 3), 12))
            self.nt_cols.append(np.tile(idx, 3))
            self.nt_vals.append(self.shapes[key][0])
            self.nr_vals.append(self.shapes[key][1])

    def model(self, info: dict[str, Any], mass: str) -> FEModel:
        """The assembled :class:`FEModel`, with its mass points and frame-element data."""
        n, n_elements = self.n, self.n_elements
        rows, cols = np.concatenate(self.rows), np.concatenate(self.cols)
        K = sp.csr_matrix((np.concatenate(self.kvals), (rows, cols)), shape=(n, n))
        M = sp.csr_matrix((np.concatenate(self.mvals), (rows, cols)), shape=(n, n))
        K, M = (K + K.T) / 2, (M + M.T) / 2
        K.eliminate_zeros()
        M.eliminate_zeros()
        n_nodes = n_elements + 1
        elements = np.column_stack([np.arange(n_elements), np.arange(1, n_nodes)]).astype(np.int64)
        model = FEModel(M.tocsr(), K.tocsr(), self.nodes, self.dof_map, np.arange(n_nodes), elements, None, info)
        if mass == "consistent":
            shape = (3 * n_elements * _GAUSS_MASS, n)
            nt_rows, nt_cols = np.concatenate(self.nt_rows), np.concatenate(self.nt_cols)
            Nt = sp.csr_matrix((np.concatenate(self.nt_vals), (nt_rows, nt_cols)), shape)
            Nr = sp.csr_matrix((np.concatenate(self.nr_vals), (nt_rows, nt_cols)), shape)
            points = MassPoints(self.positions, self.masses, self.inertias, Nt, Nr,
                                f"consistent (element Gauss points, {_GAUSS_MASS} per element)")
        else:
            points = model.lumped_mass_points()
        beam = BeamElements(self.k_local, np.repeat(self.R[None], n_elements, axis=0),
                            6 * np.arange(n_elements)[:, None] + np.arange(12)[None, :], *self.ends)
        return FEModel(model.M, model.K, self.nodes, self.dof_map, model.node_ids, elements, points, info,
                       beam=beam)


def section_force_modes(fe: FEModel, modes: np.ndarray) -> np.ndarray:
    """Section forces at both ends of every frame element for each displacement field (mode) on the FE DOFs.

    Parameters
    ----------
    fe : FEModel
        A model from :func:`beam_mesh` (possibly constrained).
    modes : ndarray (n, M)
        Displacement fields [m, rad per unit modal coordinate].

    Returns
    -------
    ndarray (M, E, 2, 6)
        ``(N, Vy, Vz, T, My, Mz)`` [N, N, N, N m, N m, N m] in element axes on the section's positive face at
        the element's first and second node (static equilibrium of the element: ``k_local @ T d``; exact
        beam-theory resultants for nodal loading).
    """
    modes = check_fields("section_force_modes", fe, modes, beam=True)
    b = fe.beam
    padded = np.vstack([modes, np.zeros((1, modes.shape[1]))])  # row -1: held DOFs
    d = padded[b.dofs]  # (E, 12, M)
    rot = np.einsum("eab,enbm->enam", b.rotation, d.reshape(d.shape[0], 4, 3, -1)).reshape(d.shape)
    f = np.einsum("eij,ejm->emi", b.k_local, rot)  # (E, M, 12) end forces on the element
    out = np.stack([-f[..., :6], f[..., 6:]], axis=2)  # section forces on the positive face
    return np.transpose(out, (1, 0, 2, 3))


def beam_stress_modes(fe: FEModel, modes: np.ndarray, fibre: tuple[float, float]) -> np.ndarray:
    """Normal stress at a fibre ``(y, z)`` of the section, per node and mode, as a stress tensor in body axes.

    ``sigma_xx = N/A + My z/Iy - Mz y/Iz`` (Euler–Bernoulli/Timoshenko beam theory, Przemieniecki 1968 §5.6
    sign conventions), averaged over the element ends meeting at a node, returned as the uniaxial tensor
    ``sigma e_x e_x^T`` in body axes (its von Mises stress is ``|sigma_xx|``). Shear stresses of torsion and
    transverse shear are not included.

    Parameters
    ----------
    fe : FEModel
        A model from :func:`beam_mesh`.
    modes : ndarray (n, M)
        Displacement fields [m, rad per unit modal coordinate].
    fibre : (float, float)
        Fibre position ``(y, z)`` in the section's principal axes [m], e.g. ``(h/2, b/2)`` for a corner.

    Returns
    -------
    ndarray (M, N, 6)
        ``(sxx, syy, szz, sxy, syz, szx)`` [Pa per unit modal coordinate] at each node.
    """
    items = [fibre] if isinstance(fibre, str | bytes) or np.ndim(fibre) != 1 else list(fibre)
    if len(items) != 2 or not all(isinstance(v, numbers.Real) and not isinstance(v, bool | np.bool_)
                                  and math.isfinite(v) for v in items):
        raise RunArgumentError(f"beam_stress_modes: argument 'fibre' must be two finite numbers (y, z) [m], got "
                               f"{fibre!r}")
    y, z = (float(v) for v in items)
    sf = section_force_modes(fe, modes)  # (M, E, 2, 6)
    b = fe.beam
    sigma = sf[..., 0] / b.A + sf[..., 4] * z / b.Iy - sf[..., 5] * y / b.Iz  # (M, E, 2)
    ex = b.rotation[:, 0, :]  # (E, 3)
    dyad = np.stack([ex[:, 0] ** 2, ex[:, 1] ** 2, ex[:, 2] ** 2, ex[:, 0] * ex[:, 1], ex[:, 1] * ex[:, 2],
                     ex[:, 2] * ex[:, 0]], axis=1)  # (E, 6)
    N = fe.nodes.shape[0]
    total = np.zeros((sigma.shape[0], N, 6))
    count = np.zeros(N)
    for end in range(2):
        nodes = fe.elements[:, end]
        np.add.at(total, (slice(None), nodes), sigma[:, :, end, None] * dyad[None])
        np.add.at(count, nodes, 1.0)
    return total / np.maximum(count, 1.0)[None, :, None]
