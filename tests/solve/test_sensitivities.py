"""Forward sensitivities (``Simulation.sensitivities``) against central finite differences of tight runs (issue 33):
a smooth oscillator, state events whose times move with the parameters (a damper that engages below a threshold, a
block that breaks away), a time event at a parameter's time, the consistent start of a steady initialisation, and
bad arguments."""

from __future__ import annotations

import os

import numpy as np
import pytest

import flexlib as fl
from flexlib import Parameter, Variable, der, eq, if_else
from flexlib.components.mechanics.translational import Damper, Fixed, Mass, Spring

TIGHT = {"rtol": 1e-11, "atol": 1e-13}


class Oscillator(fl.Model):
    """A 1 kg mass on a 40 N/m spring and a 0.5 N s/m damper, released from 0.1 m."""

    def __init__(self) -> None:
        super().__init__()
        self.mass = Mass(m=1.0, init={"s": 0.1, "v": 0.0})
        self.spring = Spring(c=40.0)
        self.damper = Damper(d=0.5)
        self.fixed = Fixed()
        self.connect(self.fixed.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.mass.flange_a)


class Engaging(fl.Model):
    """``x'' = −c x`` from x = 1 m at rest; below ``x_on`` a damper ``d`` engages (a state event whose time moves with
    ``c`` and ``x_on``), and from ``t_push`` a force ``f`` pushes (a time event at a parameter's time)."""

    c = Parameter(4.0, unit="N/m", doc="Spring rate (1 kg mass)")
    d = Parameter(1.5, unit="N.s/m", doc="Damper engaged below x_on")
    x_on = Parameter(0.3, unit="m", doc="Position below which the damper acts")
    t_push = Parameter(1.9, unit="s", doc="Start of the push")
    f = Parameter(0.7, unit="N", doc="Push")
    x = Variable(unit="m", start=1.0, fixed=True)
    v = Variable(unit="m/s", start=0.0, fixed=True)

    def equations(self) -> list:
        damping = if_else(self.x < self.x_on, -self.d * self.v, 0.0)
        push = if_else(fl.time >= self.t_push, self.f, 0.0)
        return [eq(der(self.x), self.v), eq(der(self.v), -self.c * self.x + damping + push)]


def central(sim: fl.Simulation, name: str, outputs: list[str], t_end: float, grid: np.ndarray, rel: float = 1e-4,
            **run) -> np.ndarray:
    """Central differences of the outputs by the parameter ``name`` over tight runs at the times ``grid`` (the
    value after an event there), ``(times, outputs)``."""
    v = float(sim.compiled.param_defaults[sim.compiled.param_names.index(name)])
    h = rel * abs(v)
    ends = [sim.run(t_end, params={name: v + s * h}, progress=False, **TIGHT, **run) for s in (1.0, -1.0)]
    return np.stack([(ends[0].value(o, grid, side="right") - ends[1].value(o, grid, side="right")) / (2 * h)
                     for o in outputs], axis=1)


def at(sens, grid: np.ndarray) -> np.ndarray:
    """The sensitivities at the times ``grid`` (the row after an event there), ``(times, outputs, params)``."""
    return sens.d[np.searchsorted(sens.t, grid + 1e-9, side="right") - 1]  # (output times to round-off)


