"""Reusable parts of a truck-mounted concrete-pump boom (issue 28): compose them into your boom."""

from .axis import HydraulicAxis

__all__ = ["HydraulicAxis"]
