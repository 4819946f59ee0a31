"""Hydraulics after Simscape Fluids' isothermal liquid and Hopsan: mass-flow ports, a shared
fluid record, sources, volumes, lines, orifices, valves, pumps, cylinders and motors."""

from .check_valve import CheckValve
from .counterbalance_valve import CounterbalanceValve
from .cylinder import DoubleActingCylinder
from .directional_valve import DirectionalValve43
from .fixed_displacement_pump import FixedDisplacementPump
from .flow_laws import critical_pressure, orifice_mass_flow, to_lpm
from .flow_sensor import FlowSensor
from .flow_source import FlowSource
from .fluid import HLP46, Fluid
from .hydraulic_motor import HydraulicMotor
from .interfaces import PartialTwoPort, Port, chamber_equations
from .line import Line
from .line_cylinder import LineCylinder
from .orifice import Orifice
from .pressure_compensated_pump import PressureCompensatedPump
from .pressure_relief_valve import PressureReliefValve
from .pressure_sensor import PressureSensor
from .pressure_source import PressureSource
from .relative_pressure_sensor import RelativePressureSensor
from .tank import Tank
from .variable_orifice import VariableOrifice
from .volume import Volume

__all__ = [
    "HLP46",
    "CheckValve",
    "CounterbalanceValve",
    "DirectionalValve43",
    "DoubleActingCylinder",
    "FixedDisplacementPump",
    "FlowSensor",
    "FlowSource",
    "Fluid",
    "HydraulicMotor",
    "Line",
    "LineCylinder",
    "Orifice",
    "PartialTwoPort",
    "Port",
    "PressureCompensatedPump",
    "PressureReliefValve",
    "PressureSensor",
    "PressureSource",
    "RelativePressureSensor",
    "Tank",
    "VariableOrifice",
    "Volume",
    "chamber_equations",
    "critical_pressure",
    "orifice_mass_flow",
    "to_lpm",
]
