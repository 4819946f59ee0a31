"""Parameter record of a concrete-pump truck boom of ``N`` = 4 … 6 sections (default: the 42 m-class five-section
boom; :mod:`models.pump_truck.record32` the 32 m-class four-section one): every number, its unit, its source.

The record is a frozen dataclass: copy it with :func:`dataclasses.replace` and change any number, e.g.
``replace(PumpTruckParameters(), pipe=replace(PIPE, filled=False))``. Construction checks every field and the
linkages (each must close and keep its transmission angles over its range); a bad record raises
:class:`flexlib.errors.ParameterError` naming the field.

Conventions: planar boom in the vertical ``x``–``y`` plane (``y`` up), joint 1 at the origin on top of the
turret, relative joint angles ``q`` [rad] (``q = 0``: all sections in line; ``q1 = 0``: horizontal), one per section:
joint 1 a direct cylinder drive, joints 2 … N lever-and-link drives (``len(linkages) == len(sections) − 1``). Joint
geometry is given in each joint's frame (see :mod:`models.pump_truck.kinematics`).

``python -m flexlib.models.pump_truck.parameters`` prints the mass properties and the cylinder sizing table.

Geometry (issue 28, item 3): the linkages are sized so that every cylinder is an ISO 3320 bore of 100–280 mm holding
the worst case at 80 % of 350 bar. Sources looked for and what they gave:

* Power & Motion (powermotiontech.com), "Lightweight cylinders expand realm of possibilities" (Lingk & Sturzebecher
  CFRP cylinders on the Putzmeister M55): 350 bar maximum working pressure of the boom cylinders (taken: system
  pressure); in a steel cylinder the barrel is up to 75 % of the cylinder's weight (consistent with the housing/rod
  split of :func:`~models.pump_truck.statics.cylinder_masses`).
* Source by Spec, "Truck-mounted concrete pump" guide (quotes the Putzmeister M42-5 and Schwing S 36 X data sheets):
  reach class and five-section RZ fold only; no cylinder data.
* J. Henikl, W. Kemmetmüller, M. Bader, A. Kugi, "Modeling, simulation and identification of a mobile concrete
  pump", Mathematical and Computer Modelling of Dynamical Systems 21(2), 2015; G. Cazzulani et al., "A test rig and
  numerical model for investigating truck mounted concrete pumps", Automation in Construction 20, 2011: lever-and-link
  (four-bar) joint drives as modelled here; no bores or pin coordinates published.
* The bore band 100–250 mm at ≤ 350 bar for 36–42 m booms is issue 28's statement; no data sheet with boom-cylinder
  bores was found. The pin positions are therefore an engineering choice: a numerical search (``_BASE``) for the
  smallest bore within an envelope of the sections' proportions, keeping the record's transmission-angle check and a
  retracted length of at least stroke + dead length (:func:`~models.pump_truck.statics.dead_length`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from flexlib.errors import ParameterError

from .kinematics import direct_state, fourbar_length, fourbar_state

__all__ = ["CYLINDER_BORES", "CYLINDER_RODS", "N_SECTIONS", "DirectDrive", "EndHose", "FourBar", "Pipe",
           "PumpTruckParameters", "SectionSpec", "Steel", "Turret", "box_wall_thickness"]

#: Section counts a record may have (smallest, largest): truck-mounted booms have 3 to 6 sections; 4 to 6 here.
N_SECTIONS = (4, 6)

#: ISO 3320 cylinder bores [m] (R10 series, 25–400 mm).
CYLINDER_BORES = tuple(d / 1000 for d in (25, 32, 40, 50, 63, 80, 100, 125, 140, 160, 180, 200, 220, 250, 280,
                                          320, 360, 400))
#: ISO 3320 piston-rod diameters [m] (12–360 mm).
CYLINDER_RODS = tuple(d / 1000 for d in (12, 14, 16, 18, 20, 22, 25, 28, 32, 36, 40, 45, 50, 56, 63, 70, 80, 90,
                                         100, 110, 125, 140, 160, 180, 200, 220, 250, 280, 320, 360))


def _range_text(low: float, high: float, low_open: bool, high_open: bool) -> str:
    if math.isinf(high):
        return f"{'>' if low_open else '>='} {low:g}"
    return f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"


def _number(field: str, value: object, unit: str, low: float = 0.0, high: float = math.inf, *,
            low_open: bool = True, high_open: bool = False, what: str = "") -> None:
    """``ParameterError`` naming ``field``, its unit, the accepted range and ``value`` unless ``value`` is a finite
    int or float (not a bool, not text) in the range (default: positive)."""
    ok = (isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
          and (low < value if low_open else low <= value) and (value < high if high_open else value <= high))
    if not ok:
        raise ParameterError(f"pump-truck record: {field} must be a finite number "
                             f"{_range_text(low, high, low_open, high_open)} [{unit}]{what}, got {value!r}")


def _check(owner: str, **values: tuple[object, str]) -> None:
    """Positive finite numbers: ``name=(value, unit)`` of the record part ``owner``."""
    for name, (value, unit) in values.items():
        _number(f"{owner}.{name}", value, unit)


def _point(field: str, value: object) -> tuple[float, float]:
    """A point ``(x, y)`` [m] of two finite numbers, as a tuple of floats (hashable: the record is a cache key)."""
    try:
        ok = (not isinstance(value, str | bytes) and len(value) == 2  # type: ignore[arg-type]
              and all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                      for v in value))  # type: ignore[union-attr]
    except TypeError:
        ok = False
    if not ok:
        raise ParameterError(f"pump-truck record: {field} must be a point (x, y) of two finite numbers [m], got "
                             f"{value!r}")
    return (float(value[0]), float(value[1]))  # type: ignore[index]


def _angle_range(field: str, q_min: object, q_max: object) -> None:
    """A joint range ``q_min < q_max`` inside [-pi, pi] [rad] (an angle in degrees is refused, not wrapped)."""
    _number(f"{field}.q_min", q_min, "rad", -math.pi, math.pi, low_open=False, what=" (radians)")
    _number(f"{field}.q_max", q_max, "rad", -math.pi, math.pi, low_open=False, what=" (radians)")
    if not q_min < q_max:  # type: ignore[operator]
        raise ParameterError(f"pump-truck record: {field}: q_min must be below q_max, got {q_min!r} >= {q_max!r} "
                             "[rad]")


def _instance(field: str, value: object, cls: type) -> None:
    if not isinstance(value, cls):
        raise ParameterError(f"pump-truck record: {field} must be a {cls.__name__}, got {type(value).__name__} "
                             f"{value!r}")


def box_wall_thickness(mass: float, length: float, b: float, h: float, rho: float) -> float:
    """Wall thickness [m] of a uniform steel box ``b × h`` [m] of ``length`` [m] that weighs ``mass`` [kg].

    Solves ``rho L (2 t (b + h) − 4 t²) = m`` for the thin root ``t``.
    """
    A = mass / (rho * length)
    disc = (b + h) ** 2 - 4.0 * A
    if disc < 0:
        raise ParameterError(f"box {b} x {h} m cannot reach area {A:.5f} m2 ({mass} kg over {length} m)")
    return ((b + h) - math.sqrt(disc)) / 4.0


@dataclass(frozen=True)
class Steel:
    """Structural steel (S690-class boom steel): Young's modulus ``E`` [Pa], density ``rho`` [kg/m3]."""

    E: float = 210e9
    rho: float = 7850.0
    source: str = "EN 10025-6 S690QL handbook values"

    def __post_init__(self) -> None:
        # bounds of structural metals and composites: a value in GPa or g/cm3 is refused, not used
        _number("steel.E", self.E, "Pa", 1e9, 1e12, low_open=False)
        _number("steel.rho", self.rho, "kg/m3", 1000.0, 25000.0, low_open=False)


