"""Planar linkages built from ordinary 3D multibody components (benchmark and cross-check systems).

Two mechanisms, both described by one :class:`PlanarSpec` (links with their pins, ground pivots, the
spanning tree of revolute joints and the cut joints that close the loops), so that the component-built
model (:class:`PlanarMechanism`) and the hand-written minimal DAE of ``benchmarks/minimal_dae.py`` read
the same numbers:

* :func:`fourbar_spec` — the crank-rocker four-bar of :mod:`flexlib.models.reference.four_bar`
  (crank 0.2 m, coupler 0.7 m, rocker 0.9 m, ground 0.6 m; uniform rods of 1, 2 and 1.5 kg; no gravity;
  crank started at 0.3 rad with 6 rad/s).
* :func:`three_loop_spec` — a 7-body, 3-loop, 1-DOF chain of three four-bars (Grashof crank-rockers in
  series): crank → coupler 1 → rocker 1; an arm of rocker 1 → coupler 2 → rocker 2; an arm of rocker 2 →
  coupler 3 → rocker 3. Ten revolutes, 3·(8−1) − 2·10 = 1 degree of freedom. Each four-bar is driven by
  its shortest link (s + l < p + q), so no position of the input is a dead point and the crank angle is a
  valid state throughout. Gravity 9.81 m/s² along −y.

All joint axes are the world z axis; every link moves in the x–y plane, but the model is the ordinary 3D
one (6 cut-force and cut-torque components per frame): the loop closures carry 3 redundant rows each,
found and dropped by flexlib.

Conventions: each link has its own frame with the origin at its *root pin* (the pin of its tree joint);
pins, centre of mass and inertia are given in that frame [m, kg, kg.m²]. The absolute link angle θ is
the angle of the link frame's x axis from the world x axis; tree revolutes carry the relative angle
θ_child − θ_parent (θ of the ground = 0).

References
----------
R. L. Norton, *Design of Machinery*, 5th ed., McGraw-Hill 2012, §2.7 (Grashof condition), §4.5
(four-bar position analysis).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Fixed, FixedTranslation, Revolute, World
from flexlib.registry import Scenario, register_model

__all__ = ["FourBarLinkage", "Link", "PlanarMechanism", "PlanarSpec", "ThreeLoopLinkage", "assemble",
           "fourbar_spec", "three_loop_spec"]


@dataclass
class Link:
    """A rigid planar link.

    Parameters
    ----------
    name : str
        Link name (component prefix in the flexlib model).
    m : float
        Mass [kg].
    r_cm : tuple of float
        Centre of mass in the link frame [m].
    I_zz : float
        Moment of inertia about the z axis through the centre of mass [kg.m2].
    pins : dict
        Named pins in the link frame [m]; the root pin ``"root"`` is at (0, 0).
    parent : str
        ``"ground:<pivot>"`` or ``"<link>:<pin>"``: where the tree revolute of this link sits.
    """

    name: str
    m: float
    r_cm: tuple[float, float]
    I_zz: float
    pins: dict[str, tuple[float, float]]
    parent: str


@dataclass
class PlanarSpec:
    """A planar 1-DOF mechanism of revolute joints (see the module docstring).

    Parameters
    ----------
    links : list of Link
        Moving links in tree order (a parent before its children); ``links[0]`` is the driver (crank).
    ground : dict
        Ground pivots [m] (``"O"`` is the world origin).
    cuts : list of tuple
        Loop-closing revolutes ``("<link>:<pin>", "<link>:<pin>")``.
    g : float
        Gravity along −y [m/s2].
    theta0, w0 : float
        Start angle [rad] and speed [rad/s] of the driver.
    branch : list of int
        Assembly branch of each loop (+1/−1: sign of the cross product coupler × rocker at the start).
    """

    links: list[Link]
    ground: dict[str, tuple[float, float]]
    cuts: list[tuple[str, str]]
    g: float
    theta0: float
    w0: float
    branch: list[int] = field(default_factory=list)

    def link(self, name: str) -> Link:
        """The link called ``name``."""
        return next(lk for lk in self.links if lk.name == name)


def _rod(name: str, m: float, L: float, parent: str, extra: dict | None = None) -> Link:
    """A uniform rod of length ``L`` along its x axis (tip pin at (L, 0)), plus optional extra pins."""
    return Link(name, m, (L / 2, 0.0), m * L**2 / 12, {"root": (0.0, 0.0), "tip": (L, 0.0), **(extra or {})}, parent)


def fourbar_spec() -> PlanarSpec:
    """The catalogue's four-bar (:mod:`flexlib.models.reference.four_bar`): a, b, c, d = 0.2, 0.7, 0.9, 0.6 m, no
    gravity, 0.3 rad at 6 rad/s."""
    a, b, c, d = 0.2, 0.7, 0.9, 0.6
    return PlanarSpec(
        links=[_rod("crank", 1.0, a, "ground:O"), _rod("coupler", 2.0, b, "crank:tip"),
               _rod("rocker", 1.5, c, "ground:O4")],
        ground={"O": (0.0, 0.0), "O4": (d, 0.0)}, cuts=[("coupler:tip", "rocker:tip")], g=0.0,
        theta0=0.3, w0=6.0, branch=[+1])


def three_loop_spec() -> PlanarSpec:
    """Three Grashof crank-rockers in series (7 moving links, 10 revolutes, 3 loops), gravity −y.

    Loop 1: crank O–A (0.2 m), coupler 1 (0.7 m), rocker 1 O4–B (0.9 m), ground O–O4 = 0.6 m.
    Loop 2: arm of rocker 1 (0.25 m, opposite B), coupler 2 (0.7 m), rocker 2 (0.35 m) about O6, O4–O6 = 0.7 m.
    Loop 3: arm of rocker 2 (0.24 m), coupler 3 (0.6 m), rocker 3 (0.3 m) about O8, O6–O8 = 0.6 m.
    Grashof: s + l = 0.25 + 0.7 ≤ 0.7 + 0.35 and 0.24 + 0.6 ≤ 0.6 + 0.3, the arms are the shortest links.
    """
    arm3 = (-0.2, 0.1327)  # |arm| = 0.24 m
    links = [
        _rod("crank", 1.0, 0.2, "ground:O"),
        _rod("coupler1", 2.0, 0.7, "crank:tip"),
        _rod("rocker1", 1.5, 0.9, "ground:O4", {"arm": (-0.25, 0.0)}),
        _rod("coupler2", 1.2, 0.7, "rocker1:arm"),
        _rod("rocker2", 1.0, 0.35, "ground:O6", {"arm": arm3}),
        _rod("coupler3", 1.0, 0.6, "rocker2:arm"),
        _rod("rocker3", 0.8, 0.3, "ground:O8"),
    ]
    return PlanarSpec(links=links, ground={"O": (0.0, 0.0), "O4": (0.6, 0.0), "O6": (1.3, 0.0), "O8": (1.9, 0.0)},
                      cuts=[("coupler1:tip", "rocker1:tip"), ("coupler2:tip", "rocker2:tip"),
                            ("coupler3:tip", "rocker3:tip")],
                      g=9.81, theta0=0.3, w0=6.0, branch=[+1, +1, +1])


def _rot(th: float) -> np.ndarray:
    return np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])


def pin_position(spec: PlanarSpec, theta: dict[str, float], ref: str) -> np.ndarray:
    """World position [m] of ``"ground:<pivot>"`` or ``"<link>:<pin>"`` for absolute link angles ``theta``."""
    owner, pin = ref.split(":")
    if owner == "ground":
        return np.asarray(spec.ground[pin], dtype=float)
    lk = spec.link(owner)
    return pin_position(spec, theta, lk.parent) + _rot(theta[owner]) @ np.asarray(lk.pins[pin], dtype=float)


def assemble(spec: PlanarSpec, theta_driver: float) -> dict[str, float]:
    """Absolute link angles [rad] of the assembled mechanism for a driver angle (closed-form, circle
    intersection per loop on the chosen branch; Norton §4.5).

    Each cut joins a coupler's tip to a rocker's tip; the coupler's root and the rocker's pivot are known
    once the loops before it are assembled.
    """
    theta = {spec.links[0].name: float(theta_driver)}
    for (ca_ref, cb_ref), sign in zip(spec.cuts, spec.branch, strict=True):
        coupler, rocker = spec.link(ca_ref.split(":")[0]), spec.link(cb_ref.split(":")[0])
        P = pin_position(spec, theta, coupler.parent)
        Op = pin_position(spec, theta, rocker.parent)
        b = float(np.hypot(*coupler.pins[ca_ref.split(":")[1]]))
        c = float(np.hypot(*rocker.pins[cb_ref.split(":")[1]]))
        dvec = Op - P
        dist = float(np.hypot(*dvec))
        x = (b**2 - c**2 + dist**2) / (2 * dist)
        h = math.sqrt(b**2 - x**2)
        ex = dvec / dist
        ey = np.array([-ex[1], ex[0]])
        B = P + x * ex + sign * h * ey
        pin_b, pin_c = coupler.pins[ca_ref.split(":")[1]], rocker.pins[cb_ref.split(":")[1]]
        theta[coupler.name] = math.atan2(B[1] - P[1], B[0] - P[0]) - math.atan2(pin_b[1], pin_b[0])
        theta[rocker.name] = math.atan2(B[1] - Op[1], B[0] - Op[0]) - math.atan2(pin_c[1], pin_c[0])
    return theta


class PlanarMechanism(fl.Model):
    """A :class:`PlanarSpec` built from World, Fixed, Revolute, FixedTranslation and Body (3D components).

    Per link ``<L>``: ``rev_<L>`` (tree revolute, relative angle), ``<L>_<pin>`` (FixedTranslation from the
    root to each further pin), ``<L>_mass`` (Body at the root frame with the link's centre of mass). Cut
    revolutes are ``cut1``, ``cut2``, … The driver's revolute has ``init`` (angle, speed); the others get
    ``guess`` values from :func:`assemble`.

    Parameters
    ----------
    spec : PlanarSpec
        The mechanism (structural).
    """

    experiment = fl.Experiment(t_end=10.0, dt_out=0.01)

    def __init__(self, spec: PlanarSpec) -> None:
        super().__init__()
        self.spec = spec
        theta = assemble(spec, spec.theta0)
        self.world = World(g=spec.g)
        frames = {}
        for name, (x, y) in spec.ground.items():
            if (x, y) == (0.0, 0.0):
                frames[f"ground:{name}"] = self.world.frame_b
            else:
                fixed = Fixed(r=[x, y, 0.0])
                setattr(self, f"ground_{name}", fixed)
                frames[f"ground:{name}"] = fixed.frame_b
        for k, lk in enumerate(spec.links):
            owner = lk.parent.split(":")[0]
            th_parent = 0.0 if owner == "ground" else theta[owner]
            phi = theta[lk.name] - th_parent
            rev = Revolute(init={"phi": phi, "w": spec.w0}) if k == 0 else Revolute(guess={"phi": phi})
            setattr(self, f"rev_{lk.name}", rev)
            body = Body(m=lk.m, r_CM=[*lk.r_cm, 0.0], I=np.diag([lk.I_zz, lk.I_zz, lk.I_zz]))
            setattr(self, f"{lk.name}_mass", body)
            self.connect(frames[lk.parent], rev.frame_a)
            self.connect(rev.frame_b, body.frame_a)
            frames[f"{lk.name}:root"] = rev.frame_b
            for pin, (px, py) in lk.pins.items():
                if pin == "root":
                    continue
                rod = FixedTranslation(r=[px, py, 0.0])
                setattr(self, f"{lk.name}_{pin}", rod)
                self.connect(rev.frame_b, rod.frame_a)
                frames[f"{lk.name}:{pin}"] = rod.frame_b
        for j, (a_ref, b_ref) in enumerate(spec.cuts, start=1):
            phi = theta[b_ref.split(":")[0]] - theta[a_ref.split(":")[0]]
            cut = Revolute(guess={"phi": phi})
            setattr(self, f"cut{j}", cut)
            self.connect(frames[a_ref], cut.frame_a)
            self.connect(cut.frame_b, frames[b_ref])

    def absolute_angles(self, res: fl.Result) -> dict[str, np.ndarray]:
        """Absolute link angles [rad] from a result (sums of tree-revolute angles)."""
        out: dict[str, np.ndarray] = {}
        for lk in self.spec.links:
            owner = lk.parent.split(":")[0]
            base = 0.0 if owner == "ground" else out[owner]
            out[lk.name] = base + res[f"rev_{lk.name}.phi"]
        return out


class FourBarLinkage(PlanarMechanism):
    """The crank-rocker four-bar of :func:`fourbar_spec` (3 moving links, 4 revolutes, 1 loop)."""

    def __init__(self) -> None:
        super().__init__(fourbar_spec())


class ThreeLoopLinkage(PlanarMechanism):
    """The 7-body, 3-loop planar mechanism of :func:`three_loop_spec`."""

    def __init__(self) -> None:
        super().__init__(three_loop_spec())


# -- registration (flexlib list / flexlib run) ------------------------------------------------------------------
register_model(
    "fourbar", lambda scenario: FourBarLinkage(),
    doc="crank-rocker four-bar (crank 0.2 m, coupler 0.7 m, rocker 0.9 m), one closed loop, no gravity",
    scenarios=[Scenario("spin", "free motion from 6 rad/s at the crank for 10 s", t_end=10.0, run={"dt_out": 0.01}),
               Scenario("short", "the same for 0.5 s (a quick check)", t_end=0.5, run={"dt_out": 0.01})],
    summary_signals=["rev_crank.phi", "rev_crank.w", "cut1.frame_a.f[0]", "cut1.frame_a.f[1]"], options=(), data=(),
)
register_model(
    "three-loop", lambda scenario: ThreeLoopLinkage(),
    doc="7-body, 3-loop, 1-DOF planar chain of three four-bars under gravity",
    scenarios=[Scenario("swing", "released under gravity for 10 s", t_end=10.0, run={"dt_out": 0.01})],
    summary_signals=["rev_crank.phi", "rev_crank.w"], options=(), data=(),
)
