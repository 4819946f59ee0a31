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
from functools import lru_cache
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.components.control import Constant, TimeTable, Trapezoid, Trim
from flexlib.components.mechanics import rotational
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.components.mechanics.multibody import Body, FixedTranslation, Revolute, World
from flexlib.fe import beam_mesh, circle, energies, modal_data_from_fe, nodal_stress, von_mises

from .polycrank_shield import shield_modal_data
from .statics import energy_gradient

__all__ = ["CHANNELS", "PolycrankFragment", "PolycrankParameters", "drive_torques", "mechanical_energy",
           "mount_stretch", "potential_energy", "preload_params", "rod_modal_data", "rod_stress"]

#: Drive options of :class:`PolycrankFragment`, and its driven joints (shield 4, then the discs at ``A0``)
DRIVES = ("torque", "trim", "held", "motion")
DRIVEN = ("j4", "d0o", "d0c3", "d0c4")

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
    d_rod, E_rod : float
        Pull rod (flexible variant): steel rod diameter [m] and Young's modulus [Pa]; its density is set so that the
        rod carries the whole link mass ``m_link`` (heads included).
    rod_elements, rod_modes : int
        Beam elements and fixed-interface modes per pull rod (Craig–Bampton, both pins interface).
    h_shield, b_shield, t_shield : float
        Flexible shield 5 (:mod:`.polycrank_shield`): the shell's box section, outer height in the plane of motion
        [m] (it encloses the inner channels' discs and links, pin circles up to 45 mm), outer width along the joint
        axes [m] and wall [m]: a CFRP box 130 × 80 × 5 mm.
    E_shield, nu_shield : float
        The shell's Young's modulus [Pa] (a quasi-isotropic carbon/epoxy laminate, about 50 GPa: Daniel & Ishai,
        *Engineering Mechanics of Composite Materials*, 2nd ed., 2006) and Poisson's ratio [1] (shear modulus
        ``E / (2 (1 + nu))``); its density follows from ``m_shield5`` and ``I_shield5``.
    h_spider, b_spider, E_spider, rho_spider : float
        The shield's spider (six spokes from ``A1`` to the outer pins, seed 002's spider webs): section height
        in the plane [m] and width [m], Young's modulus [Pa] and density [kg/m3] — stiff (a spoke 700 times
        stiffer at its pin than a pull rod along its axis) and light (17 g in all): it carries the pin loads to
        the bearing as a thick flange, whose compliance it does not model.
    shield_elements, shield_cb_modes, shield_modes : int
        The shell's beam elements, the fixed-interface modes of its Craig–Bampton reduction, and the in-plane
        modes the flexible shield keeps (``FlexibleBody(modes=shield_modes, plane="xy")``).
    mu, r_bearing, tau_c0 : float
        Friction of the nine bearings (``friction=True``): coefficient [1] on the radial load at the bearing radius
        [m] (cross-roller bearing, journal model) and the load-independent seal torque [N.m].
    stribeck, w_s, d_bearing : float
        The bearings' break-away to Coulomb friction ratio [1] at rest, its Stribeck speed [rad/s] and their viscous
        coefficient [N.m.s/rad] (grease) — the revolute joint's Coulomb + Stribeck + viscous law.
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
    stribeck: float = 1.3
    w_s: float = 0.05
    d_bearing: float = 2.0e-3
    d_rod: float = 0.006
    E_rod: float = 2.1e11
    rod_elements: int = 6
    rod_modes: int = 2
    h_shield: float = 0.13
    b_shield: float = 0.08
    t_shield: float = 0.005
    E_shield: float = 5.0e10
    nu_shield: float = 0.3
    h_spider: float = 0.04
    b_spider: float = 0.012
    E_spider: float = 2.1e13
    rho_spider: float = 100.0
    shield_elements: int = 8
    shield_cb_modes: int = 4
    shield_modes: int = 4

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


