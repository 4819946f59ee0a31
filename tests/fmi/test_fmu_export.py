"""FMI 2.0 co-simulation export (``flexlib.fmi.export_fmu``, issue 32), checked by an independent FMI master: fmpy.

References and tolerances: fmpy's model-description validation must find nothing; fmpy's simulation of the unit must
match flexlib's own run with the same fixed step (``solver=fl.FixedStep(h)``, the same stepper in C) to 1e-9 of the
signal's range (the issue asks 1e-6; both run the same arithmetic, so they agree to round-off): the oscillator
``x'' = −k x`` (also against ``cos(√k t)``, 1e-5 at h = 1 ms), MSL's Fourbar1 (56 unknowns: KLU inside the unit) and
MSL's CoupledClutches (time events and stick/slip state events with the event iteration inside the unit). A parameter
set through the master before initialisation gives the run with that parameter.
"""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, der, eq
from flexlib.fmi import export_fmu
from flexlib.models.reference.drive_trains import CoupledClutches
from tests.msl.test_msl_multibody_examples import Fourbar1

fmpy = pytest.importorskip("fmpy")
from fmpy.validation import validate_fmu  # noqa: E402


class Spring(fl.Model):
    """``x'' = −k x``, ``x(0) = 1``: ``x = cos(√k t)``."""

    k = Parameter(4.0, unit="N/(m.kg)", doc="Stiffness per mass")
    x = Variable(unit="m", start=1.0, fixed=True)
    v = Variable(unit="m/s", start=0.0, fixed=True)

    def equations(self):
        return [eq(der(self.x), self.v), eq(der(self.v), -self.k * self.x)]


@pytest.fixture(scope="module")
def units(tmp_path_factory):
    """Each model's simulation and its exported unit (h = 1 ms)."""
    out = {}
    folder = tmp_path_factory.mktemp("fmu")
    for name, model, outputs in (("spring", Spring(), None), ("fourbar", Fourbar1(), ["j1.phi", "j1.w"]),
                                 ("clutches", CoupledClutches(), ["J1.w", "J2.w", "J3.w", "J4.w"])):
        sim = fl.Simulation(model)
        out[name] = (sim, export_fmu(sim, folder / f"{name}.fmu", h=1e-3, outputs=outputs))
    return out


@pytest.mark.parametrize("name", ["spring", "fourbar", "clutches"])
def test_the_unit_passes_fmpys_validation(units, name):
    _, path = units[name]
    assert validate_fmu(str(path)) == []
    with zipfile.ZipFile(path) as z:
        files = set(z.namelist())
    ident = {"spring": "Spring", "fourbar": "Fourbar1", "clutches": "CoupledClutches"}[name]
    assert {"modelDescription.xml", f"binaries/linux64/{ident}.so"} <= files
    assert "sources/fmu_cs.c" in files and "sources/model.c" in files


@pytest.mark.parametrize("name, t_end, signals", [
    ("spring", 2.0, ["x", "v"]),
    ("fourbar", 1.0, ["j1.phi", "j1.w"]),
    ("clutches", 1.5, ["J1.w", "J2.w", "J3.w", "J4.w"]),
])
def test_fmpy_simulates_the_unit_as_flexlib_runs_the_model(units, name, t_end, signals):
    """fmpy stepping the unit on a 10 ms communication grid gives flexlib's fixed-step run, events included."""
    sim, path = units[name]
    got = fmpy.simulate_fmu(str(path), stop_time=t_end, output_interval=0.01)
    ref = sim.run(t_end, dt_out=0.01, progress=False, solver=fl.FixedStep(h=1e-3))
    for s in signals:
        expected = ref.value(s, got["time"])
        assert np.max(np.abs(got[s] - expected)) <= 1e-9 * np.ptp(ref[s]), s
    if name == "spring":
        assert np.max(np.abs(got["x"] - np.cos(2.0 * got["time"]))) < 1e-5
    if name == "clutches":
        assert ref.stats["state_events"] == 11 and ref.stats["time_events"] == 2


def test_a_parameter_set_before_initialisation_is_the_run_with_that_parameter(units):
    """k = 9 set by the master: the unit finds its start again (IDACalcIC) and runs x = cos 3t, as flexlib does."""
    sim, path = units["spring"]
    got = fmpy.simulate_fmu(str(path), stop_time=1.0, output_interval=0.01, start_values={"k": 9.0})
    ref = sim.run(1.0, dt_out=0.01, progress=False, params={"k": 9.0}, solver=fl.FixedStep(h=1e-3))
    assert np.max(np.abs(got["x"] - ref.value("x", got["time"]))) < 1e-9
    assert np.max(np.abs(got["x"] - np.cos(3.0 * got["time"]))) < 2e-5


