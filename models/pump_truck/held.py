"""The rigid boom held in a pose by its cylinders locked at their lengths: the mechanics of
:class:`~models.pump_truck.model.PumpTruck` without hydraulics and control, for static loads.

The static loads on each section in flexlib's own multibody formulation, the cross-check of the free-body statics that
the modal participation factor selection uses (:func:`~models.pump_truck.flexible.static_section_loads`; equal within
4e-14 of the largest load, tested to 1e-9) and the machine ``mpf_modes(record, model=HeldBoom)`` takes. Held at rest, a
hydraulic cylinder is a line force that keeps its length: the same sections, joints, levers and links and the same
cylinder housing and rod masses on their pins (:class:`~flexlib.components.hydraulics.LineTwoMasses`, MSL's
``LineForceWithTwoMasses``), with each cylinder's line length fixed at its pose (``LineForce`` with ``flange_b`` fixed
at the pin-to-pin length, the constraint force its holding force), give the same equilibrium — and a model of half the
size without a valve, pump or controller. Names as in ``PumpTruck``: ``joint{n}``, ``section{n}``, ``linkage{n}``; the
cylinders are ``axis{n}`` (``axis{n}.line.f_a`` their tension).
"""

from __future__ import annotations

from collections.abc import Sequence

import flexlib as fl
from flexlib.components.hydraulics.line_cylinder import LineTwoMasses
from flexlib.components.mechanics.multibody import LineForce, Revolute, World
from flexlib.components.mechanics.multibody.interfaces import Frame
from flexlib.components.mechanics.translational import Fixed

from .arguments import check_pose
from .geometry import LINK_PLATE
from .machine import boom_section, fixed_turret, lever_link
from .parameters import PumpTruckParameters
from .statics import design_cylinders

__all__ = ["HeldBoom", "LockedCylinder"]


class LockedCylinder(fl.Model):
    """A cylinder locked at the length ``length`` [m]: a line force between its pins whose 1D end is fixed at that
    length (the tension is the constraint force), with the housing mass ``m_housing`` [kg] at ``L_housing`` [m] from
    ``frame_a`` and the rod mass ``m_rod`` [kg] at ``L_rod`` [m] from ``frame_b`` on the line."""

    def __init__(self, length: float, m_housing: float, L_housing: float, m_rod: float, L_rod: float) -> None:
        super().__init__()
        self.frame_a, self.frame_b = Frame(doc="Housing pin"), Frame(doc="Rod-end pin")
        self.line = LineForce()
        self.lock = Fixed(s0=float(length))
        self.masses = LineTwoMasses(m_a=m_housing, L_a=L_housing, m_b=m_rod, L_b=L_rod)
        self.connect(self.frame_a, self.line.frame_a, self.masses.frame_a)
        self.connect(self.frame_b, self.line.frame_b, self.masses.frame_b)
        self.connect(self.line.flange_b, self.lock.flange)


class HeldBoom(fl.Model):
    """The rigid boom of ``record`` on a fixed turret, held at rest in ``pose`` [deg] (slew, q1 … qN; the slew is
    not modelled) by its cylinders locked at the pose's lengths (module docstring).

    Parameters
    ----------
    record : PumpTruckParameters
        The design record.
    pose : sequence of N + 1 floats
        Slew (ignored) and joint angles [deg].
    slewing : bool
        Must be False (the signature of the machines :func:`~models.pump_truck.flexible.mpf_modes` accepts).
    link_plate : float
        Cross-section of the levers and links at joint scale [m2] (as ``PumpTruck``).
    """

    def __init__(self, record: PumpTruckParameters, pose: Sequence[float], slewing: bool = False,
                 link_plate: float = LINK_PLATE) -> None:
        super().__init__()
        if slewing:
            raise fl.errors.ParameterError("HeldBoom: the held boom has no slewing turret (slewing=False)")
        q0 = check_pose(pose, record, "HeldBoom")
        self.world = World(g=record.g)
        self.turret_top, self.housing1 = fixed_turret(record)
        self.connect(self.world.frame_b, self.turret_top.frame_a)
        self.connect(self.turret_top.frame_b, self.housing1.frame_a)
        parent, prev = self.turret_top.frame_b, None
        for n, cyl in enumerate(design_cylinders(record), start=1):
            q_n = float(q0[n])
            joint = Revolute(guess={"phi": q_n, "w": 0.0, "a": 0.0})
            section = boom_section(record, n)
            axis = LockedCylinder(record.drive(n).state(q_n).length, cyl["m_housing"], cyl["L_housing"],
                                  cyl["m_rod"], cyl["L_rod"])
            for name, part in (("joint", joint), ("section", section), ("axis", axis)):
                setattr(self, f"{name}{n}", part)
            self.connect(parent, joint.frame_a)
            self.connect(joint.frame_b, section.frame_root)
            if prev is None:
                housing, rod_end = self.housing1.frame_b, section.frame_C
            else:
                linkage = lever_link(record, n, q_n, link_plate)
                setattr(self, f"linkage{n}", linkage)
                self.connect(prev.frame_P_next, linkage.frame_pivot)
                self.connect(linkage.frame_bracket, section.frame_C)
                housing, rod_end = prev.frame_H_next, linkage.frame_tip
            self.connect(housing, axis.frame_a)
            self.connect(rod_end, axis.frame_b)
            parent, prev = section.frame_tip, section
