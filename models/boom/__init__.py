"""Reusable parts of a truck-mounted concrete-pump boom: compose them into your boom.

Each part is an :class:`flexlib.Model` with SI arguments and named connectors, and has its own bench test
(``tests/models/boom/``):

- mechanics: :class:`BoomSection` (rigid or flexible behind the same named frames), :class:`LeverLink` (the
  lever-and-link drive of a folding joint), :class:`Turret` (slewing bearing and turret);
- hydraulics: :class:`HydraulicAxis` (cylinder with housing and rod masses, proportional valve, load-holding valves,
  hoses, port cartridges), :class:`PowerUnit` (pump, supply, relief, tank), :class:`SlewDrive`;
- control: :class:`JointController` (a joint's cylinder-length loop), :class:`AngleController`, and
  :class:`SmoothReference` with :func:`motion_profile`, :func:`waypoint_moves`, :func:`joint_to_length` (references
  and feed-forward with continuous speed).
"""

from .axis import HydraulicAxis
from .controller import AngleController, JointController
from .linkage import LeverLink
from .power import PowerUnit
from .reference import SmoothReference, joint_to_length, motion_profile, waypoint_moves
from .section import BoomSection
from .slew import SlewDrive
from .turret import Turret

__all__ = ["AngleController", "BoomSection", "HydraulicAxis", "JointController", "LeverLink", "PowerUnit", "SlewDrive",
           "SmoothReference", "Turret", "joint_to_length", "motion_profile", "waypoint_moves"]
