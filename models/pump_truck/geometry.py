"""The sections as built: mass properties of each section with its pipe (and the end hose on the last), memoised.

The machines (:mod:`models.pump_truck.machine`) make their rigid sections from these; the design statics that size
them, and the levers' and links' masses, are :mod:`models.pump_truck.statics` (re-exported here where the machines
read them).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .parameters import PumpTruckParameters
from .statics import LINK_PLATE, linkage_masses
from .statics import mass_properties as _mass_properties

__all__ = ["LINK_PLATE", "linkage_masses", "mass_properties", "section_mass_properties"]


@lru_cache(maxsize=64)
def mass_properties(record: PumpTruckParameters, k: int) -> dict:
    """:func:`models.pump_truck.statics.mass_properties` of section ``k`` with pipe, memoised per record (the beam
    mesh behind it costs ~50 ms; the records are frozen)."""
    return _mass_properties(record, k)


def section_mass_properties(record: PumpTruckParameters, k: int) -> dict:
    """Mass [kg], centre of mass [m] (section frame) and inertia at it [kg.m2] of section ``k`` (0-based) as built:
    box and pipe (:func:`~models.pump_truck.statics.mass_properties`), plus the end hose as a point mass at the tip
    pin for the last section."""
    mp = mass_properties(record, k)
    if k < len(record.sections) - 1:
        return mp
    m_h, x_h = record.hose.mass, np.array([record.sections[k].length, 0.0, 0.0])
    m = mp["m"] + m_h
    com = (mp["m"] * mp["com"] + m_h * x_h) / m
    inertia = mp["I"].copy()
    for mi, ci in ((mp["m"], mp["com"]), (m_h, x_h)):
        d = ci - com
        inertia += mi * (d @ d * np.eye(3) - np.outer(d, d))
    return {"m": m, "com": com, "I": inertia}
