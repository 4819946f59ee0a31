"""3D rigid pendulums of multibody components: the catalogue's open chains with a closed form.

- :class:`RigidPendulum`: World, a Revolute about z, a massless rod along the joint frame's x and a Body at its
  end; released at rest from ``phi0``. Reference: the physical-pendulum period
  (:func:`~flexlib.models.reference.closed_form.physical_pendulum_period`); invariant: the energy
  ½ (m L² + I_zz) φ'² + m g L sin φ (:meth:`RigidPendulum.energy`).
- :class:`UniversalPendulum` carrying a :class:`PointOnRod`: a conical pendulum on a Universal joint (axes x and
  z); its steady cone follows from the balance ω² L cos θ = g (Goldstein §1.6).
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World
from flexlib.components.mechanics.multibody.interfaces import Frame
from flexlib.components.mechanics.multibody.universal import Universal

__all__ = ["G", "PointOnRod", "RigidPendulum", "UniversalPendulum"]

#: Gravity [m/s2] along the world's −y.
G = 9.81


class RigidPendulum(fl.Model):
    """A Body on a massless rod of length ``L`` hinged to the world by a Revolute about z.

    Parameters
    ----------
    L : float
        Rod length [m] (along the joint frame's x: φ = 0 is horizontal, φ = −π/2 hangs down).
    m : float
        Mass of the body [kg].
    inertia : array_like, optional
        Inertia tensor [kg.m2] of the body about its centre of mass (default: MSL Body's default, a small sphere).
    phi0 : float
        Start angle [rad]; released at rest.
    """

    experiment = fl.Experiment(t_end=2.0)

    def __init__(self, L: float = 0.5, m: float = 1.0, inertia: np.ndarray | None = None, phi0: float = 0.3) -> None:
        super().__init__()
        self.world = World(g=G)
        self.rev = Revolute(init={"phi": phi0, "w": 0.0})
        self.rod = FixedTranslation(r=[L, 0, 0])
        self.body = Body(m=m) if inertia is None else Body(m=m, I=np.asarray(inertia, dtype=float))
        self.connect(self.world.frame_b, self.rev.frame_a)
        self.connect(self.rev.frame_b, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.body.frame_a)

    @staticmethod
    def energy(res: fl.Result, L: float, m: float, I_zz: float, g: float = G) -> np.ndarray:
        """Mechanical energy [J] along a run: ½ (m L² + I_zz) φ'² + m g L sin φ (height of the body L sin φ)."""
        phi, w = res["rev.phi"], res["rev.w"]
        return 0.5 * (m * L**2 + I_zz) * w**2 + m * g * L * np.sin(phi)


class UniversalPendulum(fl.Model):
    """Universal joint (n_a = x, n_b = z) at the world origin, a link hanging along its frame's −y.

    Parameters
    ----------
    link : Component
        The link, with a ``frame_a`` (e.g. :class:`PointOnRod`).
    init : dict
        Start values of the joint (``phi_a``, ``phi_b`` [rad], ``w_a``, ``w_b`` [rad/s]).
    """

    experiment = fl.Experiment(t_end=3.0)

    def __init__(self, link: fl.Component, init: dict[str, float]) -> None:
        super().__init__()
        self.world = World(g=G)
        self.joint = Universal(n_a=[1, 0, 0], n_b=[0, 0, 1], init=init)
        self.link = link
        self.connect(self.world.frame_b, self.joint.frame_a)
        self.connect(self.joint.frame_b, self.link.frame_a)


class PointOnRod(fl.Component):
    """Massless rod of length ``L`` [m] along −y carrying a point mass ``m`` [kg] (a composite link)."""

    frame_a = Frame(doc="Joint end of the rod")

    def __init__(self, L: float, m: float) -> None:
        super().__init__()
        self.rod = FixedTranslation(r=[0, -L, 0])
        self.mass = Body(m=m, I=np.zeros((3, 3)))
        self.connect(self.frame_a, self.rod.frame_a)
        self.connect(self.rod.frame_b, self.mass.frame_a)
