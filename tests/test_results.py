"""Results: access by name (aliases included), save/load round trip, metadata."""

import h5py
import numpy as np
import pytest

import flexlib as fl
from flexlib import Connector, Flow, Parameter, Potential, Variable, der, eq


class Flange(Connector):
    """Translational flange."""

    s = Potential(unit="m")
    f = Flow(unit="N")


class Mass(fl.Component):
    """Point mass."""

    m = Parameter(1.0, unit="kg", min=0.0)
    s = Variable(unit="m", state_select="prefer")
    v = Variable(unit="m/s", state_select="prefer")
    flange = Flange()

    def equations(self):
        return [eq(self.s, self.flange.s), eq(der(self.s), self.v), eq(self.m * der(self.v), self.flange.f)]


class Spring(fl.Component):
    """Linear spring to ground."""

    c = Parameter(4.0, unit="N/m", min=0.0)
    flange = Flange()

    def equations(self):
        return [eq(self.flange.f, self.c * self.flange.s)]


class Oscillator(fl.Model):
    """Mass on a spring: s(t) = s0 cos(sqrt(c/m) t)."""

    def __init__(self):
        super().__init__()
        self.mass = Mass(init={"s": 0.1, "v": 0.0})
        self.spring = Spring()
        self.connect(self.mass.flange, self.spring.flange)


def test_aliases_are_reported_and_analytic():
    res = fl.Simulation(Oscillator(), use_cache=False).run(2.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res["mass.s"], 0.1 * np.cos(2.0 * res.t), atol=1e-9)
    np.testing.assert_array_equal(res["spring.flange.s"], res["mass.s"])  # an eliminated alias
    np.testing.assert_array_equal(res["spring.flange.f"], -res["mass.flange.f"])
    assert res.unit("mass.v") == "m/s"
    with pytest.raises(KeyError, match=r"close matches:.*mass\.s"):
        res["mass.S"]
    assert res.value("mass.s", 0.005) == pytest.approx(0.1 * np.cos(0.01), abs=1e-5)  # linear interpolation


def test_save_load_identical(tmp_path):
    sim = fl.Simulation(Oscillator(), use_cache=False)
    res = sim.run(1.0, dt_out=0.1, params={"spring.c": 9.0})
    path = tmp_path / "osc.h5"
    res.save(str(path))
    back = fl.load_result(path)
    np.testing.assert_array_equal(back.t, res.t)
    np.testing.assert_array_equal(back.values, res.values)
    assert back.names == res.names and back.units == res.units
    assert back.parameters == res.parameters and back.parameters["spring.c"] == (9.0, "N/m")
    assert back.stats == pytest.approx(res.stats)
    assert back.model == "Oscillator" and back.index_report == res.index_report
    with h5py.File(path) as f:  # self-describing layout (docs/results.md)
        assert f.attrs["format"] == "flexlib-result"
        assert f.attrs["meta_casadi"] and f.attrs["meta_scikit-sundae"]
        assert f["time"].attrs["unit"] == "s"
    assert not list(tmp_path.glob("*.tmp"))


def test_plot_returns_axes():
    import matplotlib

    matplotlib.use("Agg")
    res = fl.Simulation(Oscillator(), use_cache=False).run(1.0, dt_out=0.1)
    ax = res.plot("mass.s", "mass.v")
    assert [line.get_label() for line in ax.get_lines()] == ["mass.s [m]", "mass.v [m/s]"]
    assert ax.get_ylabel() == ""  # two units: the legend says them
    assert res.plot("mass.s").get_ylabel() == "mass.s [m]"  # one variable: the axis says it (issue 29)
    assert res.plot("mass.s", "spring.flange.s").get_ylabel() == "[m]"


