"""Names shared by the compiler and the run checks for the rows a build drops as redundant.

A pass that drops a constraint row at build time (a redundant loop closure of the multibody pass) keeps the row
as an output named with :data:`CHECK_PREFIX`; code generation turns those outputs into the compiled ``chk``
function, and every run checks, at its own parameter and start values, that they still hold
(:mod:`flexlib.solve.build_checks`).
"""

from __future__ import annotations

__all__ = ["BRANCH_SUFFIX", "CHECK_PREFIX"]

#: Output-name prefix of the dropped loop rows. They travel with the model's outputs through tearing and
#: index reduction (so they end up as functions of ``t, y, yp, p``) and become the compiled ``chk``
#: function: every run checks, at its own parameter and start values, that the rows dropped as redundant
#: at build time still hold (a parameter change can make a planar loop spatial; see ``docs/engine.md``).
CHECK_PREFIX = "#dropped:"
#: Label suffix of the half-turn check of an orientation loop closure
#: (:func:`flexlib.compile.passes.multibody.redundancy.remove_redundant`).
BRANCH_SUFFIX = " (half-turn branch)"
