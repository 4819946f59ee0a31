"""FMI: a flexlib model exported as a standard co-simulation unit (:func:`export_fmu`)."""

from flexlib.fmi.export import export_fmu

__all__ = ["export_fmu"]
