"""Flexible body: floating frame of reference with modal superposition (the modal body of Adams/Flex, SIMPACK's
SID body, DLR's ``FlexibleBodies`` library and Modelica's seed-000 ``FlexibleBody``).

The body's material points move with a floating reference frame ``R`` (origin ``r_0`` in the world, orientation
``T`` world → body, angular velocity ``w`` resolved in ``R``) plus a small elastic displacement in body axes,
``u_p = Φ_p q``, spanned by the modes of a :class:`~flexlib.fe.modal_data.ModalData` (translational ``Φ_p``, rotational
``Φ*_p`` per node) with modal coordinates ``q``. With the nine inertia invariants ``I1 … I9`` (see
:mod:`flexlib.fe.invariants`), the first moment ``c(q) = I2 + I3 q``, the inertia tensor about the reference origin
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
(:mod:`flexlib.fe.geometric`) weighted by the current loads ``λ``: ``α`` (cases ``acc_*``), ``ż`` (``alpha_*``), the
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
from flexlib.errors import ModelError, ParameterError
from flexlib.fe.geometric import inertial_load_amplitudes
from flexlib.fe.modal_data import ModalData
from flexlib.fe.selection import ParticipationTable, default_damping_ratio

from ..multibody.frames import equality_constraint, skew
from ..multibody.interfaces import Frame
from ..multibody.quaternions import floating_frame_equations, quaternion_to_T
from ..multibody.world import gravity_of
from .arguments import (
    check_stiffening_data,
    check_zeta,
    choose_modes,
    damping_ratios,
    deferred_arguments,
    flag,
    frame_names,
    frame_nodes,
    is_int,
    is_real,
    modal_nominals,
    modal_source,
    modal_start,
)
from .results import (
    advise_basis,
    cayley_rotation,
    check_result,
    frame_load_amplitudes,
    participation,
    prefetch_body,
    result_gravity,
)
from .validity import check_limits, validity

__all__ = ["FlexibleBody"]

#: Mode-shape entries at a frame below this fraction of the mode's largest entry are round-off (set to zero).
SHAPE_ZERO = 1e-9
_COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")


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
    modes : int, sequence of int or ParticipationTable, optional
        The modes to keep: an ``int`` count (the lowest ``modes`` in frequency; at most the file's number of
        modes), a list of distinct indices into the file's modes (``[]``: none), or the participation table of
        :meth:`participation` (the modes it keeps: the MPF selection). Default: all. ``0`` gives the rigid body.
        Anything else (a string such as ``"4"``, a float, a bool, a nested list) is refused.
    plane : {"xy", "yz", "xz"}, optional
        Keep only modes that move the body in this plane of its axes (:func:`~flexlib.fe.planar_modes`); with
        ``modes`` a count, the lowest ``modes`` of them (``modes=4, plane="xy"``: a planar mechanism's four lowest
        in-plane modes, whatever the section's out-of-plane stiffness).
    max_frequency : float, optional
        Keep only modes at or below this frequency [Hz], ``>= 0`` (with ``modes`` as a count: both apply); a
        cut-off that keeps no mode of a body that has modes is refused (``modes=0`` is the rigid body).
    frames : sequence of int, optional
        Node ids (at least one, distinct) that get a frame connector, named ``frame_a``, ``frame_b``, … in this
        order (see :func:`frame_names`); default: the file's interface nodes. :meth:`frame_at` finds a node's
        frame.
    damping : float, sequence of float or mapping of int to float, optional
        Modal damping ratios [1] (fractions of critical, each in ``[0, 1]``: ``0.02`` is 2 %) replacing the
        file's or the default rule (1 % below 100 Hz, 10 % to 1000 Hz, 100 % above): one number for every kept
        mode (``0.0``: undamped), one per kept mode, or ``{mode: ratio}`` for some kept modes (indices into the
        kept modes). The ratios are the tunable parameter ``zeta`` (give ``damping`` or ``zeta``, not both).
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
    validity : mapping or False, optional
        Limits of the validity monitors checked after every run (:mod:`.validity`): ``deflection`` [1, fraction of
        the characteristic length, default 0.1], ``rotation`` [rad, 0.2], ``residual`` [1, share of the left-out
        modes in the recovered displacement, 0.2]; a run past one warns (``ModalValidityWarning``) and every run
        has the summary in ``result.stats["validity"][path]``. ``False``: no monitors.

    Tunable parameters: ``zeta`` (M,) [1] modal damping ratios; ``Q_start`` (4,) [1] start orientation of
    ``frame_a`` of a free body; ``w_start`` (3,) [rad/s] start angular velocity of the reference frame.

    Connectors
    ----------
    frame_a, frame_b, … : Frame
        One per node in ``frames``, at the deformed node, rotated with the node's elastic rotation.

    Variables
    ---------
    q : 1, shape (m,)
        Modal coordinates, one per kept mode (absent with zero modes; a mode shape is metres per unit ``q``).
    qd : 1/s, shape (m,)
        Modal velocities ``der(q)``.
    qdd : 1/s2, shape (m,)
        Modal accelerations ``der(qd)``.
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
    alpha = Variable(unit="m/s2", shape=3,

                         doc=("Acceleration of the reference origin less gravity, body axes: ``T (a_0 - g)``, from the "
                              "entry frame"))
    Q = Variable(unit="1", shape=4, start=[0.0, 0.0, 0.0, 1.0], state_select="prefer",
                 doc="Orientation quaternion of frame_a; used only by a free body")

    def __init__(self, modal_data: ModalData | str | os.PathLike[str], *,
                 modes: int | Sequence[int] | ParticipationTable | None = None, max_frequency: float | None = None,
                 plane: str | None = None, frames: Sequence[int] | None = None,
                 damping: Mapping[int, float] | None = None, geometric_stiffening: bool = False,
                 q_fixed: bool | None = None, orientation_fixed: bool = False, w_fixed: bool = False,
                 validity: Mapping[str, float] | bool | None = None, **kwargs: Any) -> None:
        all_modes, source = modal_source(modal_data)
        data = choose_modes(all_modes, modes, max_frequency, source, plane)
        deferred = deferred_arguments(kwargs)
        super().__init__(**kwargs)
        self._data, self._all_modes = data, all_modes
        self._validity = check_limits(validity)
        self._source = source  # how messages name the data: "modal file 'arm.h5'" or "modal data 'arm'"
        self.orientation_fixed = flag("orientation_fixed", orientation_fixed)
        self.w_fixed = flag("w_fixed", w_fixed)
        self.geometric_stiffening = flag("geometric_stiffening", geometric_stiffening)
        q_fixed = None if q_fixed is None else flag("q_fixed", q_fixed, "True, False or None")
        nodes = frame_nodes(data, frames, source)
        self.frame_nodes = tuple(nodes)
        if self.geometric_stiffening:
            check_stiffening_data(type(self).__name__, data, source)
        self._declare_frames(nodes)
        if "zeta" in deferred and damping is not None:
            raise ModelError(f"{type(self).__name__}: both damping={damping!r} and zeta are given: damping sets the "
                             "parameter zeta (the modal damping ratios); give one of them")
        self._declare_modes(damping, q_fixed)
        self._apply_starts(deferred)

    def _declare_frames(self, nodes: list[int]) -> None:
        """One frame connector per node, ``frame_a`` the root of the body's frames."""
        names = frame_names(len(nodes))
        for name in names:
            setattr(self, name, Frame(doc=f"Frame at node {nodes[names.index(name)]}"))
        self._frames = [getattr(self, n) for n in names]
        for other in self._frames[1:]:
            self.branch(self._frames[0], other)
        self.potential_root(self._frames[0])

    def _declare_modes(self, damping: Any, q_fixed: bool | None) -> None:
        """The modal damping ratios ``zeta`` and the modal coordinates ``q``, ``qd``, ``qdd`` of the kept modes
        (none for a rigid body, whose ``damping`` is checked all the same)."""
        data = self._data
        m = data.n_modes
        if not m:
            damping_ratios(np.zeros(0), damping)  # checks the value; {mode: ratio} names a mode not kept
            return
        zeta = default_damping_ratio(data.frequencies) if data.damping_ratio is None else data.damping_ratio
        zeta = damping_ratios(np.array(zeta, dtype=float), damping)
        self.zeta = Parameter(zeta, unit="1", shape=m, min=0.0, max=1.0,
                              doc="Modal damping ratios (fractions of critical)")
        q_nom, qd_nom = modal_nominals(data)
        self.q = Variable(unit="1", shape=m, start=np.zeros(m), state_select="prefer", nominal=q_nom,
                          doc="Modal coordinates")
        self.qd = Variable(unit="1/s", shape=m, start=np.zeros(m), state_select="prefer", nominal=qd_nom,
                           doc="Modal velocities der(q)")
        self.qdd = Variable(unit="1/s2", shape=m, doc="Modal accelerations der(qd)")
        fixed = "default" if q_fixed is None else q_fixed
        self.set_start("q", np.zeros(m), fixed=fixed)
        self.set_start("qd", np.zeros(m), fixed=fixed)

    def _apply_starts(self, deferred: dict[str, Any]) -> None:
        """The ``zeta``, ``init``, ``guess`` and ``state_select`` arguments (applied once the variables exist), and
        the start orientation from ``Q_start``."""
        m = self._data.n_modes
        if "zeta" in deferred:
            check_zeta(deferred["zeta"], m)
            zeta_given = deferred.pop("zeta")
            if m or np.size(zeta_given):  # an empty zeta fits a body without modes
                self._assign("zeta", zeta_given)
        for kind, fixed_start in (("init", True), ("guess", False)):
            for name, value in (deferred.get(kind) or {}).items():
                if name in ("q", "qd") and m:
                    value = modal_start(kind, name, value, m)
                # a dotted name ("frame_b.r_0") sets a variable of a frame connector, as for any component
                self._start_target(name, kind).set_start(name.rpartition(".")[2], value, fixed=fixed_start)
        for name, value in (deferred.get("state_select") or {}).items():
            self._start_target(name, "state_select").set_state_select(name.rpartition(".")[2], value)
        q0 = self.parameter_value("Q_start")
        if np.linalg.norm(q0) > 1e-12:
            self.set_start("Q", q0 / np.linalg.norm(q0), fixed=False)

    def check(self, values: dict[str, np.ndarray]) -> None:
        """``Q_start`` must be a quaternion (not all zero): it is normalised, and a zero one has no direction."""
        q0 = values.get("Q_start")
        if q0 is not None and not np.linalg.norm(q0) > 1e-12:
            raise ParameterError(f"{self.param_label('Q_start')} = {np.asarray(q0).tolist()} [1] is not a rotation: "
                                 "give a non-zero quaternion (x, y, z, w), e.g. [0, 0, 0, 1] for no rotation")

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
        """The frame connector at node id ``node`` (an int).

        Raises
        ------
        ModelError
            ``node`` is not a node id (text, a bool, a fractional number) or has no frame; the message lists the
            frames' nodes.
        """
        if not is_int(node) and not (is_real(node) and float(node).is_integer()):
            raise ModelError(f"{self.where}: frame_at: node must be a node id (an int), got {node!r} "
                             f"({type(node).__name__}); frames at nodes {list(self.frame_nodes)}")
        if int(node) not in self.frame_nodes:
            raise ModelError(f"{self.where}: node {node} has no frame (frames at nodes {list(self.frame_nodes)})")
        return self._frames[self.frame_nodes.index(int(node))]

    def motion(self, result: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The body's motion in a simulation result, for :mod:`flexlib.fe.output` (deformation, stress, VTK, animation).

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

        Raises
        ------
        RunArgumentError
            ``result`` is not a :class:`~flexlib.Result`, or it belongs to another model: it holds no variables of
            this body, or another number of modal coordinates or frames (a run of another build of the body).
        EmptyResultError
            The result has no rows.
        """
        nt = check_result(self, result, "motion", self._source)
        t = np.asarray(result.t, dtype=float)
        q = (np.asarray(result[f"{self.path}.q"], dtype=float).reshape(nt, self.n_modes) if self.n_modes
             else np.zeros((nt, 0)))
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
        ModalFileError
            The modal data hold no static load responses (for loads at a frame's node); a ``ValueError``.
        RunArgumentError, EmptyResultError
            As :meth:`motion`: a result of another model, or one without rows.
        """
        d = self._data
        if d.load_cases is None:
            d.residual_fields()  # raises the explanatory error
        check_result(self, result, "load_amplitudes", self._source)
        prefetch_body(self, result)
        t, _q, _r0, T = self.motion(result)
        nt = t.size
        g = result_gravity(self, result)
        a_0 = np.asarray(result[f"{self.path}.a_0"], dtype=float).reshape(nt, 3)
        w = np.asarray(result[f"{self.path}.w"], dtype=float).reshape(nt, 3)
        z = np.asarray(result[f"{self.path}.z"], dtype=float).reshape(nt, 3)
        values = inertial_load_amplitudes(np.einsum("kij,kj->ki", T, a_0 - g), z, w)
        values.update(frame_load_amplitudes(self, result, T))
        zero = np.zeros(nt)
        return np.column_stack([values.get(c, zero) for c in d.load_cases]) if d.load_cases else np.zeros((nt, 0))

    def participation(self, result: Any, *, threshold: float = 0.01, at: float | None = None) -> ParticipationTable:
        """Modal participation factors (seed 001's MPF method) of all the modal data's modes from this body's own
        loads in ``result`` — typically a run with ``modes=0`` (the rigid body): its frames' cut loads and its
        inertia loads at the most critical instant (the largest static modal response) or at ``at`` [s]; pass the
        table as ``modes=`` (:func:`~.results.participation`, :func:`~flexlib.fe.participation_from_load_cases`).
        """
        return participation(self, self._all_modes, self.load_amplitudes(result), np.asarray(result.t, dtype=float),
                             threshold, at)

    def check_run(self, result: Any) -> dict[str, Any] | None:
        """The validity monitors over a run (:mod:`.validity`): warnings past the limits, and the summary."""
        return None if self._validity is None else validity(self, result, self._validity)

    def advise(self) -> None:
        """A clamped basis at a reference node on a free revolute warns (:func:`~.results.advise_basis`)."""
        advise_basis(self, self._source)

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
        free = entry == 0 and self.is_root(e)
        if free:  # the body's own coordinates give the entry frame's motion
            eqs += floating_frame_equations(e, self.Q)
            eqs.append(eq(e.w, ca.mtimes(Tr_e, w) + wr_e))
        else:  # the entry frame's motion gives the body's
            eqs.append(eq(self.Q, [0.0, 0.0, 0.0, 1.0]))
            eqs.append(eq(w, ca.mtimes(Tr_e.T, e.w - wr_e)))
        eqs.append(eq(self.r_0, e.r_0 - ca.mtimes(T.T, x_e)))
        # the entry frame's origin x_e(q) moves with xd = Phi_e qd, xdd = Phi_e qdd in body axes; its angular velocity
        # Tr_e w + wr_e(q, qd) changes at the rate d/dt of that expression (componentwise in the frame: its z)
        xd_e, xdd_e = lin(kin[entry][3], qd), lin(kin[entry][3], qdd)
        qq = ca.vertcat(q, qd) if m else ca.SX.zeros(0, 1)
        qqd = ca.vertcat(qd, qdd) if m else ca.SX.zeros(0, 1)
        z_e = ca.mtimes(Tr_e, z) + (ca.jtimes(ca.mtimes(Tr_e, w) + wr_e, qq, qqd) if m else ca.SX.zeros(3, 1))
        g = gravity_of(self)
        alpha = self.alpha  # T (a_0 - g): the origin's acceleration less gravity, body axes
        if free:
            eqs += [eq(der(self.r_0), self.v_0), eq(der(self.v_0), self.a_0), eq(der(w), z),
                    eq(alpha, ca.mtimes(T, self.a_0 - g), label="acceleration in body axes")]
        else:  # the body reads the entry frame's v, a, z, which the multibody pass carries along the tree
            acc_e = ca.cross(z, x_e) + ca.cross(w, ca.cross(w, x_e)) + 2 * ca.cross(w, xd_e) + xdd_e
            v_origin = ca.mtimes(Tr_e.T, e.v) - ca.cross(w, x_e) - xd_e  # origin velocity, body axes
            eqs += [eq(alpha, ca.mtimes(Tr_e.T, e.a) - acc_e, label="acceleration in body axes"),
                    eq(self.v_0, ca.mtimes(T.T, v_origin)), eq(self.a_0, ca.mtimes(T.T, alpha) + g), eq(e.z, z_e)]
        # the other frames, written from the entry frame (not from r_0): the frame chain stays explicit in frame
        # variables, as the loop-redundancy analysis needs (flexlib.compile.passes.multibody.redundancy), and the
        # multibody pass reads them as a relative motion of the entry frame to carry v, a, z on
        w_body = ca.mtimes(Tr_e.T, e.w - wr_e) if free else w
        for k, f in enumerate(frames):
            if k != entry:
                x, Tr, wr = kin[k][:3]
                eqs += [eq(f.r_0, e.r_0 + ca.mtimes(T.T, x - x_e)), eq(f.T, ca.mtimes(Tr, T)),
                        eq(f.w, ca.mtimes(Tr, w_body) + wr)]
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


