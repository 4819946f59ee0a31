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
from flexlib.errors import EmptyResultError, ModalFileError, ModelError, ParameterError, RunArgumentError

from ..multibody.frames import equality_constraint, skew
from ..multibody.interfaces import Frame
from ..multibody.quaternions import floating_frame_equations, quaternion_to_T
from ..multibody.world import World, gravity_of
from .modal_data import LOAD_CASE_NAMES, ModalData
from .selection import default_damping_ratio, select_modes

__all__ = ["FlexibleBody", "cayley_rotation", "frame_names", "inertial_load_amplitudes"]

_LETTERS = "abcdefghijklmnopqrstuvwxyz"
#: Mode-shape entries at a frame below this fraction of the mode's largest entry are round-off (set to zero).
SHAPE_ZERO = 1e-9
_COMPONENTS = ("ux", "uy", "uz", "rx", "ry", "rz")


def frame_names(n: int) -> list[str]:
    """Connector names of ``n`` frames: ``frame_a``, ``frame_b``, … (``frame_z``, then ``frame_26``, …)."""
    if not _is_int(n) or n < 0:
        raise RunArgumentError(f"frame_names: n must be a number of frames (an int >= 0), got {n!r}")
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
        The modes to keep: an ``int`` count (the lowest ``modes`` in frequency; at most the file's number of
        modes) or a list of distinct indices into the file's modes (``[]``: none). Default: all. ``0`` gives the
        rigid body. Anything else (a string such as ``"4"``, a float, a bool, a nested list) is refused.
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
        if isinstance(modal_data, ModalData):
            title = modal_data.title
            data, source = modal_data, f"modal data {title!r}" if title else "modal data (untitled)"
        elif isinstance(modal_data, str | os.PathLike):
            data, source = ModalData.read(modal_data), f"modal file {os.fspath(modal_data)!r}"
        else:
            raise ModelError(f"FlexibleBody: modal_data must be a ModalData or the path of a modal file (str or "
                             f"Path), got {modal_data!r} ({type(modal_data).__name__})")
        data = _choose_modes(data, modes, max_frequency, source)
        deferred = {k: kwargs.pop(k) for k in ("zeta", "init", "guess", "state_select") if k in kwargs}
        for kind in ("init", "guess", "state_select"):
            given = deferred.get(kind)
            if given is not None and not isinstance(given, Mapping):
                accepted = ("{variable: 'always' | 'prefer' | 'default' | 'avoid' | 'never'}" if kind == "state_select"
                            else "{variable name: start value}, e.g. {'q': np.zeros(n_modes)}")
                raise ModelError(f"FlexibleBody: {kind} must be a dict {accepted}, got {type(given).__name__} "
                                 f"{given!r:.60}")
        super().__init__(**kwargs)
        self._data = data
        self._source = source  # how messages name the data: "modal file 'arm.h5'" or "modal data 'arm'"
        self.orientation_fixed = _flag("orientation_fixed", orientation_fixed)
        self.w_fixed = _flag("w_fixed", w_fixed)
        self.geometric_stiffening = _flag("geometric_stiffening", geometric_stiffening)
        q_fixed = None if q_fixed is None else _flag("q_fixed", q_fixed, "True, False or None")
        nodes = _frame_nodes(data, frames, source)
        self.frame_nodes = tuple(nodes)
        if self.geometric_stiffening:
            if data.geometric_stiffness is None:
                raise ModelError(f"{type(self).__name__}: geometric_stiffening=True, but the {source} has no "
                                 "'/geometric_stiffness' (build it with modal_data_from_fe(..., "
                                 "geometric_stiffening=True))")
            if not data.geometric_stiffness:
                raise ModelError(f"{type(self).__name__}: geometric_stiffening=True, but the group "
                                 f"'/geometric_stiffness' of the {source} holds no load case (expected "
                                 f"{LOAD_CASE_NAMES}): no stiffening term could be added")
        names = frame_names(len(nodes))
        for name in names:
            setattr(self, name, Frame(doc=f"Frame at node {nodes[names.index(name)]}"))
        self._frames = [getattr(self, n) for n in names]
        for other in self._frames[1:]:
            self.branch(self._frames[0], other)
        self.potential_root(self._frames[0])
        m = data.n_modes
        if "zeta" in deferred and damping is not None:
            raise ModelError(f"{type(self).__name__}: both damping={damping!r} and zeta are given: damping sets the "
                             "parameter zeta (the modal damping ratios); give one of them")
        if m:
            zeta = default_damping_ratio(data.frequencies) if data.damping_ratio is None else data.damping_ratio
            zeta = _damping_ratios(np.array(zeta, dtype=float), damping)
            self.zeta = Parameter(zeta, unit="1", shape=m, min=0.0, max=1.0,
                                  doc="Modal damping ratios (fractions of critical)")
            q_nom, qd_nom = _modal_nominals(data)
            self.q = Variable(unit="1", shape=m, start=np.zeros(m), state_select="prefer", nominal=q_nom,
                              doc="Modal coordinates")
            self.qd = Variable(unit="1/s", shape=m, start=np.zeros(m), state_select="prefer", nominal=qd_nom,
                               doc="Modal velocities der(q)")
            self.qdd = Variable(unit="1/s2", shape=m, doc="Modal accelerations der(qd)")
            fixed = "default" if q_fixed is None else q_fixed
            self.set_start("q", np.zeros(m), fixed=fixed)
            self.set_start("qd", np.zeros(m), fixed=fixed)
        else:
            _damping_ratios(np.zeros(0), damping)  # checks the value; {mode: ratio} names a mode not kept
        if "zeta" in deferred:
            _check_zeta(deferred["zeta"], m)
            zeta_given = deferred.pop("zeta")
            if m or np.size(zeta_given):  # an empty zeta fits a body without modes
                self._assign("zeta", zeta_given)
        for kind, fixed_start in (("init", True), ("guess", False)):
            for name, value in (deferred.get(kind) or {}).items():
                if name in ("q", "qd") and m:
                    value = _modal_start(kind, name, value, m)
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
        if not _is_int(node) and not (_is_real(node) and float(node).is_integer()):
            raise ModelError(f"{self.where}: frame_at: node must be a node id (an int), got {node!r} "
                             f"({type(node).__name__}); frames at nodes {list(self.frame_nodes)}")
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

        Raises
        ------
        RunArgumentError
            ``result`` is not a :class:`~flexlib.Result`, or it belongs to another model: it holds no variables of
            this body, or another number of modal coordinates or frames (a run of another build of the body).
        EmptyResultError
            The result has no rows.
        """
        nt = self._check_result(result, "motion")
        t = np.asarray(result.t, dtype=float)
        q = (np.asarray(result[f"{self.path}.q"], dtype=float).reshape(nt, self.n_modes) if self.n_modes
             else np.zeros((nt, 0)))
        T_a = np.asarray(result[f"{self.path}.frame_a.T"], dtype=float).reshape(nt, 3, 3, order="F")
        Psi = self._node_shapes(self.frame_nodes[0])[2]
        T_rel = cayley_rotation(q @ Psi.T if self.n_modes else np.zeros((nt, 3)))
        T = np.einsum("kji,kjl->kil", T_rel, T_a)  # T_rel^T T_a
        return t, q, np.asarray(result[f"{self.path}.r_0"], dtype=float).reshape(nt, 3), T

    def _check_result(self, result: Any, func: str) -> int:
        """The number of rows of ``result``, after checking it holds this body as built: its modal coordinates
        (as many as the body keeps) and its frames."""
        from flexlib.results.result import Result

        where = f"{self.where}.{func}"
        if not isinstance(result, Result):
            raise RunArgumentError(f"{where}: argument 'result' must be a flexlib Result (of Simulation.run or "
                                   f"Result.load), got {type(result).__name__}")
        if not self.path:
            raise RunArgumentError(f"{where}: this FlexibleBody is not part of a model; use the body of the model "
                                   f"that made the result of {result.model}")
        prefix = f"{self.path}."
        own = [n for n in result.names if n.startswith(prefix)]
        if not own:
            raise RunArgumentError(f"{where}: the result of {result.model} holds no variables of {self.path} "
                                   f"({prefix}*): it belongs to another model")
        n_q = sum(1 for n in own if n == f"{prefix}q" or n.startswith(f"{prefix}q["))
        if n_q != self.n_modes:
            raise RunArgumentError(f"{where}: the result of {result.model} holds {n_q} modal coordinates for "
                                   f"{self.path} ({prefix}q), but the body has {self.n_modes} (modes kept from the "
                                   f"{self._source}): the result belongs to another model (another build of "
                                   "this body); use the body of the model that made it")
        held = {n[len(prefix):].split(".")[0] for n in own if n.startswith(f"{prefix}frame_")}
        names = frame_names(len(self.frame_nodes))
        if set(names) != held:
            raise RunArgumentError(f"{where}: the result of {result.model} holds the frames {sorted(held)} of "
                                   f"{self.path}, but the body has {names} (at nodes {list(self.frame_nodes)}): "
                                   "the result belongs to another model")
        nt = int(np.size(result.t))
        if not nt:
            raise EmptyResultError(f"{where}: the result of {result.model} has no rows; the run is "
                                   f"{result.status}" + (f" ({result.message})" if result.message else ""))
        return nt

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
        self._check_result(result, "load_amplitudes")
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
                raise ModalFileError(f"{self.path}.{frame}: loads at node {node}, but the modal data {d.title!r} "
                                     f"hold no static responses for loads there (its load cases cover the interface "
                                     f"nodes {sorted(carried)}): make node {node} an interface node of the "
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
                # variables, as the loop-redundancy analysis needs (flexlib.compile.passes.multibody.redundancy)
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


def _is_int(value: Any) -> bool:
    """A Python or numpy integer, not a bool."""
    return isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_)


def _is_real(value: Any) -> bool:
    """A Python or numpy real number, not a bool."""
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool | np.bool_)


def _flag(name: str, value: Any, accepted: str = "True or False") -> bool:
    if isinstance(value, bool | np.bool_):
        return bool(value)
    raise ModelError(f"FlexibleBody: {name} must be {accepted}, got {value!r} ({type(value).__name__})")


def _int_list(name: str, value: Any, what: str, example: str) -> list[int]:
    """``value`` as a list of ints: a list, tuple, range or 1-D integer array whose items are all integers."""
    if isinstance(value, str | bytes | Mapping) or not isinstance(value, Sequence | np.ndarray | range):
        raise ModelError(f"FlexibleBody: {name} must be {what}, got {value!r} ({type(value).__name__}); "
                         f"for example {example}")
    if isinstance(value, np.ndarray):
        if value.ndim != 1:
            raise ModelError(f"FlexibleBody: {name} must be a flat list of {what}, got an array of shape "
                             f"{value.shape}")
        items = value.tolist()
    else:
        items = list(value)
    for k, item in enumerate(items):
        if not _is_int(item):
            hint = ""
            if isinstance(item, float | np.floating) and float(item).is_integer():
                hint = f" (write {int(item)})"
            elif isinstance(item, str) and item.strip().lstrip("-").isdigit():
                hint = f" (write {int(item)}, without quotes)"
            raise ModelError(f"FlexibleBody: {name}[{k}] is {item!r} ({type(item).__name__}): {name} must be "
                             f"{what}{hint}")
    return [int(i) for i in items]


def _frame_nodes(data: ModalData, frames: Any, source: str) -> list[int]:
    """The node ids of the frames: given, else the file's interface nodes; at least one, distinct, in the file."""
    if frames is None:
        nodes = [int(n) for n in data.interface_nodes]
        if not nodes:
            raise ModelError(f"FlexibleBody: no frames: the {source} has no interface nodes ('/interface/node_ids' "
                             f"is empty); pass frames=[node ids] (nodes {int(data.node_ids.min())}.."
                             f"{int(data.node_ids.max())})")
        return nodes
    nodes = _int_list("frames", frames, "a list of node ids (ints)", "frames=[0, 6]")
    if not nodes:
        iface = [int(n) for n in data.interface_nodes]
        raise ModelError(f"FlexibleBody: frames is empty: a flexible body needs at least one frame (frame_a) to be "
                         f"connected; pass node ids, e.g. frames={iface or [int(data.node_ids[0])]}, or leave "
                         f"frames out for the interface nodes of the {source} {iface}")
    if len(set(nodes)) != len(nodes):
        twice = sorted({n for n in nodes if nodes.count(n) > 1})
        raise ModelError(f"FlexibleBody: frames {nodes} name a node twice (node {twice[0]}); each node gets at most "
                         "one frame")
    for node in nodes:
        try:
            data.node_index(node)
        except KeyError:
            raise ModelError(f"FlexibleBody: frames: node {node} is not in the {source} (nodes "
                             f"{int(data.node_ids.min())}..{int(data.node_ids.max())})") from None
    return nodes


