"""Examples of the 1D rotational library (after ``Modelica.Mechanics.Rotational.Examples``).

One model per module, each runnable as a script: ``python -m flexlib.models.examples.rotational.first``.
"""
