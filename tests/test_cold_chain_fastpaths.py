"""The scalar fast paths and caches of the front end (issue 9, deliverable 7) give what the general paths give.

* Node paths are cached until the next attachment: a sub-tree attached after its paths were read reports the
  new paths (reference: the path spelled out by hand, exact equality).
* Declarations and sub-component templates are read once per class; a declaration added to a class later is
  seen by the next instance.
* ``Parameter.check`` of a plain ``float``/``int`` returns what the NumPy path returns for the same value
  passed as ``np.float64`` (exact equality), and refuses the same values with the same class of error naming
  the parameter.
* ``der()`` and ``eq()`` of scalars: the same values as the general vector path (``der`` of a 1-element
  vector, ``jacobian``-based directional derivative), at a random point, to 1e-15 (same arithmetic).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib.core.variables import lookup
from flexlib.errors import ParameterError
from flexlib.models.n_mass_chain import ChainMass, NMassChain


def test_cached_paths_follow_a_later_attachment() -> None:
    mass = ChainMass()
    assert mass.flange_a.path == "flange_a"  # read (and cached) while the mass is the root
    chain = NMassChain(1)
    assert chain.mass0.flange_b.path == "mass0.flange_b"
    chain.extra = mass
    assert mass.flange_a.path == "extra.flange_a"

    class ChainHolder(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.inner = chain

    ChainHolder()
    assert chain.mass0.flange_b.path == "inner.mass0.flange_b"
    assert mass.flange_a.path == "inner.extra.flange_a"


def test_declaration_added_to_a_class_later_is_seen() -> None:
    class Box(fl.Component):
        x = fl.Variable(unit="m")

        def equations(self) -> list:
            return [fl.eq(self.x, 1.0)]

    assert "k" not in Box()._decls
    Box.k = fl.Parameter(2.0, unit="1")
    box = Box()
    assert "k" in box._decls and float(box.parameter_value("k")) == 2.0


@pytest.mark.parametrize("value", [0.0, 0, 3, 2.5, 10.0, 1e-300])
def test_scalar_parameter_check_matches_numpy_path(value: float) -> None:
    decl = fl.Parameter(1.0, unit="kg", min=0.0, max=10.0)
    fast, general = decl.check("m", value), decl.check("m", np.float64(value))
    assert isinstance(fast, np.ndarray) and fast.shape == () and fast.dtype == float
    assert fast == general


@pytest.mark.parametrize(("kwargs", "value", "words"), [
    ({"min": 0.0}, -1.0, "below its minimum"),
    ({"max": 1.0}, 2, "above its maximum"),
    ({"gt": 0.0}, 0.0, "must be > 0"),
    ({"lt": 1.0}, 1, "must be < 1"),
    ({}, float("nan"), "not finite"),
    ({}, float("inf"), "not finite"),
])
def test_scalar_parameter_check_refuses_like_numpy_path(kwargs: dict, value: float, words: str) -> None:
    decl = fl.Parameter(0.5, unit="kg", **kwargs)
    for v in (value, np.float64(value)):
        with pytest.raises(ParameterError, match=words) as err:
            decl.check("box.m", v)
        assert "box.m" in str(err.value)


class _Two(fl.Component):
    x = fl.Variable(unit="m")
    y = fl.Variable(unit="m")
    p = fl.Parameter(3.0, unit="1")


def test_scalar_der_and_eq_match_the_vector_path() -> None:
    two = _Two()
    x, y, p = two.x, two.y, two.p
    dx, dy = lookup(x).der_info.sym, lookup(y).der_info.sym
    assert ca.is_equal(fl.der(x), dx)
    assert float(ca.DM(fl.der(p))) == 0.0
    expr = p * x**3 - ca.sin(y)
    fast = fl.der(expr)
    general = fl.der(ca.vertcat(expr, 0 * x))[0]  # a 2-element column: the vec/reshape path
    reference = ca.jtimes(expr, ca.vertcat(x, y), ca.vertcat(dx, dy))
    args = ca.vertcat(x, y, dx, dy, p)
    f = ca.Function("f", [args], [fast, general, reference])
    point = np.random.default_rng(0).uniform(0.5, 1.5, 5)
    vals = [float(v) for v in f(point)]
    assert vals[0] == pytest.approx(vals[2], rel=1e-15) and vals[1] == pytest.approx(vals[2], rel=1e-15)
    neg = fl.der(-x)
    assert float(ca.Function("g", [dx], [neg])(2.0)) == -2.0

    scalar = fl.eq(x, p * y).residual
    column = fl.eq(ca.vertcat(x, x), ca.vertcat(p * y, p * y)).residual
    assert scalar.shape == (1, 1) and column.shape == (2, 1)
    g = ca.Function("g", [args], [scalar, column[0], fl.eq(x, 2.0).residual])
    s, c, k = (float(v) for v in g(point))
    assert s == c == point[0] - point[4] * point[1] and k == point[0] - 2.0
