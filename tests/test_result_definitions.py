"""Unknowns that residual rows give explicitly: set by their rows in a run's recorded rows, not stored in a result file,
derived when read (issue 29: the rigid expand-fold's file 58 → 35 MB; ``flexlib.results.stored.row_definitions``)."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import flexlib as fl
from flexlib.errors import CacheWarning
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
    defs = row_definitions_of(sim._rows, sim.compiled)
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
    defs = row_definitions_of(sim._rows, sim.compiled)
    F_after, Y_after = _residuals(sim, res)
    monkeypatch.setattr(assemble, "row_definitions_of", lambda rows, model, key=None: RowDefinitions(
        np.arange(model.n), np.zeros(0, dtype=np.int64), None))
    plain = fl.Simulation(FourBarLinkage(), use_cache=False)
    F_before, Y_before = _residuals(plain, plain.run(1.0, dt_out=0.01))
    change = np.abs(Y_after - Y_before).max(axis=0)[defs.given]
    assert np.all(change <= 1e-4 * np.ptp(Y_before, axis=0)[defs.given] + 1e-12), change
    untouched = np.setdiff1d(np.arange(sim.compiled.n), defs.given)
    np.testing.assert_array_equal(Y_after[:, untouched], Y_before[:, untouched])
    assert np.all(F_after <= 2 * F_before + 1e-12), (F_before, F_after)
    assert np.count_nonzero(F_after < F_before) >= defs.given.size // 2  # (the defining rows: to round-off)


def test_the_definitions_are_kept_with_the_build(tmp_path, monkeypatch):
    """Found once per build and kept in the cache beside its entry: a later process reads them back; a damaged file
    is named in a CacheWarning, removed and made again, and the run's file is still right."""
    import flexlib.solve.definitions_cache as dc

    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path / "cache"))
    fl.Simulation(FourBarLinkage()).run(0.2, dt_out=0.05)
    kept = list((tmp_path / "cache").glob("*-rows.npz"))
    assert len(kept) == 1
    calls = []
    monkeypatch.setattr(dc, "row_definitions", lambda *a: calls.append(a) or pytest.fail("made again"))
    res = fl.Simulation(FourBarLinkage()).run(0.2, dt_out=0.05)  # read back, not made
    assert not calls
    monkeypatch.undo()
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path / "cache"))
    kept[0].write_bytes(b"not an npz archive")
    with pytest.warns(CacheWarning, match="row definitions"):
        again = fl.Simulation(FourBarLinkage()).run(0.2, dt_out=0.05)
    np.testing.assert_allclose(again.values, res.values, rtol=1e-12, atol=0.0)
    again.save(tmp_path / "again.h5")
    back = fl.load_result(tmp_path / "again.h5")
    np.testing.assert_allclose(back.values, again.values, rtol=1e-12, atol=1e-300)
