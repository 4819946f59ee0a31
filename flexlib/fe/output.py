"""Flexible-body output: nodal deformation and stress from modal coordinates.

Given a body's :class:`~flexlib.fe.ModalData` and the time series of its motion —
modal coordinates ``q(t)`` (nt, M), the floating frame's origin ``r_0(t)`` (nt, 3) [m, world axes] and its
orientation ``T(t)`` (nt, 3, 3), world to body (``v_body = T @ v_world``, as in flexlib's ``Frame``) — this
module recovers, at any node ``p`` with undeformed position ``s_p`` and mode shapes ``Phi_p``, ``Phi*_p``,
``S_p``:

- kinetic, strain and gravitational energy of the body (:func:`energies`, from the inertia invariants);
- elastic displacement ``u_p = Phi_p q`` [m] and small rotation ``theta_p = Phi*_p q`` [rad] in body axes;
- world position ``r_p = r_0 + T^T (s_p + u_p)`` [m] (floating frame of reference, Shabana ch. 5);
- stress ``sigma_p = S_p q`` [Pa] (modal stress recovery: superposition of the stress modes) and its von Mises
  equivalent stress;
- optionally, by the *mode-acceleration method*, the quasi-static response of the modes the body left out:
  ``u_p = Phi_p q + sum_c R_cp l_c(t)`` with the residual static responses ``R_c`` of the unit load cases
  (:meth:`ModalData.residual_fields`) and their amplitudes ``l_c(t)`` in the run
  (:meth:`FlexibleBody.load_amplitudes`); pass ``loads=``. Loads applied at a point excite many modes a little
  each, and quantities near the load (the slope at a driven pin, the stress at a joint) converge slowly with
  the number of modes in plain modal superposition; the residual term restores their static part exactly.

Every output function takes either the data and the time series (``node_displacements(data, q, nodes)``) or the
body and a result of its run (``node_displacements(model.arm, result, nodes)``). Given the body and its result, the
output is **recovered by default** whenever the modal data carry the static load responses it needs (made with
``modal_data_from_fe(..., static_loads=True)``, the default) — ``loads=False`` gives plain superposition, and
where the data cannot recover (no responses for that field, or a frame at a node without load cases) the output is
plain superposition with a :class:`~flexlib.errors.ModalDataWarning` saying why;

and gives the VTK series for ParaView (:mod:`.vtk_series`) and the matplotlib stills and animations
(:mod:`.drawing`) their fields.

References
----------
- A. A. Shabana, *Dynamics of Multibody Systems*, 3rd ed., 2005, ch. 5 (floating frame of reference, modal
  superposition of deformation and stress).
- R. R. Craig, A. J. Kurdila, *Fundamentals of Structural Dynamics*, 2nd ed., Wiley 2006, §10.4 (the
  mode-acceleration method); O. Dickens, J. M. Nakagawa, M. J. Wittbrodt, "A critique of mode acceleration and
  modal truncation augmentation methods for modal response analysis", *Comput. Struct.* 62 (1997) 985–998.
- R. von Mises, "Mechanik der festen Körper im plastisch-deformablen Zustand", *Göttinger Nachrichten* (1913);
  the equivalent stress ``sqrt(((sxx-syy)^2 + (syy-szz)^2 + (szz-sxx)^2) / 2 + 3 (sxy^2 + syz^2 + szx^2))``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from flexlib.errors import ModalFileError, RunArgumentError
from flexlib.units import g_n

from .modal_data import ModalData

__all__ = ["FIELDS", "body_series", "check_scale", "data_label", "deformed_positions", "energies", "field_values",
           "motion_series", "nodal_stress", "node_displacements", "node_rotations", "section_forces", "von_mises"]

#: Nodal fields that can be drawn or written (:func:`field_values`).
FIELDS = ("displacement", "rotation", "von_mises", "stress")
_ORTHO_TOL = 1e-6  # |T T^T - I| above which an orientation is refused


# ---------------------------------------------------------------------------------------------- argument checks
def data_label(data: ModalData) -> str:
    """``"modal data 'arm'"``: how messages name modal data."""
    return f"modal data {data.title!r}" if data.title else "modal data (untitled)"


def _check_data(data: Any, func: str) -> ModalData:
    if not isinstance(data, ModalData):
        raise RunArgumentError(f"{func}: argument 'data' must be a ModalData, got {type(data).__name__}")
    return data


def _finite(func: str, arg: str, a: np.ndarray) -> None:
    bad = ~np.isfinite(a)
    if bad.any():
        where = tuple(int(x) for x in np.argwhere(bad)[0])
        raise RunArgumentError(f"{func}: argument {arg!r} has a non-finite value {a[where]} at index {where}")


def _array(func: str, arg: str, value: Any) -> np.ndarray:
    try:
        kind = np.asarray(value).dtype.kind
    except (TypeError, ValueError):  # ragged nesting
        kind = "O"
    if kind in "USbc":  # text ('1e-3' stays text: numbers are not read out of strings), bools or complex numbers
        what = {"b": "bools", "c": "complex numbers (the imaginary part would be dropped)"}.get(kind, "text")
        raise RunArgumentError(f"{func}: argument {arg!r} must be an array of real numbers, got {what}: "
                               f"{value!r:.80}")
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise RunArgumentError(f"{func}: argument {arg!r} must be an array of real numbers: {exc}") from None
    _finite(func, arg, a)
    return a


def check_scale(func: str, scale: Any) -> float:
    """A drawing magnification: one finite real number."""
    a = _array(func, "scale", scale)
    if a.ndim != 0:
        raise RunArgumentError(f"{func}: argument 'scale' must be a number, got shape {a.shape}")
    return float(a)


def _modal_coordinates(data: ModalData, q: Any, func: str) -> tuple[np.ndarray, bool]:
    """``q`` as (nt, M) and whether it was a single instant (M,)."""
    a = _array(func, "q", q)
    M = data.n_modes
    if a.ndim == 1 and a.shape[0] == M:
        return a[None, :], True
    if a.ndim == 2 and a.shape[1] == M:
        return a, False
    raise RunArgumentError(f"{func}: argument 'q' has shape {a.shape}, expected (nt, {M}) or ({M},): "
                           f"{data_label(data)} has {M} modes (pass the modal data a body was built with, "
                           "body.modal_data, with the q of body.motion(result))")


def _node_indices(data: ModalData, nodes: Sequence[int] | np.ndarray | None, func: str) -> np.ndarray:
    if nodes is None:
        return np.arange(data.n_nodes)
    ids = np.asarray(nodes).ravel()
    if ids.size and not np.issubdtype(ids.dtype, np.integer):
        raise RunArgumentError(f"{func}: argument 'nodes' must be node ids (integers), got {ids[:3].tolist()}...")
    lookup = {int(k): i for i, k in enumerate(data.node_ids.tolist())}
    missing = [int(k) for k in ids.tolist() if int(k) not in lookup]
    if missing:
        raise RunArgumentError(f"{func}: argument 'nodes': {data_label(data)} has no node with id {missing[:5]} "
                               f"(node ids {int(data.node_ids.min())}..{int(data.node_ids.max())})")
    return np.array([lookup[int(k)] for k in ids.tolist()], dtype=np.int64)


def _frame_motion(r_0: Any, T: Any, nt: int, func: str) -> tuple[np.ndarray, np.ndarray]:
    """``r_0`` as (nt, 3) and ``T`` as (nt, 3, 3), broadcasting a single value; T must be orthogonal."""
    r = _array(func, "r_0", r_0)
    if r.shape == (3,):
        r = np.broadcast_to(r, (nt, 3))
    elif r.shape != (nt, 3):
        raise RunArgumentError(f"{func}: argument 'r_0' has shape {r.shape}, expected ({nt}, 3) or (3,) [m]")
    R = _array(func, "T", T)
    if R.shape == (3, 3):
        R = np.broadcast_to(R, (nt, 3, 3))
    elif R.shape != (nt, 3, 3):
        raise RunArgumentError(f"{func}: argument 'T' has shape {R.shape}, expected ({nt}, 3, 3) or (3, 3): "
                               "orientation matrices world -> body")
    err = np.abs(np.einsum("tij,tkj->tik", R, R) - np.eye(3)).max(axis=(1, 2)) if nt else np.zeros(0)
    if err.size and err.max() > _ORTHO_TOL:
        k = int(np.argmax(err))
        raise RunArgumentError(f"{func}: argument 'T' at index {k} is not orthogonal (max |T T^T - I| = "
                               f"{err[k]:.3g}): expected rotation matrices world -> body")
    det = np.linalg.det(R) if nt else np.ones(0)
    if np.any(det < 0):
        k = int(np.argmax(det < 0))
        raise RunArgumentError(f"{func}: argument 'T' at index {k} is a reflection (det T = {det[k]:.3g}), not a "
                               "rotation: it would draw the body mirrored; expected rotation matrices world -> body")
    return r, R


def _times(times: Any, nt: int, func: str) -> np.ndarray:
    t = _array(func, "times", times)
    t = t.reshape(1) if t.ndim == 0 else t
    if t.shape != (nt,):
        raise RunArgumentError(f"{func}: argument 'times' has shape {t.shape}, expected ({nt},) like 'q' [s]")
    if nt > 1 and np.any(np.diff(t) < 0):
        k = int(np.argmax(np.diff(t) < 0))
        raise RunArgumentError(f"{func}: argument 'times' decreases at index {k + 1} ({t[k]!r} -> {t[k + 1]!r})")
    return t


def _stress_modes(data: ModalData, func: str) -> np.ndarray:
    if data.stress_modes is None:
        raise ModalFileError(f"{func}: {data_label(data)} has no stress modes (dataset '/modes/stress'): von Mises "
                             "stress needs them; beam models get them from modal_data_from_fe(..., "
                             "stress_fibre=(y, z))")
    return data.stress_modes


# ---------------------------------------------------------------------------------------------- nodal quantities
_RESIDUAL = {"translational": "translations", "rotational": "rotations", "stress": "stress",
             "section_forces": "section_forces"}


def _residual(func: str, data: ModalData, kind: str, loads: Any, nt: int,
              single: bool) -> tuple[np.ndarray, np.ndarray]:
    """The residual static responses of ``kind`` (C, n, ...) and the load amplitudes ``loads`` as (nt, C)."""
    try:
        fields = data.residual_fields()
    except ValueError as exc:
        raise ModalFileError(f"{func}: {exc}") from None
    key = _RESIDUAL[kind]
    if key not in fields:
        raise ModalFileError(f"{func}: {data_label(data)} has no static load responses for {key} "
                             f"(dataset '/static_loads/{key}')")
    C = len(fields["cases"])
    a = _array(func, "loads", loads)
    if single and a.ndim == 1:
        a = a[None, :]
    if a.ndim != 2 or a.shape != (nt, C):
        raise RunArgumentError(f"{func}: argument 'loads' has shape {a.shape}, expected ({nt}, {C}): one amplitude "
                               f"per load case {list(fields['cases'][:4])}... of {data_label(data)} and instant")
    return fields[key], a


def _is_body(data: Any) -> bool:
    """A FlexibleBody (its run's result gives ``q`` and the load amplitudes), not modal data."""
    return not isinstance(data, ModalData) and callable(getattr(data, "motion", None)) \
        and callable(getattr(data, "load_amplitudes", None))


def body_series(func: str, body: Any, result: Any, loads: Any, kind: str = "translational"
                ) -> tuple[ModalData, np.ndarray, Any, np.ndarray, np.ndarray]:
    """``(data, q, loads, r_0, T)`` of a body's run (:meth:`FlexibleBody.motion`), ``loads`` the amplitudes for
    mode-acceleration recovery of ``kind`` (a key of ``_RESIDUAL``): as given, None for ``False`` (plain
    superposition) or, for None, the run's own when the data carry the static responses of ``kind`` — None when they
    were made without any, and None with a :class:`~flexlib.errors.ModalDataWarning` naming the body and why when
    they cannot give these (no responses for ``kind``, a loaded frame at a node without load cases)."""
    import warnings

    from flexlib.errors import ModalDataWarning

    _t, q, r_0, T = body.motion(result)
    data = body.modal_data
    if loads is not None or data.load_cases is None:
        return data, q, (None if loads is False else loads), r_0, T
    try:
        if _RESIDUAL[kind] not in data.residual_fields():
            raise ModalFileError(f"{data_label(data)} has no static load responses for {_RESIDUAL[kind]}")
        loads = body.load_amplitudes(result)
    except ModalFileError as err:
        warnings.warn(ModalDataWarning(f"{func}({body.path}): plain modal superposition, not recovered: {err}"),
                      stacklevel=4)
    return data, q, loads, r_0, T


def _inputs(func: str, data: Any, q: Any, loads: Any, kind: str) -> tuple[Any, Any, Any]:
    """``(data, q, loads)`` of an output function given modal data and ``q``, or a body and its result
    (:func:`body_series`); ``loads=False`` is plain superposition."""
    if _is_body(data):
        data, q, loads, _r_0, _T = body_series(func, data, q, loads, kind)
    return data, q, None if loads is False else loads


def _superpose(func: str, data: Any, q: Any, nodes: Sequence[int] | np.ndarray | None, kind: str,
               loads: Any = None) -> np.ndarray:
    """``sum_j q_j X_j`` (+ ``sum_c l_c R_c``) at the nodes for the fields ``X`` of one kind (arguments checked)."""
    data, q, loads = _inputs(func, data, q, loads, kind)
    data = _check_data(data, func)
    modes = _stress_modes(data, func) if kind == "stress" else getattr(data, f"{kind}_modes")
    q2, single = _modal_coordinates(data, q, func)
    idx = _node_indices(data, nodes, func)
    out = _combine(q2, modes[:, idx, :])
    if loads is not None:
        R, amp = _residual(func, data, kind, loads, q2.shape[0], single)
        out = out + _combine(amp, R[:, idx, :])
    _overflow(func, out)
    return out[0] if single else out


def _combine(a: np.ndarray, fields: np.ndarray) -> np.ndarray:
    """``sum_m a[t, m] fields[m, n, k]``: one matrix product (BLAS; ``einsum`` loops in C without it)."""
    m, n, k = fields.shape
    with np.errstate(over="ignore", invalid="ignore"):  # a result beyond the float range is refused by _overflow
        out = np.asarray(a, dtype=float) @ np.ascontiguousarray(fields, dtype=float).reshape(m, n * k)
    return out.reshape(-1, n, k)


def _overflow(func: str, out: np.ndarray) -> None:
    """Finite inputs whose superposition is not finite: values beyond the floating-point range."""
    if not np.all(np.isfinite(out)):
        raise RunArgumentError(f"{func}: the result overflows the floating-point range (largest finite "
                               f"{np.finfo(float).max:.3g}): 'q' (or 'loads') is far beyond a small elastic "
                               "deformation")


def node_displacements(data: ModalData, q: Any, nodes: Sequence[int] | np.ndarray | None = None, *,
                       loads: Any = None) -> np.ndarray:
    """Elastic displacement ``u_p = Phi_p q`` of nodes relative to the floating frame, in body axes.

    Parameters
    ----------
    data : ModalData or FlexibleBody
        The body's modal data, or the body itself (then ``q`` is a result of its run).
    q : array_like (nt, M) or (M,), or Result
        Modal coordinates over time (or at one instant) [1], or the result of the body's run.
    nodes : sequence of int, optional
        Node ids (as in ``data.node_ids``); default all nodes in file order.
    loads : array_like (nt, C) or (C,), or False, optional
        Amplitudes of the data's unit load cases (:meth:`FlexibleBody.load_amplitudes`): adds the left-out
        modes' static response (mode-acceleration method, module docstring). Given a body and its result, the
        amplitudes of the run by default (``False``: plain superposition).

    Returns
    -------
    ndarray (nt, n, 3) or (n, 3)
        Displacements [m] in body axes.

    Raises
    ------
    RunArgumentError
        ``q`` of the wrong shape (naming the number of modes) or non-finite; an unknown node id.
    """
    return _superpose("node_displacements", data, q, nodes, "translational", loads)


def node_rotations(data: ModalData, q: Any, nodes: Sequence[int] | np.ndarray | None = None, *,
                   loads: Any = None) -> np.ndarray:
    """Small elastic rotation ``theta_p = Phi*_p q`` of nodes relative to the floating frame, in body axes.

    Parameters
    ----------
    data : ModalData
        The body's modal data.
    q : array_like (nt, M) or (M,)
        Modal coordinates [1].
    nodes : sequence of int, optional
        Node ids; default all nodes.
    loads : array_like (nt, C) or (C,), optional
        Amplitudes of the data's unit load cases (:meth:`FlexibleBody.load_amplitudes`): adds the left-out
        modes' static response (mode-acceleration method, module docstring).

    Returns
    -------
    ndarray (nt, n, 3) or (n, 3)
        Rotation vectors [rad] in body axes (small-rotation approximation of the linear modes).

    Raises
    ------
    RunArgumentError
        As :func:`node_displacements`.
    """
    return _superpose("node_rotations", data, q, nodes, "rotational", loads)


def deformed_positions(data: Any, q: Any, r_0: Any = None, T: Any = None,
                       nodes: Sequence[int] | np.ndarray | None = None, *, scale: float = 1.0,
                       loads: Any = None) -> np.ndarray:
    """World positions ``r_p = r_0 + T^T (s_p + scale * u_p)`` of nodes of the deformed body, ``u_p = Phi_p q``
    (``+ sum_c R_cp l_c`` recovered).

    Parameters
    ----------
    data : ModalData or FlexibleBody
        The body's modal data (undeformed coordinates ``s_p`` in the body frame), or the body itself (then ``q``
        is a result of its run, which gives ``r_0`` and ``T``).
    q : array_like (nt, M) or (M,), or Result
        Modal coordinates [1], or the result of the body's run.
    r_0 : array_like (nt, 3) or (3,)
        Origin of the floating frame, world axes [m] (one value: the same at every instant); not with a body.
    T : array_like (nt, 3, 3) or (3, 3)
        Orientation of the floating frame, world to body (``v_body = T @ v_world``); orthogonal (1e-6); not with
        a body.
    nodes : sequence of int, optional
        Node ids; default all nodes.
    scale : float
        Magnification of the elastic displacement for drawing (1: true positions).
    loads : array_like (nt, C) or (C,), or False, optional
        As :func:`node_displacements`: with a body and its result, recovered by default.

    Returns
    -------
    ndarray (nt, n, 3) or (n, 3)
        World positions [m].

    Raises
    ------
    RunArgumentError
        Shapes of ``q``, ``r_0`` or ``T`` that do not match (naming the argument), a ``T`` that is not 3 x 3 or
        not orthogonal, non-finite values, an unknown node id.
    """
    func = "deformed_positions"
    if _is_body(data):
        if r_0 is not None or T is not None:
            raise RunArgumentError(f"{func}: with a body and its result, r_0 and T come from the result; give "
                                   "nodes=, scale= and loads= by keyword")
        data, q, loads, r_0, T = body_series(func, data, q, loads)
    elif r_0 is None or T is None:
        raise RunArgumentError(f"{func}: give the floating frame's motion r_0 and T with modal data and q (or the "
                               "body and its result: deformed_positions(model.arm, result))")
    u = _superpose(func, data, q, nodes, "translational", loads)
    data = _check_data(data, func)
    q2, single = _modal_coordinates(data, q, func)
    idx = _node_indices(data, nodes, func)
    nt = q2.shape[0]
    r, R = _frame_motion(r_0, T, nt, func)
    scale = check_scale(func, scale)
    body = data.coordinates[idx][None, :, :] + scale * (u[None] if single else u)
    out = r[:, None, :] + np.einsum("tji,tnj->tni", R, body)
    _overflow(func, out)
    return out[0] if single else out


def nodal_stress(data: ModalData, q: Any, nodes: Sequence[int] | np.ndarray | None = None, *,
                 loads: Any = None) -> np.ndarray:
    """Stress ``sigma_p = sum_j q_j S_jp`` at nodes from the stress modes, body axes.

    Parameters
    ----------
    data : ModalData
        Modal data with stress modes (``/modes/stress``).
    q : array_like (nt, M) or (M,)
        Modal coordinates [1].
    nodes : sequence of int, optional
        Node ids; default all nodes.
    loads : array_like (nt, C) or (C,), optional
        Amplitudes of the data's unit load cases (:meth:`FlexibleBody.load_amplitudes`): adds the left-out
        modes' static response (mode-acceleration method, module docstring).

    Returns
    -------
    ndarray (nt, n, 6) or (n, 6)
        ``(sxx, syy, szz, sxy, syz, szx)`` [Pa].

    Raises
    ------
    ModalFileError
        The data has no stress modes (the message names the data's title and the dataset).
    RunArgumentError
        As :func:`node_displacements`.
    """
    return _superpose("nodal_stress", data, q, nodes, "stress", loads)


def section_forces(data: ModalData, q: Any, *, loads: Any = None) -> np.ndarray:
    """Beam section forces ``(N, Vy, Vz, T, My, Mz)`` at both ends of every element, element axes.

    Parameters
    ----------
    data : ModalData
        Modal data of a beam model (``/modes/section_forces``).
    q : array_like (nt, M) or (M,)
        Modal coordinates [1].
    loads : array_like (nt, C) or (C,), optional
        Load-case amplitudes for mode-acceleration recovery (as :func:`node_displacements`).

    Returns
    -------
    ndarray (nt, E, 2, 6) or (E, 2, 6)
        Forces [N] and moments [N m].

    Raises
    ------
    ModalFileError
        The data has no section forces (not a beam model) or, with ``loads``, no static load responses.
    RunArgumentError
        ``q`` or ``loads`` of the wrong shape.
    """
    func = "section_forces"
    data, q, loads = _inputs(func, data, q, loads, "section_forces")
    data = _check_data(data, func)
    if data.section_forces is None:
        raise ModalFileError(f"{func}: {data_label(data)} has no section forces (dataset '/modes/section_forces'): "
                             "only beam models made by beam_mesh have them")
    q2, single = _modal_coordinates(data, q, func)
    out = np.einsum("tm,mekl->tekl", q2, data.section_forces)
    if loads is not None:
        R, amp = _residual(func, data, "section_forces", loads, q2.shape[0], single)
        out = out + np.einsum("tc,cekl->tekl", amp, R)
    return out[0] if single else out


def von_mises(stress: Any) -> np.ndarray:
    """Von Mises equivalent stress of stress tensors in Voigt order ``(sxx, syy, szz, sxy, syz, szx)``.

    ``sqrt(((sxx - syy)^2 + (syy - szz)^2 + (szz - sxx)^2) / 2 + 3 (sxy^2 + syz^2 + szx^2))``: ``|s|`` for a
    uniaxial stress ``s``, ``sqrt(3) tau`` for pure shear ``tau``, 0 for a hydrostatic state.

    Parameters
    ----------
    stress : array_like (..., 6)
        Stress components [Pa] (tensor shear components, not engineering strains).

    Returns
    -------
    ndarray (...)
        Equivalent stress [Pa].

    Raises
    ------
    RunArgumentError
        The last axis is not of length 6, or a value is not finite.
    """
    s = _array("von_mises", "stress", stress)
    if s.ndim == 0 or s.shape[-1] != 6:
        raise RunArgumentError(f"von_mises: argument 'stress' has shape {s.shape}, expected (..., 6): "
                               "(sxx, syy, szz, sxy, syz, szx) [Pa]")
    sxx, syy, szz, sxy, syz, szx = np.moveaxis(s, -1, 0)
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * (sxy**2 + syz**2 + szx**2))