def _ratio(where: str, value: Any) -> float:
    """A modal damping ratio: a real number in [0, 1]."""
    accepted = "a modal damping ratio in [0, 1] (a fraction of critical damping: 0.02 for 2 %)"
    if not _is_real(value):
        raise ModelError(f"FlexibleBody: {where} must be {accepted}, got {value!r} ({type(value).__name__})")
    v = float(value)
    if not 0.0 <= v <= 1.0:  # NaN fails too
        hint = f" (a percentage? {v:g} % is {v / 100:g})" if 1.0 < v <= 100.0 else ""
        raise ModelError(f"FlexibleBody: {where} must be {accepted}, got {v!r}{hint}")
    return v


def _damping_ratios(zeta: np.ndarray, damping: Any) -> np.ndarray:
    """The modal damping ratios of the kept modes: ``zeta`` (file or default rule) with ``damping`` applied."""
    m = zeta.size
    if damping is None:
        return zeta
    if isinstance(damping, np.ndarray) and damping.ndim == 0:
        damping = damping.item()
    if isinstance(damping, Mapping):
        if damping and not m:
            raise ModelError(f"FlexibleBody: damping given for modes {sorted(damping, key=str)}, but no modes are "
                             "kept")
        for mode, value in damping.items():
            if not _is_int(mode):
                raise ModelError(f"FlexibleBody: damping: key {mode!r} ({type(mode).__name__}) must be the index "
                                 f"(int) of a kept mode, 0..{m - 1}")
            if not 0 <= mode < m:
                raise ModelError(f"FlexibleBody: damping given for mode {mode}, but {m} modes are kept (indices "
                                 f"0..{m - 1} into the kept modes)")
            zeta[int(mode)] = _ratio(f"damping[{mode}]", value)
        return zeta
    if _is_real(damping):
        zeta[:] = _ratio("damping", damping)
        return zeta
    if isinstance(damping, str | bytes) or not isinstance(damping, Sequence | np.ndarray):
        raise ModelError(f"FlexibleBody: damping must be a modal damping ratio for every kept mode (e.g. 0.02), one "
                         f"per kept mode ({m}) or {{mode: ratio}}, got {damping!r} ({type(damping).__name__})")
    values = list(damping.tolist() if isinstance(damping, np.ndarray) else damping)
    nested = any(isinstance(v, Sequence | np.ndarray) and not isinstance(v, str) for v in values)
    if nested or len(values) != m:
        raise ModelError(f"FlexibleBody: damping has {len(values)} {'nested ' if nested else ''}values, but {m} "
                         "modes are kept: give one ratio per kept mode, one number for all, or {mode: ratio}")
    for k, value in enumerate(values):
        zeta[k] = _ratio(f"damping[{k}]", value)
    return zeta


