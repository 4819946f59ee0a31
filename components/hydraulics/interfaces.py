"""Connector and partial models of the hydraulics library.

The port carries the absolute pressure ``p`` (Pa, potential) and the **mass** flow rate
``m_flow`` (kg/s, flow, positive into the component). Mass flow is what a connection
node conserves exactly (Σ m_flow = 0) even when density depends on pressure, as in
Simscape Fluids' isothermal-liquid domain and Modelica.Fluid. Volume flow is derived
inside components, ``q = m_flow / rho(p)``, and reported in L/min by results helpers.

References
----------
MathWorks Simscape Fluids, *Isothermal Liquid* domain (mass flow rate through variable).
Modelica Standard Library 4.0, ``Modelica.Fluid.Interfaces.FluidPort``.
"""

from __future__ import annotations

from typing import Any, ClassVar

from flexlib import Component, Connector, Flow, Input, Potential, Variable, der, eq
from flexlib.core.options import flag, remember_option
from flexlib.errors import ModelError

from ._checks import store_fluid
from .flow_laws import critical_pressure, orifice_mass_flow
from .fluid import HLP46, Fluid

__all__ = ["CHAMBER_FORMS", "PartialFluidComponent", "PartialSource", "PartialTwoPort", "Port", "chamber_equations",
           "chamber_mass_nominal", "check_chamber_form"]

#: Nominal values (IDA's error weights are ``rtol·|y| + atol·nominal``) of the hydraulics library, chosen from the
#: physics so that the default tolerances control what a user reads, not round-off of near-zero variables:
#: pressures 1e7 Pa (100 bar, the working range), pressure drops 1e6 Pa, mass flows 1 kg/s (≈ 70 L/min),
#: volume flows 1e-3 m3/s (60 L/min), shaft speeds 100 rad/s, torques 100 N.m, forces 1e4 N (1e3 N friction, stops),
#: normalised spool travel 1 and spool speed 100 1/s (a 30 Hz spool crosses its stroke in ~10 ms); per
#: instance, from the geometry at the build's values (each component's ``nominals()``, evaluated by
#: :mod:`flexlib.compile.scaling`): piston position and speed ``stroke`` (m, m/s), chamber volume ``A_p·stroke``,
#: and chamber mass deviations ``chamber_mass_nominal(V)``.
P_NOMINAL = 1e7


class Port(Connector):
    """Hydraulic port: absolute pressure and mass flow rate (positive into the component)."""

    p = Potential(unit="Pa", nominal=1e7, doc="Absolute pressure at the port")
    m_flow = Flow(unit="kg/s", doc="Mass flow rate through the port, positive into the component")

    def check_connection(self, members: list[Connector]) -> None:
        """One fluid per connection set: ports of components built with different :class:`Fluid` records (a
        circuit given ``fluid=water`` on some components and the default HLP46 on others) ran with mass flows
        carried between two density laws without a word; refused naming the fluids and their components."""
        users: dict[Fluid, list[str]] = {}
        for port in members:
            owner = port._parent
            fluid = owner.__dict__.get("fluid") if owner is not None else None
            if isinstance(fluid, Fluid):
                users.setdefault(fluid, []).append(owner.path or type(owner).__name__)
        if len(users) > 1:
            from flexlib.errors import ConnectError

            parts = [f"{fluid.name!r} ({', '.join(paths)})" for fluid, paths in users.items()]
            raise ConnectError(f"ports {', '.join(p.path for p in members)} are connected but their components use "
                               f"different fluids: {'; '.join(parts)}. Give every component of a circuit the same "
                               "fluid=... record")


