"""Modelling API: declarations, components, connectors, equations."""