@dataclass(frozen=True)
class SectionSpec:
    """One boom section as a uniform steel box: length [m], target mass [kg], outer width ``b`` and height ``h`` [m].

    The wall thickness :meth:`t` follows from the mass (:func:`box_wall_thickness`).
    """

    length: float
    mass: float
    b: float
    h: float
    source: str = ("length and mass: Putzmeister M42 / Schwing S 42 SX data sheets, order of magnitude; b, h: "
                   "chosen here (taper root to tip); t: sized here so the box weighs the target mass")

    def t(self, rho: float) -> float:
        """Wall thickness [m] for steel density ``rho`` [kg/m3]."""
        return box_wall_thickness(self.mass, self.length, self.b, self.h, rho)


@dataclass(frozen=True)
class Pipe:
    """Concrete delivery pipe (DN125) clamped on top of each section.

    ``empty_mass_per_m`` [kg/m] (steel pipe, couplings, clamps), ``inner_diameter`` [m], ``concrete_density``
    [kg/m3], ``offset`` [m] of the pipe axis above the section's top face, ``filled`` (bool).
    """

    empty_mass_per_m: float = 10.5
    inner_diameter: float = 0.125
    concrete_density: float = 2400.0
    offset: float = 0.15
    filled: bool = True
    source: str = ("DN125 twin-wall boom pipe 10.5 kg/m empty (Esser / Putzmeister pipe catalogues, order of "
                   "magnitude); concrete 2400 kg/m3 (EN 206); filled 10.5 + 29.5 = 40 kg/m as in issue 11")

    def __post_init__(self) -> None:
        _check("pipe", empty_mass_per_m=(self.empty_mass_per_m, "kg/m"), concrete_density=(self.concrete_density,
                                                                                          "kg/m3"))
        _number("pipe.inner_diameter", self.inner_diameter, "m", 0.0, 1.0, what=" (metres, not mm)")
        _number("pipe.offset", self.offset, "m", 0.0, 2.0)
        if not isinstance(self.filled, bool):
            raise ParameterError(f"pump-truck record: pipe.filled must be True or False, got {self.filled!r}")

    @property
    def mass_per_m(self) -> float:
        """Pipe mass per metre in its current state (filled or empty) [kg/m]."""
        fill = self.concrete_density * math.pi / 4.0 * self.inner_diameter**2 if self.filled else 0.0
        return self.empty_mass_per_m + fill


