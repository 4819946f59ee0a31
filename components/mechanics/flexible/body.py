"""Flexible body: floating frame of reference with modal superposition (the modal body of Adams/Flex, SIMPACK's
SID body, DLR's ``FlexibleBodies`` library and Modelica's seed-000 ``FlexibleBody``).

The body's material points move with a floating reference frame ``R`` (origin ``r_0`` in the world, orientation
``T`` world → body, angular velocity ``w`` resolved in ``R``) plus a small elastic displacement in body axes,
``u_p = Φ_p q``, spanned by the modes of a :class:`~.modal_data.ModalData` (translational ``Φ_p``, rotational
``Φ*_p`` per node) with modal coordinates ``q``. With the nine inertia invariants ``I1 … I9`` (see
:mod:`.invariants`), the first moment ``c(q) = I2 + I3 q``, the inertia tensor about the reference origin
``J(q) = I7 + Σ_j q_j (I8_j + I8_jᵀ) + Σ_j q_j B_j``, ``B_j = Σ_k q_k I9_jk``, the rotation–mode coupling
``C(q) = I4 + Σ_j q_j I5_j`` and ``α = T (a_0 − g)`` (origin acceleration minus gravity, body axes), the
Newton–Euler equations of the reference frame and the modal equations read (all in body axes; Lagrange's
equations in quasi-coordinates for the kinetic energy of the mass points, each point's rotational inertia
fixed in body axes)::

    m α + ż × c + w × (w × c) + 2 w × (I3 q̇) + I3 q̈                 = Σ_k F_k
    c × α + J ż + w × (J w) + J̇ w + w × (C q̇) + C q̈                = Σ_k (x_k × F_k + M_k)
    I3ᵀ α + Cᵀ ż + I6 q̈ + h_ω + h_c + D q̇ + (K + K_G) q              = Σ_k (Φ_kᵀ F_k + Φ*_kᵀ M_k)

with the centrifugal modal forces ``h_ω,j = −wᵀ (I8_jᵀ + B_j) w``, the Coriolis ones
``h_c,j = 2 wᵀ (Σ_k q̇_k I5_k)[:, j]``, the modal damping ``D = diag(2 ζ_j ω_j I6_jj)`` and, with
``geometric_stiffening=True``, the geometric stiffness ``K_G = Σ_c λ_c G_c`` of the file's unit load cases
(:mod:`.geometric`) weighted by the current loads ``λ``: ``α`` (cases ``acc_*``), ``ż`` (``alpha_*``), the
products ``w_a w_b`` (``omega_*``) and the frame loads ``F_k, M_k`` (``F<node>_*``). The centrifugal cases are
kept energy-consistent: their stiffening is the ``q``-derivative of the kinetic-energy term ``−½ wᵀ S(q) w``
(the foreshortening of the bent body, ``S_aa = qᵀ G_ωaa q``, ``S_ab = ½ qᵀ G_ωab q``), so the rotation equation
gets its counterpart ``−(S ż + Ṡ w + w × S w)``; without it a body whose reference frame spins up and down
gains energy from the stiffening term. ``F_k``, ``M_k`` are the cut
force and torque of frame ``k`` resolved in body axes and ``x_k = s_k + Φ_k q`` the deformed position of its node.

Each frame sits at a node: ``r_0,k = r_0 + Tᵀ x_k`` and ``T_k = T_rel(θ_k) T`` with ``θ_k = Φ*_k q`` its small
elastic rotation, turned into an exact rotation by the Cayley map ``T_rel = I + 2/(1 + a·a) (a×a× − a×)``,
``a = θ_k/2`` (orthogonal for every ``q``, equal to the linear ``I − θ_k×`` to first order), and
``w_k = T_rel w + 2/(1 + a·a) (ȧ − a × ȧ)``, so the frame rule ``der(T_k) = −[w_k×] T_k`` holds exactly.
The orientation enters through whichever frame is nearest the root of the orientation tree (or, for a body
that nothing orients, from the body's own quaternion on ``frame_a``, as :class:`~..multibody.body.Body`).
Velocities and accelerations enter the same way (recursive kinematics, :class:`~..multibody.interfaces.Frame`):
from the entry frame's ``v``, ``a`` (less gravity) and ``z``, resolved in that frame, ``α`` and ``ż`` follow
with the body's own coordinates (``α = T_relᵀ a_e − (ż × x_e + w × (w × x_e) + 2 w × ẋ_e + ẍ_e)``, ``ẋ = Φ q̇``),
and every other frame's ``v``, ``a``, ``z`` from them, so the equations never read the orientation or position of
the body in the world (which depend on every joint and modal coordinate between it and the root).

With zero modes the equations are exactly the rigid body's (``Body`` about its frame with the same mass
properties).

References
----------
- A. A. Shabana, *Dynamics of Multibody Systems*, 3rd ed., Cambridge University Press 2005, ch. 5 (floating
  frame of reference, inertia shape integrals) and §5.6 (equations of motion with modal coordinates).
- R. Schwertassek, O. Wallrapp, *Dynamik flexibler Mehrkörpersysteme*, Vieweg 1999, ch. 5–6 (the standard
  input data and the equations of motion in terms of the invariants).
- O. Wallrapp, R. Schwertassek, "Representation of geometric stiffening in multibody system simulation",
  *Int. J. Numer. Methods Eng.* 32 (1991) 1833–1850.
- M. D. Shuster, "A survey of attitude representations", *J. Astronaut. Sci.* 41 (1993) 439–517, §6 (Cayley
  transform / Gibbs vector and its kinematic equation).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import casadi as ca
import numpy as np

from flexlib import Component, Parameter, Variable, der, eq
from flexlib.errors import ModelError

from ..multibody.frames import equality_constraint, skew
from ..multibody.interfaces import Frame
from ..multibody.quaternions import floating_frame_equations, quaternion_to_T
from ..multibody.world import World, gravity_of
from .modal_data import ModalData
from .selection import default_damping_ratio, select_modes

__all__ = ["FlexibleBody", "cayley_rotation", "frame_names", "inertial_load_amplitudes"]

_LETTERS = "abcdefghijklmnopqrstuvwxyz"
#: Mode-shape entries at a frame below this fraction of the mode's largest entry are round-off (set to zero).
SHAPE_ZERO = 1e-9
_COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")


def frame_names(n: int) -> list[str]:
    """Connector names of ``n`` frames: ``frame_a``, ``frame_b``, … (``frame_z``, then ``frame_26``, …)."""
    return [f"frame_{_LETTERS[i]}" if i < len(_LETTERS) else f"frame_{i}" for i in range(n)]


def _cayley(theta: Any, theta_dot: Any) -> tuple[Any, Any]:
    """Exact rotation ``T_rel`` (body → node frame) of a small-rotation vector ``theta`` [rad] and the relative
    angular velocity [rad/s] resolved in the node frame, from ``theta_dot`` [rad/s] (module docstring)."""
    a, ad = theta / 2, theta_dot / 2
    A = skew(a)
    k = 2 / (1 + ca.dot(a, a))
    return ca.SX.eye(3) + k * (ca.mtimes(A, A) - A), k * (ad - ca.cross(a, ad))


class FlexibleBody(Component):
    """Flexible body in the floating frame of reference with modal superposition (module docstring).

    Parameters
    ----------
    modal_data : ModalData or path
        The body's modal data, or the path of its HDF5 modal file (``docs/modal_file.md``); read and validated
        once. The compiled-model cache keys on the data's content (:meth:`ModalData.content_hash`), not on
        the path.
    modes : int or sequence of int, optional
        The modes to keep: a count (the lowest ``modes`` in frequency) or indices into the file's modes.
        Default: all. ``0`` gives the rigid body.
    max_frequency : float, optional
        Keep only modes at or below this frequency [Hz] (with ``modes`` as a count: both apply).
    frames : sequence of int, optional
        Node ids that get a frame connector, named ``frame_a``, ``frame_b``, … in this order (see
        :func:`frame_names`); default: the file's interface nodes. :meth:`frame_at` finds a node's frame.
    damping : mapping of int to float, optional
        Modal damping ratios [1] replacing, per kept mode (index into the kept modes), the file's or the
        default rule (1 % below 100 Hz, 10 % to 1000 Hz, 100 % above). The ratios are the tunable parameter
        ``zeta``.
    geometric_stiffening : bool
        Add the geometric stiffness of the file's unit load cases (needs ``/geometric_stiffness`` in the
        file: ``modal_data_from_fe(..., geometric_stiffening=True)``).
    q_fixed : bool, optional
        How the start values of ``q`` and ``qd`` (zero: undeformed and at rest, unless ``init``/``guess`` give
        others) enter the initialisation. Default (``None``): as initial conditions where the model needs them
        — a mode that joints lock, or that ``run(steady_state=True)`` determines, takes its value from the
        equations (``Component.set_start(fixed="default")``). ``True``: always initial conditions; ``False``:
        guesses only.
    orientation_fixed, w_fixed : bool
        A free body (nothing orients it): its start orientation ``Q_start`` / angular velocity ``w_start`` are
        initial conditions (as :class:`~..multibody.body.Body`).

    Tunable parameters: ``zeta`` (M,) [1] modal damping ratios; ``Q_start`` (4,) [1] start orientation of
    ``frame_a`` of a free body; ``w_start`` (3,) [rad/s] start angular velocity of the reference frame.

    Connectors
    ----------
    frame_a, frame_b, … : Frame
        One per node in ``frames``, at the deformed node, rotated with the node's elastic rotation.

    Variables
    ---------
    r_0 [m], v_0 [m/s], a_0 [m/s2]: reference-frame origin in the world; w [rad/s], z [rad/s2]: its angular
    velocity and acceleration in body axes; alpha [m/s2]: ``α = T (a_0 − g)``, the origin's acceleration less
    gravity in body axes, from the entry frame (module docstring); q [1], qd [1/s], qdd [1/s2]: modal coordinates and
    their rates (absent with zero modes; a mode shape is metres per unit ``q``); Q [1]: quaternion of ``frame_a`` of
    a free body.
    """

    #: Small-motion (elastic) coordinates: held by ``flexlib.analysis.modal_analysis(lock="rigid")`` to find the
    #: mechanism's rigid degrees of freedom
    elastic_coordinates = ("q",)

    Q_start = Parameter([0.0, 0.0, 0.0, 1.0], unit="1", shape=4, doc="Start orientation quaternion of frame_a")
    w_start = Parameter([0.0, 0.0, 0.0], unit="rad/s", shape=3, doc="Start angular velocity of the reference frame")
    r_0 = Variable(unit="m", shape=3, state_select="avoid", doc="Reference-frame origin resolved in world")
    v_0 = Variable(unit="m/s", shape=3, state_select="avoid", doc="Velocity of the reference origin in world")
    a_0 = Variable(unit="m/s2", shape=3, doc="Acceleration of the reference origin in world")
    w = Variable(unit="rad/s", shape=3, state_select="avoid", doc="Angular velocity of the reference frame, body axes")
    z = Variable(unit="rad/s2", shape=3, doc="Angular acceleration of the reference frame, body axes")
    alpha = Variable(unit="m/s2", shape=3, doc="Acceleration of the reference origin less gravity, body axes")
    Q = Variable(unit="1", shape=4, start=[0.0, 0.0, 0.0, 1.0], state_select="prefer",
                 doc="Orientation quaternion of frame_a; used only by a free body")

    def __init__(self, modal_data: ModalData | str | os.PathLike[str], *, modes: int | Sequence[int] | None = None,
                 max_frequency: float | None = None, frames: Sequence[int] | None = None,
                 damping: Mapping[int, float] | None = None, geometric_stiffening: bool = False,
                 q_fixed: bool | None = None, orientation_fixed: bool = False, w_fixed: bool = False,
                 **kwargs: Any) -> None:
        data = modal_data if isinstance(modal_data, ModalData) else ModalData.read(modal_data)
        data = _choose_modes(data, modes, max_frequency)
        deferred = {k: kwargs.pop(k) for k in ("zeta", "init", "guess", "state_select") if k in kwargs}
        super().__init__(**kwargs)
        self._data = data
        self._source = str(modal_data) if not isinstance(modal_data, ModalData) else data.title
        self.orientation_fixed = bool(orientation_fixed)
        self.w_fixed = bool(w_fixed)
        self.geometric_stiffening = bool(geometric_stiffening)
        nodes = [int(n) for n in (data.interface_nodes if frames is None else frames)]
        if not nodes:
            raise ModelError(f"{type(self).__name__}: no frames (the modal data {data.title!r} has no interface "
                             "nodes; pass frames=[node ids])")
        if len(set(nodes)) != len(nodes):
            raise ModelError(f"{type(self).__name__}: frames {nodes} name a node twice")
        for node in nodes:
            try:
                data.node_index(node)
            except KeyError:
                raise ModelError(f"{type(self).__name__}: frames: node {node} is not in the modal data "
                                 f"{self._source!r} (nodes {int(data.node_ids.min())}..{int(data.node_ids.max())})")\
                    from None
        self.frame_nodes = tuple(nodes)
        if self.geometric_stiffening and data.geometric_stiffness is None:
            raise ModelError(f"{type(self).__name__}: geometric_stiffening=True, but the modal data "
                             f"{self._source!r} has no '/geometric_stiffness' (build it with "
                             "modal_data_from_fe(..., geometric_stiffening=True))")
        names = frame_names(len(nodes))
        for name in names:
            setattr(self, name, Frame(doc=f"Frame at node {nodes[names.index(name)]}"))
        self._frames = [getattr(self, n) for n in names]
        for other in self._frames[1:]:
            self.branch(self._frames[0], other)
        self.potential_root(self._frames[0])
        m = data.n_modes
        if m:
            zeta = default_damping_ratio(data.frequencies) if data.damping_ratio is None else data.damping_ratio
            zeta = np.array(zeta, dtype=float)
            for mode, value in (damping or {}).items():
                if not 0 <= int(mode) < m:
                    raise ModelError(f"{type(self).__name__}: damping given for mode {mode}, but {m} modes are kept")
                zeta[int(mode)] = float(value)
            self.zeta = Parameter(zeta, unit="1", shape=m, min=0.0, doc="Modal damping ratios")
            q_nom, qd_nom = _modal_nominals(data)
            self.q = Variable(unit="1", shape=m, start=np.zeros(m), state_select="prefer", nominal=q_nom,
                              doc="Modal coordinates")
            self.qd = Variable(unit="1/s", shape=m, start=np.zeros(m), state_select="prefer", nominal=qd_nom,
                               doc="Modal velocities der(q)")
            self.qdd = Variable(unit="1/s2", shape=m, error_test=False, doc="Modal accelerations der(qd)")
            fixed = "default" if q_fixed is None else bool(q_fixed)
            self.set_start("q", np.zeros(m), fixed=fixed)
            self.set_start("qd", np.zeros(m), fixed=fixed)
        elif damping:
            raise ModelError(f"{type(self).__name__}: damping given, but no modes are kept")
        if "zeta" in deferred:
            zeta_given = deferred.pop("zeta")
            if m or np.size(zeta_given):  # an empty zeta fits a body without modes
                self._assign("zeta", zeta_given)
        for name, value in (deferred.get("init") or {}).items():
            self.set_start(name, value, fixed=True)
        for name, value in (deferred.get("guess") or {}).items():
            self.set_start(name, value, fixed=False)
        for name, value in (deferred.get("state_select") or {}).items():
            self.set_state_select(name, value)
        q0 = self.parameter_value("Q_start")
        if np.linalg.norm(q0) > 1e-12:
            self.set_start("Q", q0 / np.linalg.norm(q0), fixed=False)

    # ------------------------------------------------------------------ data access
    @property
    def modal_data(self) -> ModalData:
        """The (selected) modal data the equations are built from."""
        return self._data

    @property
    def n_modes(self) -> int:
        """Number of kept modes."""
        return self._data.n_modes

    def frame_at(self, node: int) -> Frame:
        """The frame connector at node id ``node``."""
        if int(node) not in self.frame_nodes:
            raise ModelError(f"{self.where}: node {node} has no frame (frames at nodes {list(self.frame_nodes)})")
        return self._frames[self.frame_nodes.index(int(node))]

    def motion(self, result: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The body's motion in a simulation result, for :mod:`.output` (deformation, stress, VTK, animation).

        Parameters
        ----------
        result : Result
            A result of a model containing this body.

        Returns
        -------
        t : ndarray (nt,)
            Times [s].
        q : ndarray (nt, M)
            Modal coordinates [1].
        r_0 : ndarray (nt, 3)
            Reference-frame origin in the world [m].
        T : ndarray (nt, 3, 3)
            Reference-frame orientation, world → body [1] (from ``frame_a`` and its elastic rotation).
        """
        t = np.asarray(result.t, dtype=float)
        nt = t.size
        q = np.asarray(result[f"{self.path}.q"], dtype=float).reshape(nt, -1) if self.n_modes else np.zeros((nt, 0))
        T_a = np.asarray(result[f"{self.path}.frame_a.T"], dtype=float).reshape(nt, 3, 3, order="F")
        Psi = self._node_shapes(self.frame_nodes[0])[2]
        T_rel = cayley_rotation(q @ Psi.T if self.n_modes else np.zeros((nt, 3)))
        T = np.einsum("kji,kjl->kil", T_rel, T_a)  # T_rel^T T_a
        return t, q, np.asarray(result[f"{self.path}.r_0"], dtype=float).reshape(nt, 3), T

    def load_amplitudes(self, result: Any) -> np.ndarray:
        """Amplitudes of the modal data's unit load cases over a result, for mode-acceleration recovery.

        ``acc_*``: ``T (a_0 − g)``, the reference origin's acceleration less gravity in body axes [m/s2];
        ``alpha_*``: ``z`` [rad/s2]; ``omega_aa``: ``w_a²``, ``omega_ab``: ``w_a w_b`` [rad2/s2]; ``F{node}_{c}``:
        the cut force [N] or torque [N m] on the body at that node's frame, in body axes (zero at an interface node
        without a frame). These are the loads the equations apply, so ``Phi q + sum_c R_c l_c`` (with
        :meth:`ModalData.residual_fields`) is the mode-acceleration recovery of the deformation.

        Parameters
        ----------
        result : Result
            A result of a model containing this body.

        Returns
        -------
        ndarray (nt, C)
            Amplitudes in the order of ``modal_data.load_cases``.

        Raises
        ------
        ValueError
            The modal data hold no static load responses.
        """
        d = self._data
        if d.load_cases is None:
            d.residual_fields()  # raises the explanatory error
        t, _q, _r0, T = self.motion(result)
        nt = t.size
        g = _result_gravity(self, result)
        a_0 = np.asarray(result[f"{self.path}.a_0"], dtype=float).reshape(nt, 3)
        w = np.asarray(result[f"{self.path}.w"], dtype=float).reshape(nt, 3)
        z = np.asarray(result[f"{self.path}.z"], dtype=float).reshape(nt, 3)
        values = inertial_load_amplitudes(np.einsum("kij,kj->ki", T, a_0 - g), z, w)
        for node, frame in zip(self.frame_nodes, frame_names(len(self.frame_nodes)), strict=True):
            Tf = np.asarray(result[f"{self.path}.{frame}.T"], dtype=float).reshape(nt, 3, 3, order="F")
            to_body = np.einsum("kij,klj->kil", T, Tf)  # T_body T_frame^T = T_rel^T
            for kind, offset in (("f", 0), ("t", 3)):
                load = np.einsum("kij,kj->ki", to_body, np.asarray(result[f"{self.path}.{frame}.{kind}"],
                                                                      dtype=float).reshape(nt, 3))
                for i in range(3):
                    values[f"F{node}_{_COMPONENTS[offset + i]}"] = load[:, i]
        carried = {int(k) for k in d.interface_nodes}  # the reduction made load cases for all their free DOFs
        for node, frame in zip(self.frame_nodes, frame_names(len(self.frame_nodes)), strict=True):
            if node not in carried and np.abs(np.column_stack(
                    [values[f"F{node}_{c}"] for c in _COMPONENTS])).max(initial=0.0) > 0.0:
                raise ValueError(f"{self.path}.{frame}: loads at node {node}, but the modal data {d.title!r} hold no "
                                 f"static responses for loads there (its load cases cover the interface nodes "
                                 f"{sorted(carried)}): make node {node} an interface node of the "
                                 "reduction for mode-acceleration recovery")
        zero = np.zeros(nt)
        return np.column_stack([values.get(c, zero) for c in d.load_cases]) if d.load_cases else np.zeros((nt, 0))

    def structure_key(self) -> Any:
        """The modal data's content hash: a changed file rebuilds the compiled model, a moved one does not."""
        return self._data.content_hash()

    # ------------------------------------------------------------------ equations
    def initial_equations(self):
        """``orientation_fixed``: frame_a's start orientation; ``w_fixed``: the reference frame's angular velocity."""
        out = []
        if self.orientation_fixed:
            q0 = self.Q_start / ca.norm_2(self.Q_start)
            out.append(eq(equality_constraint(quaternion_to_T(q0), self._frames[0].T), 0.0, label="start orientation"))
        if self.w_fixed:
            out.append(eq(self.w, self.w_start, label="start angular velocity"))
        return out

    def _node_shapes(self, node: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Undeformed position [m], translational (3, M) [m] and rotational (3, M) [rad] mode shapes at ``node``.

        Entries below ``SHAPE_ZERO`` times the mode's largest translation (rotation) over all nodes are round-off
        of the reduction (a planar mode's out-of-plane components at 1e-13): they are set to exact zeros, so the
        structure of the frame equations is the physics' (a planar loop keeps its redundant rows redundant)."""
        d = self._data
        i = d.node_index(node)
        out = []
        for shapes in (d.translational_modes, d.rotational_modes):
            scale = np.abs(shapes).max(axis=(1, 2)) if d.n_modes else np.zeros(0)
            at = shapes[:, i, :].T.copy()
            at[np.abs(at) <= SHAPE_ZERO * scale[None, :]] = 0.0
            out.append(at)
        return d.coordinates[i], out[0], out[1]

    def equations(self):
        d, inv = self._data, self._data.invariants
        m = d.n_modes
        zero = ca.SX.zeros(0, 1)
        q, qd, qdd = (self.q, self.qd, self.qdd) if m else (zero, zero, zero)
        w, z = self.w, self.z

        def lin(A: np.ndarray, x: Any) -> Any:  # A (..., M) · x, with numeric A and symbolic x
            return ca.mtimes(ca.DM(A), x) if m else ca.SX.zeros(A.shape[0], 1)

        # per-frame kinematics in body axes: position x_k, exact elastic rotation T_rel,k, relative w_k
        kin = []
        for node in self.frame_nodes:
            s, Phi, Psi = self._node_shapes(node)
            x = ca.DM(s) + lin(Phi, q)
            if m and np.any(Psi):
                T_rel, w_rel = _cayley(lin(Psi, q), lin(Psi, qd))
            else:
                T_rel, w_rel = ca.SX.eye(3), ca.SX.zeros(3, 1)
            kin.append((x, T_rel, w_rel, Phi, Psi))

        frames = self._frames
        entry = next((k for k in range(1, len(frames)) if self.rooted(frames[k])), 0)
        e = frames[entry]
        x_e, Tr_e, wr_e = kin[entry][:3]
        T = ca.mtimes(Tr_e.T, e.T)  # world -> body
        eqs = []
        if entry == 0 and self.is_root(e):
            eqs += floating_frame_equations(e, self.Q)
        else:
            eqs.append(eq(self.Q, [0.0, 0.0, 0.0, 1.0]))
        eqs += [
            eq(w, ca.mtimes(Tr_e.T, e.w - wr_e)),
            eq(self.r_0, e.r_0 - ca.mtimes(T.T, x_e)),
        ]
        # velocities and accelerations along the tree (recursive kinematics): a frame's origin x_k(q) moves with
        # xd = Phi_k qd, xdd = Phi_k qdd in body axes; its angular velocity Tr_k w + wr_k(q, qd) changes at the
        # rate d/dt of that expression (componentwise in the frame: the frame's z)
        qq = ca.vertcat(q, qd) if m else ca.SX.zeros(0, 1)
        qqd = ca.vertcat(qd, qdd) if m else ca.SX.zeros(0, 1)

        def rates(k: int) -> tuple:
            x_k, Tr_k, wr_k, Phi_k, _ = kin[k]
            xd, xdd = lin(Phi_k, qd), lin(Phi_k, qdd)
            wk = ca.mtimes(Tr_k, w) + wr_k
            zk = ca.mtimes(Tr_k, z) + (ca.jtimes(wk, qq, qqd) if m else ca.SX.zeros(3, 1))
            return x_k, xd, xdd, zk

        _, xd_e, xdd_e, z_e = rates(entry)
        g = gravity_of(self)

        def acc(x: Any, xd: Any, xdd: Any) -> Any:  # a material point's acceleration relative to the origin, body axes
            return ca.cross(z, x) + ca.cross(w, ca.cross(w, x)) + 2 * ca.cross(w, xd) + xdd

        alpha = self.alpha  # T (a_0 - g): the origin's acceleration less gravity, body axes
        v_origin = ca.mtimes(Tr_e.T, e.v) - ca.cross(w, x_e) - xd_e  # origin velocity, body axes
        if entry == 0 and self.is_root(e):
            eqs += [eq(der(self.r_0), self.v_0), eq(der(self.v_0), self.a_0), eq(der(w), z),
                    eq(alpha, ca.mtimes(T, self.a_0 - g), label="acceleration in body axes"),
                    eq(e.v, ca.mtimes(Tr_e, ca.mtimes(T, self.v_0) + ca.cross(w, x_e) + xd_e)),
                    eq(e.a, ca.mtimes(Tr_e, alpha + acc(x_e, xd_e, xdd_e))), eq(e.z, z_e)]
        else:
            eqs += [eq(alpha, ca.mtimes(Tr_e.T, e.a) - acc(x_e, xd_e, xdd_e), label="acceleration in body axes"),
                    eq(self.v_0, ca.mtimes(T.T, v_origin)), eq(self.a_0, ca.mtimes(T.T, alpha) + g), eq(e.z, z_e)]
        for k, f in enumerate(frames):
            if k != entry:
                x, Tr, wr = kin[k][:3]
                _, xd, xdd, z_k = rates(k)
                # written from the entry frame (not from r_0): the frame chain stays explicit in frame
                # variables, as the loop-redundancy analysis needs (flexlib.compile.redundancy)
                eqs += [eq(f.r_0, e.r_0 + ca.mtimes(T.T, x - x_e)), eq(f.T, ca.mtimes(Tr, T)),
                        eq(f.w, ca.mtimes(Tr, w) + wr),
                        eq(f.v, ca.mtimes(Tr, v_origin + ca.cross(w, x) + xd)),
                        eq(f.a, ca.mtimes(Tr, alpha + acc(x, xd, xdd))), eq(f.z, z_k)]
        if m:
            eqs += [eq(der(q), qd), eq(der(qd), qdd)]

        # loads of the frames in body axes, their resultant about the reference origin and modal projection
        F = ca.SX.zeros(3, 1)
        Mo = ca.SX.zeros(3, 1)
        Qf = ca.SX.zeros(m, 1)
        loads = []
        for f, (x, Tr, _wr, Phi, Psi) in zip(frames, kin, strict=True):
            Fk, Mk = ca.mtimes(Tr.T, f.f), ca.mtimes(Tr.T, f.t)
            loads.append((Fk, Mk))
            F += Fk
            Mo += ca.cross(x, Fk) + Mk
            if m:
                Qf += ca.mtimes(ca.DM(Phi.T), Fk) + ca.mtimes(ca.DM(Psi.T), Mk)

        mass = float(inv["I1"])
        alpha = self.alpha
        I3 = inv["I3"]
        c = ca.DM(inv["I2"]) + lin(I3, q)
        I8 = inv["I8"]  # (M, 3, 3)
        if m:
            # B_j = sum_k q_k I9[j, k]   (M x 3 x 3, linear in q)
            B = ca.reshape(ca.mtimes(ca.DM(inv["I9"].transpose(0, 2, 3, 1).reshape(m * 9, m)), q), 9, m)
            # column j of B (3x3, row-major flattened) -> matrix; I8 likewise
            def mat(flat: Any) -> Any:
                return ca.reshape(flat, 3, 3).T

            I8q = mat(ca.mtimes(ca.DM(I8.reshape(m, 9).T), q))      # sum_j q_j I8_j
            Bq = mat(ca.mtimes(B, q))                                 # sum_j q_j B_j
            J = ca.DM(inv["I7"]) + I8q + I8q.T + Bq
            I5 = inv["I5"]  # (M, 3, M): I5[j] = sum m phi~_j Phi
            C = ca.DM(inv["I4"]) + ca.reshape(ca.mtimes(ca.DM(I5.transpose(1, 2, 0).reshape(3 * m, m)), q), m, 3).T
            Jd = mat(ca.mtimes(ca.DM(I8.reshape(m, 9).T), qd)) + mat(ca.mtimes(B, qd))  # dJ/dt = Jd + Jd^T
            cor_rot = ca.mtimes(Jd + Jd.T, w) + ca.cross(w, ca.mtimes(C, qd))
            I5qd = ca.reshape(ca.mtimes(ca.DM(I5.transpose(1, 2, 0).reshape(3 * m, m)), qd), m, 3).T  # 3 x M
            h_w = ca.vertcat(*[-ca.mtimes(ca.mtimes(w.T, mat(ca.DM(I8[j].reshape(9))).T + mat(B[:, j])), w)
                               for j in range(m)])
            h_c = 2 * ca.mtimes(I5qd.T, w)
            omega = 2 * np.pi * d.frequencies
            D = 2 * self.zeta * ca.DM(omega * np.diag(d.generalized_mass))
            Kq = ca.mtimes(ca.DM(d.generalized_stiffness), q)
            if self.geometric_stiffening:
                KGq, S = self._geometric_stiffness(q, alpha, z, w, loads)
                Kq += KGq
                # the centrifugal part as kinetic energy -1/2 w^T S(q) w (foreshortening): its rotational terms
                Sd = ca.reshape(ca.jtimes(ca.vec(S), q, qd), 3, 3)
                cor_rot -= ca.mtimes(S, z) + ca.mtimes(Sd, w) + ca.cross(w, ca.mtimes(S, w))
            eqs += [
                eq(mass * alpha + ca.cross(z, c) + ca.cross(w, ca.cross(w, c)) + 2 * ca.cross(w, lin(I3, qd))
                   + lin(I3, qdd), F, label="translation"),
                eq(ca.cross(c, alpha) + ca.mtimes(J, z) + ca.cross(w, ca.mtimes(J, w)) + cor_rot
                   + ca.mtimes(C, qdd), Mo, label="rotation"),
                eq(ca.mtimes(ca.DM(I3.T), alpha) + ca.mtimes(C.T, z) + ca.mtimes(ca.DM(inv["I6"]), qdd) + h_w + h_c
                   + D * qd + Kq, Qf, label="modal"),
            ]
        else:
            J = ca.DM(inv["I7"])
            eqs += [
                eq(mass * alpha + ca.cross(z, c) + ca.cross(w, ca.cross(w, c)), F, label="translation"),
                eq(ca.cross(c, alpha) + ca.mtimes(J, z) + ca.cross(w, ca.mtimes(J, w)), Mo, label="rotation"),
            ]
        return eqs

    def _geometric_stiffness(self, q: Any, alpha: Any, z: Any, w: Any, loads: list) -> tuple[Any, Any]:
        """``K_G q`` with ``K_G = Σ_c λ_c G_c`` over the file's unit load cases, and the centrifugal inertia
        ``S(q)`` (3×3) with ``S_aa = qᵀ G_ωaa q``, ``S_ab = ½ qᵀ G_ωab q`` (module docstring)."""
        G = self._data.geometric_stiffness
        axes = "xyz"
        weights: dict[str, Any] = {}
        for a in range(3):
            weights[f"acc_{axes[a]}"] = alpha[a]
            weights[f"alpha_{axes[a]}"] = z[a]
            weights[f"omega_{axes[a]}{axes[a]}"] = w[a] * w[a]
        for a, b in ((0, 1), (1, 2), (2, 0)):
            weights[f"omega_{axes[a]}{axes[b]}"] = w[a] * w[b]
        for node, (Fk, Mk) in zip(self.frame_nodes, loads, strict=True):
            for i, comp in enumerate(_COMPONENTS):
                weights[f"F{node}_{comp}"] = Fk[i] if i < 3 else Mk[i - 3]
        out = ca.SX.zeros(q.shape[0], 1)
        S = ca.SX.zeros(3, 3)
        for name, Gc in sorted(G.items()):
            lam = weights.get(name)
            if lam is None or not np.any(Gc):  # a node without a frame carries no load here
                continue
            Gq = ca.mtimes(ca.DM(Gc), q)
            out += lam * Gq
            if name.startswith("omega_"):
                a, b = axes.index(name[-2]), axes.index(name[-1])
                if a == b:
                    S[a, a] = ca.dot(q, Gq)
                else:
                    S[a, b] = S[b, a] = 0.5 * ca.dot(q, Gq)
        return out, S


def _modal_nominals(data: ModalData) -> tuple[float, float]:
    """Nominal sizes of the modal coordinates [1] and rates [1/s]: the ``q`` that deflects the body by 1e-3 of its
    size (small elastic deformation), and that ``q`` oscillating at the lowest modal frequency. They scale the
    integrator's absolute tolerance and the loop-redundancy rank test (``flexlib.compile.redundancy``)."""
    size = float(np.linalg.norm(np.ptp(data.coordinates, axis=0))) or 1.0
    shape = float(np.abs(data.translational_modes).max())
    if not shape > 0:  # rotation-only modes
        shape = float(np.abs(data.rotational_modes).max()) * size
    q_nom = 1e-3 * size / shape if shape > 0 else 1.0
    f = data.frequencies[data.frequencies > 0]
    return q_nom, q_nom * 2 * np.pi * (float(f.min()) if f.size else 1.0)


def _choose_modes(data: ModalData, modes: int | Sequence[int] | None, max_frequency: float | None) -> ModalData:
    if modes is None or isinstance(modes, (int, np.integer)):
        if modes is not None and int(modes) < 0:
            raise ModelError(f"FlexibleBody: modes must be >= 0, got {modes}")
        if modes is None and max_frequency is None:
            return data
        return select_modes(data, count=None if modes is None else int(modes), max_frequency=max_frequency)
    idx = [int(i) for i in modes]
    bad = [i for i in idx if not 0 <= i < data.n_modes]
    if bad:
        raise ModelError(f"FlexibleBody: modes {bad} are not in the modal data {data.title!r} "
                         f"({data.n_modes} modes: 0..{data.n_modes - 1})")
    out = data.select(idx)
    return out if max_frequency is None else select_modes(out, max_frequency=max_frequency)


def inertial_load_amplitudes(alpha: np.ndarray, z: np.ndarray, w: np.ndarray) -> dict[str, np.ndarray]:
    """Amplitudes of the inertial unit load cases (:func:`~.geometric.inertial_load_cases`) of a reference frame
    with origin acceleration less gravity ``alpha`` [m/s2], angular acceleration ``z`` [rad/s2] and angular
    velocity ``w`` [rad/s], all (nt, 3) in body axes: ``acc_*``, ``alpha_*``, ``omega_aa`` = ``w_a²``,
    ``omega_ab`` = ``w_a w_b``."""
    axes = "xyz"
    values: dict[str, np.ndarray] = {}
    for a in range(3):
        values[f"acc_{axes[a]}"] = alpha[:, a]
        values[f"alpha_{axes[a]}"] = z[:, a]
        values[f"omega_{axes[a]}{axes[a]}"] = w[:, a] ** 2
    for a, b in ((0, 1), (1, 2), (2, 0)):
        values[f"omega_{axes[a]}{axes[b]}"] = w[:, a] * w[:, b]
    return values


def cayley_rotation(theta: np.ndarray) -> np.ndarray:
    """The exact rotation ``T_rel`` (body → node axes) a frame gets from its node's elastic rotation vector.

    The Cayley map of ``a = theta / 2``: ``T_rel = I + 2 (A² − A) / (1 + |a|²)`` with ``A = [a×]``; orthogonal
    for any ``theta`` and ``I − [theta×]`` to first order (the frame equations of :class:`FlexibleBody`).

    Parameters
    ----------
    theta : ndarray (..., 3)
        Small-rotation vectors [rad] in body axes.

    Returns
    -------
    ndarray (..., 3, 3)
    """
    a = np.asarray(theta, dtype=float) / 2
    A = np.zeros((*a.shape[:-1], 3, 3))
    A[..., 0, 1], A[..., 0, 2], A[..., 1, 2] = -a[..., 2], a[..., 1], -a[..., 0]
    A -= np.swapaxes(A, -1, -2)
    k = (2 / (1 + np.einsum("...a,...a->...", a, a)))[..., None, None]
    return np.eye(3) + k * (A @ A - A)


def _result_gravity(body: Any, result: Any) -> np.ndarray:
    """The World's gravity vector [m/s2] used in ``result`` (its recorded parameters, else the model's)."""
    worlds = [n for n in body.root.walk() if isinstance(n, World)]
    if len(worlds) != 1:
        raise ModelError(f"{body.path}: the model needs exactly one World (found {len(worlds)})")
    world = worlds[0]
    params = getattr(result, "parameters", {}) or {}

    def value(name: str, shape: int | None) -> np.ndarray:
        default = np.asarray(world.parameter_value(name), dtype=float)
        if shape is None:
            key = f"{world.path}.{name}"
            return np.asarray(params[key][0], dtype=float) if key in params else default
        keys = [f"{world.path}.{name}[{i}]" for i in range(shape)]
        return np.array([params[k][0] for k in keys], dtype=float) if all(k in params for k in keys) else default

    g, n = float(value("g", None)), value("n", 3)
    return g * n / np.linalg.norm(n)
