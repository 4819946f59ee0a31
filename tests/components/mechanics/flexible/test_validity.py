"""Validity monitors of modal bodies (issue 30, item 6; ``components/mechanics/flexible/validity.py``): a run
warns, naming the body, the node and the time, when the elastic deformation leaves the small-deformation range
(deflection past 10 % of the characteristic length, Adams' linear limit; rotation past 0.2 rad) or when the left-out
modes carry more than 20 % of the recovered displacement; every run has the summary in ``result.stats["validity"]``.

References: the seed-001 beam's own run (tip rotation 0.087 rad, deflection 2 % of its length: inside the range;
the geometrically exact reference agrees to 1.6 %), the same beam under six times the torque (the deformation
scales linearly: 0.5 rad); a cantilever whose one kept mode bends it across the load (Euler–Bernoulli: that mode
takes none of the load, the static residual all of it).
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib import ModalValidityWarning, ModelError
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.fe import beam_mesh, modal_data_from_fe, rectangle
from flexlib.models.pinned_free_beam import TORQUE, PinnedFreeBeam, beam_modal_data, bending_modes
from tests.components.mechanics.flexible.benches import TipLoaded

QUIET = {"progress": False}


@pytest.fixture(scope="module")
def beam():
    """The seed-001 beam with its two lowest bending modes, built once."""
    data = beam_modal_data(16)
    model = PinnedFreeBeam(data, bending_modes(data)[:2], True, frames=[0, 16])
    return model, fl.Simulation(model)


def test_the_seed_beam_stays_in_range_and_says_so(beam):
    """The seed's run: no warning (the suite turns warnings into errors), the summary with the peaks in range."""
    _model, sim = beam
    res = sim.run(2.0, dt_out=0.01, **QUIET)
    v = res.stats["validity"]["beam"]
    assert v["ok"] and v["limits"] == {"deflection": 0.1, "rotation": 0.2, "residual": 0.2}
    assert 0.05 < v["rotation"] < 0.12 and 0.01 < v["deflection"] < 0.04 and v["residual"] < 0.05
    assert v["characteristic_length"] == pytest.approx(1.5)
    assert v["rotation_node"] == 16 and 0.0 <= v["rotation_t"] <= 2.0


def test_a_beam_pushed_past_the_limits_warns_with_body_node_and_time(beam, tmp_path):
    """Ten times the seed's torque (per run, no rebuild): the tip rotation passes 0.2 rad (0.63) and the deflection
    10 % of the length (15 %: centrifugal stiffening keeps it from growing linearly); both warn, naming the body,
    the node and the time; the summary says not ok; the summary is kept in the result file."""
    _model, sim = beam
    push = {"profile.offset": 10 * TORQUE, "profile.height": -20 * TORQUE}
    with pytest.warns(ModalValidityWarning) as caught:
        res = sim.run(2.0, dt_out=0.01, params=push, **QUIET)
    texts = [str(w.message) for w in caught]
    assert any(t.startswith("beam: elastic rotation") and "node 16" in t and "limit 0.2 rad" in t for t in texts)
    assert any(t.startswith("beam: elastic displacement") and "characteristic length 1.5 m" in t for t in texts)
    v = res.stats["validity"]["beam"]
    assert not v["ok"] and v["rotation"] > 0.4 and v["deflection"] > 0.1
    res.save(tmp_path / "pushed.h5")
    assert fl.load_result(tmp_path / "pushed.h5").stats["validity"]["beam"] == v


def test_a_mode_that_cannot_carry_the_load_warns():
    """A cantilever (20 × 40 mm, 1 m) keeping only its lowest mode, which bends it along z, under a 500 N tip load
    along −y: the kept mode takes none of it, the left-out modes' static response all (share ≈ 100 %): the warning
    names the body and asks for more modes; a limit raised by the user keeps it silent. Keeping the y-bending mode
    instead is silent (share ~3 %)."""
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 16, rectangle(0.02, 0.04), E=2.1e11, rho=7850.0)
    data = modal_data_from_fe(fe, [16], 8, reference_node=0)
    lowest = int(np.argmin(data.frequencies))
    shape = np.abs(data.translational_modes[lowest])
    assert shape[:, 2].max() > 10 * shape[:, 1].max()  # it bends the beam along z
    model = TipLoaded(data, 500.0, modes=[lowest], frames=[0, 16])
    with pytest.warns(ModalValidityWarning, match=r"^beam: the left-out modes' static response carries 100 % .*keep"):
        res = fl.Simulation(model).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
    assert res.stats["validity"]["beam"]["residual"] == pytest.approx(1.0, abs=1e-3)
    tolerant = TipLoaded(data, 500.0, modes=[lowest], frames=[0, 16], validity={"residual": 1.5})
    assert fl.Simulation(tolerant).run(0.01, dt_out=0.005, steady_state=True, **QUIET).stats["validity"]["beam"]["ok"]
    y_bending = int(np.argmax(np.abs(data.translational_modes[:, 16, 1]) / np.sqrt(data.frequencies)))
    good = TipLoaded(data, 500.0, modes=[y_bending], frames=[0, 16])
    res = fl.Simulation(good).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
    assert res.stats["validity"]["beam"]["ok"] and res.stats["validity"]["beam"]["residual"] < 0.1


@pytest.mark.parametrize("bad, message", [
    ("tight", "validity must be None"),
    ({"strain": 0.1}, "unknown limit 'strain'"),
    ({"rotation": -1.0}, r"validity\['rotation'\] must be a positive number"),
    ({"deflection": True}, r"validity\['deflection'\] must be a positive number"),
])
def test_bad_limits_are_named(bad, message):
    data = beam_modal_data(8)
    with pytest.raises(ModelError, match=message):
        FlexibleBody(data, modes=1, validity=bad)


def test_monitors_off_and_a_rigid_body_have_no_summary():
    """``validity=False`` and a body without modes: no monitors, no summary."""
    data = beam_modal_data(8)
    for kwargs in ({"modes": 1, "validity": False}, {"modes": 0}):
        model = TipLoaded(data, 1.0, frames=[0, 8], **kwargs)
        res = fl.Simulation(model).run(0.01, dt_out=0.005, steady_state=True, **QUIET)
        assert "validity" not in res.stats
