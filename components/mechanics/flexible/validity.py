"""Validity monitors of a modal body's run: is the deformation still small, and do the kept modes carry it?

The floating frame of reference with modal superposition assumes small elastic deformation: a node's displacement
``u_p = Φ_p q`` is linear in ``q``, and a frame's elastic rotation ``θ_p = Ψ_p q`` a small-rotation vector. Two
checks over every node and every output row of a run, from the recovered deformation (mode acceleration,
``Φ q + Σ_c R_c l_c`` when the modal data carry static load responses):

- **small deformation**: the largest displacement ``max |u_p|`` against ``deflection`` × the body's characteristic
  length ``L`` (the diagonal of its nodes' bounding box; Adams Solver's linear limit check is 10 % of its
  ``CHAR_LEN``), and the largest elastic rotation ``max |θ_p|`` against ``rotation`` [rad] (0.2 rad: the
  linearised rotation's error ``1 − sin θ/θ`` is 0.7 %; the seed-001 beam reaches 0.087 rad);
- **left-out modes**: the share of the recovered displacement the static residual of the left-out modes carries,
  ``max |Σ_c R_c l_c| / max |u_p|`` over nodes and rows, against ``residual`` (0.2): above it the kept modes do not
  carry the loads the run applies, and more modes (or other ones: :meth:`FlexibleBody.participation`) are needed.
  Data without static load responses, or a loaded frame at a node without load cases, give the plain deformation
  and no residual check (``residual`` None in the summary).

A check past its limit is a :class:`~flexlib.errors.ModalValidityWarning` naming the body, the quantity, the node
and the time; both are summarised per body in ``result.stats["validity"]``.

References
----------
- A. A. Shabana, *Dynamics of Multibody Systems*, 4th ed., Cambridge 2013, §7 (floating frame of reference: small
  deformation relative to the body frame).
- MSC Software, *Adams Solver*: ``FLEX_BODY/CHAR_LEN`` and ``PREFERENCES/FLEX_LIMIT_CHECK`` (linear limit 10 % of the
  characteristic length).
- R. R. Craig, A. J. Kurdila, *Fundamentals of Structural Dynamics*, Wiley 2006, §10.4 (mode-acceleration method:
  the residual static part of the left-out modes).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np

from flexlib.errors import ModalFileError, ModalValidityWarning, ModelError
from flexlib.fe.output import node_displacements, node_rotations

from .results import prefetch_body

__all__ = ["DEFAULT_LIMITS", "characteristic_length", "check_limits", "validity"]

#: Default limits: deflection [1, fraction of the characteristic length], rotation [rad], residual share [1]
DEFAULT_LIMITS = {"deflection": 0.10, "rotation": 0.20, "residual": 0.20}


def check_limits(limits: Any) -> dict[str, float] | None:
    """``limits`` of ``FlexibleBody(validity=...)``: None the defaults, False no monitors, or a mapping of some of
    ``deflection``, ``rotation``, ``residual`` to positive numbers (the others default)."""
    if limits is None:
        return dict(DEFAULT_LIMITS)
    if limits is False:
        return None
    if not isinstance(limits, Mapping):
        raise ModelError(f"FlexibleBody: validity must be None (the default limits {DEFAULT_LIMITS}), False (no "
                         f"monitors) or a mapping of some of {sorted(DEFAULT_LIMITS)} to limits, got {limits!r}")
    unknown = sorted(set(limits) - set(DEFAULT_LIMITS), key=str)
    if unknown:
        raise ModelError(f"FlexibleBody: validity has the unknown limit {unknown[0]!r}; known: "
                         f"{', '.join(sorted(DEFAULT_LIMITS))}")
    out = dict(DEFAULT_LIMITS)
    for key, value in limits.items():
        if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating) \
                or not float(value) > 0 or not np.isfinite(value):
            raise ModelError(f"FlexibleBody: validity[{key!r}] must be a positive number, got {value!r}")
        out[key] = float(value)
    return out


def characteristic_length(data: Any) -> float:
    """The diagonal of the bounding box of the body's nodes [m]."""
    x = np.asarray(data.coordinates, dtype=float)
    return float(np.linalg.norm(x.max(axis=0) - x.min(axis=0))) if x.size else 0.0


