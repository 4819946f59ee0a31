"""The parallel robots of seed 002: the Cartesian manipulator (:mod:`.cartesian`) and the POLYCRANK
power-transmission fragment (:mod:`.polycrank`)."""

from .cartesian import (
    CartesianParameters,
    CartesianRobot,
    arm_mass,
    arm_modal_data,
    holding_forces,
    leg_angles,
    potential_energy,
)
from .polycrank import PolycrankFragment, PolycrankParameters, drive_torques

__all__ = ["CartesianParameters", "CartesianRobot", "PolycrankFragment", "PolycrankParameters", "arm_mass",
           "arm_modal_data", "drive_torques", "holding_forces", "leg_angles", "potential_energy"]
