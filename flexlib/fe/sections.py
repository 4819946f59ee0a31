"""Beam cross-sections: area, second moments, torsion constant and shear areas (SI units).

Every constructor returns a :class:`Section` whose properties are given about the section's centroidal
principal axes: local ``y`` and ``z`` of the beam element (``x`` runs along the beam axis).

References
----------
- W. D. Pilkey, *Formulas for Stress, Strain, and Structural Matrices*, 2nd ed., Wiley 2005, ch. 2 and
  tab. 2.5 (section properties, torsion constants).
- W. C. Young, R. G. Budynas, *Roark's Formulas for Stress and Strain*, 7th ed., McGraw-Hill 2002, tab. 10.7
  (torsion constants of solid, thin-walled closed and open sections).
- G. R. Cowper, "The shear coefficient in Timoshenko's beam theory", *J. Appl. Mech.* 33 (1966) 335-340
  (shear coefficients of the solid rectangle, solid and hollow circle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from flexlib.errors import RunArgumentError

__all__ = ["Section", "box", "circle", "i_section", "rectangle", "tube"]


@dataclass(frozen=True)
class Section:
    """Properties of a beam cross-section about its centroidal principal axes.

    Parameters
    ----------
    A : float
        Area [m2].
    Iy, Iz : float
        Second moments of area about the local ``y`` and ``z`` axes [m4]; ``Iz`` governs bending in the
        ``x``-``y`` plane, ``Iy`` bending in the ``x``-``z`` plane.
    J : float
        Saint-Venant torsion constant [m4] (equals the polar moment only for circular sections).
    Asy, Asz : float
        Shear areas for shear force along ``y`` and ``z`` [m2] (``kappa * A``); ``inf`` means rigid in shear.
    name : str
        Description used in error messages and provenance.
    """

    A: float
    Iy: float
    Iz: float
    J: float
    Asy: float = math.inf
    Asz: float = math.inf
    name: str = "section"

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise RunArgumentError(f"Section: name must be a string (the description in messages and provenance), "
                                   f"got {type(self.name).__name__} {self.name!r}")
        for field in ("A", "Iy", "Iz", "J", "Asy", "Asz"):
            value = getattr(self, field)
            if isinstance(value, bool) or not isinstance(value, int | float) or math.isnan(value) or value <= 0:
                raise RunArgumentError(f"section {self.name!r}: {field} must be a positive number, got {value!r}")
        for field in ("A", "Iy", "Iz", "J"):
            if math.isinf(getattr(self, field)):
                raise RunArgumentError(f"section {self.name!r}: {field} must be finite")

    @property
    def Ip(self) -> float:
        """Polar second moment of area ``Iy + Iz`` [m4] (rotary inertia in torsion)."""
        return self.Iy + self.Iz


def _positive(name: str, **values: float) -> None:
    for key, value in values.items():
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value) or value <= 0:
            raise RunArgumentError(f"{name} section: {key} must be a positive finite length [m], got {value!r}")


def _poisson(name: str, nu: float) -> None:
    if isinstance(nu, bool) or not isinstance(nu, int | float) or not -1.0 < nu <= 0.5:
        raise RunArgumentError(f"{name} section: Poisson's ratio nu must be a number in (-1, 0.5], got {nu!r}")


def rectangle(b: float, h: float, nu: float = 0.3) -> Section:
    """Solid rectangle of width ``b`` (along local ``z``) and height ``h`` (along local ``y``) [m].

    ``Iz = b h^3/12`` (bending in the ``x``-``y`` plane), ``Iy = h b^3/12``; torsion constant
    ``J = a c^3 [1/3 - 0.21 (c/a)(1 - c^4/(12 a^4))]`` with ``a = max(b, h)``, ``c = min(b, h)``
    (Roark tab. 10.7 case 4, error below 0.5 %); shear coefficient ``10(1+nu)/(12+11nu)`` (Cowper 1966).

    Parameters
    ----------
    b, h : float
        Width and height [m].
    nu : float
        Poisson's ratio [1], for the shear coefficient.
    """
    _positive("rectangle", b=b, h=h)
    _poisson("rectangle", nu)
    a, c = max(b, h), min(b, h)
    J = a * c**3 * (1.0 / 3.0 - 0.21 * (c / a) * (1.0 - c**4 / (12.0 * a**4)))
    kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)
    A = b * h
    return Section(A=A, Iy=h * b**3 / 12.0, Iz=b * h**3 / 12.0, J=J, Asy=kappa * A, Asz=kappa * A,
                   name=f"rectangle {b:g} x {h:g} m")


def circle(d: float, nu: float = 0.3) -> Section:
    """Solid circle of diameter ``d`` [m]: ``I = pi d^4/64``, ``J = pi d^4/32``, shear coefficient
    ``6(1+nu)/(7+6nu)`` (Cowper 1966).

    Parameters
    ----------
    d : float
        Diameter [m].
    nu : float
        Poisson's ratio [1].
    """
    _positive("circle", d=d)
    _poisson("circle", nu)
    I = math.pi * d**4 / 64.0
    A = math.pi * d**2 / 4.0
    kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)
    return Section(A=A, Iy=I, Iz=I, J=2.0 * I, Asy=kappa * A, Asz=kappa * A, name=f"circle d={d:g} m")


def tube(d: float, t: float, nu: float = 0.3) -> Section:
    """Circular tube of outer diameter ``d`` and wall thickness ``t`` [m]: ``I = pi (d^4 - d_i^4)/64``,
    ``J = 2 I``; shear coefficient of the hollow circle with ``m = d_i/d`` (Cowper 1966, tab. 1):
    ``6(1+nu)(1+m^2)^2 / ((7+6nu)(1+m^2)^2 + (20+12nu) m^2)``.

    Parameters
    ----------
    d, t : float
        Outer diameter and wall thickness [m], ``0 < t <= d/2``.
    nu : float
        Poisson's ratio [1].
    """
    _positive("tube", d=d, t=t)
    _poisson("tube", nu)
    if t > d / 2:
        raise RunArgumentError(f"tube section: wall thickness t={t!r} m exceeds the radius d/2={d / 2!r} m")
    di = d - 2.0 * t
    I = math.pi * (d**4 - di**4) / 64.0
    A = math.pi * (d**2 - di**2) / 4.0
    m2 = (di / d) ** 2
    kappa = 6.0 * (1.0 + nu) * (1.0 + m2) ** 2 / ((7.0 + 6.0 * nu) * (1.0 + m2) ** 2 + (20.0 + 12.0 * nu) * m2)
    return Section(A=A, Iy=I, Iz=I, J=2.0 * I, Asy=kappa * A, Asz=kappa * A, name=f"tube d={d:g} m t={t:g} m")


def box(b: float, h: float, t: float) -> Section:
    """Rectangular hollow (box) section of outer width ``b`` (along ``z``), outer height ``h`` (along ``y``)
    and uniform wall thickness ``t`` [m].

    Second moments from the outer minus the inner rectangle; torsion constant from Bredt's thin-walled
    formula ``J = 4 A_m^2 t / p_m`` on the wall mid-line (Roark tab. 10.7 case 16); shear areas are the
    wall areas parallel to the shear force (``2 h t`` for shear along ``y``; Pilkey §2.9).

    Parameters
    ----------
    b, h, t : float
        Outer width, outer height, wall thickness [m], ``t < min(b, h)/2``.
    """
    _positive("box", b=b, h=h, t=t)
    if 2.0 * t >= min(b, h):
        raise RunArgumentError(f"box section: wall thickness t={t!r} m leaves no hollow in {b!r} x {h!r} m")
    bi, hi = b - 2.0 * t, h - 2.0 * t
    A = b * h - bi * hi
    Iz = (b * h**3 - bi * hi**3) / 12.0
    Iy = (h * b**3 - hi * bi**3) / 12.0
    bm, hm = b - t, h - t
    J = 4.0 * (bm * hm) ** 2 * t / (2.0 * (bm + hm))
    return Section(A=A, Iy=Iy, Iz=Iz, J=J, Asy=2.0 * h * t, Asz=2.0 * b * t, name=f"box {b:g} x {h:g} x {t:g} m")


def i_section(b: float, h: float, tw: float, tf: float) -> Section:
    """Doubly symmetric I section: flange width ``b`` (along ``z``), overall height ``h`` (along ``y``), web
    thickness ``tw``, flange thickness ``tf`` [m].

    Second moments exact for the three rectangles; torsion constant of the thin-walled open section
    ``J = (2 b tf^3 + (h - tf) tw^3)/3`` (Roark tab. 10.7 case 26, mid-line web length); shear areas: web
    ``h tw`` for shear along ``y`` and flanges ``5/6 * 2 b tf`` along ``z`` (Pilkey §2.9).

    Parameters
    ----------
    b, h, tw, tf : float
        Flange width, overall height, web thickness, flange thickness [m].
    """
    _positive("I", b=b, h=h, tw=tw, tf=tf)
    if 2.0 * tf >= h or tw >= b:
        raise RunArgumentError(f"I section: flanges tf={tf!r} m or web tw={tw!r} m do not fit in {b!r} x {h!r} m")
    hw = h - 2.0 * tf
    A = 2.0 * b * tf + hw * tw
    Iz = (b * h**3 - (b - tw) * hw**3) / 12.0
    Iy = (2.0 * tf * b**3 + hw * tw**3) / 12.0
    J = (2.0 * b * tf**3 + (h - tf) * tw**3) / 3.0
    return Section(A=A, Iy=Iy, Iz=Iz, J=J, Asy=h * tw, Asz=5.0 / 6.0 * 2.0 * b * tf,
                   name=f"I {b:g} x {h:g} tw={tw:g} tf={tf:g} m")