class PartialFluidComponent(Component):
    """Base of the components built for one :class:`Fluid` record, the structural constructor argument ``fluid``
    (attached by :func:`~._checks.store_fluid`: its numbers enter the equations as constants).

    Parameters
    ----------
    fluid : Fluid
        Fluid property record (structural; default HLP46).
    """

    def __init__(self, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(**kw)
        store_fluid(self, fluid)


class PartialSource(PartialFluidComponent):
    """Base of the ideal sources: the imposed value is the parameter named by ``source_parameter`` or, with
    ``use_input``, the signal input of that name with ``_in`` appended (same unit and description).

    Parameters
    ----------
    use_input : bool
        True if the imposed value comes from the signal input (structural).
    """

    source_parameter: ClassVar[str]

    def __init__(self, use_input: bool = False, fluid: Fluid = HLP46, **kw: Any) -> None:
        super().__init__(fluid=fluid, **kw)
        self.use_input = flag(self, "use_input", use_input, structural=True)
        if self.use_input:
            decl = self._decls[self.source_parameter]
            setattr(self, f"{self.source_parameter}_in", Input(unit=decl.unit, doc=decl.doc))

    def source_value(self) -> Any:
        """The imposed value: the signal input if ``use_input``, else the parameter."""
        name = self.source_parameter
        return getattr(self, f"{name}_in" if self.use_input else name)


class PartialTwoPort(PartialFluidComponent):
    """Component with ports ``port_a`` and ``port_b`` that stores no mass.

    ``port_a.m_flow + port_b.m_flow = 0``; ``m_flow`` is the mass flow from ``a`` to ``b``,
    ``dp = port_a.p - port_b.p`` the pressure drop, and ``q`` the volume flow from a to b at
    the upstream density (``rho`` of the higher-pressure port, smooth through dp = 0 by using
    the mean pressure). A subclass adds one equation relating ``m_flow`` (or ``q``) and ``dp``.

    Connectors
    ----------
    port_a, port_b : Port
        Flow from a to b is positive.

    References
    ----------
    MathWorks Simscape Fluids, isothermal-liquid two-port restrictions (``Local Restriction (IL)``).
    """

    port_a = Port(doc="Port a (flow from a to b is positive)")
    port_b = Port(doc="Port b")
    m_flow = Variable(unit="kg/s", nominal=1.0, doc="Mass flow rate from port_a to port_b")
    q = Variable(unit="m3/s", nominal=1e-3, doc="Volume flow rate from port_a to port_b at the mean-pressure density")
    dp = Variable(unit="Pa", nominal=1e6, doc="Pressure drop port_a.p - port_b.p")

    def mean_density(self) -> Any:
        """Density of the fluid at the mean port pressure [kg/m3]."""
        return self.fluid.density(0.5 * (self.port_a.p + self.port_b.p))

    def orifice_flow(self, dp: Any, area: Any) -> Any:
        """Mass flow [kg/s] of the orifice law (:func:`~.flow_laws.orifice_mass_flow`) through the opening ``area``
        [m2] at the pressure drop ``dp`` [Pa], with the component's ``Cd`` and ``Re_cr`` and the mean-pressure
        density."""
        rho = self.mean_density()
        p_cr = critical_pressure(area, self.Cd, rho, self.fluid.nu, self.Re_cr)
        return orifice_mass_flow(dp, area, self.Cd, rho, p_cr)

    def equations(self) -> list:
        a, b = self.port_a, self.port_b
        return [eq(a.m_flow, self.m_flow), eq(a.m_flow + b.m_flow, 0.0),
                eq(self.dp, a.p - b.p), eq(self.m_flow, self.mean_density() * self.q)]


#: Formulations of :func:`chamber_equations` (structural ``chamber_form`` option of the chamber components).
CHAMBER_FORMS = ("mass", "pressure", "mass_total")


def chamber_equations(fluid: Fluid, m: Any, p: Any, V: Any, m_flow_in: Any, *, dm: Any = None, V_ref: Any = None,
                      dV: Any = None, mc: Any = None, form: str = "mass") -> list:
    """Mass balance of a lumped compressible chamber (volume, cylinder chamber, hose).

    ``form="mass"`` (default; needs ``dm`` and ``V_ref``): the state is the *deviation* ``dm`` of the stored
    mass from the reference mass ``m_0 = rho_0·V_ref`` (the chamber at a reference volume, filled at the
    pressure ``p_0 = fluid.p_zero``: 0 Pa absolute for a pure liquid, so ``rho_0 = rho(0)``), and every term of
    the pressure law is written as a deviation::

        der(dm) = Σ m_flow_in,
        dm = rho_0·dV + (rho(p) − rho_0)·V,    dV = V − V_ref,    m = m_0 + dm

    With ``mc`` (a chamber whose volume a piston changes: :class:`~.cylinder.DoubleActingCylinder`) the state is
    instead the *compression mass* ``mc = (rho(p) − rho_0)·V``, the part of the stored mass that the pressure puts
    there, and the displaced mass ``rho_0·dV`` is written as a derivative of the position::

        der(mc) + rho_0·der(dV) = Σ m_flow_in,
        mc = (rho(p) − rho_0)·V,    dm = rho_0·dV + mc,    m = m_0 + dm

    ``dm`` is then a linear combination of states (``mc`` and the position in ``dV``), so BDF keeps the mass balance
    exact, and the discretization is the same up to round-off (BDF is invariant under linear changes of state).
    What changes is round-off: once the piston has moved, ``dm`` is mostly displaced mass while the pressure lives
    in ``mc``, so with ``dm`` as state the pressure of a chamber squeezed to its dead volume is a cancellation of
    many digits. With ``mc`` round-off scales with the compression mass, and ``rtol·|mc|`` is ``rtol·p`` in pressure
    units in any piston position.

    ``form="mass_total"``: the state is the stored mass itself, ``der(m) = Σ m_flow_in``, ``m = rho(p)·V``.
    ``form="pressure"``: the pressure is the state, ``der(rho(p)·V) = Σ m_flow_in`` (i.e.
    ``dp/dt = beta_eff/V·(Σ q_in − dV/dt)``) and ``m = rho(p)·V`` is an output.

    The mass forms conserve mass exactly: ``dm`` (or ``m``) enters linearly, BDF methods preserve linear
    invariants, so the total mass of a circuit is conserved to the Newton tolerance whatever the step
    (the circuit mass-balance test checks 1e-9). The pressure form conserves it only to the integration
    tolerance. Why the deviation: the stored mass varies by ``Δp/beta`` ≈ 0.6 % over 100 bar, so with
    ``m`` itself as the state the pressure is a difference of nearly equal numbers — IDA's predictor,
    corrector and error estimate for ``m`` work on absolute values of ~0.01–1 kg whose last digits carry the
    pressure (one unit of round-off in ``m`` is ``beta·eps`` ≈ 4e-7 Pa, and the ``rtol·|m|`` part of its
    error weight is ``rtol·beta`` = 16 Pa at rtol 1e-8, a thousand times looser than ``rtol·p``). With
    ``dm`` the state, ``dV`` and ``rho − rho_0`` computed directly (``expm1``), round-off scales with the
    deviation, and since ``dm ≈ rho_0·V·p/beta`` (at the reference volume) its error weight ``rtol·|dm|`` is
    ``rtol·p`` in pressure units — the weight of a pressure state; the linear invariant survives. (A
    deviation from the mass at ``p_ref`` instead would make ``rtol·|dm|`` vanish near atmospheric pressure.)
    Measurements: ``docs/decisions/010-hydraulic-chamber-compression-mass-state.md``.

    Parameters
    ----------
    fluid : Fluid
        Fluid property record.
    m : casadi.SX
        Stored mass variable [kg].
    p : casadi.SX
        Chamber pressure variable [Pa].
    V : casadi.SX or float
        Chamber volume [m3], > 0 (may depend on a piston position or on the pressure).
    m_flow_in : casadi.SX
        Net mass flow into the chamber [kg/s].
    dm : casadi.SX, optional
        Mass deviation variable ``m − rho(p_zero)·V_ref`` [kg] (the state of ``form="mass"`` without ``mc``).
    V_ref : casadi.SX or float, optional
        Reference volume [m3] (a parameter expression: e.g. the start volume of a cylinder chamber).
    dV : casadi.SX or float, optional
        ``V − V_ref`` written without cancellation (e.g. ``A_p·(x − x_start)``); default ``V − V_ref``.
    mc : casadi.SX, optional
        Compression mass variable ``m − rho(p_zero)·V`` [kg]: with ``form="mass"``, the state instead of ``dm``
        (for volumes that a piston changes; ``dV`` must then be linear in the position).
    form : str
        ``"mass"``, ``"pressure"`` or ``"mass_total"`` (see above).

    References
    ----------
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §2.3 (continuity equation).
    K. E. Brenan, S. L. Campbell, L. R. Petzold, *Numerical Solution of Initial-Value Problems in DAEs*,
    SIAM 1996, §3.1 (BDF preserves linear invariants).
    """
    if form == "mass_total":
        return [eq(m, fluid.density(p) * V), eq(der(m), m_flow_in)]
    if form == "pressure":
        return [eq(m, fluid.density(p) * V), eq(der(fluid.density(p) * V), m_flow_in)]
    if form != "mass":
        raise ValueError(f"chamber form must be one of {CHAMBER_FORMS}, got {form!r}")
    if dm is None or V_ref is None:
        raise ValueError("chamber_equations(form='mass') needs the deviation variable dm and V_ref")
    dV = V - V_ref if dV is None else dV
    rho_0 = float(fluid.density(fluid.p_zero))
    if mc is not None:
        return [eq(der(mc) + rho_0 * der(dV), m_flow_in),
                eq(mc, fluid.density_deviation(p, fluid.p_zero) * V, label="chamber pressure law (compression mass)"),
                eq(dm, rho_0 * dV + mc), eq(m, rho_0 * V_ref + dm)]
    return [eq(der(dm), m_flow_in),
            eq(dm, rho_0 * dV + fluid.density_deviation(p, fluid.p_zero) * V, label="chamber pressure law (deviation)"),
            eq(m, rho_0 * V_ref + dm)]


def chamber_mass_nominal(fluid: Fluid, V: float) -> float:
    """Nominal of a chamber's mass deviation [kg]: the mass ``rho_ref·V·P_NOMINAL/beta`` that 100 bar adds to a
    chamber of volume ``V`` [m3] (so that ``atol·nominal`` is ``atol·P_NOMINAL`` in pressure units, as for a
    pressure state)."""
    return float(fluid.rho_ref * V * P_NOMINAL / fluid.beta)


def check_chamber_form(node: Any, form: str) -> str:
    """Validate a component's structural ``chamber_form`` option (error names the component); a later
    ``node.chamber_form = ...`` is checked the same way."""
    if not isinstance(form, str) or form not in CHAMBER_FORMS:
        raise ModelError(f"{type(node).__name__}: chamber_form must be one of {list(CHAMBER_FORMS)}, got {form!r}")
    remember_option(node, "chamber_form", lambda v: check_chamber_form(node, v))
    return form
