"""LineCylinder with housing and rod point masses (MSL ``LineForceWithTwoMasses``): bench tests.

References: hand statics of a two-pin member (each point mass's weight: its component along the line to its own
pin, its component across the line split between the pins by the lever rule, moment balance about each pin);
the compound pendulum (two point masses on a line swinging about one pin; period of the nonlinear pendulum
``T = 4 sqrt(I/(g S)) K(sin(θ0/2))``, energy ``½ I ω² − g S cos θ`` conserved); free fall of the rod mass along a
vertical line (``s(t) = s0 − g t²/2``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import ellipk

import flexlib as fl
from flexlib.components.hydraulics import LineCylinder, Tank
from flexlib.components.mechanics.multibody import CutForce, Fixed, FixedTranslation, Prismatic, Revolute, World
from flexlib.units import g_n

G = g_n  # standard gravity: the World's default, as MSL's
CYL = {"d_bore": 0.08, "d_rod": 0.045, "stroke": 1.0, "m": 0.0, "V_dead_A": 1e-4, "V_dead_B": 1e-4}
M_H, L_H, M_R, L_R = 60.0, 0.4, 35.0, 0.7  # housing and rod masses [kg] and their distances from the pins [m]


def run(model: fl.Model, t_end: float, **kw) -> fl.Result:
    kw.setdefault("rtol", 1e-9)
    kw.setdefault("atol", 1e-10)
    return fl.Simulation(model).run(t_end, progress=False, **kw)


def vented_cylinder(model: fl.Model, L0: float) -> LineCylinder:
    """The massive cylinder (closed length ``L0``) as ``model.cylinder``, both chambers vented to a tank."""
    model.cylinder = LineCylinder(L0=L0, m_housing=M_H, L_housing=L_H, m_rod=M_R, L_rod=L_R, **CYL)
    model.tank_a, model.tank_b = Tank(), Tank()
    model.connect(model.cylinder.port_A, model.tank_a.port)
    model.connect(model.cylinder.port_B, model.tank_b.port)
    return model.cylinder


class Pinned(fl.Model):
    """A massive cylinder between two world-fixed pins in a tilted pose, chambers vented to tank; a cut-force
    sensor in each pin."""

    def __init__(self, r_a, r_b) -> None:
        super().__init__()
        self.world = World()
        self.pin_a, self.pin_b = Fixed(r=r_a), Fixed(r=r_b)
        self.cut_a, self.cut_b = CutForce(resolve_in_frame="world"), CutForce(resolve_in_frame="world")
        L = float(np.linalg.norm(np.subtract(r_b, r_a)))
        cyl = vented_cylinder(self, L - 0.5)
        self.connect(self.pin_a.frame_b, self.cut_a.frame_a)
        self.connect(self.cut_a.frame_b, cyl.frame_a)
        self.connect(self.pin_b.frame_b, self.cut_b.frame_a)
        self.connect(self.cut_b.frame_b, cyl.frame_b)


def test_pin_reactions_of_the_weights():
    """Cylinder from (0.3, −0.2, 0.1) to (1.5, 1.4, −0.4) m (tilted 51° from the horizontal, out of plane), at rest.

    Hand statics (gravity −y): the line's weight 95 kg·g is carried by the pins; for each mass, the part of its
    weight along the line goes to its own pin (housing → frame_a, rod → frame_b), the part across the line splits by
    the lever rule (moment balance about each pin): housing (1 − L_H/ℓ) to a, L_H/ℓ to b; rod L_R/ℓ to a,
    (1 − L_R/ℓ) to b. The chambers are at tank (= ambient) pressure: no cylinder force. Tolerance 1e-6 of the
    weight (measured ~1e-15).
    """
    r_a, r_b = np.array([0.3, -0.2, 0.1]), np.array([1.5, 1.4, -0.4])
    res = run(Pinned(r_a.tolist(), r_b.tolist()), 0.01, dt_out=0.01)
    L = np.linalg.norm(r_b - r_a)
    e = (r_b - r_a) / L
    up = np.array([0.0, 1.0, 0.0])
    F_a, F_b = np.zeros(3), np.zeros(3)
    for m, own, x_other in ((M_H, "a", L_H / L), (M_R, "b", L_R / L)):
        W = m * G * up  # support the pins must give the mass
        along, across = e * (W @ e), W - e * (W @ e)
        if own == "a":
            F_a += along + (1 - x_other) * across
            F_b += x_other * across
        else:
            F_b += along + (1 - x_other) * across
            F_a += x_other * across
    tol = 1e-6 * (M_H + M_R) * G
    for k in range(3):
        assert res[f"cut_a.force[{k}]"][-1] == pytest.approx(F_a[k], abs=tol)
        assert res[f"cut_b.force[{k}]"][-1] == pytest.approx(F_b[k], abs=tol)
    # moment balance about pin a, written out independently: ℓ e × F_b = Σ r_i × W_i
    r_h, r_r = L_H * e, (L - L_R) * e
    M = np.cross(r_h, M_H * G * up) + np.cross(r_r, M_R * G * up)
    np.testing.assert_allclose(np.cross(L * e, F_b), M, rtol=0, atol=1e-6 * np.abs(M).max())


class Pendulum(fl.Model):
    """The cylinder's line swings about its housing pin: frame_b on a massless crank (revolute about z at the
    housing pin, crank length ℓ), so the line keeps its length and the two point masses make a compound pendulum."""

    def __init__(self, theta0: float, ell: float) -> None:
        super().__init__()
        self.world = World()
        self.hinge = Revolute(n=[0, 0, 1], init={"phi": theta0, "w": 0.0})
        self.crank = FixedTranslation(r=[0.0, -ell, 0.0])
        cyl = vented_cylinder(self, ell - 0.5)
        self.connect(self.world.frame_b, self.hinge.frame_a, cyl.frame_a)
        self.connect(self.hinge.frame_b, self.crank.frame_a)
        self.connect(self.crank.frame_b, cyl.frame_b)


def test_compound_pendulum():
    """Swing from θ0 = 60°: period vs the nonlinear compound pendulum and conservation of energy.

    Reference: point masses M_H at L_H and M_R at ℓ − L_R from the pivot: ``I = M_H L_H² + M_R (ℓ − L_R)²``,
    ``S = M_H L_H + M_R (ℓ − L_R)``, ``I θ̈ = −g S sin θ``; period ``T = 4 sqrt(I/(g S)) K(k)``, ``k = sin(θ0/2)``
    (complete elliptic integral of the first kind, parameter k²). Tolerances: period 1e-5 relative (zero crossings
    of θ̇ interpolated on 1 ms output), energy 1e-6 of ``g S`` (rtol 1e-9 of the run).
    """
    ell, theta0 = 2.0, math.radians(60.0)
    I_p = M_H * L_H**2 + M_R * (ell - L_R) ** 2
    S = M_H * L_H + M_R * (ell - L_R)
    T_ref = 4 * math.sqrt(I_p / (G * S)) * ellipk(math.sin(theta0 / 2) ** 2)
    res = run(Pendulum(theta0, ell), 1.2 * T_ref, dt_out=1e-3)
    t, phi, w = res["time"], res["hinge.phi"], res["hinge.w"]
    energy = 0.5 * I_p * w**2 - G * S * np.cos(phi)
    np.testing.assert_allclose(energy, energy[0], rtol=0, atol=1e-6 * G * S)
    # θ̇ crosses zero (downwards → upwards) at T/2 and T
    idx = np.nonzero((w[:-1] > 0) & (w[1:] <= 0))[0]
    assert len(idx) >= 1
    i = idx[0]
    t_cross = t[i] - w[i] * (t[i + 1] - t[i]) / (w[i + 1] - w[i])
    assert t_cross == pytest.approx(T_ref, rel=1e-5)
    assert np.min(phi) == pytest.approx(-theta0, abs=1e-6)


class Drop(fl.Model):
    """Vertical cylinder, housing pin fixed, rod pin on a massless vertical slide: the rod mass falls along the
    line (chambers vented, no friction)."""

    def __init__(self, s0: float) -> None:
        super().__init__()
        self.world = World()
        self.slide = Prismatic(n=[0, -1, 0], init={"s": s0, "v": 0.0})
        cyl = vented_cylinder(self, s0 - 0.5)
        self.connect(self.world.frame_b, self.slide.frame_a, cyl.frame_a)
        self.connect(self.slide.frame_b, cyl.frame_b)


def test_rod_mass_falls_along_the_line():
    """The rod mass alone moves along the line: ``s(t) = s0 + g t²/2`` (s measured downwards); the housing's weight
    stays on the fixed pin. Tolerance 1e-7 m over 0.3 s (0.44 m of fall)."""
    s0 = 1.0
    res = run(Drop(s0), 0.3, dt_out=0.01)
    t = res["time"]
    np.testing.assert_allclose(res["slide.s"], s0 + 0.5 * G * t**2, rtol=0, atol=1e-7)


def test_no_masses_is_the_massless_cylinder():
    """Without masses no ``masses`` component is built (the model is that of the massless cylinder)."""
    cyl = LineCylinder(L0=1.0, **CYL)
    assert not hasattr(cyl, "masses")
    assert hasattr(LineCylinder(L0=1.0, m_rod=1.0, **CYL), "masses")


@pytest.mark.parametrize("name", ["m_housing", "L_housing", "m_rod", "L_rod"])
def test_negative_mass_arguments(name):
    with pytest.raises(fl.ParameterError, match=f"LineCylinder: {name} must be a number >= 0"):
        LineCylinder(L0=1.0, **{name: -1.0}, **CYL)
