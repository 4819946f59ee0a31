"""1D mechanics: ``rotational`` and ``translational`` (after ``Modelica.Mechanics``)."""

from . import rotational, translational

__all__ = ["rotational", "translational"]