def _check_zeta(value: Any, m: int) -> None:
    """``zeta`` given directly: numbers (not text or bools), one per kept mode (the parameter checks the bounds)."""
    items = np.asarray(value, dtype=object).ravel().tolist() if not isinstance(value, str | bytes) else [value]
    for item in items:
        if not _is_real(item):
            raise ParameterError(f"FlexibleBody: zeta must be modal damping ratios (numbers in [0, 1]), one per kept "
                                 f"mode ({m}), got {value!r} (an item {item!r} of type {type(item).__name__})")
    if not m and items:
        raise ParameterError(f"FlexibleBody: zeta has {len(items)} values, but no modes are kept (zeta is absent "
                             "for the rigid body)")


def _modal_start(kind: str, name: str, value: Any, m: int) -> np.ndarray:
    """A start value of the modal coordinates ``q`` [1] or rates ``qd`` [1/s]: finite numbers, one per kept mode."""
    where = f"FlexibleBody: {kind}[{name!r}]"
    items = [value] if isinstance(value, str | bytes) or np.ndim(value) == 0 else np.asarray(
        value, dtype=object).ravel().tolist()
    for item in items:
        if not _is_real(item):
            raise ModelError(f"{where} must be numbers, one per kept mode ({m}), got {value!r} (an item {item!r} of "
                             f"type {type(item).__name__})")
    if np.ndim(value) != 1 or len(items) != m:
        raise ModelError(f"{where} has shape {np.shape(value)}, but {m} modes are kept: give one value per kept "
                         f"mode, e.g. {kind}={{{name!r}: np.zeros({m})}}")
    out = np.array(items, dtype=float)
    if not np.all(np.isfinite(out)):
        raise ModelError(f"{where} has a non-finite value {float(out[~np.isfinite(out)][0])!r} at index "
                         f"{int(np.flatnonzero(~np.isfinite(out))[0])}")
    return out


