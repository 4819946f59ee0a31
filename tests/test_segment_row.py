"""Tables selected by time without events (``fl.segment_row``): the row of the segment holding the time, looked up in
O(log N) and bound at compile (``flexlib/core/tables.py``). References: the selection by ``numpy.searchsorted``
(side ``right``) and the closed-form integral of a piecewise-linear function of time."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import flexlib as fl
from flexlib import Output, Variable, der, eq
from flexlib.core.tables import CURRENT_TABLES, bind_tables
from flexlib.errors import ModelError

BREAKS = np.array([0.3, 0.7, 1.1, 1.6, 2.2, 2.9])
RATES = np.array([0.5, -1.0, 2.0, 0.0, 3.0, -0.5, 1.5])  # one per segment (len(BREAKS) + 1)


class RampTable(fl.Model):
    """``x' = r(t)`` with ``r`` the rate of the segment holding ``t`` and ``s = t − t_k`` its time in the segment,
    so ``y = r·s + x_k`` is the integral restarted at each break (continuous): ``y = x`` along the whole run."""

    x = Variable(start=0.0, fixed=True, unit="1")
    y = Output(unit="1")
    rate = Output(unit="1/s")

    def equations(self) -> list:
        starts = np.concatenate([[0.0], BREAKS])  # segment k starts at starts[k] (segment 0 at t = 0)
        at_start = np.concatenate([[0.0], np.cumsum(RATES[:-1] * np.diff(starts))])
        r, t_k, x_k = fl.segment_row(fl.time, BREAKS, np.column_stack([RATES, starts, at_start]))
        return [eq(der(self.x), r), eq(self.rate, r), eq(self.y, x_k + r * (fl.time - t_k))]


def _exact(t: np.ndarray) -> np.ndarray:
    starts = np.concatenate([[0.0], BREAKS])
    at_start = np.concatenate([[0.0], np.cumsum(RATES[:-1] * np.diff(starts))])
    k = np.searchsorted(BREAKS, t, side="right")
    return at_start[k] + RATES[k] * (t - starts[k])


def test_the_row_is_the_segments_at_and_between_the_breaks():
    """The bound lookup gives the ``searchsorted(side="right")`` row, exactly, at every break (just below, at, just
    above) and at random times before, inside and after the breaks; one break and no break too."""
    rng = np.random.default_rng(4)
    for n in (0, 1, 2, 6, 300):
        breaks = np.cumsum(rng.uniform(0.01, 1.0, n))
        rows = rng.normal(size=(n + 1, 3))
        tables: list = []
        token = CURRENT_TABLES.set(tables)
        try:
            syms = fl.segment_row(fl.time, breaks, rows)
        finally:
            CURRENT_TABLES.reset(token)
        (bound,) = bind_tables([ca.vertcat(*syms)], tables)
        f = ca.Function("f", [fl.time], [bound])
        top = breaks[-1] + 1 if n else 1.0
        x = np.concatenate([breaks, np.nextafter(breaks, -np.inf), np.nextafter(breaks, np.inf),
                            rng.uniform(-1.0, top, 500)])
        got = np.array(f.map(x.size)(x)).T
        np.testing.assert_array_equal(got, rows[np.searchsorted(breaks, x, side="right")])


def test_a_model_with_a_table_runs_exactly_and_without_events():
    """``x' = r(t)`` integrates the piecewise-constant rate (to IDA's tolerance); ``y`` (the integral restarted at each
    break from the table) equals the closed form to 1e-12 at every row; no event stops the run at a break."""
    res = fl.Simulation(RampTable(), use_cache=False).run(3.5, dt_out=0.01, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["y"], _exact(res.t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(res["x"], _exact(res.t), rtol=0, atol=1e-7)
    assert not res.events and res.stats["time_events"] == 0
    k = np.searchsorted(BREAKS, res.t, side="right")
    np.testing.assert_array_equal(res["rate"], RATES[k])


def test_table_symbols_are_constant_to_derivatives():
    """``der`` of an expression of table symbols is 0 (piecewise constant); a column with one value in every segment
    is that constant (no lookup)."""
    tables: list = []
    token = CURRENT_TABLES.set(tables)
    try:
        a, b = fl.segment_row(fl.time, [1.0, 2.0], [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]])
        assert float(ca.evalf(der(a * b + a))) == 0.0
        assert ca.is_equal(ca.simplify(der(fl.time * a)), a)
        same, varying = fl.segment_row(fl.time, [1.0, 2.0], [[4.0, 1.0], [4.0, 2.0], [4.0, 3.0]])
        assert same.is_constant() and float(same) == 4.0 and varying.is_symbolic()  # one value: no lookup
        assert len(tables) == 2 and len(tables[-1].symbols) == 1
    finally:
        CURRENT_TABLES.reset(token)


class _BadX(fl.Model):
    """A table selected by a state instead of time."""

    x = Variable(start=0.0, unit="1")
    y = Output(unit="1")

    def equations(self) -> list:
        (r,) = fl.segment_row(self.x, [1.0], [[0.0], [1.0]])
        return [eq(der(self.x), 1.0), eq(self.y, r)]


@pytest.mark.parametrize(("breaks", "rows", "match"), [
    ([1.0, 1.0], [[0.0], [1.0], [2.0]], "strictly increasing"),
    ([1.0, 2.0], [[0.0], [1.0]], "len\\(breaks\\) \\+ 1 = 3 rows"),
    ([1.0, np.nan], [[0.0], [1.0], [2.0]], "finite"),
])
def test_bad_tables_are_refused(breaks, rows, match):
    """Breaks not strictly increasing, a wrong number of rows, non-finite entries, ``x`` not of time only and a call
    outside ``equations()`` are errors that say what is wrong."""
    tables: list = []
    token = CURRENT_TABLES.set(tables)
    try:
        with pytest.raises(ModelError, match=match):
            fl.segment_row(fl.time, breaks, rows)
    finally:
        CURRENT_TABLES.reset(token)
    with pytest.raises(ModelError, match="inside equations"):
        fl.segment_row(fl.time, [1.0], [[0.0], [1.0]])
    with pytest.raises(ModelError, match="time only"):
        fl.build(_BadX(), use_cache=False)
