"""Integrator backends: adapters behind :class:`flexlib.solve.backends.base.Integrator`, driven by
:func:`flexlib.solve.loop.run_loop`. One file per backend; no backend imports another."""
