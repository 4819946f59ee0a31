"""Lumped compressible volume."""

from __future__ import annotations

from typing import Any

from flexlib import Component, Parameter, Variable, eq

from ._checks import PositiveParameters, pressure_start, store_fluid
from .fluid import HLP46, Fluid
from .interfaces import Port, chamber_equations, chamber_mass_nominal, check_chamber_form

__all__ = ["Volume"]


class Volume(PositiveParameters, Component):
    """Constant lumped volume of compressible fluid (hydraulic capacitance).

    Mass balance with the stored mass as state (:func:`chamber_equations`), written as the deviation
    ``dm`` from the mass ``rho_0·V`` the volume would hold at ``p_0 = fluid.p_zero`` (0 Pa for a pure liquid):

    .. math::

        \\dot{dm} = \\sum \\dot m_{in}, \\qquad dm = (\\rho(p) - \\rho_0)\\, V, \\qquad m = \\rho_0 V + dm

    i.e. ``dp/dt = beta_eff(p) / V * q_in``; the circuit's mass is conserved exactly. Any number of
    components can be connected to the single ``port`` (a node of the circuit).

    Parameters
    ----------
    p_start : float or None
        Initial absolute pressure [Pa] (structural: fixes ``p`` at the start time). ``None``
        leaves the initial pressure free (start guess ``fluid.p_ref``), to be set by
        ``init={"p": ...}``, by ``run(steady_state=True)`` or by the circuit.
    fluid : Fluid
        Fluid property record (structural; default HLP46).
    chamber_form : str
        ``"mass"`` (default: mass deviation as state, exact mass balance), ``"pressure"`` (pressure as
        state) or ``"mass_total"`` (the stored mass itself as state; kept for comparison), structural; see
        :func:`chamber_equations`.

    Connectors
    ----------
    port : Port
        Node port; ``port.m_flow`` is the mass flow into the volume.

    Notes
    -----
    ``V`` must be > 0 (checked at construction, at flatten and for run-time ``params``).

    References
    ----------
    MathWorks Simscape Fluids, *Constant Volume Chamber (IL)* block documentation.
    Hopsan component library, *Volume* (``HydraulicVolumeMultiPort``).
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §2.3 (continuity equation).
    """

    _positive = ("V",)
    V = Parameter(unit="m3", min=0.0, doc="Volume")
    p = Variable(unit="Pa", nominal=1e7, start=1.01325e5, doc="Pressure in the volume")
    m = Variable(unit="kg", nominal=0.1, doc="Stored mass")
    dm = Variable(unit="kg", nominal=1e-3, state_select="prefer",
                  doc="Stored mass minus ``rho(p_zero)·V`` (differential state)")
    port = Port(doc="Node port")

    def __init__(self, p_start: float | None = None, fluid: Fluid = HLP46, chamber_form: str = "mass",
                 **kw: Any) -> None:
        super().__init__(**kw)
        store_fluid(self, fluid)
        self.chamber_form = check_chamber_form(self, chamber_form)
        p_start = pressure_start(self, p_start)
        if p_start is not None:
            self.set_start("p", p_start, fixed=True)
        else:
            self.set_start("p", fluid.p_ref, fixed=False)

    def nominals(self) -> dict[str, float]:
        """The stored mass by the volume at the build's values (``interfaces.P_NOMINAL``;
        :mod:`flexlib.compile.scaling`)."""
        V = self.parameter_value("V")
        if V is None:
            return {}
        return {"m": self.fluid.rho_ref * float(V), "dm": chamber_mass_nominal(self.fluid, float(V))}

    def equations(self) -> list:
        eqs = [eq(self.port.p, self.p), *chamber_equations(self.fluid, self.m, self.p, self.V, self.port.m_flow,
                                                           dm=self.dm, V_ref=self.V, dV=0.0, form=self.chamber_form)]
        if self.chamber_form != "mass":
            eqs.append(eq(self.dm, self.m - float(self.fluid.density(self.fluid.p_zero)) * self.V))
        return eqs