# ---------------------------------------------------------------------------------------------- drawing data
def motion_series(func: str, data: Any, times: Any, q: Any, r_0: Any, T: Any, scale: float = 1.0,
                  loads: Any = None) -> dict[str, Any]:
    """Checked time series and the world positions and elastic displacement (world axes) of every node; with the
    load-case amplitudes ``loads`` (nt, C) recovered by the mode-acceleration method (as :func:`node_displacements`)."""
    data = _check_data(data, func)
    q2, single = _modal_coordinates(data, q, func)
    nt = q2.shape[0]
    if nt == 0:
        raise RunArgumentError(f"{func}: argument 'q' has no samples (shape {q2.shape})")
    t = _times(times, nt, func)
    r, R = _frame_motion(r_0, T, nt, func)
    scale = check_scale(func, scale)
    if loads is not None:  # one row per sample, as q2
        loads = _array(func, "loads", loads)
        loads = loads[None, :] if single and loads.ndim == 1 else loads
    u_body = _superpose(func, data, q2, None, "translational", loads)
    u_world = np.einsum("tji,tnj->tni", R, u_body)
    points = r[:, None, :] + np.einsum("tji,tnj->tni", R, data.coordinates[None]) + scale * u_world
    return {"data": data, "q": q2, "t": t, "R": R, "points": points, "u": u_world, "loads": loads}


