"""Reusable parts of a truck-mounted concrete-pump boom: compose them into your boom."""

from .controller import AngleController, JointController
from .power import PowerUnit
from .reference import SmoothReference, joint_to_length, motion_profile, waypoint_moves
from .slew import SlewDrive

__all__ = ["AngleController", "JointController", "PowerUnit", "SlewDrive", "SmoothReference", "joint_to_length",
           "motion_profile", "waypoint_moves"]
