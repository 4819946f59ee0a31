"""Planar four-bar linkages of four ordinary 3D Revolutes: the catalogue's closed kinematic loop.

Crank O2–A (length a), coupler A–B (b), rocker O4–B (c), ground O2–O4 (d) along world x; every joint axis along z;
the loop is closed at the coupler–rocker revolute ``rev3`` (3 redundant rows). Reference: the closed-form position
and velocity analysis (Norton, *Design of Machinery*, §4.5) in :mod:`flexlib.models.reference.closed_form`.
Invariants: the loop closure ``coupler.frame_b.r_0 = rocker.frame_b.r_0`` and, without gravity and friction, the
kinetic energy of the three links.
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Fixed, FixedTranslation, Revolute, World
from flexlib.models.reference.closed_form import fourbar_angles

__all__ = [
    "TA",
    "TB",
    "TC",
    "TD",
    "A",
    "B",
    "C",
    "D",
    "FourBar",
    "TripleRocker",
    "link_body",
    "loop_residual",
]

#: Crank, coupler, rocker, ground lengths [m] of the crank-rocker (Grashof: s + l = 1.1 < p + q = 1.3).
A, B, C, D = 0.2, 0.7, 0.9, 0.6
#: Non-Grashof link lengths [m] (s + l = 1.0 > p + q = 0.95): a triple rocker. Every link reverses at its toggle
#: positions, where its angle cannot be a state, so a fixed state selection fails.
TA, TB, TC, TD = 0.5, 0.4, 0.45, 0.6


def link_body(m: float, L: float) -> Body:
    """A slender link's mass ``m`` [kg] at its centre, frame_a at the link's far end (length ``L`` [m]; uniform rod
    inertia m L²/12 about the axes perpendicular to it)."""
    return Body(m=m, r_CM=[-L / 2, 0, 0], I=np.diag([1e-6, m * L**2 / 12, m * L**2 / 12]))


class FourBar(fl.Model):
    """Crank O2–A, coupler A–B, rocker O4–B; all joint axes along z; the loop is closed at rev3.

    Parameters
    ----------
    theta2 : float
        Start crank angle [rad] (absolute, from world x).
    theta3, theta4 : float, optional
        Guesses of the coupler and rocker angles [rad]; default: the consistent ones on the open branch
        (:func:`~flexlib.models.reference.closed_form.fourbar_angles`).
    w2 : float
        Start crank speed [rad/s].
    lengths : tuple of float
        (crank, coupler, rocker, ground) [m].
    g : float
        Gravity [m/s2] along −y.
    """

    experiment = fl.Experiment(t_end=1.0)

    def __init__(self, theta2: float = 0.3, theta3: float | None = None, theta4: float | None = None,
                 w2: float = 6.0, lengths: tuple[float, float, float, float] = (A, B, C, D), g: float = 0.0) -> None:
        super().__init__()
        a, b, c, d = lengths
        if theta3 is None or theta4 is None:
            theta3, theta4 = (float(x) for x in fourbar_angles(a, b, c, d, theta2, "open"))
        self.world = World(g=g)
        self.ground4 = Fixed(r=[d, 0, 0])
        self.rev1 = Revolute(init={"phi": theta2, "w": w2})
        self.crank = FixedTranslation(r=[a, 0, 0])
        self.crank_mass = link_body(1.0, a)
        self.rev2 = Revolute(guess={"phi": theta3 - theta2})
        self.coupler = FixedTranslation(r=[b, 0, 0])
        self.coupler_mass = link_body(2.0, b)
        self.rev4 = Revolute(guess={"phi": theta4})
        self.rocker = FixedTranslation(r=[c, 0, 0])
        self.rocker_mass = link_body(1.5, c)
        self.rev3 = Revolute(guess={"phi": theta4 - theta3})
        self.connect(self.world.frame_b, self.rev1.frame_a)
        self.connect(self.rev1.frame_b, self.crank.frame_a)
        self.connect(self.crank.frame_b, self.crank_mass.frame_a, self.rev2.frame_a)
        self.connect(self.rev2.frame_b, self.coupler.frame_a)
        self.connect(self.coupler.frame_b, self.coupler_mass.frame_a, self.rev3.frame_a)
        self.connect(self.ground4.frame_b, self.rev4.frame_a)
        self.connect(self.rev4.frame_b, self.rocker.frame_a)
        self.connect(self.rocker.frame_b, self.rocker_mass.frame_a)
        self.connect(self.rev3.frame_b, self.rocker.frame_b)


def loop_residual(res: fl.Result) -> np.ndarray:
    """Loop-closure error [m] of a :class:`FourBar` run: the distance between the coupler's and the rocker's ends."""
    return np.linalg.norm(np.asarray(res["coupler.frame_b.r_0"]) - np.asarray(res["rocker.frame_b.r_0"]), axis=-1)


class TripleRocker(FourBar):
    """:class:`FourBar` with the non-Grashof lengths :data:`TA`…:data:`TD`, no gravity, assembled on its open branch.

    Parameters
    ----------
    theta2 : float
        Start crank angle [rad].
    w2 : float
        Start crank speed [rad/s].
    """

    experiment = fl.Experiment(t_end=5.0)

    def __init__(self, theta2: float, w2: float) -> None:
        th3, th4 = fourbar_angles(TA, TB, TC, TD, theta2, "open")
        super().__init__(theta2, th3, th4, w2, lengths=(TA, TB, TC, TD))