def test_oscillator_sensitivities_match_central_differences():
    """∂s/∂c, ∂s/∂d, ∂s/∂m and ∂v/∂· of a damped oscillator over 2 s: within 1e-6 of their range (issue: 1e-5 on
    smooth cases) of central differences of runs at rtol 1e-11."""
    sim = fl.Simulation(Oscillator())
    params = ["spring.c", "damper.d", "mass.m"]
    sens = sim.sensitivities(2.0, params, ["mass.s", "mass.v"], dt_out=0.05, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(sens.value("mass.s"), sens.result["mass.s"], rtol=0, atol=1e-14)
    grid = np.linspace(0.0, 2.0, 41)
    for k, name in enumerate(params):
        fd = central(sim, name, ["mass.s", "mass.v"], 2.0, grid, dt_out=0.05)
        err = np.max(np.abs(at(sens, grid)[:, :, k] - fd), axis=0) / np.ptp(fd, axis=0)
        assert np.all(err < 1e-6), (name, err)


def test_event_times_moving_with_the_parameters_make_the_sensitivities_jump():
    """The damper's engagement (a state event) and the push (a time event at ``t_push``) move with the parameters:
    the sensitivities of x and v after them match central differences within 1e-6 of range, and leaving out the
    jump at the events would not (the ∂x/∂x_on and ∂x/∂t_push after the events are the jump alone)."""
    sim = fl.Simulation(Engaging())
    params = ["c", "d", "x_on", "t_push", "f"]
    sens = sim.sensitivities(3.0, params, ["x", "v"], dt_out=0.05, rtol=1e-10, atol=1e-12)
    events = [t for t, _ in sens.result.events]
    assert sens.stats["events"] == 3 and abs(events[1] - 1.9) < 1e-12, sens.result.events
    grid = np.linspace(0.0, 3.0, 61)
    grid = grid[np.min(np.abs(grid[:, None] - np.array(events)[None, :]), axis=1) > 0.01]  # not at an event
    for k, name in enumerate(params):
        fd = central(sim, name, ["x", "v"], 3.0, grid, dt_out=0.05)
        err = np.max(np.abs(at(sens, grid)[:, :, k] - fd), axis=0) / np.ptp(fd, axis=0)
        assert np.all(err < 1e-6), (name, err)
    after = grid > events[1]
    assert np.max(np.abs(at(sens, grid)[after, 0, params.index("t_push")])) > 0.01


def test_bad_arguments_are_named():
    """Unknown parameters and outputs are refused with close matches; so are unknown run arguments."""
    sim = fl.Simulation(Oscillator())
    with pytest.raises(fl.RunArgumentError, match=r"spring\.c"):
        sim.sensitivities(1.0, ["spring.k"], ["mass.s"])
    with pytest.raises(fl.RunArgumentError, match=r"mass\.s"):
        sim.sensitivities(1.0, ["spring.c"], ["mass.x"])
    with pytest.raises(fl.RunArgumentError, match="twice"):
        sim.sensitivities(1.0, ["spring.c", "spring.c"], ["mass.s"])
    with pytest.raises(fl.RunArgumentError, match="unknown run arguments"):
        sim.sensitivities(1.0, ["spring.c"], ["mass.s"], dt=0.1)
    sens = sim.sensitivities(0.5, ["spring.c"], ["mass.s"], dt_out=0.1)
    with pytest.raises(KeyError, match="no parameter"):
        sens["mass.s", "damper.d"]


def test_peak_and_final_sensitivities_match_central_differences_of_the_reductions():
    """The derivatives of reductions (the final position, the peak |v|) by the spring rate and the mass, against
    central differences of the same reductions over tight runs on the same output grid (1e-5 relative)."""
    sim = fl.Simulation(Oscillator())
    params = ["spring.c", "mass.m"]
    sens = sim.sensitivities(1.5, params, ["mass.s", "mass.v"], dt_out=0.001, rtol=1e-10, atol=1e-12)
    final, peak = sens.final("mass.s"), sens.peak("mass.v")
    for name in params:
        v = float(sim.compiled.param_defaults[sim.compiled.param_names.index(name)])
        h = 1e-4 * v
        r = [sim.run(1.5, dt_out=0.001, params={name: v + s * h}, progress=False, **TIGHT) for s in (1.0, -1.0)]
        fd_final = (r[0]["mass.s"][-1] - r[1]["mass.s"][-1]) / (2 * h)
        fd_peak = (np.max(np.abs(r[0]["mass.v"])) - np.max(np.abs(r[1]["mass.v"]))) / (2 * h)
        assert abs(final[name] - fd_final) < 1e-5 * abs(fd_final), (name, final[name], fd_final)
        assert abs(peak[name] - fd_peak) < 1e-5 * abs(fd_peak), (name, peak[name], fd_peak)


def test_breakaway_of_a_stuck_block_moves_with_the_breakaway_force():
    """A block stuck on a support (10 N sliding, ``peak``·10 N breakaway) pushed by 10 N/s breaks away at
    ``t_b = peak`` s (a latch's event: the start-forward flag), then ``v = 5 (t² − t_b²) − 10 (t − t_b)``: the
    sensitivities of position and speed by ``peak`` match the closed form ``∂v/∂peak = −10 t_b + 10`` and central
    differences (1e-6 of their largest)."""
    from flexlib.components.control import Ramp
    from flexlib.components.mechanics.translational import Force, SupportFriction

    class Block(fl.Model):
        def __init__(self) -> None:
            super().__init__()
            self.source = Ramp(height=30.0, duration=3.0)
            self.push = Force()
            self.block = Mass(m=1.0, init={"s": 0.0, "v": 0.0})
            self.friction = SupportFriction(f_pos=[[0.0, 10.0]], peak=1.5)
            self.connect(self.source.y, self.push.f)
            self.connect(self.push.flange, self.block.flange_a)
            self.connect(self.block.flange_b, self.friction.flange_a)

    sim = fl.Simulation(Block())
    sens = sim.sensitivities(3.0, ["friction.peak"], ["block.s", "block.v"], dt_out=0.05, rtol=1e-10, atol=1e-12)
    grid = np.linspace(1.6, 3.0, 29)
    got = at(sens, grid)[:, :, 0]
    np.testing.assert_allclose(got[:, 1], -10 * 1.5 + 10, rtol=1e-6)
    fd = central(sim, "friction.peak", ["block.s", "block.v"], 3.0, grid, dt_out=0.05)
    err = np.max(np.abs(got - fd), axis=0) / np.max(np.abs(fd), axis=0)
    assert np.all(err < 1e-6), err


def test_the_studies_page_sensitivity_example_runs_as_written(tmp_path, monkeypatch):
    """``docs/studies.md``'s sensitivity example runs on its own (a reader pasting it)."""
    from tests.doc_blocks import python_blocks

    blocks = [b for b in python_blocks("docs/studies.md") if ".sensitivities(" in b]
    assert len(blocks) == 1
    monkeypatch.chdir(tmp_path)
    exec(compile(blocks[0], "docs/studies.md", "exec"), {})


def test_the_compiled_sensitivity_dae_gives_the_same_sensitivities(monkeypatch, tmp_path):
    """Above ``SMALL`` unknowns the DAE and its forward derivative are generated C (gcc, cached on disk with their
    SHA-256): forced here for the event model, the sensitivities equal the virtual machine's to 1e-9 of range, and
    a library whose bytes no longer match its recorded hash is compiled again, not loaded."""
    import shutil

    import flexlib.solve.sensitivities as sens_mod

    if shutil.which("gcc") is None and shutil.which("cc") is None:
        pytest.skip("no C compiler")
    params = ["c", "x_on", "t_push"]
    vm = fl.Simulation(Engaging()).sensitivities(3.0, params, ["x", "v"], dt_out=0.05, rtol=1e-10, atol=1e-12)
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(sens_mod, "SMALL", 0)
    c = fl.Simulation(Engaging()).sensitivities(3.0, params, ["x", "v"], dt_out=0.05, rtol=1e-10, atol=1e-12)
    libs = list((tmp_path / "sensitivity").glob("sens_*.so"))
    assert len(libs) == 1
    np.testing.assert_allclose(c.d, vm.d, rtol=0, atol=1e-9 * np.ptp(vm.d))
    tampered = tmp_path / "tampered.so"  # a new file put in its place (the loaded one stays mapped)
    tampered.write_bytes(libs[0].read_bytes() + b"\0")
    os.replace(tampered, libs[0])  # its hash no longer matches the recorded one
    again = fl.Simulation(Engaging()).sensitivities(3.0, params, ["x", "v"], dt_out=0.05, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(again.d, vm.d, rtol=0, atol=1e-9 * np.ptp(vm.d))
    import json

    from flexlib.compile.integrity import sha256_file

    (manifest,) = (tmp_path / "sensitivity").glob("sens_*.json")
    assert sha256_file(libs[0]) == json.loads(manifest.read_text())["sha256"]  # compiled again


def test_what_is_not_differentiated_is_refused_by_name():
    """A ``fl.reinit`` event (a bouncing ball's impact sets its speed) is refused, naming the relation and its time;
    before the first impact the sensitivities exist."""
    from tests.test_engine_events import BouncingBall

    sim = fl.Simulation(BouncingBall())
    with pytest.raises(fl.SolverError, match=r"reinit\(\).*t = 0\.45"):
        sim.sensitivities(1.0, ["e"], ["h"], dt_out=0.01)
    sens = sim.sensitivities(0.4, ["e"], ["h"], dt_out=0.01)
    assert np.all(sens["h", "e"] == 0.0)  # the restitution acts only at the impact
