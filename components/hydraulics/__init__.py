"""Hydraulics after Simscape Fluids' isothermal liquid and Hopsan: mass-flow ports, a shared
fluid record, sources, volumes, lines, orifices, valves, pumps, cylinders and motors."""

from .fluid import HLP46, Fluid
from .interfaces import PartialTwoPort, Port

__all__ = ["HLP46", "Fluid", "PartialTwoPort", "Port"]