def _choose_modes(data: ModalData, modes: Any, max_frequency: Any, source: str) -> ModalData:
    """The kept modes: ``modes`` (None, an int count or a list of indices) and ``max_frequency`` (module rules)."""
    n = data.n_modes
    accepted = ("an int count of the lowest modes (e.g. modes=4) or a list of mode indices into the file's "
                f"modes 0..{n - 1} (e.g. modes=[0, 2])")
    if max_frequency is not None:
        if not _is_real(max_frequency) or not float(max_frequency) >= 0.0:
            raise ModelError(f"FlexibleBody: max_frequency must be a frequency [Hz] >= 0, got {max_frequency!r} "
                             f"({type(max_frequency).__name__})")
        max_frequency = float(max_frequency)
    idx: list[int] = []
    if modes is None or _is_int(modes):
        if modes is not None and int(modes) < 0:
            raise ModelError(f"FlexibleBody: modes must be >= 0, got {modes} (a count of the lowest modes; 0 for the "
                             "rigid body)")
        if modes is not None and int(modes) > n:
            raise ModelError(f"FlexibleBody: modes={int(modes)} asks for the {int(modes)} lowest modes, but the "
                             f"{source} has only {n}")
        if modes is None and max_frequency is None:
            return data
        out = select_modes(data, count=None if modes is None else int(modes), max_frequency=max_frequency)
    else:
        if isinstance(modes, bool | np.bool_):
            raise ModelError(f"FlexibleBody: modes={modes!r} is a bool; modes must be {accepted}")
        if isinstance(modes, str):
            hint = ""
            if modes.strip().isdigit():
                k = int(modes)
                hint = f"; write modes={k} for the {k} lowest modes, or modes=[{k}] for the mode of index {k}"
            raise ModelError(f"FlexibleBody: modes={modes!r} is a string; modes must be {accepted}{hint}")
        if isinstance(modes, float | np.floating):
            hint = f"; write modes={int(modes)}" if float(modes).is_integer() else ""
            raise ModelError(f"FlexibleBody: modes={modes!r} is a float; modes must be {accepted}{hint}")
        idx = _int_list("modes", modes, accepted, "modes=[0, 2]")
        twice = sorted({i for i in idx if idx.count(i) > 1})
        if twice:
            raise ModelError(f"FlexibleBody: modes {idx} name mode {twice[0]} twice; each mode is kept once")
        bad = [i for i in idx if not 0 <= i < n]
        if bad:
            raise ModelError(f"FlexibleBody: modes {bad} are not in the {source} ({n} modes: 0..{n - 1})")
        out = data.select(idx)
        if max_frequency is not None:
            out = select_modes(out, max_frequency=max_frequency)
    rigid_asked = modes is not None and (int(modes) == 0 if _is_int(modes) else not idx)
    if max_frequency is not None and n and not out.n_modes and not rigid_asked:
        raise ModelError(f"FlexibleBody: max_frequency={max_frequency:g} Hz keeps no mode of the {source} (lowest "
                         f"{float(data.frequencies.min()):.4g} Hz); pass modes=0 for a rigid body")
    return out


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
    try:
        bad = isinstance(theta, str | bytes) or np.asarray(theta).dtype.kind not in "iuf"
    except (TypeError, ValueError):
        bad = True
    if bad or np.ndim(theta) == 0 or np.shape(theta)[-1] != 3 or not np.all(np.isfinite(theta)):
        raise RunArgumentError(f"cayley_rotation: argument 'theta' must be finite rotation vectors (..., 3) [rad], got "
                               f"{type(theta).__name__} of shape {np.shape(theta)}: {theta!r:.60}")
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
