"""Result files and Result accessors: bad files give ResultFileError naming the path and the problem, a failing
save never hides the result or the solver error, writes leave nothing behind, and results without rows
(a run that failed at t0) can be summarised, plotted, saved and loaded (issue 8)."""

import errno
import os
import subprocess
import sys

import h5py
import numpy as np
import pytest

import flexlib as fl
from flexlib import Variable, assert_, der, eq
from flexlib.models.reference.blow_up import BlowUp
from flexlib.models.reference.mass_spring_damper import Oscillator
from flexlib.results import hdf5


class BadStart(fl.Model):
    """x' = -x with an assertion that is false at t0: the run fails before its first row."""

    x = Variable(unit="Pa")

    def equations(self):
        assert_(self.x <= 0.5, "x must stay below 0.5 Pa")
        return [eq(der(self.x), -self.x)]


@pytest.fixture(scope="module")
def osc():
    return fl.Simulation(Oscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


@pytest.fixture(scope="module")
def saved(osc, tmp_path_factory):
    """A good result file (reference: x = cos t) to damage in the tests."""
    path = tmp_path_factory.mktemp("good") / "good.h5"
    osc.run(1.0, dt_out=0.1, rtol=1e-8, atol=1e-10).save(path)
    return path


@pytest.fixture(scope="module")
def empty():
    """The result of a run that failed at t0 (assertion false at the start)."""
    sim = fl.Simulation(BadStart(init={"x": 1.0}), use_cache=False)
    with pytest.raises(fl.SolverError, match=r"x must stay below 0\.5 Pa") as err:
        sim.run(1.0)
    return err.value.result


def copy_of(saved, tmp_path, name="copy.h5"):
    path = tmp_path / name
    path.write_bytes(saved.read_bytes())
    return path


# -- loading bad files -------------------------------------------------------------------------------------

def test_load_missing_file(tmp_path):
    path = tmp_path / "nope.h5"
    with pytest.raises(fl.ResultFileError, match=rf"{path}: no such file"):
        fl.load_result(path)


def test_load_a_directory(tmp_path):
    with pytest.raises(fl.ResultFileError, match=rf"{tmp_path}: it is a directory"):
        fl.load_result(tmp_path)


def test_load_empty_file(tmp_path):
    path = tmp_path / "empty.h5"
    path.write_bytes(b"")
    with pytest.raises(fl.ResultFileError, match=r"empty\.h5: an empty file"):
        fl.load_result(path)


def test_load_random_bytes(tmp_path):
    path = tmp_path / "random.h5"
    path.write_bytes(np.random.default_rng(1).integers(0, 256, 4096, dtype=np.uint8).tobytes())
    with pytest.raises(fl.ResultFileError, match=r"random\.h5: not an HDF5 file \(4096 bytes of binary data\)"):
        fl.load_result(path)


def test_load_csv(tmp_path):
    path = tmp_path / "run.csv"
    path.write_text("time,x\n0,1\n0.1,0.995\n")
    with pytest.raises(fl.ResultFileError, match=r"run\.csv: not an HDF5 file but CSV text.*'time,x'"):
        fl.load_result(path)


def test_load_truncated_hdf5(saved, tmp_path):
    path = tmp_path / "truncated.h5"
    path.write_bytes(saved.read_bytes()[: saved.stat().st_size // 2])
    with pytest.raises(fl.ResultFileError, match=r"truncated\.h5: .*truncated or damaged HDF5 file"):
        fl.load_result(path)


def test_load_hdf5_that_is_not_a_result(tmp_path):
    path = tmp_path / "other.h5"
    with h5py.File(path, "w") as f:
        f["data"] = np.arange(3.0)
    with pytest.raises(fl.ResultFileError, match=r"other\.h5: not a flexlib result file \(no 'format' attribute"):
        fl.load_result(path)


def test_load_hdf5_with_another_format(tmp_path):
    path = tmp_path / "other.h5"
    with h5py.File(path, "w") as f:
        f.attrs["format"] = "someone-else"
    with pytest.raises(fl.ResultFileError, match=r"not a flexlib result file \(format attribute 'someone-else'"):
        fl.load_result(path)


@pytest.mark.parametrize("member", ["events", "variables/names", "parameters", "time"])
def test_load_with_a_group_or_dataset_missing(saved, tmp_path, member):
    path = copy_of(saved, tmp_path)
    with h5py.File(path, "a") as f:
        del f[member]
    with pytest.raises(fl.ResultFileError, match=rf"copy\.h5: incomplete flexlib result, missing .*/{member}"):
        fl.load_result(path)


def test_load_with_an_attribute_missing(saved, tmp_path):
    path = copy_of(saved, tmp_path)
    with h5py.File(path, "a") as f:
        del f.attrs["solver_stats"]
    with pytest.raises(fl.ResultFileError, match=r"missing attribute 'solver_stats'"):
        fl.load_result(path)


@pytest.mark.parametrize(("attr", "value", "message"), [
    ("format_version", 99, r"copy\.h5: format_version 99 is not supported: this flexlib reads "
                           r"format_version 1 \.\.\. 2.*upgrade flexlib"),
    ("format_version", "one", r"format_version is missing or not an integer \('one'\)"),
    ("solver_stats", "{steps: 3", r"'solver_stats' is not JSON"),
    ("status", "maybe", r"status 'maybe' is not one of success, failed, interrupted"),
], ids=["newer_format", "text_format_version", "bad_solver_stats", "unknown_status"])
def test_load_with_a_bad_attribute(saved, tmp_path, attr, value, message):
    path = copy_of(saved, tmp_path)
    with h5py.File(path, "a") as f:
        f.attrs[attr] = value
    with pytest.raises(fl.ResultFileError, match=message):
        fl.load_result(path)


def test_load_with_inconsistent_shapes(saved, tmp_path):
    path = copy_of(saved, tmp_path)
    with h5py.File(path, "a") as f:
        del f["time"]
        f["time"] = np.arange(3.0)
    with pytest.raises(fl.ResultFileError, match=r"/variables/values has shape \(11, \d+\), expected \(3, \d+\)"):
        fl.load_result(path)


@pytest.mark.parametrize("bad", [None, 42, b"run.h5"])
def test_load_with_a_path_of_the_wrong_type(bad):
    with pytest.raises(fl.RunArgumentError, match=r"load_result: the path must be a str or os\.PathLike"):
        fl.load_result(bad)


def test_good_file_still_loads(saved):
    """Reference: x = cos t, |error| < 1e-6 at rtol 1e-8."""
    res = fl.load_result(saved)
    assert res.status == "success" and len(res.t) == 11
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-6)


# -- saving ------------------------------------------------------------------------------------------------

def test_save_under_a_file(osc, tmp_path):
    res = osc.run(0.2)
    (tmp_path / "plain").write_text("x")
    with pytest.raises(fl.ResultFileError, match=r"plain/run\.h5: cannot create its directory .*plain"):
        res.save(tmp_path / "plain" / "run.h5")


def test_save_onto_a_directory(osc, tmp_path):
    with pytest.raises(fl.ResultFileError, match=rf"{tmp_path}: it is a directory"):
        osc.run(0.2).save(tmp_path)


def test_save_with_a_path_of_the_wrong_type(osc):
    with pytest.raises(fl.RunArgumentError, match=r"save_result: the path must be a str or os\.PathLike.*int"):
        osc.run(0.2).save(3)


def test_disk_full_during_save_leaves_the_old_file_and_no_temporary(osc, saved, tmp_path, monkeypatch):
    path = copy_of(saved, tmp_path, "run.h5")
    before = path.read_bytes()
    real_write = hdf5._write

    def full(result, tmp, *args):
        real_write(result, tmp, *args)
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(hdf5, "_write", full)
    with pytest.raises(fl.ResultFileError, match=r"run\.h5: No space left on device"):
        osc.run(0.2).save(path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.h5"]


def test_temporary_name_carries_the_pid(osc, tmp_path, monkeypatch):
    seen = []
    real = os.replace

    def spy(src, dst):
        seen.append(os.path.basename(src))
        real(src, dst)

    monkeypatch.setattr(hdf5.os, "replace", spy)
    osc.run(0.2).save(tmp_path / "run.h5")
    assert len(seen) == 1 and seen[0].startswith(f"run.h5.{hdf5._host()}.{os.getpid()}.")
    assert seen[0].endswith(".tmp")


def test_orphaned_temporaries_of_dead_writers_are_removed(osc, tmp_path):
    """A writer killed mid-save leaves ``run.h5.<host>.<pid>.<random>.tmp``; the next save of that file removes
    it once that pid is gone, and keeps temporaries of live writers, of other hosts and of other files."""
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()  # a pid that no longer exists
    host = hdf5._host()
    orphan = tmp_path / f"run.h5.{host}.{child.pid}.k3j2x9qa.tmp"
    orphan.write_bytes(b"\x89HDF half written")
    live = tmp_path / f"run.h5.{host}.{os.getppid()}.a1b2c3d4.tmp"  # the parent of pytest is alive
    live.write_bytes(b"busy")
    elsewhere = tmp_path / f"run.h5.{host}x.{child.pid}.q1w2e3r4.tmp"  # another host on a shared file system
    elsewhere.write_bytes(b"maybe busy")
    other = tmp_path / f"other.h5.{host}.{child.pid}.zzzzzzzz.tmp"
    other.write_bytes(b"not ours")
    osc.run(0.2).save(tmp_path / "run.h5")
    assert not orphan.exists()
    assert live.exists() and elsewhere.exists() and other.exists()
    assert fl.load_result(tmp_path / "run.h5").success


def test_run_returns_the_result_when_the_save_fails(osc, tmp_path, monkeypatch):
    """The directory checked before the run is replaced by a file while the run integrates: the save fails,
    the run warns naming the path and the OS reason, and returns the result (x = cos t, atol 1e-5)."""
    from flexlib.solve import simulation

    outdir = tmp_path / "out"
    name = "run_loop"  # the run loop of every backend
    real = getattr(simulation, name)

    def then_break_the_directory(*args, **kwargs):
        traj = real(*args, **kwargs)
        outdir.write_text("a file where the directory was")
        return traj

    monkeypatch.setattr(simulation, name, then_break_the_directory)
    with pytest.warns(fl.ResultSaveWarning, match=r"out/run\.h5: cannot create its directory .*kept in memory"):
        res = osc.run(1.0, dt_out=0.1, rtol=1e-8, atol=1e-10, result_file=outdir / "run.h5")
    assert res.success and len(res.t) == 11
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-5)


def test_solver_error_is_kept_when_its_save_fails(tmp_path, monkeypatch):
    """A run that fails (x' = x² blows up at t = 1) and cannot save: the SolverError with its result is raised
    unchanged, the save failure is a warning."""

    def no_space(result, tmp, *args):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(hdf5, "_write", no_space)
    sim = fl.Simulation(BlowUp(init={"x": 1.0}), use_cache=False)
    with pytest.warns(fl.ResultSaveWarning, match=r"failed\.h5: No space left on device"):
        with pytest.raises(fl.SolverError, match=r"at t = 0\.9") as err:
            sim.run(2.0, dt_out=0.01, result_file=tmp_path / "failed.h5")
    res = err.value.result
    assert res.status == "failed" and 0.9 < res.t[-1] < 1.0
    early = res.t < 0.9
    np.testing.assert_allclose(res["x"][early], 1 / (1 - res.t[early]), rtol=1e-3)
    assert list(tmp_path.iterdir()) == []


# -- results without rows, bad names ------------------------------------------------------------------------

def test_run_failing_at_t0_gives_an_empty_failed_result(empty):
    assert empty.status == "failed" and "x must stay below 0.5 Pa" in empty.message
    assert len(empty.t) == 0 and empty["x"].shape == (0,)
    assert "0 points" in repr(empty)


def test_summary_of_an_empty_result(empty):
    text = empty.summary("x")
    assert "x" in text and "-" in text.splitlines()[1]
    assert text.splitlines()[-1].startswith("(failed: assertion failed at t = 0")


def test_display_of_an_empty_result(empty):
    values, unit = empty.display("x")
    assert values.shape == (0,) and unit == "bar"


@pytest.mark.parametrize("call", ["value", "final"])
def test_values_of_an_empty_result(empty, call):
    args = ("x", 0.5) if call == "value" else ("x",)
    with pytest.raises(fl.EmptyResultError, match=rf"{call}\('x'.*BadStart has no rows; the run is failed"):
        getattr(empty, call)(*args)


def test_plot_of_an_empty_result(empty):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ax = empty.plot("x")
    assert "no rows" in ax.get_title()
    plt.close(ax.figure)


def test_save_and_load_an_empty_result(empty, tmp_path):
    empty.save(tmp_path / "empty.h5")
    back = fl.load_result(tmp_path / "empty.h5")
    assert back.status == "failed" and back.values.shape == (0, len(empty.names)) and back.message == empty.message


def test_unknown_name_says_did_you_mean(osc):
    res = osc.run(0.2)
    with pytest.raises(fl.ResultKeyError, match=r"no variable 'xx' in the result of Osc.*did you mean 'x'\?") as err:
        res["xx"]
    assert isinstance(err.value, KeyError) and isinstance(err.value, fl.FlexlibError)
    with pytest.raises(KeyError, match=r"did you mean 'x'"):  # older callers catching KeyError
        res.unit("xx")


def test_wrong_component_path_suggests_the_same_leaf(osc):
    res = osc.run(0.2)
    with pytest.raises(fl.ResultKeyError, match=r"'pendulum\.body\.v'.*did you mean 'v'"):
        res.value("pendulum.body.v", 0.1)


def test_name_of_the_wrong_type(osc):
    with pytest.raises(fl.ResultKeyError, match=r"looked up by name \(str\), got 3 \(int\)"):
        osc.run(0.2)[3]
