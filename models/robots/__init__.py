"""The parallel robots of seed 002: the Cartesian manipulator (:mod:`.cartesian`)."""

from .cartesian import (
    CartesianParameters,
    CartesianRobot,
    arm_mass,
    arm_modal_data,
    holding_forces,
    leg_angles,
    potential_energy,
)

__all__ = ["CartesianParameters", "CartesianRobot", "arm_mass", "arm_modal_data", "holding_forces", "leg_angles",
           "potential_energy"]
