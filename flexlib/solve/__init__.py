"""Solving: initialisation, IDA integration with events, the Simulation front end."""
