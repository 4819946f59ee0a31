"""Hydraulics after Simscape Fluids' isothermal liquid and Hopsan: mass-flow ports, a shared
fluid record, sources, volumes, lines, orifices, valves, pumps, cylinders and motors."""

from .flow_laws import critical_pressure, orifice_mass_flow, to_lpm
from .fluid import HLP46, Fluid
from .interfaces import PartialTwoPort, Port, chamber_equations

__all__ = ["HLP46", "Fluid", "PartialTwoPort", "Port", "chamber_equations", "critical_pressure", "orifice_mass_flow",
           "to_lpm"]
