"""An N-link planar pendulum chain of rigid bodies and revolute joints (benchmark system).

Each link is a Revolute about z followed by a massless rod of length ``L`` along the link's x
axis and a Body at its end; gravity along −y. Released at rest with every joint at ``phi0``.
"""

from __future__ import annotations

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World

__all__ = ["NLinkPendulum"]


class NLinkPendulum(fl.Model):
    """N revolute-jointed links hanging from the world origin.

    Parameters
    ----------
    n : int
        Number of links (structural).
    L : float
        Link length [m].
    m : float
        Mass at the end of each link [kg].
    phi0 : float
        Start angle of the first joint from the world x axis [rad]; the others start at 0.
    """

    def __init__(self, n: int = 5, L: float = 0.5, m: float = 1.0, phi0: float = -0.8) -> None:
        super().__init__()
        self.n = n
        self.world = World()
        prev = self.world.frame_b
        for k in range(n):
            joint = Revolute(init={"phi": phi0 if k == 0 else 0.0, "w": 0.0})
            rod = FixedTranslation(r=[L, 0, 0])
            body = Body(m=m, I=np.diag([1e-4, m * L**2 / 12, m * L**2 / 12]))
            setattr(self, f"joint{k + 1}", joint)
            setattr(self, f"rod{k + 1}", rod)
            setattr(self, f"body{k + 1}", body)
            self.connect(prev, joint.frame_a)
            self.connect(joint.frame_b, rod.frame_a)
            self.connect(rod.frame_b, body.frame_a)
            prev = rod.frame_b