def test_display_units_in_plots_and_summary():
    """Plots and summaries show volume flow in L/min, pressure in bar and speed in rpm (results stay SI):
    a FlowSource of 1e-4 m3/s reads 6 L/min; the tank's 1.01325e5 Pa reads 1.01325 bar."""
    import matplotlib

    from flexlib.components.hydraulics import FlowSensor, FlowSource, Tank

    matplotlib.use("Agg")

    class Feed(fl.Model):
        def __init__(self):
            super().__init__()
            self.source, self.sensor, self.tank = FlowSource(q=1e-4), FlowSensor(), Tank()
            self.connect(self.source.port, self.sensor.port_a)
            self.connect(self.sensor.port_b, self.tank.port)

    res = fl.Simulation(Feed(), use_cache=False).run(0.1, dt_out=0.05)
    assert res.unit("sensor.q") == "m3/s" and res["sensor.q"][-1] == pytest.approx(1e-4, rel=1e-12)
    values, unit = res.display("sensor.q")
    assert unit == "L/min" and values[-1] == pytest.approx(6.0, rel=1e-12)
    ax = res.plot("sensor.q", "tank.port.p")
    assert [line.get_label() for line in ax.get_lines()] == ["sensor.q [L/min]", "tank.port.p [bar]"]
    assert ax.get_lines()[1].get_ydata()[-1] == pytest.approx(1.01325, rel=1e-12)
    table = res.summary("sensor.q", "tank.port.p").splitlines()
    assert "L/min" in table[1] and "6" in table[1].split()[2] and "bar" in table[2]


def _read_one_by_one_equals_all(make_sim, t_end: float, **run) -> fl.Result:
    """Every variable read by name from a fresh run (evaluated alone, from the recorded rows) equals the same run's
    full ``values`` (every variable evaluated at once by the compiled ``out``) to 1e-12 relative."""
    lazy = make_sim().run(t_end, **run)
    one_by_one = {name: np.array(lazy[name]) for name in lazy.names}
    assert lazy._values is None  # nothing evaluated the whole table
    full = make_sim().run(t_end, **run)
    for k, name in enumerate(full.names):
        scale = max(float(np.max(np.abs(full.values[:, k]), initial=0.0)), 1e-300)
        assert np.max(np.abs(one_by_one[name] - full.values[:, k]), initial=0.0) <= 1e-12 * scale, name
    np.testing.assert_array_equal(lazy.values, full.values)  # and the table itself, read after the columns
    return lazy


def test_variables_are_evaluated_when_read():
    """A run's result evaluates a variable when it is read (issue 29: the table of every variable at every row
    costs more than the integration on a machine), the same values as the whole table."""
    res = _read_one_by_one_equals_all(lambda: fl.Simulation(Oscillator(), use_cache=False), 2.0, dt_out=0.01)
    assert res["mass.s"].shape == res.t.shape and res["spring.flange.f"][0] == pytest.approx(0.4)


def test_variables_are_evaluated_when_read_across_state_switches():
    """The same over a run whose model changes with its state selection (rows of several models)."""
    from flexlib.models.reference.cartesian_pendulum import CartesianPendulum

    res = _read_one_by_one_equals_all(
        lambda: fl.Simulation(CartesianPendulum(init={"x": 0.0, "u": 8.0}, guess={"y": -1.0}), use_cache=False),
        3.0, rtol=1e-8, atol=1e-10)
    assert res.stats["state_switches"] >= 1


def test_result_file_has_the_users_file_mode(tmp_path):
    """A saved result gets the mode any file the user writes gets (0666 less the umask: 0644 with umask 022), not
    the 0600 of the temporary file it is written through (issue 29)."""
    import os
    import stat

    res = fl.Simulation(Oscillator(), use_cache=False).run(0.1, dt_out=0.05)
    old = os.umask(0o022)
    try:
        res.save(tmp_path / "r.h5")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "r.h5").stat().st_mode) == 0o644