@dataclass(frozen=True)
class EndHose:
    """End hose hanging from the tip: ``length`` [m], ``mass`` [kg] (filled; its weight acts at the tip pin)."""

    length: float = 4.0
    mass: float = 150.0
    source: str = "4 m DN125 end hose, about 150 kg filled (issue 11; pump-maker end-hose data)"

    def __post_init__(self) -> None:
        _check("hose", length=(self.length, "m"), mass=(self.mass, "kg"))


@dataclass(frozen=True)
class Turret:
    """Slewing turret: ``mass`` [kg], slewing inertia ``J_slew`` about the vertical axis [kg.m2], height of joint
    1 above the slewing bearing ``height`` [m]."""

    mass: float = 2500.0
    J_slew: float = 3500.0
    height: float = 1.2
    friction: str = "regularised"
    """The slewing ring's friction law: ``"regularised"`` or ``"stick-slip"`` (``models.boom.Turret``)."""
    source: str = ("order of magnitude for a 42 m pump turret (cast slewing housing ~2.5 t, radius of gyration "
                   "~1.2 m: J = 2500 * 1.18^2)")

    def __post_init__(self) -> None:
        _check("turret", mass=(self.mass, "kg"), J_slew=(self.J_slew, "kg.m2"), height=(self.height, "m"))
        if self.friction not in ("regularised", "stick-slip"):
            raise ParameterError(f"turret: friction must be 'regularised' or 'stick-slip', got {self.friction!r}")


@dataclass(frozen=True)
class DirectDrive:
    """Joint 1: cylinder from ``H`` (turret) to ``c`` (on section 1) [m], joint range ``q_min``–``q_max`` [rad]."""

    H: tuple[float, float] = (1.0, -2.2)
    c: tuple[float, float] = (1.36, 0.0)
    q_min: float = math.radians(-5.0)
    q_max: float = math.radians(80.0)
    source: str = ("engineering choice (no published pin coordinates found): housing low on the turret front, bracket "
                   "1.36 m out on section 1, from a differential-evolution search for the smallest bore with "
                   "transmission >= 22.5 deg and retracted length >= stroke + dead length; lever arm 1.34 m "
                   "extended, stroke 1.51 m, bore 250 mm with levers and links counted (220 mm reaches 280.7 bar, "
                   "over the 280 bar limit; real 36-42 m booms: ~200-250 mm)")

    def __post_init__(self) -> None:
        object.__setattr__(self, "H", _point("joint1.H", self.H))
        object.__setattr__(self, "c", _point("joint1.c", self.c))
        _angle_range("joint1", self.q_min, self.q_max)

    def state(self, q: float):
        """Drive state at ``q`` [rad] (:func:`models.pump_truck.kinematics.direct_state`)."""
        return direct_state(q, np.array(self.H), np.array(self.c))

    def length(self, q: float) -> float:
        """The cylinder's pin-to-pin length [m] at ``q`` [rad] (``state(q).length``)."""
        return self.state(q).length