def test_model_description_lists_parameters_outputs_and_units(units):
    _, path = units["spring"]
    md = fmpy.read_model_description(str(path))
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["k"].causality == "parameter" and by_name["k"].variability == "fixed"
    assert float(by_name["k"].start) == 4.0 and by_name["k"].unit == "N/(m.kg)"
    assert by_name["x"].causality == "output" and by_name["x"].unit == "m"  # the states, by default
    assert md.coSimulation is not None and md.modelExchange is None
    assert md.defaultExperiment.stepSize == "0.001"


def test_bad_requests_are_refused_by_name(tmp_path):
    sim = fl.Simulation(Spring())
    with pytest.raises(fl.RunArgumentError, match="output 'y' is not a variable of Spring"):
        export_fmu(sim, tmp_path / "a.fmu", outputs=["y"])
    with pytest.raises(fl.RunArgumentError, match="positive number of seconds"):
        export_fmu(sim, tmp_path / "b.fmu", h=0.0)
    from tests.test_engine_events import BouncingBall

    with pytest.raises(fl.ModelError, match=r"BouncingBall: reinit\(\) .* is not supported in an FMU"):
        export_fmu(fl.Simulation(BouncingBall()), tmp_path / "c.fmu")
    assert not any(tmp_path.iterdir())  # nothing half-written


class Pushed(fl.Model):
    """A 2 kg mass pushed by the top-level input force ``u``; its position is the top-level output ``y``."""

    u = fl.Input(unit="N", start=0.5, doc="Force")
    y = fl.Output(unit="m", doc="Position")
    x = Variable(unit="m", start=0.0, fixed=True)
    v = Variable(unit="m/s", start=0.0, fixed=True)

    def equations(self):
        return [eq(der(self.x), self.v), eq(2.0 * der(self.v), self.u), eq(self.y, self.x)]


def test_top_level_inputs_and_outputs_are_the_units_inputs_and_outputs(tmp_path):
    """The input force set by the master between steps: u = 0.5 N until 1 s, then 2 N (a step on the communication
    grid): y = u t²/4 piecewise, in closed form (BDF2 is exact for a quadratic, so to round-off after its Euler
    start: 1e-6 m); in a flexlib run the input is a parameter (its start value, or ``params``)."""
    sim = fl.Simulation(Pushed())
    assert sim.run(1.0, dt_out=0.5, progress=False, params={"u": 2.0})["y"][-1] == pytest.approx(0.5, rel=1e-6)
    path = export_fmu(sim, tmp_path / "pushed.fmu", h=1e-3)
    md = fmpy.read_model_description(str(path))
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["u"].causality == "input" and float(by_name["u"].start) == 0.5 and by_name["u"].unit == "N"
    assert by_name["y"].causality == "output" and "x" not in by_name  # the top-level outputs, not the states
    assert validate_fmu(str(path)) == []
    signal = np.array([(0.0, 0.5), (1.0, 0.5), (1.0, 2.0), (2.0, 2.0)], dtype=[("time", float), ("u", float)])
    got = fmpy.simulate_fmu(str(path), stop_time=2.0, output_interval=0.01, input=signal)
    t = got["time"]
    exact = np.where(t <= 1.0, 0.5 * t**2 / 4, 0.5 / 4 + 0.5 / 2 * (t - 1) + 2.0 * (t - 1) ** 2 / 4)
    assert np.max(np.abs(got["y"] - exact)) < 1e-6


def test_the_cli_passes_the_units_stepper_options(tmp_path, monkeypatch):
    """``flexlib export-fmu MODEL --step H --max-halvings N``: the unit's fixed step and its halvings as given (the
    export itself is tested above; here the command's options reach it)."""
    from click.testing import CliRunner

    import flexlib.fmi
    from flexlib.cli import cli

    seen = {}

    def fake_export(sim, out, **kwargs):
        seen.update(kwargs)
        (tmp_path / "x.fmu").write_bytes(b"")
        return tmp_path / "x.fmu"

    monkeypatch.setattr(flexlib.fmi, "export_fmu", fake_export)
    res = CliRunner().invoke(cli, ["export-fmu", "fourbar", "--out", str(tmp_path / "x.fmu"), "--step", "0.002",
                                   "--max-halvings", "0"], catch_exceptions=False)
    assert res.exit_code == 0, res.output
    assert seen["h"] == 0.002 and seen["max_halvings"] == 0
    seen.clear()
    res = CliRunner().invoke(cli, ["export-fmu", "fourbar", "--out", str(tmp_path / "x.fmu")], catch_exceptions=False)
    assert res.exit_code == 0 and seen["h"] == 1e-3 and "max_halvings" not in seen  # the export's default (2)