def test_to_dataframe_by_name_with_units():
    """``Result.to_dataframe`` (issue 29, for notebooks): the chosen variables (an array variable by element) as
    columns indexed by time, the same numbers as indexing, units in ``attrs``; display units on request; a wrong
    name is the indexing error."""
    from flexlib.components.mechanics.multibody import Body, Revolute, World

    class Swing(fl.Model):
        def __init__(self):
            super().__init__()
            self.world, self.hinge = World(), Revolute(n=[0, 0, 1], init={"phi": -1.0, "w": 0.0})
            self.bob = Body(m=1.0, r_CM=[0.5, 0.0, 0.0])
            self.connect(self.world.frame_b, self.hinge.frame_a)
            self.connect(self.hinge.frame_b, self.bob.frame_a)

    res = fl.Simulation(Swing(), use_cache=False).run(0.5, dt_out=0.1)
    frame = res.to_dataframe("hinge.phi", "hinge.w", "bob.frame_a.r_0")
    assert list(frame.columns) == ["hinge.phi", "hinge.w", "bob.frame_a.r_0[0]", "bob.frame_a.r_0[1]",
                                   "bob.frame_a.r_0[2]"]
    np.testing.assert_array_equal(frame.index.to_numpy(), res.t)
    np.testing.assert_array_equal(frame["hinge.w"].to_numpy(), res["hinge.w"])
    assert frame.attrs["units"]["hinge.w"] == "rad/s" and frame.index.name == "time [s]"
    shown = res.to_dataframe("hinge.w", display=True)
    np.testing.assert_allclose(shown["hinge.w"].to_numpy(), res["hinge.w"] * 60 / (2 * np.pi))
    assert shown.attrs["units"]["hinge.w"] == "rpm"
    assert len(res.to_dataframe().columns) == len(res.names)
    with pytest.raises(KeyError, match="close matches"):
        res.to_dataframe("hinge.W")


def test_a_run_result_pickles_with_its_values():
    """A run's result (variables evaluated when read) pickles and deep-copies as a whole result: the values are
    evaluated into it, the run's functions are not carried (a process pool or a study gets a plain result)."""
    import copy
    import pickle

    res = fl.Simulation(Oscillator(), use_cache=False).run(0.5, dt_out=0.1)
    back = pickle.loads(pickle.dumps(res))
    assert back.source is None and back.names == res.names
    np.testing.assert_array_equal(back.values, res.values)
    np.testing.assert_array_equal(copy.deepcopy(res)["mass.s"], res["mass.s"])


# -- result files: the run's rows stored, every other variable derived when read (format 2) --------------------------
def _file_equals_memory(res: fl.Result, path, **save) -> fl.Result:
    """``res`` saved and loaded back: every variable read by name equals the run's in memory to 1e-12 relative
    (issue 29's check), and the whole table read at once too."""
    res.save(path, **save)
    back = fl.load_result(path)
    assert back.names == res.names and back.units == res.units and back.kinds == res.kinds
    np.testing.assert_array_equal(back.t, res.t)
    for k, name in enumerate(res.names):
        x = res.values[:, k]
        scale = max(float(np.max(np.abs(x), initial=0.0)), 1e-300)
        assert np.max(np.abs(back[name] - x), initial=0.0) <= 1e-12 * scale, name
    np.testing.assert_allclose(back.values, res.values, rtol=1e-12, atol=0.0)
    return back


def test_a_file_stores_the_rows_and_derives_every_variable(tmp_path):
    """A result file stores the run's rows (unknowns, relation values, the output function), not every variable;
    read back, every variable equals the run's (1e-12 relative). ``outputs="all"`` stores every variable as a
    column (the format-1 content) and reads back the same; the default file is the smaller."""
    import h5py

    res = fl.Simulation(Oscillator(), use_cache=False).run(2.0, dt_out=0.01)
    _file_equals_memory(res, tmp_path / "rows.h5")
    _file_equals_memory(res, tmp_path / "all.h5", outputs="all")
    with h5py.File(tmp_path / "rows.h5") as f:
        assert f["variables/values"].shape == (len(res.t), 0) and "rows/0/out" in f
        assert f["rows/0/y"].shape[1] <= res.stats["n_unknowns"] < len(res.names)
    with h5py.File(tmp_path / "all.h5") as f:
        assert f["variables/values"].shape == (len(res.t), len(res.names)) and "rows" not in f