#: Lever-and-link base design at joint 2's size (folds upwards, positive q, −2…178 deg), from a differential-evolution
#: search (issue 28) for the smallest bore that holds 700 kN.m ∝ cos q over the range at 280 bar (rod 0.7 bore), with
#: every transmission angle >= 22.5 deg, retracted length >= stroke + dead length, flow <= 144 L/min at 0.03 rad/s,
#: pins inside an envelope of the sections' proportions (housing up to 6 m behind the joint, pins up to 0.8 m off the
#: section axis, lever up to 1.5 m); scaled per joint. Extended lever arm 0.70 m at joint 2 (was 0.31 m).
_BASE = {"P": (0.30, 0.77), "H": (-6.0, 0.34), "c": (-1.09, -0.80), "r": 1.50, "s": 0.817, "sigma": -1}


@dataclass(frozen=True)
class FourBar:
    """Lever-and-link drive of one joint (2 … N), in the joint frame [m]: lever pivot ``P`` and cylinder housing
    ``H`` on section k−1, link bracket ``c`` on section k, lever length ``r``, link length ``s``, assembly
    branch ``sigma`` (±1), range ``q_min``–``q_max`` [rad]."""

    P: tuple[float, float]
    H: tuple[float, float]
    c: tuple[float, float]
    r: float
    s: float
    sigma: int
    q_min: float
    q_max: float
    source: str = ("engineering choice (no published pin coordinates found): base lever-and-link design scaled per "
                   "joint (see _BASE)")

    def __post_init__(self) -> None:
        for name in ("P", "H", "c"):
            object.__setattr__(self, name, _point(f"linkage.{name}", getattr(self, name)))
        _check("linkage", r=(self.r, "m"), s=(self.s, "m"))
        if self.sigma not in (1, -1) or isinstance(self.sigma, bool):
            raise ParameterError(f"pump-truck record: linkage.sigma (assembly branch) must be +1 or -1, got "
                                 f"{self.sigma!r}")
        _angle_range("linkage", self.q_min, self.q_max)

    @classmethod
    def scaled(cls, scale: float, fold: int) -> FourBar:
        """The base design scaled by ``scale`` and folding upwards (``fold = +1``) or downwards (``-1``, mirrored)."""
        m = np.array([1.0, float(fold)])
        P, H, c = (tuple(float(v) for v in scale * m * np.array(_BASE[k])) for k in ("P", "H", "c"))
        lo, hi = math.radians(-2.0), math.radians(178.0)
        q_min, q_max = (lo, hi) if fold > 0 else (-hi, -lo)
        return cls(P, H, c, scale * _BASE["r"], scale * _BASE["s"], _BASE["sigma"] * fold, q_min, q_max)

    def state(self, q: float):
        """Drive state at ``q`` [rad] (:func:`models.pump_truck.kinematics.fourbar_state`)."""
        return fourbar_state(q, np.array(self.P), np.array(self.H), np.array(self.c), self.r, self.s, self.sigma)

    def length(self, q: float) -> float:
        """The cylinder's pin-to-pin length [m] at ``q`` [rad] (``state(q).length``, without the rest of the state)."""
        return fourbar_length(q, np.array(self.P), np.array(self.H), np.array(self.c), self.r, self.s, self.sigma)


_SECTIONS = (SectionSpec(9.0, 2200.0, 0.45, 0.70), SectionSpec(7.7, 1500.0, 0.40, 0.60),
             SectionSpec(7.6, 1100.0, 0.35, 0.50), SectionSpec(7.4, 700.0, 0.30, 0.40),
             SectionSpec(5.9, 350.0, 0.25, 0.30))
_LINKAGES = (FourBar.scaled(1.0, +1), FourBar.scaled(0.8, -1), FourBar.scaled(0.6, +1), FourBar.scaled(0.35, -1))


