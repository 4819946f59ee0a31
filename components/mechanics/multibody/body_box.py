"""Rigid box-shaped body from geometry and density (MSL ``MultiBody.Parts.BodyBox``)."""

from __future__ import annotations

from typing import Any

import numpy as np

from flexlib.errors import ParameterError

from .body_shape import BodyShape, positive_size, solid_axes

__all__ = ["BodyBox"]


class BodyBox(BodyShape):
    """Box (optionally with a rectangular hole along its length) between frame_a and frame_b.

    The box starts at ``r_shape`` and extends ``length`` along ``length_direction``; its cross-section is
    ``width`` along ``width_direction`` (made orthogonal to the length direction) by ``height`` along the
    third axis, with an inner rectangular hole ``inner_width × inner_height`` over the whole length.
    With ``ρ`` the density:

    ``m_o = ρ L W H``, ``m_i = ρ L W_i H_i``, ``m = m_o − m_i``,
    ``r_CM = r_shape + e_L L/2``,
    ``I = Rᵀ diag(m_o(W²+H²) − m_i(W_i²+H_i²), m_o(L²+H²) − m_i(L²+H_i²), m_o(L²+W²) − m_i(L²+W_i²))/12 R``,

    with ``R = from_nxy(length_direction, width_direction)`` (rows: box axes resolved in frame_a). MSL
    orients the inertia with ``from_nxy(r, widthDirection)`` but places the centre of mass along
    ``lengthDirection``; here both use ``length_direction`` (identical for the default ``length_direction =
    r − r_shape``).

    The geometry and the density are **constructor arguments**: the mass properties are computed once
    (NumPy) and become the run-time parameters ``<name>.body.m``, ``<name>.body.r_CM``, ``<name>.body.I``
    and ``<name>.frame_translation.r`` of the :class:`BodyShape` parts. To change the geometry, build a new
    model instance (the structure is unchanged, so a cached compilation is reused); overriding the body
    parameters at run time does not re-derive them from the geometry.

    Parameters
    ----------
    r : array_like (3,)
        Vector from the origin of frame_a to the origin of frame_b, resolved in frame_a [m].
    r_shape : array_like (3,), optional
        Vector from frame_a to the start of the box, resolved in frame_a [m]; default 0.
    length_direction : array_like (3,), optional
        Direction of the box length, resolved in frame_a [1]; default ``r − r_shape`` (must not be zero).
    width_direction : array_like (3,), optional
        Direction of the box width, resolved in frame_a [1]; default ``(0, 1, 0)``. Only its part
        orthogonal to ``length_direction`` counts; if it is parallel, MSL's fallback axis is used.
    length : float, optional
        Length of the box [m], > 0; default ``|r − r_shape|``.
    width : float, optional
        Width of the box [m], > 0; default ``length/20``.
    height : float, optional
        Height of the box [m], > 0; default ``width``.
    inner_width : float, optional
        Width of the inner hole [m], ``0 ≤ inner_width < width``; default 0 (solid box).
    inner_height : float, optional
        Height of the inner hole [m], ``0 ≤ inner_height < height``; default ``inner_width``.
    density : float, optional
        Density of the material [kg/m3], > 0; default 7700 (steel).

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Parts.BodyBox`` (the animation parameters are not provided).
    """

    def __init__(self, *, r: Any, r_shape: Any = (0.0, 0.0, 0.0), length_direction: Any = None,
                 width_direction: Any = (0.0, 1.0, 0.0), length: float | None = None, width: float | None = None,
                 height: float | None = None, inner_width: float = 0.0, inner_height: float | None = None,
                 density: float = 7700.0, Q_start: Any = None, w_start: Any = None, orientation_fixed: bool = False,
                 w_fixed: bool = False, doc: str = "") -> None:
        owner = type(self).__name__
        r, r_shape, R, L = solid_axes(owner, r, r_shape, length_direction, width_direction, length)
        W = positive_size(L / 20 if width is None else width, "width", owner)
        H = positive_size(W if height is None else height, "height", owner)
        Wi = positive_size(inner_width, "inner_width", owner, allow_zero=True)
        Hi = positive_size(Wi if inner_height is None else inner_height, "inner_height", owner, allow_zero=True)
        rho = positive_size(density, "density", owner)
        if not Wi < W:
            raise ParameterError(f"{owner}: inner_width = {Wi} must be smaller than width = {W}")
        if not Hi < H:
            raise ParameterError(f"{owner}: inner_height = {Hi} must be smaller than height = {H}")
        mo, mi = rho * L * W * H, rho * L * Wi * Hi
        D = np.diag([mo * (W**2 + H**2) - mi * (Wi**2 + Hi**2), mo * (L**2 + H**2) - mi * (L**2 + Hi**2),
                     mo * (L**2 + W**2) - mi * (L**2 + Wi**2)]) / 12
        I = R.T @ D @ R
        super().__init__(r=r, r_CM=r_shape + R[0] * L / 2, m=mo - mi, I=0.5 * (I + I.T), Q_start=Q_start,
                         w_start=w_start, orientation_fixed=orientation_fixed, w_fixed=w_fixed, doc=doc)