@lru_cache(maxsize=16)
def rod_modal_data(par: PolycrankParameters, length: float) -> Any:
    """Craig–Bampton data of one pull rod of free length ``length`` [m] (beam along x, both pins interface,
    reference frame at the first pin, geometric stiffening of the unit load cases, stresses at the rod's surface
    fibre in the plane of motion, ``y = d/2``, where the in-plane bending adds to the axial stress)."""
    section = circle(par.d_rod)
    rho = par.m_link / (section.A * length)
    fe = beam_mesh((0.0, 0.0, 0.0), (length, 0.0, 0.0), par.rod_elements, section, E=par.E_rod, rho=rho)
    return modal_data_from_fe(fe, [0, par.rod_elements], par.rod_modes, reference_node=0, attachment="pinned",
                              title=f"POLYCRANK pull rod {length:.6f} m, d {par.d_rod} m",
                              stress_fibre=(par.d_rod / 2, 0.0), geometric_stiffening=True)


def mount_stretch(par: PolycrankParameters, length: float, preload: float) -> float:
    """Stretch [m] that mounting a pull rod of free length ``length`` [m] between its pins needs for the tension
    ``preload`` [N]: ``T L / (E A)`` (the rod is that much shorter than the pin distance)."""
    return preload * length / (par.E_rod * circle(par.d_rod).A)


def preload_params(model: PolycrankFragment, preload: float) -> dict[str, list[float]]:
    """Run-time parameters (``run(params=...)``) that mount every pull rod of a flexible ``model`` with the tension
    ``preload`` [N]: each rod's mount offset ``<link>_mount<k>.r`` (no rebuild).

    The model must be built with a preload > 0: built with none, its zero mount offsets are assumed zero (planar
    mechanism, ``flexlib.compile.constants``) and a run with others raises ``StructureChangedError``."""
    if not model.flexible:
        raise fl.ParameterError("preload_params: the model has rigid links (flexible=False)")
    if preload and not model.preload:
        raise fl.ParameterError("preload_params: the model was built without preload (its mount offsets are "
                                "assumed zero); build it with PolycrankFragment(preload=...) > 0 to vary the preload "
                                "at run time")
    if not (preload >= 0 and math.isfinite(preload)):
        raise fl.ParameterError(f"preload_params: preload must be a finite tension >= 0 N, got {preload!r}")
    out = {}
    for name, length in model._mounts:
        out[f"{name}.r"] = [-mount_stretch(model.par, length, preload), 0.0, 0.0]
    return out


def rod_stress(model: PolycrankFragment, result: fl.Result) -> dict[str, np.ndarray]:
    """Von Mises stress [Pa] of every pull rod of a flexible ``model`` over a result: the largest over the rod's
    nodes at its in-plane surface fibre (stress modes superposed with the run's modal coordinates,
    :func:`~flexlib.fe.nodal_stress`), by rod path (``o4_rod1`` …), each (nt,)."""
    if not model.flexible:
        raise fl.ParameterError("rod_stress: the model has rigid links (flexible=False)")
    out = {}
    for node in model.walk():
        if isinstance(node, FlexibleBody) and node is not model.shield5:
            sigma = nodal_stress(node.modal_data, result[f"{node.path}.q"])
            out[node.path] = von_mises(sigma).max(axis=1)
    return out


def mechanical_energy(model: PolycrankFragment, result: fl.Result) -> np.ndarray:
    """Kinetic plus gravitational energy of every body, plus the strain energy of the flexible pull rods and shield
    (:func:`~flexlib.fe.energies`), minus the work potential of the constant drive
    torques (``−Σ τ_drive φ``, with ``drive="trim"`` ``−Σ b φ`` of the trims) [J], over a result: constant
    without friction, damping, interval torques and driven motion."""
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
        elif isinstance(node, FlexibleBody):  # the reference frame's orientation: frame_a's less its elastic turn
            p = node.path
            _, q, r_0, T = node.motion(result)
            qd = result[f"{p}.qd"] if node.n_modes else np.zeros((n, 0))
            E += energies(node.modal_data, q, qd, r_0, result[f"{p}.v_0"], result[f"{p}.w"], T,
                          g=(0.0, -g, 0.0))["total"]
        elif isinstance(node, Revolute):
            E -= float(node.parameter_value("tau_drive")) * result[f"{node.path}.phi"]
    for name in DRIVEN:  # drive="trim": the holding torque's work potential (the interval torques do work)
        if f"trim_{name}.b" in result:
            E -= result[f"trim_{name}.b"] * result[f"{name}.phi"]
    return E


