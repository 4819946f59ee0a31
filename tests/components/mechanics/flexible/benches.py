"""Test models shared by the flexible-body tests (models, not tests)."""

from __future__ import annotations

from typing import Any

import flexlib as fl
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.components.mechanics.multibody import World, WorldForce
from flexlib.fe import ModalData
from flexlib.models.reference.signal_chain import VectorConstant


class TipLoaded(fl.Model):
    """A flexible body clamped at frame_a to the world (gravity ``g`` [m/s2] along −y) with the world force
    ``P`` [N] along −y at frame_b; ``beam`` are the FlexibleBody's further arguments."""

    def __init__(self, data: ModalData, P: float, g: float = 0.0, **beam: Any) -> None:
        super().__init__()
        self.world = World(g=g)
        self.beam = FlexibleBody(data, **beam)
        self.src = VectorConstant(k=[0.0, -P, 0.0])
        self.force = WorldForce()
        self.connect(self.world.frame_b, self.beam.frame_a)
        self.connect(self.src.y, self.force.force)
        self.connect(self.force.frame_b, self.beam.frame_b)