def test_a_file_derives_across_state_switches(tmp_path):
    """Rows of several models (the state selection switched): each part derives with its own output function."""
    from flexlib.models.reference.cartesian_pendulum import CartesianPendulum

    res = fl.Simulation(CartesianPendulum(init={"x": 0.0, "u": 8.0}, guess={"y": -1.0}), use_cache=False).run(
        3.0, rtol=1e-8, atol=1e-10)
    assert res.stats["state_switches"] >= 1
    back = _file_equals_memory(res, tmp_path / "switch.h5")
    assert len(back.source.parts) >= 2
    _file_equals_memory(back, tmp_path / "again.h5")  # a loaded result saves its rows again


def test_outputs_are_stored_as_columns(tmp_path):
    """``outputs=`` stores the named variables (patterns, array names) as columns besides the rows; a pattern that
    matches nothing is named in a warning and the file is written without it (nothing lost)."""
    import h5py

    sim = fl.Simulation(Oscillator(), use_cache=False)
    res = sim.run(1.0, dt_out=0.1, result_file=tmp_path / "r.h5", outputs=["spring.*", "mass.s"])
    with h5py.File(tmp_path / "r.h5") as f:
        stored = [res.names[k] for k in f["variables/stored"][()]]
    assert "mass.s" in stored and stored and all(n == "mass.s" or n.startswith("spring.") for n in stored)
    back = fl.load_result(tmp_path / "r.h5")
    np.testing.assert_array_equal(back["spring.flange.f"], res["spring.flange.f"])
    with pytest.warns(fl.ResultSaveWarning, match=r"outputs 'nosuch\.\*' is not stored"):
        sim.run(1.0, dt_out=0.1, result_file=tmp_path / "w.h5", outputs=["nosuch.*", "mass.v"])
    np.testing.assert_array_equal(fl.load_result(tmp_path / "w.h5")["mass.v"], res["mass.v"])
    with pytest.raises(fl.RunArgumentError, match=r"outputs = 3 is invalid"):
        sim.run(1.0, outputs=3)


def test_a_derived_variable_needs_the_stored_function(tmp_path):
    """A file whose output function cannot be read (another CasADi wrote it; here: damaged) still gives its
    unknowns and constants; a derived variable is a ResultFileError saying why and what to do."""
    import h5py

    res = fl.Simulation(Oscillator(), use_cache=False).run(1.0, dt_out=0.1)
    res.save(tmp_path / "r.h5")
    with h5py.File(tmp_path / "r.h5", "a") as f:
        del f["rows/0/out"]
        f["rows/0/out"] = np.frombuffer(b"not a function", dtype=np.uint8)
        source = f["rows/0/source"][()]
    back = fl.load_result(tmp_path / "r.h5")
    unknown = next(n for n, s in zip(res.names, source, strict=True) if s >= 0)
    derived = next(n for n, s in zip(res.names, source, strict=True) if s == -1)
    np.testing.assert_array_equal(back[unknown], res[unknown])
    with pytest.raises(fl.ResultFileError, match=r"r\.h5.*output function.*cannot be read.*outputs="):
        back[derived]


@pytest.mark.parametrize(("change", "problem"), [
    (lambda f: f["rows/0/rows"].__setitem__(0, 5), r"increasing row indices|holds row"),
    (lambda f: f.__delitem__("rows/0/y_columns"), r"missing /rows/0/y_columns"),
    (lambda f: f.__delitem__("rows"), r"no /rows to derive"),
    (lambda f: f["rows/0/source"].__setitem__(0, 10**6), r"source must hold unknown indices"),
])
def test_a_damaged_rows_group_is_named(tmp_path, change, problem):
    import h5py

    res = fl.Simulation(Oscillator(), use_cache=False).run(1.0, dt_out=0.1)
    res.save(tmp_path / "r.h5")
    with h5py.File(tmp_path / "r.h5", "a") as f:
        change(f)
    with pytest.raises(fl.ResultFileError, match=r"r\.h5: .*" + f"(?:{problem})"):
        fl.load_result(tmp_path / "r.h5")


