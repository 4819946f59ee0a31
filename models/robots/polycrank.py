"""The power-transmission fragment of the POLYCRANK robot (seed 002, §4): bodies 4 and 5 with five six-link
parallelogram linkages.

Seed 002 describes the fragment (Warsaw University of Technology; its Figs. 6–9): rotational discs on
cross-roller bearings, composite shields, parallelogram linkages of six links each (head – pull rod – head),
the pull rods mounted with preload, friction in the bearings, a 5 kg point mass on the upper disc, 16.25 kg in
all; Grübler count −111, real mobility 4 — the two inner parallelograms of body 4 and the two of body 5 carry two
channels to the grip, the outer parallelogram of body 4 turns the upper shield (body 5), and body 4 is turned by
a drive on body 3. The paper gives the kinematic schema (its Fig. 7b), not dimensions; every number below is
assumed (:class:`PolycrankParameters`) and all joint axes are parallel (the fragment in its straight pose).

Kinematic schema as built (axes ``A0`` fixed, ``A1`` at the end of shield 4, ``A2`` at the end of shield 5):

* shield 4 on a bearing at ``A0`` (joint ``j4``), shield 5 on a bearing at ``A1`` (``j5``);
* outer channel ``o``: disc ``d0o`` at ``A0`` → six links along shield 4 → pins on shield 5 at ``A1``;
* inner channels ``c3``, ``c4``: disc ``d0c`` at ``A0`` → six links → double disc ``d1c`` at ``A1`` (bearing on
  shield 4) → six links along shield 5 → grip disc ``d2c`` at ``A2`` (bearing on shield 5).

Bodies: ground, 2 shields, 7 discs, 30 links: ``n = 40``; revolute joints: 9 bearings + 60 link pins ``j = 69``:
``M = 6 (n − 1 − j) + j = 6·(−30) + 69 = −111`` (the seed's count). Real mobility 4: shield 4 and the three
channel discs at ``A0``. In a parallelogram every link is parallel to the line of the disc axes and translates
with the discs, so the 30 closed loops repeat constraints many times over; flexlib finds and drops them
(``sim.report``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World

from .statics import energy_gradient

__all__ = ["CHANNELS", "PolycrankFragment", "PolycrankParameters", "drive_torques", "mechanical_energy",
           "potential_energy"]

#: The channels and their pin radius attribute in the parameter record: outer (shield 5), inner 3 and 4 (grip)
CHANNELS = ("o", "c3", "c4")


@dataclass(frozen=True)
class PolycrankParameters:
    """Every number of the fragment (SI units; assumed, the paper gives only the total mass and the 5 kg load).

    Attributes
    ----------
    L4, L5 : float
        Distances between the bearing axes of shield 4 (``A0``–``A1``) and shield 5 (``A1``–``A2``) [m].
    r_o, r_c3, r_c4 : float
        Pin-circle radii of the outer and the two inner parallelograms [m].
    n_links : int
        Links per parallelogram (six in the robot), pins evenly spaced on the pin circle.
    m_shield4, m_shield5 : float
        Shield masses (composite shell with the bearing housings) [kg]; centre of mass mid-way between the axes.
    I_shield4, I_shield5 : float
        Shield moments of inertia about their centre of mass, about the joint axes [kg.m2].
    m_disc, I_disc : float
        Mass [kg] and axial moment of inertia [kg.m2] of each disc (a double disc counts twice).
    m_link : float
        Mass of one link (two heads and the pull rod) [kg], centre of mass mid-way between its pins.
    m_load : float
        Point mass on the upper disc (grip and object), at ``A2`` [kg].
    g : float
        Gravity [m/s2], along ``−y`` (in the plane of motion).
    mu, r_bearing, tau_c0 : float
        Friction of the nine bearings (``friction=True``): coefficient [1] on the radial load at the bearing radius
        [m] (cross-roller bearing, journal model) and the load-independent seal torque [N.m].
    """

    L4: float = 0.30
    L5: float = 0.25
    r_o: float = 0.060
    r_c3: float = 0.045
    r_c4: float = 0.030
    n_links: int = 6
    m_shield4: float = 2.75
    I_shield4: float = 0.030
    m_shield5: float = 2.35
    I_shield5: float = 0.020
    m_disc: float = 0.35
    I_disc: float = 4.0e-4
    m_link: float = 0.10
    m_load: float = 5.0
    g: float = 9.81
    mu: float = 0.004
    r_bearing: float = 0.05
    tau_c0: float = 0.02

    @property
    def total_mass(self) -> float:
        """Mass of the fragment with the load [kg] (seed 002: 16.25 kg)."""
        discs = 1 + 2 * 2 + 2 * 2  # outer disc; two double discs at A1 (counted twice); two at A0 and two at A2
        return (self.m_shield4 + self.m_shield5 + discs * self.m_disc + 5 * self.n_links * self.m_link
                + self.m_load)

    def radius(self, channel: str) -> float:
        return float(getattr(self, f"r_{channel}"))


def _pin(rho: float, k: int, n: int) -> list[float]:
    a = 2 * math.pi * k / n
    return [rho * math.cos(a), rho * math.sin(a), 0.0]


def _e(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle)])


def potential_energy(par: PolycrankParameters, th4: float, th_o: float, th_c3: float, th_c4: float) -> float:
    """Gravitational potential energy [J] (heights along +y) for absolute angles [rad] of shield 4 and the three
    channel discs at ``A0`` (a parallelogram keeps its discs' absolute angles equal: shield 5 turns with ``th_o``,
    the inner double discs and grip discs with ``th_c3``/``th_c4``); each link's centre is the mid-point of its
    pins, which translate with the discs."""
    g, n = par.g, par.n_links
    A1 = par.L4 * _e(th4)
    A2 = A1 + par.L5 * _e(th_o)
    V = par.m_shield4 * (A1[1] / 2) + par.m_shield5 * ((A1 + A2)[1] / 2) + par.m_load * A2[1]
    V += par.m_disc * (0.0 + 2 * 0.0 + 2 * 2 * A1[1] + 2 * A2[1])  # discs on their axes: A0 (3), A1 (2×2), A2 (2)
    for ch, th in (("o", th_o), ("c3", th_c3), ("c4", th_c4)):
        rho = par.radius(ch)
        for k in range(n):
            pin = rho * _e(th + 2 * math.pi * k / n)
            V += par.m_link * ((pin + A1 + pin) / 2)[1]  # body-4 links: between A0 + pin and A1 + pin
            if ch != "o":
                V += par.m_link * ((A1 + pin + A2 + pin) / 2)[1]  # body-5 links
    return g * V


def drive_torques(par: PolycrankParameters, angles: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0),
                  h: float = 1e-6) -> np.ndarray:
    """Hand statics by virtual work: the drive torques [N.m] on shield 4 and on the outer, c3 and c4 discs at
    ``A0`` that hold the fragment at rest (``∂V/∂θ``, central differences of :func:`potential_energy`)."""
    return energy_gradient(lambda x: potential_energy(par, *x), np.asarray(angles, dtype=float), h)


def mechanical_energy(model: PolycrankFragment, result: fl.Result) -> np.ndarray:
    """Kinetic plus gravitational energy of every body, minus the work potential of the constant drive torques
    (``−Σ τ_drive φ``) [J], over a result: constant without friction, falling with it."""
    n = len(result.t)
    E = np.zeros(n)
    g = model.par.g
    for node in model.walk():
        if isinstance(node, Body):
            m = float(node.parameter_value("m"))
            r_cm = np.asarray(node.parameter_value("r_CM"), dtype=float)
            inertia = np.asarray(node.parameter_value("I"), dtype=float).reshape(3, 3)
            T = result[f"{node.path}.frame_a.T"].reshape(n, 3, 3, order="F")
            w = result[f"{node.path}.w_a"]
            v_cm = result[f"{node.path}.v_0"] + np.einsum("nji,nj->ni", T, np.cross(w, r_cm))
            x_cm = result[f"{node.path}.r_0"] + np.einsum("nji,j->ni", T, r_cm)
            E += 0.5 * m * np.sum(v_cm**2, axis=1) + 0.5 * np.einsum("ni,ij,nj->n", w, inertia, w) + m * g * x_cm[:, 1]
        elif isinstance(node, Revolute):
            E -= float(node.parameter_value("tau_drive")) * result[f"{node.path}.phi"]
    return E


class PolycrankFragment(fl.Model):
    """The POLYCRANK power-transmission fragment (module docstring), rigid links.

    Parameters
    ----------
    angles, speeds : tuple of float
        Start angles [rad] and angular velocities [rad/s] of shield 4 and of the outer, c3 and c4 discs at ``A0``
        (absolute).
    friction : bool
        Coulomb + viscous friction in the nine bearings (the revolute joints' journal model: ``mu`` on the radial
        load at ``r_bearing``, plus ``tau_c0``).

    Range: a parallelogram link passes a change point (its pins on the line of the disc axes) every 60° of
    relative rotation of its discs; there the rows kept for that link lose rank and the rigid model stops with a
    singular Jacobian. Motion through change points needs the compliance of flexible pull rods (or a redundancy
    selection made again during the run): not built yet.

    The pull rods' preload (seed 002: "links of parallelogram linkages are mounted with initial load") is a
    self-stress of the statically indeterminate linkage: with rigid links it is carried by the links themselves
    and changes nothing (the redundant links' reactions are indeterminate and set to zero), so it belongs to the
    variant with flexible pull rods.
    hold : bool
        Each drive (``j4`` and the three discs at ``A0``) carries the constant torque that holds the fragment at
        rest (:func:`drive_torques`, as ``tau_drive``); otherwise the drives carry no torque.
    params : PolycrankParameters
        The numbers.
    """

    def __init__(self, *, angles: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0), hold: bool = True,
                 speeds: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0), friction: bool = False,
                 params: PolycrankParameters | None = None) -> None:
        super().__init__()
        par = params or PolycrankParameters()
        self.par, self.friction = par, bool(friction)
        w4, w_o, w_c3, w_c4 = (float(w) for w in speeds)
        th4, th_o, th_c3, th_c4 = (float(a) for a in angles)
        tau = drive_torques(par, (th4, th_o, th_c3, th_c4)) if hold else np.zeros(4)
        z = [0.0, 0.0, 1.0]
        self.world = World(g=par.g, n=[0.0, -1.0, 0.0])
        # shields on their bearings
        bearing = {"use_friction": True, "mu": par.mu, "r_bearing": par.r_bearing, "tau_c0": par.tau_c0} \
            if friction else {}
        self.j4 = Revolute(n=z, init={"phi": th4, "w": w4}, tau_drive=float(tau[0]), **bearing)
        self.shield4 = Body(m=par.m_shield4, r_CM=[par.L4 / 2, 0, 0], I=np.eye(3) * par.I_shield4)
        self.to_A1 = FixedTranslation(r=[par.L4, 0.0, 0.0])
        self.j5 = Revolute(n=z, guess={"phi": th_o - th4}, **bearing)
        self.shield5 = Body(m=par.m_shield5, r_CM=[par.L5 / 2, 0, 0], I=np.eye(3) * par.I_shield5)
        self.to_A2 = FixedTranslation(r=[par.L5, 0.0, 0.0])
        self.load = Body(m=par.m_load, r_CM=[0.0, 0.0, 0.0], I=np.eye(3) * 1e-6)
        self.connect(self.world.frame_b, self.j4.frame_a)
        self.connect(self.j4.frame_b, self.shield4.frame_a)
        self.connect(self.j4.frame_b, self.to_A1.frame_a)
        self.connect(self.to_A1.frame_b, self.j5.frame_a)
        self.connect(self.j5.frame_b, self.shield5.frame_a)
        self.connect(self.j5.frame_b, self.to_A2.frame_a)
        self.connect(self.to_A2.frame_b, self.load.frame_a)
        disc = {"m": par.m_disc, "r_CM": [0.0, 0.0, 0.0], "I": np.diag([par.I_disc / 2, par.I_disc / 2, par.I_disc])}
        for ch, th, t_drive, w in (("o", th_o, tau[1], w_o), ("c3", th_c3, tau[2], w_c3), ("c4", th_c4, tau[3], w_c4)):
            d0 = Revolute(n=z, init={"phi": th, "w": w}, tau_drive=float(t_drive), **bearing)
            setattr(self, f"d0{ch}", d0)
            setattr(self, f"disc0{ch}", Body(**disc))
            self.connect(self.world.frame_b, d0.frame_a)
            self.connect(d0.frame_b, getattr(self, f"disc0{ch}").frame_a)
            if ch == "o":  # the outer links end on shield 5's pin circle at A1
                self._parallelogram(f"{ch}4", d0.frame_b, self.j5.frame_b, par.radius(ch), par.L4, th, th4)
                continue
            d1 = Revolute(n=z, guess={"phi": th - th4}, **bearing)
            setattr(self, f"d1{ch}", d1)
            setattr(self, f"disc1{ch}", Body(**{**disc, "m": 2 * par.m_disc, "I": 2 * disc["I"]}))
            self.connect(self.to_A1.frame_b, d1.frame_a)
            self.connect(d1.frame_b, getattr(self, f"disc1{ch}").frame_a)
            self._parallelogram(f"{ch}4", d0.frame_b, d1.frame_b, par.radius(ch), par.L4, th, th4)
            d2 = Revolute(n=z, guess={"phi": th - th_o}, **bearing)
            setattr(self, f"d2{ch}", d2)
            setattr(self, f"disc2{ch}", Body(**disc))
            self.connect(self.to_A2.frame_b, d2.frame_a)
            self.connect(d2.frame_b, getattr(self, f"disc2{ch}").frame_a)
            self._parallelogram(f"{ch}5", d1.frame_b, d2.frame_b, par.radius(ch), par.L5, th, th_o)

    def _parallelogram(self, name: str, disc_a, disc_b, rho: float, length: float, th_disc: float,
                       th_body: float) -> None:
        """Six links from the pin circle of ``disc_a`` to that of ``disc_b``: pin revolute, link (massive rod of
        ``length`` along its x axis), pin revolute; every link parallel to the body carrying the discs."""
        par = self.par
        for k in range(par.n_links):
            pa = FixedTranslation(r=_pin(rho, k, par.n_links))
            ja = Revolute(n=[0.0, 0.0, 1.0], guess={"phi": th_body - th_disc})
            rod = FixedTranslation(r=[length, 0.0, 0.0])
            mass = Body(m=par.m_link, r_CM=[length / 2, 0.0, 0.0], I=np.diag([1e-6, 1.0, 1.0]) * par.m_link
                        * length**2 / 12 + np.eye(3) * 1e-7)
            jb = Revolute(n=[0.0, 0.0, 1.0], guess={"phi": th_disc - th_body})
            pb = FixedTranslation(r=_pin(rho, k, par.n_links))
            for part, comp in (("pa", pa), ("ja", ja), ("rod", rod), ("mass", mass), ("jb", jb), ("pb", pb)):
                setattr(self, f"{name}_{part}{k + 1}", comp)
            self.connect(disc_a, pa.frame_a)
            self.connect(pa.frame_b, ja.frame_a)
            self.connect(ja.frame_b, rod.frame_a)
            self.connect(ja.frame_b, mass.frame_a)
            self.connect(rod.frame_b, jb.frame_a)
            self.connect(disc_b, pb.frame_a)
            self.connect(pb.frame_b, jb.frame_b)