@dataclass(frozen=True)
class PumpTruckParameters:
    """The machine's design record (see the module docstring).

    Attributes
    ----------
    sections : tuple of SectionSpec
        The ``N`` boom sections, root to tip, ``N`` in :data:`N_SECTIONS` (4 … 6; this record: five).
    steel, pipe, hose, turret : Steel, Pipe, EndHose, Turret
        Material, delivery pipe, end hose, turret.
    joint1 : DirectDrive
        Joint 1 cylinder.
    linkages : tuple of FourBar
        Lever-and-link drives of joints 2 … ``N``: ``len(linkages) == len(sections) − 1`` (checked).
    g : float
        Gravity [m/s2], > 0.
    p_system : float
        System pressure [Pa], 1e6 … 1e8 (10 … 1000 bar: a value in bar or MPa is refused); ``p_hold_fraction``
        the allowed share of it for holding [1], in (0, 1].
    min_transmission_deg : float
        Smallest allowed transmission angle over every joint's range [deg], in (0, 90).

    Every field is checked on construction (type, and each number against its range, e.g. positive lengths and
    masses, ``steel.E`` 1e9 … 1e12 Pa, joint ranges within ±pi rad); a refused value raises
    :class:`~flexlib.errors.ParameterError` naming the field, its unit, the accepted range and the value.
    """

    sections: tuple[SectionSpec, ...] = _SECTIONS
    steel: Steel = field(default_factory=Steel)
    pipe: Pipe = field(default_factory=Pipe)
    hose: EndHose = field(default_factory=EndHose)
    turret: Turret = field(default_factory=Turret)
    joint1: DirectDrive = field(default_factory=DirectDrive)
    linkages: tuple[FourBar, ...] = _LINKAGES
    g: float = 9.81
    p_system: float = 35e6
    p_hold_fraction: float = 0.8
    min_transmission_deg: float = 20.0
    source: str = ("issue 11 (42 m class, five sections); system pressure 350 bar as on Putzmeister/Schwing booms "
                   "(350 bar working pressure of the boom cylinders of the Putzmeister M55: Power & Motion, "
                   "'Lightweight cylinders expand realm of possibilities'); linkage proportions: engineering choice "
                   "(module docstring)")

    def __post_init__(self) -> None:
        for name, cls in (("sections", SectionSpec), ("linkages", FourBar)):
            value = getattr(self, name)
            if isinstance(value, str | bytes) or not hasattr(value, "__len__") \
                    or not all(isinstance(v, cls) for v in value):
                got = (f"{type(value).__name__} of {len(value)}: "
                       f"{', '.join(type(v).__name__ for v in value)}" if isinstance(value, list | tuple)
                       else repr(value))
                raise ParameterError(f"pump-truck record: {name} must be a sequence of {cls.__name__} records "
                                     f"({'root to tip' if name == 'sections' else 'joints 2 ... N'}), got {got}")
            object.__setattr__(self, name, tuple(value))  # hashable: the record is a cache key
        n = len(self.sections)
        if not N_SECTIONS[0] <= n <= N_SECTIONS[1]:
            raise ParameterError(f"pump-truck record: sections must be {N_SECTIONS[0]} to {N_SECTIONS[1]} "
                                 f"SectionSpec records (root to tip), got {n}")
        if len(self.linkages) != n - 1:  # one lever-and-link drive per joint 2 ... N
            m = len(self.linkages)
            raise ParameterError(f"pump-truck record: sections must be {m + 1} SectionSpec records (root to tip), "
                                 f"got tuple of {n}, for {m} linkages (joints 2 ... {m + 1}): sections and linkages "
                                 f"disagree, len(linkages) must be len(sections) - 1")
        for name, cls in (("steel", Steel), ("pipe", Pipe), ("hose", EndHose), ("turret", Turret),
                          ("joint1", DirectDrive)):
            _instance(name, getattr(self, name), cls)
        for i, sec in enumerate(self.sections):
            _check(f"sections[{i}]", length=(sec.length, "m"), mass=(sec.mass, "kg"))
            for side in ("b", "h"):  # a box much shorter than wide is a unit slip (mm for m)
                _number(f"sections[{i}].{side}", getattr(sec, side), "m", 0.0, sec.length, high_open=True,
                        what=f" (below the section's length {sec.length:g} m)")
            try:
                t = sec.t(self.steel.rho)
            except ParameterError as err:
                raise ParameterError(f"pump-truck record: sections[{i}].mass: {err}") from None
            if 2 * t >= min(sec.b, sec.h):
                raise ParameterError(f"pump-truck record: sections[{i}].mass {sec.mass} kg needs a solid box")
        _number("g", self.g, "m/s2")
        _number("p_system", self.p_system, "Pa", 1e6, 1e8, low_open=False, what=" (10 ... 1000 bar)")
        _number("p_hold_fraction", self.p_hold_fraction, "1", 0.0, 1.0,
                what=" (the share of p_system allowed for holding)")
        _number("min_transmission_deg", self.min_transmission_deg, "deg", 0.0, 90.0, high_open=True)
        if not isinstance(self.source, str):
            raise ParameterError(f"pump-truck record: source must be a str, got {self.source!r}")
        for j, drive in enumerate((self.joint1, *self.linkages)):
            name = "joint1" if j == 0 else f"linkages[{j - 1}] (joint {j + 1})"
            for q in np.linspace(drive.q_min, drive.q_max, 91):
                try:
                    st = drive.state(float(q))
                except ValueError as err:
                    raise ParameterError(f"pump-truck record: {name} cannot reach its range: {err}") from None
                worst = min(st.transmission.values())
                if worst < self.min_transmission_deg:
                    raise ParameterError(
                        f"pump-truck record: {name} cannot reach its range: transmission angle {worst:.1f} deg "
                        f"< min_transmission_deg {self.min_transmission_deg} at q = {math.degrees(q):.1f} deg")

    @property
    def n_sections(self) -> int:
        """Number of boom sections ``N`` (= number of boom joints; joint 1 the direct drive, 2 … N lever and link)."""
        return len(self.sections)

    def drive(self, k: int):
        """Drive of joint ``k`` (1 … ``n_sections``)."""
        return self.joint1 if k == 1 else self.linkages[k - 2]


