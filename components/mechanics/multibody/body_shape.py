"""Rigid body with two frames (MSL ``MultiBody.Parts.BodyShape``): a FixedTranslation plus a Body."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from flexlib import Component
from flexlib.core.values import not_a_scalar, numeric_array
from flexlib.errors import ParameterError

from .body import Body
from .fixed_translation import FixedTranslation
from .interfaces import Frame

__all__ = ["BodyShape"]


class BodyShape(Component):
    """Rigid body with mass properties at frame_a and a second frame at ``r`` (a composite).

    Built as in MSL from two parts, both attached at frame_a: ``frame_translation``
    (:class:`FixedTranslation`, frame_a → frame_b by ``r``) and ``body`` (:class:`Body` with ``m``,
    ``r_CM``, ``I``). It has no equations of its own. If no World or Fixed frame reaches the body
    through joints with an orientation branch, ``body`` becomes the root of its orientation tree
    (quaternion states), as a lone :class:`Body` does.

    The values below are constructor arguments; they become the run-time parameters of the two parts:
    ``<name>.frame_translation.r``, ``<name>.body.m``, ``<name>.body.r_CM``, ``<name>.body.I`` (change
    them with ``sim.run(params={...})`` under those names).

    Parameters
    ----------
    r : array_like (3,)
        Vector from the origin of frame_a to the origin of frame_b, resolved in frame_a [m].
    r_CM : array_like (3,)
        Vector from the origin of frame_a to the centre of mass, resolved in frame_a [m].
    m : float
        Mass [kg], ≥ 0.
    I : array_like (3, 3), optional
        Inertia tensor about the centre of mass, resolved in frame_a [kg.m2]; symmetric positive
        semi-definite, triangle inequality (checked). Default ``diag(1e-3, 1e-3, 1e-3)``.
    Q_start, w_start, orientation_fixed, w_fixed
        Start orientation [1] and start angular velocity [rad/s] of frame_a and whether they are initial
        conditions (structural); passed to :class:`Body` (used when the body is an orientation root, or to
        fix the orientation reached through joints).

    Connectors
    ----------
    frame_a : Frame
        Frame at which the mass properties are given.
    frame_b : Frame
        Frame at ``r`` from frame_a (same orientation).

    Variables
    ---------
    None of its own; see ``body`` (``r_0``, ``v_0``, ``a_0``, ``w_a``, ``z_a``, ``Q``) and ``frame_translation``.
    The attributes ``mass`` [kg], ``center_of_mass`` [m] and ``inertia`` [kg.m2] return the current values
    of ``body.m``, ``body.r_CM`` and ``body.I``.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Parts.BodyShape`` (the animation parameters are not provided).
    """

    frame_a = Frame(doc="Frame at which the mass properties are given")
    frame_b = Frame(doc="Frame at r from frame_a")

    def __init__(self, *, r: Any, r_CM: Any, m: float, I: Any = None, Q_start: Any = None, w_start: Any = None,
                 orientation_fixed: bool = False, w_fixed: bool = False, doc: str = "") -> None:
        super().__init__(doc=doc)
        body_args: dict[str, Any] = {"m": m, "r_CM": r_CM}
        for key, value in (("I", I), ("Q_start", Q_start), ("w_start", w_start)):
            if value is not None:
                body_args[key] = value
        self.frame_translation = build_part(self, FixedTranslation, r=r)
        self.body = build_part(self, Body, orientation_fixed=orientation_fixed, w_fixed=w_fixed, **body_args)
        self.connect(self.frame_a, self.frame_translation.frame_a, self.body.frame_a)
        self.connect(self.frame_translation.frame_b, self.frame_b)

    @property
    def mass(self) -> float:
        """Current value of the mass ``body.m`` [kg]."""
        return float(self.body.parameter_value("m"))

    @property
    def center_of_mass(self) -> np.ndarray:
        """Current centre of mass ``body.r_CM`` from frame_a, resolved in frame_a [m]."""
        return np.array(self.body.parameter_value("r_CM"), dtype=float)

    @property
    def inertia(self) -> np.ndarray:
        """Current inertia tensor ``body.I`` about the centre of mass, resolved in frame_a [kg.m2]."""
        return np.array(self.body.parameter_value("I"), dtype=float)


def build_part(owner: Component, factory: Callable[..., Any], **kwargs: Any) -> Any:
    """Build a part of a composite; a bad value is reported with the composite's class name."""
    try:
        return factory(**kwargs)
    except ParameterError as exc:
        raise ParameterError(f"{type(owner).__name__}: {exc}") from exc


def unit_vector(v: Any, what: str, owner: str) -> np.ndarray:
    v = vector3(v, what, owner)
    norm = np.linalg.norm(v)
    if not norm > 1e-12:
        raise ParameterError(f"{owner}: {what} = {v.tolist()} has zero length")
    return v / norm


def from_nxy(n_x: Any, n_y: Any, owner: str) -> np.ndarray:
    """Transformation matrix frame → shape frame whose x axis is ``n_x`` and whose y axis is in the plane
    of ``n_x`` and ``n_y`` (MSL ``Frames.TransformationMatrices.from_nxy``, including its fallback when
    ``n_y`` is parallel to ``n_x``). Rows are the shape axes resolved in the frame."""
    e_x = unit_vector(n_x, "length_direction (default r − r_shape)", owner)
    n_y = vector3(n_y, "width_direction", owner)
    aux = np.cross(e_x, n_y)
    if not aux @ aux > 1e-6:
        n_y = np.array([0.0, 1.0, 0.0]) if abs(e_x[0]) > 1e-6 else np.array([1.0, 0.0, 0.0])
        aux = np.cross(e_x, n_y)
    e_z = aux / np.linalg.norm(aux)
    return np.vstack([e_x, np.cross(e_z, e_x), e_z])


def solid_axes(owner: str, r: Any, r_shape: Any, length_direction: Any, width_direction: Any,
               length: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """``(r, r_shape, R, L)`` of a solid between frame_a and frame_b (MSL ``BodyBox``, ``BodyCylinder``).

    ``r`` and ``r_shape`` checked 3-vectors [m]; the rows of ``R`` are the solid's length, width and height axes
    resolved in frame_a (:func:`from_nxy` of ``length_direction``, default ``r − r_shape``, and
    ``width_direction``); ``L`` is its length [m], default ``|r − r_shape|``.
    """
    r = vector3(r, "r", owner)
    r_shape = vector3(r_shape, "r_shape", owner)
    if length_direction is None:
        length_direction = r - r_shape
    R = from_nxy(length_direction, unit_vector(width_direction, "width_direction", owner), owner)
    L = positive_size(np.linalg.norm(r - r_shape) if length is None else length, "length", owner)
    return r, r_shape, R, L


def positive_size(value: Any, what: str, owner: str, allow_zero: bool = False) -> float:
    """A size or density: a real number (not a string such as ``density="7800"``, a bool or an array), > 0."""
    why = not_a_scalar(value)
    if why is not None:
        raise ParameterError(f"{owner}: {what} = {value!r:.80} is not a number ({why})")
    x = float(value)
    if not np.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        bound = "≥ 0" if allow_zero else "> 0"
        raise ParameterError(f"{owner}: {what} = {value!r} must be {bound}")
    return x


def vector3(v: Any, what: str, owner: str) -> np.ndarray:
    """A 3-vector of real numbers (strings, bools, None and dicts are refused naming ``what``)."""
    arr = numeric_array(v, f"{owner}: {what} =", "a finite 3-vector of real numbers", ParameterError).reshape(-1)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ParameterError(f"{owner}: {what} must be a finite 3-vector, got {v!r}")
    return arr
