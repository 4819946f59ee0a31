"""Stage 8 — linear analysis of assembled models: linearisation, modes (free or with joints locked),
frequency response and pose sweeps (``docs/linear_analysis.md``)."""

from flexlib.analysis.linear import LinearSystem, OperatingPoint, linearize, operating_point
from flexlib.analysis.modal import ModalSweep, Modes, mobility, modal_analysis, modal_sweep

__all__ = ["LinearSystem", "ModalSweep", "Modes", "OperatingPoint", "linearize", "mobility", "modal_analysis",
           "modal_sweep", "operating_point"]