def describe(record: PumpTruckParameters) -> str:
    from .statics import mass_properties, sizing

    lines = ["section  L [m]  m [kg]  b x h x t [mm]        mesher m [kg]  com x,y [m]      Izz(com) [kg.m2]"]
    for k, sec in enumerate(record.sections):
        mp = mass_properties(record, k, pipe=False)
        t = sec.t(record.steel.rho)
        lines.append(f"{k + 1:7d}  {sec.length:5.2f}  {sec.mass:6.0f}  {sec.b * 1e3:4.0f} x {sec.h * 1e3:4.0f} x "
                     f"{t * 1e3:5.2f}  {mp['m']:13.2f}  {mp['com'][0]:6.3f},{mp['com'][1]:6.3f}  "
                     f"{mp['I'][2, 2]:12.1f}")
    lines.append(f"pipe {record.pipe.mass_per_m:.2f} kg/m ({'filled' if record.pipe.filled else 'empty'}), "
                 f"hose {record.hose.mass:.0f} kg at the tip")
    lines.append("")
    lines.append("joint  bore/rod [mm]  stroke [m]  l_min [m]  dead [m]  min transm. [deg]  lever arm ext. [m]  "
                 "F ext. [kN]  p ext. [MPa]  worst p [MPa] at q [deg]  flow [L/min]  housing/rod [kg]  cyl. share")
    for row in sizing(record):
        lines.append(f"{row['joint']:5d}  {row['bore'] * 1e3:4.0f}/{row['rod'] * 1e3:4.0f}    {row['stroke']:9.3f}  "
                     f"{row['l_min']:9.3f}  {row['dead']:8.3f}  {row['min_transmission_deg']:17.1f}  "
                     f"{row['lever_arm']:18.3f}  {row['F'] / 1e3:11.1f}  {row['p'] / 1e6:12.2f}  "
                     f"{row['p_worst'] / 1e6:13.2f} at {math.degrees(row['q_worst']):6.1f}  {row['flow'] * 6e4:12.0f}  "
                     f"{row['m_housing']:7.0f}/{row['m_rod']:4.0f}  {row['cylinder_share']:10.1%}")
    lines.append(f"limit {record.p_hold_fraction * record.p_system / 1e6:.1f} MPa "
                 f"({record.p_hold_fraction:.0%} of {record.p_system / 1e6:.0f} MPa); sized once on the worst case "
                 "(pipe filled, whatever the record's pipe state); 'ext.' = fully extended, horizontal; worst = joint "
                 "swept over its range, the others extended; dead = smallest retracted length minus stroke; flow at "
                 "0.03 rad/s and the largest lever arm; cyl. share = the cylinders' share of the joint's gravity "
                 "torque, extended")
    return "\n".join(lines)


if __name__ == "__main__":
    print(describe(PumpTruckParameters()))
