"""Unknowns that residual rows give explicitly: set by their rows in a run's recorded rows, not stored in a result file,
derived when read (issue 29: the rigid expand-fold's file 58 → 35 MB; ``flexlib.compile.explicit.row_definitions``)."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import flexlib as fl
from flexlib.models.planar_mechanisms import FourBarLinkage
from flexlib.solve.assemble import row_definitions_of


@pytest.fixture(scope="module")
def fourbar():
    sim = fl.Simulation(FourBarLinkage(), use_cache=False)
    return sim, sim.run(1.0, dt_out=0.01)


@pytest.mark.filterwarnings("ignore::flexlib.errors.IndeterminateReactionWarning")  # (every name read: the planar
def test_a_file_leaves_out_the_unknowns_rows_give_and_reads_them_back(fourbar, tmp_path):  # loop's out-of-plane ones)
    """The four-bar's 25 unknowns: the frame velocities, accelerations and cut forces that one row each defines are
    given (11), the file stores the other 14 (distinct columns) and the definitions; every variable reads back equal
    to the run in memory (1e-12 relative), and a loaded result saves again the same way."""
    sim, res = fourbar
    defs = row_definitions_of(sim.compiled)
    assert defs.given.size >= 5 and not np.asarray(sim.compiled.differential, dtype=bool)[defs.given].any()
    res.save(tmp_path / "r.h5")
    with h5py.File(tmp_path / "r.h5") as f:
        assert f["rows/0/y"].shape[1] <= sim.compiled.n - defs.given.size
        np.testing.assert_array_equal(f["rows/0/given"][()], defs.given)
        assert (f["rows/0/y_columns"][()][defs.given] == -1).all()
    for path in (tmp_path / "r.h5", tmp_path / "again.h5"):
        back = fl.load_result(path)
        for k, name in enumerate(res.names):
            x = res.values[:, k]
            scale = max(float(np.max(np.abs(x), initial=0.0)), 1e-300)
            assert np.max(np.abs(back[name] - x), initial=0.0) <= 1e-12 * scale, name
        if path.name == "r.h5":
            back.save(tmp_path / "again.h5")


def _residuals(sim: fl.Simulation, res: fl.Result) -> tuple[np.ndarray, np.ndarray]:
    """Largest |F(t, y, y')| of each equation over the recorded rows, and the rows' unknowns."""
    model, _, T, Y, YP, rel = res.source.parts[0]
    P = np.hstack([np.broadcast_to(res.source.pvec, (len(T), len(res.source.pvec))), rel])
    return np.abs(sim._rows.evaluate(model, "res", T, Y, YP, P)).max(axis=0), Y


def test_given_unknowns_change_the_rows_within_the_solver_tolerance(fourbar, monkeypatch):
    """Against the rows as IDA left them (the definitions switched off): the given unknowns move by less than 1e-4 of
    their range (IDA's tolerance: cut forces are outside its error test), their own rows' residuals are 0 and no
    equation's residual grows by more than a factor 2 (the differential rows keep the residual of IDA's
    interpolated derivatives)."""
    import flexlib.solve.assemble as assemble
    from flexlib.results.stored import RowDefinitions

    sim, res = fourbar
    defs = row_definitions_of(sim.compiled)
    F_after, Y_after = _residuals(sim, res)
    monkeypatch.setattr(assemble, "row_definitions_of", lambda model: RowDefinitions(
        np.arange(model.n), np.zeros(0, dtype=np.int64), None))
    plain = fl.Simulation(FourBarLinkage(), use_cache=False)
    F_before, Y_before = _residuals(plain, plain.run(1.0, dt_out=0.01))
    change = np.abs(Y_after - Y_before).max(axis=0)[defs.given]
    assert np.all(change <= 1e-4 * np.ptp(Y_before, axis=0)[defs.given] + 1e-12), change
    untouched = np.setdiff1d(np.arange(sim.compiled.n), defs.given)
    np.testing.assert_array_equal(Y_after[:, untouched], Y_before[:, untouched])
    assert np.all(F_after <= 2 * F_before + 1e-12), (F_before, F_after)
    assert np.count_nonzero(F_after < F_before) >= defs.given.size // 2  # (the defining rows: to round-off)


def test_the_definitions_are_part_of_the_build(tmp_path, monkeypatch):
    """Found when the model is compiled and kept with the build: a cached build carries the same given unknowns and
    definitions, without finding them again, and its run's file reads back the same."""
    import flexlib.compile.codegen as codegen

    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path / "cache"))
    first = fl.Simulation(FourBarLinkage())
    res = first.run(0.2, dt_out=0.05)
    calls = []
    monkeypatch.setattr(codegen, "row_definitions", lambda *a: calls.append(a) or pytest.fail("found again"))
    cached = fl.Simulation(FourBarLinkage())
    again = cached.run(0.2, dt_out=0.05)
    assert not calls and cached.build_info.get("cached")
    np.testing.assert_array_equal(cached.compiled.given, first.compiled.given)
    assert cached.compiled.given.size >= 5
    np.testing.assert_allclose(again.values, res.values, rtol=1e-12, atol=0.0)
    again.save(tmp_path / "again.h5")
    back = fl.load_result(tmp_path / "again.h5")
    np.testing.assert_allclose(back.values, again.values, rtol=1e-12, atol=1e-300)


class _Spring(fl.Model):
    """``m x'' = −k x`` with the spring force an output (derived when read: ``f = k·x``)."""

    k = fl.Parameter(4.0, unit="N/m")
    m = fl.Parameter(1.0, unit="kg")
    x = fl.Variable(start=1.0, fixed=True, unit="m")
    v = fl.Variable(start=0.0, fixed=True, unit="m/s")
    f = fl.Output(unit="N")

    def equations(self) -> list:
        return [fl.eq(fl.der(self.x), self.v), fl.eq(self.m * fl.der(self.v), -self.f), fl.eq(self.f, self.k * self.x)]


def test_results_of_one_simulation_with_other_parameters_read_their_own_values():
    """Variables derived when read use the parameters of their own run (folded into the reading function), also when
    read alternately after a later run of the same simulation with other values: ``f = k·x`` to 1e-14."""
    sim = fl.Simulation(_Spring(), use_cache=False)
    a = sim.run(1.0, dt_out=0.1)
    b = sim.run(1.0, dt_out=0.1, params={"k": 9.0})
    for res, k in ((b, 9.0), (a, 4.0), (b, 9.0), (a, 4.0)):
        np.testing.assert_allclose(res["f"], k * res["x"], rtol=1e-14, atol=1e-14)