def _peak(values: np.ndarray) -> tuple[float, int, int]:
    """Largest norm over rows and nodes of ``values`` (nt, N, 3): the value, its row and its node index."""
    squares = np.einsum("kni,kni->kn", values, values)  # the squared norms (one pass, no temporary per axis)
    row, node = np.unravel_index(int(np.argmax(squares)), squares.shape)
    return float(np.linalg.norm(values[row, node])), int(row), int(node)


def validity(body: Any, result: Any, limits: dict[str, float]) -> dict[str, Any] | None:
    """The monitors of ``body`` over ``result`` (module docstring): warns past a limit and returns the summary
    (limits, peaks with their times and nodes, ``ok``); None for a body without modes or a result without rows."""
    data = body.modal_data
    if not data.n_modes or not np.size(result.t):
        return None
    prefetch_body(body, result)
    t, q, _r0, _T = body.motion(result)
    loads = None
    if data.load_cases is not None:
        try:
            loads = body.load_amplitudes(result)
        except ModalFileError:  # a loaded frame at a node without load cases: plain superposition, no residual check
            loads = None
    plain = node_displacements(data, q)
    u = plain if loads is None else node_displacements(data, q, loads=loads)
    residual = u - plain
    rotation_loads = loads if loads is not None and "rotations" in data.residual_fields() else None
    theta = node_rotations(data, q, loads=rotation_loads)
    L = characteristic_length(data)
    du, row_u, node_u = _peak(u)
    dth, row_th, node_th = _peak(theta)
    res, row_r, node_r = _peak(residual)
    share = res / du if du > 0 else 0.0
    ids = data.node_ids
    summary = {
        "limits": dict(limits), "characteristic_length": L,
        "deflection": du / L if L > 0 else 0.0, "deflection_m": du, "deflection_t": float(t[row_u]),
        "deflection_node": int(ids[node_u]),
        "rotation": dth, "rotation_t": float(t[row_th]), "rotation_node": int(ids[node_th]),
        "residual": share if loads is not None else None, "residual_t": float(t[row_r]),
        "residual_node": int(ids[node_r]),
    }
    where = body.path or type(body).__name__
    alerts = []
    if summary["deflection"] > limits["deflection"]:
        alerts.append(f"{where}: elastic displacement {du:.4g} m at node {summary['deflection_node']}, t = "
                      f"{summary['deflection_t']:.6g} s, is {100 * summary['deflection']:.3g} % of the body's "
                      f"characteristic length {L:.4g} m (limit {100 * limits['deflection']:g} %): past the small "
                      "deformation the modal body assumes; split the body or use a nonlinear FE model")
    if dth > limits["rotation"]:
        alerts.append(f"{where}: elastic rotation {dth:.4g} rad at node {summary['rotation_node']}, t = "
                      f"{summary['rotation_t']:.6g} s (limit {limits['rotation']:g} rad): past the small "
                      "rotations the modal body assumes")
    if loads is not None and share > limits["residual"]:
        alerts.append(f"{where}: the left-out modes' static response carries {100 * share:.3g} % of the recovered "
                      f"displacement (node {summary['residual_node']}, t = {summary['residual_t']:.6g} s; limit "
                      f"{100 * limits['residual']:g} %): the {data.n_modes} kept modes do not carry the run's loads; "
                      "keep more modes (FlexibleBody.participation selects them from a run's loads)")
    for text in alerts:
        warnings.warn(ModalValidityWarning(text), stacklevel=4)
    summary["ok"] = not alerts
    return summary
