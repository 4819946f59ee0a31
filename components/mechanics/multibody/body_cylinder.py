"""Rigid cylindrical body from geometry and density (MSL ``MultiBody.Parts.BodyCylinder``)."""

from __future__ import annotations

from typing import Any

import numpy as np

from flexlib.errors import ParameterError

from .body_shape import BodyShape, positive_size, solid_axes

__all__ = ["BodyCylinder"]


class BodyCylinder(BodyShape):
    """Cylinder (optionally a tube) between frame_a and frame_b.

    The cylinder starts at ``r_shape`` and extends ``length`` along ``length_direction``; outer radius
    ``r_o = diameter/2``, inner radius ``r_i = inner_diameter/2``. With ``ρ`` the density:

    ``m_o = ρ π L r_o²``, ``m_i = ρ π L r_i²``, ``m = m_o − m_i``, ``r_CM = r_shape + e_L L/2``,
    ``I_axis = (m_o r_o² − m_i r_i²)/2``, ``I_perp = (m_o (L² + 3 r_o²) − m_i (L² + 3 r_i²))/12``,
    ``I = Rᵀ diag(I_axis, I_perp, I_perp) R``, ``R = from_nxy(length_direction, (0, 1, 0))`` (MSL uses
    ``from_nxy(r, …)``; identical for the default ``length_direction = r − r_shape``).

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
        Vector from frame_a to the start of the cylinder, resolved in frame_a [m]; default 0.
    length_direction : array_like (3,), optional
        Direction of the cylinder axis, resolved in frame_a [1]; default ``r − r_shape`` (must not be zero).
    length : float, optional
        Length of the cylinder [m], > 0; default ``|r − r_shape|``.
    diameter : float, optional
        Outer diameter [m], > 0; default ``length/20``.
    inner_diameter : float, optional
        Inner diameter [m], ``0 ≤ inner_diameter < diameter``; default 0 (solid cylinder).
    density : float, optional
        Density of the material [kg/m3], > 0; default 7700 (steel).

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Parts.BodyCylinder`` (the animation parameters are not
    provided).
    """

    def __init__(self, *, r: Any, r_shape: Any = (0.0, 0.0, 0.0), length_direction: Any = None,
                 length: float | None = None, diameter: float | None = None, inner_diameter: float = 0.0,
                 density: float = 7700.0, Q_start: Any = None, w_start: Any = None, orientation_fixed: bool = False,
                 w_fixed: bool = False, doc: str = "") -> None:
        owner = type(self).__name__
        r, r_shape, R, L = solid_axes(owner, r, r_shape, length_direction, (0.0, 1.0, 0.0), length)
        d = positive_size(L / 20 if diameter is None else diameter, "diameter", owner)
        di = positive_size(inner_diameter, "inner_diameter", owner, allow_zero=True)
        rho = positive_size(density, "density", owner)
        if not di < d:
            raise ParameterError(f"{owner}: inner_diameter = {di} must be smaller than diameter = {d}")
        ro, ri = d / 2, di / 2
        mo, mi = rho * np.pi * L * ro**2, rho * np.pi * L * ri**2
        I_axis = (mo * ro**2 - mi * ri**2) / 2
        I_perp = (mo * (L**2 + 3 * ro**2) - mi * (L**2 + 3 * ri**2)) / 12
        I = R.T @ np.diag([I_axis, I_perp, I_perp]) @ R
        super().__init__(r=r, r_CM=r_shape + R[0] * L / 2, m=mo - mi, I=0.5 * (I + I.T), Q_start=Q_start,
                         w_start=w_start, orientation_fixed=orientation_fixed, w_fixed=w_fixed, doc=doc)
