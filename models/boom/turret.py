"""The slewing turret of a truck-mounted concrete-pump boom: slewing bearing, turret body, joint-1 frames.

What ``PumpTruck.__init__`` builds under the boom today (``slew``, ``turret``, ``turret_top``,
``joint1_housing``), as a part; its default values are the pump truck's (cited per parameter).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute
from flexlib.components.mechanics.multibody.interfaces import Frame
from flexlib.components.mechanics.rotational import BearingFriction
from flexlib.components.mechanics.rotational.interfaces import Flange
from flexlib.errors import ParameterError
from flexlib.models.pump_truck.parameters import DirectDrive
from flexlib.models.pump_truck.parameters import Turret as TurretRecord

from ._checks import finite, positive

__all__ = ["SLEW_FRICTION", "SLEW_W_REG", "Turret"]

PART = "Turret"

# The slewing ring of the 42 m pump truck (today also in models/pump_truck/model.py, which imports this part when it
# is recomposed; defined here, not imported from model.py, so that import does not go round in a circle).
#: Slewing-ring friction torque [N.m]: Rothe Erde's estimate mu/2 (4.4 M_k + F_a D_L) with mu = 0.005, tilting
#: moment M_k = 1.5 MN.m, axial load F_a = 150 kN, raceway diameter D_L = 1.5 m (42 m boom, filled, working pose).
SLEW_FRICTION = 0.005 / 2 * (4.4 * 1.5e6 + 150e3 * 1.5)
#: Regularisation speed of the slewing-ring friction [rad/s] (smaller fails Newton in the truck; decision 024).
SLEW_W_REG = 1e-2
#: The slewing-ring friction laws: ``"regularised"`` (the revolute's ``tanh`` law) or ``"stick-slip"`` (MSL's
#: ``BearingFriction`` on the slew axis: sticking exact, breakaway and stops as state events)
SLEW_FRICTION_LAWS = ("regularised", "stick-slip")


class Turret(fl.Model):
    """Slewing bearing carrying the turret, with the boom's joint-1 frame at its top.

    Diagram (world ``y`` up; the slewing axis is ``y``)::

        frame_a ── slew (Revolute about y, axis flange, friction) ──┬── body (Body: mass, J_slew)
                                                                   └── top (height along y) ── frame_joint1
                                                                              └── housing (H1) ── frame_housing1

    ``slew`` is a :class:`~flexlib.components.mechanics.multibody.Revolute` about ``n = (0, 1, 0)`` with its drive
    flange (``axis``) and Coulomb friction ``tau_c`` (``tau_f = tau_c tanh(w / w_reg)``: regularised, below
    ``w_reg`` a held torque creeps) — the slewing ring. Its support is grounded in the world (MSL's rule for an
    unconnected support): ``frame_a`` is the ground (chassis at rest). The turret body has its centre of mass at
    half ``height`` on the axis and inertia ``diag(J_slew/2, J_slew, J_slew/2)`` (as ``PumpTruck``). The joint-1
    frame sits ``height`` above the bearing with the bearing's orientation: ``x`` horizontal (along the boom at
    slew angle 0), ``y`` up, ``z`` the boom joints' axis. The slewing joint starts at ``phi_start``, at rest.

    Parameters
    ----------
    mass : float
        Turret mass [kg] (default 2500: ``models.pump_truck.parameters.Turret``).
    J_slew : float
        Turret inertia about the slewing axis [kg.m2] (default 3500: same source).
    height : float
        Joint 1 above the slewing bearing [m] (default 1.2: same source).
    H1 : 2 floats
        Joint-1 cylinder housing pin in the joint-1 frame [m] (default (0.45, −2.0):
        ``models.pump_truck.parameters.DirectDrive.H``).
    tau_c : float
        Slewing-ring Coulomb friction torque [N.m] (default :data:`SLEW_FRICTION`, Rothe Erde's estimate for the
        42 m boom, as ``models.pump_truck.model``); 0: no friction.
    w_reg : float
        Regularisation speed of the friction [rad/s] (default :data:`SLEW_W_REG`, as ``models.pump_truck.model``).
    friction : str
        ``"regularised"`` (default: ``tau_c tanh(w / w_reg)`` in the revolute) or ``"stick-slip"``: a
        :class:`~flexlib.components.mechanics.rotational.BearingFriction` of ``tau_c`` between the revolute's axis
        and its support (sticking exact; ``w_reg`` unused). Measured on the slew scenario in ``docs/pump_truck.md``.
    phi_start : float
        Start slew angle [rad] (the joint starts there at rest).

    Connectors
    ----------
    frame_a : Frame
        Ground side of the slewing bearing.
    frame_joint1 : Frame
        The boom's joint-1 pin (the first section's ``frame_root`` goes on it through the joint).
    frame_housing1 : Frame
        The joint-1 cylinder's housing pin.
    axis : rotational Flange
        The slewing drive flange (slew angle ``slew.phi``, torque into the bearing).

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Joints.Revolute`` (useAxisFlange); Rothe Erde, *Slewing bearings*
    catalogue (friction torque estimate).
    """

    def __init__(self, mass: float = TurretRecord.mass, J_slew: float = TurretRecord.J_slew,
                 height: float = TurretRecord.height, H1: Sequence[float] = DirectDrive.H,
                 tau_c: float = SLEW_FRICTION, w_reg: float = SLEW_W_REG, phi_start: float = 0.0,
                 friction: str = "regularised") -> None:
        super().__init__()
        mass, J_slew = positive(PART, "mass", mass, "kg"), positive(PART, "J_slew", J_slew, "kg.m2")
        self.height = positive(PART, "height", height, "m", allow_zero=True)
        tau_c, w_reg = positive(PART, "tau_c", tau_c, "N.m", allow_zero=True), positive(PART, "w_reg", w_reg, "rad/s")
        phi_start = finite(PART, "phi_start", phi_start, "rad")
        if friction not in SLEW_FRICTION_LAWS:
            raise ParameterError(f"Turret: friction must be one of {', '.join(SLEW_FRICTION_LAWS)}, got {friction!r}")
        hybrid = friction == "stick-slip" and tau_c > 0
        h1 = np.asarray(H1, dtype=float) if not isinstance(H1, str) else np.array([])
        if h1.shape != (2,) or not np.all(np.isfinite(h1)):
            raise ParameterError(f"Turret: H1 must be 2 finite numbers (x, y) [m], got {H1!r}")
        self.frame_a = Frame(doc="Ground side of the slewing bearing")
        self.frame_joint1 = Frame(doc="Joint-1 pin at the turret top")
        self.frame_housing1 = Frame(doc="Joint-1 cylinder housing pin")
        self.axis = Flange(doc="Slewing drive flange")
        self.slew = Revolute(n=[0, 1, 0], use_axis_flange=True, use_friction=not hybrid,
                             **({} if hybrid else {"tau_c0": tau_c, "w_reg": w_reg}), init={"phi": phi_start, "w": 0.0})
        if hybrid:
            self.ring = BearingFriction(tau_pos=[[0.0, tau_c]], use_support=True)
            self.connect(self.slew.axis, self.ring.flange_a)
            self.connect(self.slew.support, self.ring.support)
        self.body = Body(m=mass, r_CM=[0.0, self.height / 2, 0.0], I=np.diag([J_slew / 2, J_slew, J_slew / 2]))
        self.top = FixedTranslation(r=[0.0, self.height, 0.0])
        self.housing = FixedTranslation(r=[float(h1[0]), float(h1[1]), 0.0])
        self.connect(self.frame_a, self.slew.frame_a)
        self.connect(self.slew.frame_b, self.body.frame_a, self.top.frame_a)
        self.connect(self.top.frame_b, self.housing.frame_a, self.frame_joint1)
        self.connect(self.housing.frame_b, self.frame_housing1)
        self.connect(self.axis, self.slew.axis)