def test_compare_reads_files_block_by_block(tmp_path):
    """``compare`` of two result files (variables derived as read, a block at a time) ranks as the comparison of
    the runs in memory, and keeps no column of either file."""
    from flexlib.results.compare import compare

    sim = fl.Simulation(Oscillator(), use_cache=False)
    a, b = sim.run(2.0, dt_out=0.01), sim.run(2.0, dt_out=0.01, params={"mass.m": 1.02})
    a.save(tmp_path / "a.h5")
    b.save(tmp_path / "b.h5")
    fa, fb = fl.load_result(tmp_path / "a.h5"), fl.load_result(tmp_path / "b.h5")
    on_files, in_memory = compare(fa, fb), compare(a, b)
    assert [r["name"] for r in on_files.rows] == [r["name"] for r in in_memory.rows]
    for r, s in zip(on_files.rows, in_memory.rows, strict=True):
        assert r["ratio"] == pytest.approx(s["ratio"], rel=1e-9) and r["same"] == s["same"]
    assert fa._values is None and not fa._columns


# -- arrays in their shape, and the side of an event (issue 30, item 4) ----------------------------------------------
def test_value_before_and_after_an_event():
    """At an event time a result holds several rows (t = 1 s: the torque before, -1 → +1 after, BangBang's time
    event): ``value(t)`` and ``row(t)`` give the value after it, ``side="left"`` the value before it; between rows
    both interpolate the same; any other side is refused, naming it."""
    from flexlib.models.reference.events import BangBang

    res = fl.Simulation(BangBang(init={"w": 0.0}), use_cache=False).run(4.0, dt_out=0.5, rtol=1e-8, atol=1e-10)
    at = np.flatnonzero(res.t == 1.0)
    assert len(at) >= 2
    before, after = res["tau"][at[0]], res["tau"][at[-1]]
    assert before != after
    assert res.value("tau", 1.0) == after and res.value("tau", 1.0, side="left") == before
    k = res.names.index("tau")
    assert res.row(1.0)[k] == after and res.row(1.0, side="left")[k] == before
    assert res.value("w", 0.7, side="left") == pytest.approx(res.value("w", 0.7), abs=0.0)
    with pytest.raises(fl.RunArgumentError, match=r"side must be 'right'.*got 'middle'"):
        res.value("tau", 1.0, side="middle")


def test_a_matrix_variable_comes_in_its_shape(tmp_path):
    """``result["frame.T"]`` is ``(len(t), 3, 3)``, element ``[i, j]`` the variable named ``T[i,j]`` (stored in column
    order: reshaping the flat columns in C order would transpose it); ``value``, ``final`` and a file read back keep
    the shape; a vector stays ``(len(t), 3)``."""
    from flexlib.models.reference.rigid_pendulum import RigidPendulum

    res = fl.Simulation(RigidPendulum(), use_cache=False).run(0.5, dt_out=0.1)
    name = next(n.rpartition("[")[0] for n in res.names if n.endswith(".T[1,0]"))
    T = res[name]
    assert T.shape == (len(res.t), 3, 3)
    for i in range(3):
        for j in range(3):
            np.testing.assert_array_equal(T[:, i, j], res[f"{name}[{i},{j}]"])
    assert res.elements(name)[:2] == [f"{name}[0,0]", f"{name}[1,0]"]
    np.testing.assert_allclose(np.einsum("kij,kil->kjl", T, T), np.broadcast_to(np.eye(3), T.shape), atol=1e-9)
    assert res.value(name, 0.25).shape == (3, 3) and res.value(name, [0.1, 0.2]).shape == (2, 3, 3)
    np.testing.assert_array_equal(res.final(name), T[-1])
    res.save(tmp_path / "r.h5")
    np.testing.assert_array_equal(fl.load_result(tmp_path / "r.h5")[name], T)
    vector = next(n.rpartition("[")[0] for n in res.names if n.endswith(".r_0[2]"))
    assert res[vector].shape == (len(res.t), 3)