def _check_drive(drive: str, motion: tuple | None, torques: tuple | None) -> None:
    """``PolycrankFragment``'s drive options: a known ``drive``, four motion tuples for ``"motion"``, four torque
    tables only with ``"trim"``."""
    if drive not in DRIVES:
        raise fl.ParameterError(f"PolycrankFragment: drive must be one of {DRIVES}, got {drive!r}")
    if drive == "motion" and (motion is None or len(motion) != 4 or any(len(m) != 4 for m in motion)):
        raise fl.ParameterError("PolycrankFragment: drive='motion' needs motion = four (peak [rad/s], ramp "
                                f"[s], plateau [s], start [s]) tuples, got {motion!r}")
    if torques is not None and (drive != "trim" or len(torques) != 4):
        raise fl.ParameterError("PolycrankFragment: torques (four (times [s], torques [N.m]) tables) go with "
                                f"drive='trim', got drive={drive!r}, torques={torques!r}")


class PolycrankFragment(fl.Model):
    """The POLYCRANK power-transmission fragment (module docstring), rigid or with flexible pull rods and a flexible
    shield 5.

    A parallelogram link passes a change point (its pins on the line of the disc axes) every 30° of relative
    rotation of its discs; there the loop rows kept for a rigid link lose rank and a run released with speeds can
    stop with a singular Jacobian. Flexible pull rods carry no torque there and run through
    (``tests/models/test_robots_polycrank_flexible.py``).

    The pull rods' preload (seed 002: "links of parallelogram linkages are mounted with initial load") is a
    self-stress of the statically indeterminate linkage: with rigid links it is carried by the links themselves
    and changes nothing (the redundant links' reactions are indeterminate and set to zero), so it belongs to the
    variant with flexible pull rods.

    Parameters
    ----------
    angles, speeds : tuple of float
        Start angles [rad] and angular velocities [rad/s] of shield 4 and of the outer, c3 and c4 discs at ``A0``
        (absolute; the speeds with ``drive="torque"``).
    friction : bool
        Coulomb + Stribeck + viscous friction in the nine bearings (the revolute joints' law: ``mu`` on the radial
        load at ``r_bearing``, plus ``tau_c0``; :class:`PolycrankParameters`).
    hold : bool
        ``drive="torque"``: each drive (``j4`` and the three discs at ``A0``) carries the constant torque that holds
        the rigid fragment at rest (:func:`drive_torques`, as ``tau_drive``); otherwise the drives carry no torque.
    drive : {"torque", "trim", "held", "motion"}
        ``"torque"``: constant drive torques (``hold``), the start angles and speeds initial conditions.
        ``"trim"``: each drive a torque source (``motor_j4`` …) whose torque is the holding torque that the
        initialisation finds for the start at rest (a :class:`~flexlib.components.control.Trim`, ``trim_j4`` …,
        guessed from the hand statics; the drive joints start at rest and not accelerating) plus the interval
        torques ``torques`` — the seed's torque-driven runs, rigid or flexible (with ``run(steady_state=True)``).
        ``"held"``: each drive's axis held at its start angle by a position source (``hold_j4``, ``hold_d0o``,
        ``hold_d0c3``, ``hold_d0c4``: ``flange.tau`` is the holding torque, a result) — the drives of a static
        start (``run(steady_state=True)``) of the flexible fragment, whose holding torques differ from the rigid
        hand statics by what the links' compliance changes.
        ``"motion"``: each drive's speed follows a trapezoid (``motion``) from its start angle.
    motion : tuple of 4 (peak, ramp, plateau, start)
        ``drive="motion"``: per drive, peak speed [rad/s], ramp and plateau durations [s] and start time [s].
    torques : tuple of 4 (times, torques)
        ``drive="trim"``: per drive, a table of torques [N.m] added to the trim, constant from each time [s] to the
        next (default none).
    flexible : bool
        Each pull rod a Craig–Bampton :class:`~flexlib.components.mechanics.flexible.FlexibleBody` (beam mesh of a
        ``d_rod`` steel rod, both pins interface, geometric stiffening of its axial force: without it a tensioned
        rod of the linear floating-frame model shortens its chord by bending instead of stretching and finds a
        spurious bent equilibrium). Static start: ``drive="trim"`` or ``"held"`` and ``run(steady_state=True)``.
    flexible_shield : bool
        Shield 5 a Craig–Bampton :class:`~flexlib.components.mechanics.flexible.FlexibleBody`
        (:func:`~.polycrank_shield.shield_modal_data`, seed 002's flexible shield of body 5): a beam frame of the
        CFRP shell from ``A1`` to ``A2`` and a stiff spider to the outer channel's six pins, with the rigid
        shield's mass, centre of mass and inertia; reference frame pinned at ``A1`` (on the free bearing ``j5``);
        the ``shield_modes`` lowest in-plane modes. Its frames: ``frame_a`` at ``A1`` (on ``j5``), ``frame_b`` at
        ``A2`` (the load and the grip discs' bearings), ``frame_c`` … ``frame_h`` at the outer channel's pins (the
        links' far pin joints). With rigid or flexible pull rods.
    preload : float
        Tension of every pull rod when mounted [N] (``flexible=True``): each rod hangs on its far pin through a
        mount offset ``−T L / (E A)`` along it (a run-time parameter: :func:`preload_params`).
    params : PolycrankParameters
        The numbers.
    """

    def __init__(self, *, angles: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0), hold: bool = True,
                 speeds: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0), friction: bool = False,
                 drive: str = "torque", motion: tuple | None = None, torques: tuple | None = None,
                 flexible: bool = False, flexible_shield: bool = False,
                 preload: float = 0.0, params: PolycrankParameters | None = None) -> None:
        super().__init__()
        par = params or PolycrankParameters()
        if preload and not flexible:
            raise fl.ParameterError("PolycrankFragment: preload needs flexible=True (with rigid links a pull rod's "
                                    "preload is a self-stress the rigid links carry; see the class docstring)")
        if not (preload >= 0 and math.isfinite(preload)):
            raise fl.ParameterError(f"PolycrankFragment: preload must be a finite tension >= 0 N, got {preload!r}")
        self.par, self.friction, self.flexible, self.preload = par, bool(friction), bool(flexible), float(preload)
        self.flexible_shield = bool(flexible_shield)
        w4, w_o, w_c3, w_c4 = (float(w) for w in speeds)
        th4, th_o, th_c3, th_c4 = (float(a) for a in angles)
        hand = drive_torques(par, (th4, th_o, th_c3, th_c4))
        tau = hand if hold and drive == "torque" else np.zeros(4)  # constant drive torques (drive="torque")
        self.world = World(g=par.g, n=[0.0, -1.0, 0.0])
        # shields on their bearings
        bearing = {"use_friction": True, "mu": par.mu, "r_bearing": par.r_bearing, "tau_c0": par.tau_c0,
                   "stribeck": par.stribeck, "w_s": par.w_s, "d": par.d_bearing} if friction else {}
        _check_drive(drive, motion, torques)
        self.drive = drive
        self._sources: list = []
        self._mounts: list[tuple[str, float]] = []
        drives = {"bearing": bearing, "hand": hand, "motion": motion, "torques": torques}
        self.j4 = self._driven("j4", th4, w4, tau[0], **drives)
        self._arm(th4, th_o, bearing)
        disc = {"m": par.m_disc, "r_CM": [0.0, 0.0, 0.0], "I": np.diag([par.I_disc / 2, par.I_disc / 2, par.I_disc])}
        for ch, th, t_drive, w in (("o", th_o, tau[1], w_o), ("c3", th_c3, tau[2], w_c3), ("c4", th_c4, tau[3], w_c4)):
            d0 = self._driven(f"d0{ch}", th, w, t_drive, **drives)
            self._disc_stack(ch, d0, disc, th, th4, th_o, bearing)
        for joint, source, ref, trim in self._sources:
            if trim is not None:
                self.connect(ref.y, trim.u)
                self.connect(trim.y, source.tau)
            else:
                self.connect(ref.y, source.phi_ref if drive == "held" else source.w_ref)
            self.connect(source.flange, joint.axis)

    def _driven(self, name: str, th: float, w: float, t_drive: float, *, bearing: dict, hand: np.ndarray,
                motion: tuple | None, torques: tuple | None) -> Revolute:
        """A drive joint: constant torque, or its axis held / moved / trimmed by a source (``drive``)."""
        drive, z = self.drive, [0.0, 0.0, 1.0]
        if drive == "torque":
            return Revolute(n=z, tau_drive=float(t_drive), init={"phi": th, "w": w}, **bearing)
        k = DRIVEN.index(name)
        start = {"held": {"guess": {"phi": th}}, "motion": {"init": {"phi": th}},
                 "trim": {"init": {"phi": th, "w": 0.0, "a": 0.0}}}[drive]
        joint = Revolute(n=z, use_axis_flange=True, **bearing, **start)
        trim = None
        if drive == "held":
            source, ref, name_s = rotational.Position(), Constant(k=th), f"hold_{name}"
        elif drive == "motion":
            peak, ramp, plateau, t0 = (float(v) for v in motion[k])
            ref = Trapezoid(amplitude=peak, rising=ramp, width=plateau, falling=ramp,
                            period=2 * ramp + plateau + 1e3, nperiod=1, start_time=t0)
            source, name_s = rotational.Speed(), f"speed_{name}"
        else:  # the holding torque found at the start (trim) plus the interval torques
            times, values = torques[k] if torques is not None else ((0.0,), (0.0,))
            ref = (TimeTable([float(t) for t in times], [float(v) for v in values], smoothness="constant")
                   if len(times) > 1 else Constant(k=float(values[0])))
            trim = Trim(guess={"b": float(hand[k])})
            setattr(self, f"trim_{name}", trim)
            source, name_s = rotational.Torque(), f"motor_{name}"
        setattr(self, name_s, source)
        setattr(self, f"ref_{name}", ref)
        self._sources.append((joint, source, ref, trim))
        return joint

    def _arm(self, th4: float, th_o: float, bearing: dict) -> None:
        """Shield 4 on the base joint ``j4``, shield 5 on ``j5`` at its end and the load at shield 5's end; sets
        ``_A2`` (the frame at ``A2`` that the grip discs' bearings and the load hang on) and ``_pins5`` (shield 5's
        pin frames of the outer channel: ``None`` for the rigid shield, whose pins are offsets from ``j5``)."""
        par, z = self.par, [0.0, 0.0, 1.0]
        self.shield4 = Body(m=par.m_shield4, r_CM=[par.L4 / 2, 0, 0], I=np.eye(3) * par.I_shield4)
        self.to_A1 = FixedTranslation(r=[par.L4, 0.0, 0.0])
        self.j5 = Revolute(n=z, guess={"phi": th_o - th4}, **bearing)
        if self.flexible_shield:  # frames at A1, A2 and the six pins (polycrank_shield.SHIELD_FRAMES)
            self.shield5 = FlexibleBody(shield_modal_data(par), modes=par.shield_modes, plane="xy")
        else:
            self.shield5 = Body(m=par.m_shield5, r_CM=[par.L5 / 2, 0, 0], I=np.eye(3) * par.I_shield5)
            self.to_A2 = FixedTranslation(r=[par.L5, 0.0, 0.0])
        self.load = Body(m=par.m_load, r_CM=[0.0, 0.0, 0.0], I=np.eye(3) * 1e-6)
        self.connect(self.world.frame_b, self.j4.frame_a)
        self.connect(self.j4.frame_b, self.shield4.frame_a)
        self.connect(self.j4.frame_b, self.to_A1.frame_a)
        self.connect(self.to_A1.frame_b, self.j5.frame_a)
        self.connect(self.j5.frame_b, self.shield5.frame_a)
        if self.flexible_shield:
            self._A2 = self.shield5.frame_b
            self._pins5 = [self.shield5.frame_at(node) for node in self.shield5.frame_nodes[2:]]
        else:
            self.connect(self.j5.frame_b, self.to_A2.frame_a)
            self._A2, self._pins5 = self.to_A2.frame_b, None
        self.connect(self._A2, self.load.frame_a)

    def _disc_stack(self, ch: str, d0: Revolute, disc: dict, th: float, th4: float, th_o: float,
                    bearing: dict) -> None:
        """Chain ``ch``'s discs on the base (``d0``), at A1 and at A2, joined by parallelograms of links (the outer
        chain's links end on shield 5's pin circle at A1)."""
        par, z = self.par, [0.0, 0.0, 1.0]
        setattr(self, f"d0{ch}", d0)
        setattr(self, f"disc0{ch}", Body(**disc))
        self.connect(self.world.frame_b, d0.frame_a)
        self.connect(d0.frame_b, getattr(self, f"disc0{ch}").frame_a)
        if ch == "o":
            self._parallelogram(f"{ch}4", d0.frame_b, self.j5.frame_b, par.radius(ch), par.L4, th, th4,
                                pins_b=self._pins5)
            return
        d1 = Revolute(n=z, guess={"phi": th - th4}, **bearing)
        setattr(self, f"d1{ch}", d1)
        setattr(self, f"disc1{ch}", Body(**{**disc, "m": 2 * par.m_disc, "I": 2 * disc["I"]}))
        self.connect(self.to_A1.frame_b, d1.frame_a)
        self.connect(d1.frame_b, getattr(self, f"disc1{ch}").frame_a)
        self._parallelogram(f"{ch}4", d0.frame_b, d1.frame_b, par.radius(ch), par.L4, th, th4)
        d2 = Revolute(n=z, guess={"phi": th - th_o}, **bearing)
        setattr(self, f"d2{ch}", d2)
        setattr(self, f"disc2{ch}", Body(**disc))
        self.connect(self._A2, d2.frame_a)
        self.connect(d2.frame_b, getattr(self, f"disc2{ch}").frame_a)
        self._parallelogram(f"{ch}5", d1.frame_b, d2.frame_b, par.radius(ch), par.L5, th, th_o)

    def _parallelogram(self, name: str, disc_a, disc_b, rho: float, length: float, th_disc: float,
                       th_body: float, pins_b: list | None = None) -> None:
        """Six links from the pin circle of ``disc_a`` to that of ``disc_b`` (or to the frames ``pins_b``: the
        flexible shield's pin nodes): pin revolute, link (massive rod of ``length`` along its x axis), pin revolute;
        every link parallel to the body carrying the discs."""
        par = self.par
        for k in range(par.n_links):
            pa = FixedTranslation(r=_pin(rho, k, par.n_links))
            ja = Revolute(n=[0.0, 0.0, 1.0], guess={"phi": th_body - th_disc})
            jb = Revolute(n=[0.0, 0.0, 1.0], guess={"phi": th_disc - th_body})
            pb = None if pins_b else FixedTranslation(r=_pin(rho, k, par.n_links))
            if self.flexible:  # the pull rod; its mount offset along the rod shortens it by the preload stretch
                rod = FlexibleBody(rod_modal_data(par, length), geometric_stiffening=True)
                mount = FixedTranslation(r=[-mount_stretch(par, length, self.preload), 0.0, 0.0])
                self._mounts.append((f"{name}_mount{k + 1}", length))
                parts = (("pa", pa), ("ja", ja), ("rod", rod), ("mount", mount), ("jb", jb), ("pb", pb))
            else:
                rod = FixedTranslation(r=[length, 0.0, 0.0])
                mass = Body(m=par.m_link, r_CM=[length / 2, 0.0, 0.0], I=np.diag([1e-6, 1.0, 1.0]) * par.m_link
                            * length**2 / 12 + np.eye(3) * 1e-7)
                parts = (("pa", pa), ("ja", ja), ("rod", rod), ("mass", mass), ("jb", jb), ("pb", pb))
            for part, comp in parts:
                if comp is not None:
                    setattr(self, f"{name}_{part}{k + 1}", comp)
            if not self.flexible:
                self.connect(ja.frame_b, mass.frame_a)
            self.connect(disc_a, pa.frame_a)
            self.connect(pa.frame_b, ja.frame_a)
            self.connect(ja.frame_b, rod.frame_a)
            if self.flexible:
                self.connect(rod.frame_b, mount.frame_a)
                self.connect(mount.frame_b, jb.frame_a)
            else:
                self.connect(rod.frame_b, jb.frame_a)
            if pins_b:
                self.connect(pins_b[k], jb.frame_b)
            else:
                self.connect(disc_b, pb.frame_a)
                self.connect(pb.frame_b, jb.frame_b)