def field_values(s: dict[str, Any], field: str, func: str) -> np.ndarray:
    """(nt, N) or (nt, N, k) values of one drawable field."""
    data: ModalData = s["data"]
    if field == "displacement":
        return s["u"]
    if field == "rotation":
        return np.einsum("tji,tnj->tni", s["R"], _superpose(func, data, s["q"], None, "rotational", s["loads"]))
    if field in ("von_mises", "stress"):
        sigma = _superpose(func, data, s["q"], None, "stress", s["loads"])
        return von_mises(sigma) if field == "von_mises" else sigma
    raise RunArgumentError(f"{func}: unknown field {field!r}; choose from {list(FIELDS)}")


def energies(data: ModalData, q: Any, qd: Any, r_0: Any, v_0: Any, w: Any, T: Any,
             g: Sequence[float] = (0.0, -g_n, 0.0)) -> dict[str, np.ndarray]:
    """Kinetic, strain and gravitational potential energy of a flexible body over a run [J].

    With the body-axes velocity ``v = T v_0`` of the reference origin, its angular velocity ``w`` (body axes) and
    the inertia invariants (:mod:`.invariants`), the kinetic energy of the mass points is (Shabana §5.4;
    Schwertassek & Wallrapp ch. 5)::

        E_kin = ½ I1 v·v + v·(w × c) + v·(I3 q̇) + ½ wᵀ J(q) w + wᵀ C(q) q̇ + ½ q̇ᵀ I6 q̇

    with ``c = I2 + I3 q``, ``J(q) = I7 + Σ_j q_j (I8_j + I8_jᵀ) + Σ_jk q_j q_k I9_jk`` and
    ``C(q) = I4 + Σ_j q_j I5_j`` — the terms whose Lagrange equations are FlexibleBody's equations of motion, so
    their sum with the strain energy ``E_strain = ½ qᵀ K q`` and the potential ``E_pot = −g·(I1 r_0 + Tᵀ c)`` is
    conserved in a run without damping, friction or drives. (The geometric stiffness of ``geometric_stiffening``
    adds the work of the body's loads on its foreshortening, not counted here.)

    Parameters
    ----------
    data : ModalData
        The body's modal data (the modes it was built with: ``FlexibleBody.data``).
    q, qd : array_like (nt, M)
        Modal coordinates [1] and their rates [1/s] (``<body>.q``, ``<body>.qd``).
    r_0, v_0 : array_like (nt, 3)
        Origin of the reference frame and its velocity, world axes [m], [m/s] (``<body>.r_0``, ``<body>.v_0``).
    w : array_like (nt, 3)
        Angular velocity of the reference frame, body axes [rad/s] (``<body>.w``).
    T : array_like (nt, 3, 3)
        Orientation of the reference frame, world to body (for a body whose ``frame_a`` sits at the reference
        node, ``<body>.frame_a.T``).
    g : sequence of 3 float
        Gravity [m/s2], world axes (default: the World's, standard gravity along −y).

    Returns
    -------
    dict
        ``kinetic``, ``strain``, ``potential`` and ``total``, each (nt,) [J].
    """
    func = "energies"
    _check_data(data, func)
    qa, _ = _modal_coordinates(data, q, func)
    qda, _ = _modal_coordinates(data, qd, func)
    nt = qa.shape[0]
    if qda.shape != qa.shape:
        raise RunArgumentError(f"{func}: argument 'qd' has shape {np.shape(qd)}, but 'q' {np.shape(q)}: one rate per "
                               "modal coordinate and instant")
    r, R = _frame_motion(r_0, T, nt, func)
    vecs = {}
    for name, value in (("v_0", v_0), ("w", w)):
        a = _array(func, name, value)
        if a.shape != (nt, 3):
            raise RunArgumentError(f"{func}: argument {name!r} has shape {a.shape}, expected ({nt}, 3)")
        vecs[name] = a
    gv = _array(func, "g", g)
    if gv.shape != (3,):
        raise RunArgumentError(f"{func}: argument 'g' has shape {gv.shape}, expected (3,) [m/s2]")
    inv = data.invariants
    v = np.einsum("tij,tj->ti", R, vecs["v_0"])
    w_ = vecs["w"]
    c = inv["I2"][None, :] + np.einsum("am,tm->ta", inv["I3"], qa)
    J = (inv["I7"][None] + np.einsum("tj,jab->tab", qa, inv["I8"] + np.swapaxes(inv["I8"], 1, 2))
         + np.einsum("tj,tk,jkab->tab", qa, qa, inv["I9"]))
    C = inv["I4"][None] + np.einsum("tj,jck->tck", qa, inv["I5"])
    kinetic = (0.5 * float(inv["I1"]) * np.einsum("ti,ti->t", v, v)
               + np.einsum("ti,ti->t", v, np.cross(w_, c))
               + np.einsum("ti,am,tm->t", v, inv["I3"], qda)
               + 0.5 * np.einsum("ta,tab,tb->t", w_, J, w_)
               + np.einsum("ta,tak,tk->t", w_, C, qda)
               + 0.5 * np.einsum("tm,mn,tn->t", qda, inv["I6"], qda))
    strain = 0.5 * np.einsum("tm,mn,tn->t", qa, data.generalized_stiffness, qa)
    potential = -(float(inv["I1"]) * r @ gv + np.einsum("tji,tj,i->t", R, c, gv))
    return {"kinetic": kinetic, "strain": strain, "potential": potential, "total": kinetic + strain + potential}
