"""Event re-initialisation with the model's own ``res``/``jac`` (``init.reinit.StatesHeld``), used for models
above the C threshold of unknowns instead of a symbolic Jacobian built per run (issue 9: 0.4 s at the boom proxy's
one time event).

References: the symbolic Jacobian of the held problem (``ca.jacobian``, exact), and the closed-form bouncing
contact of ``tests/test_engine_events.py``.
"""


import casadi as ca
import numpy as np
import scipy.sparse as sps

import flexlib as fl
from flexlib.models.reference.events import BouncingContact
from flexlib.solve.init import reinit
from flexlib.solve.init.initializer import Initializer
from flexlib.solve.init.reinit import StatesHeld


def _symbolic_held(init: Initializer) -> tuple[ca.Function, ca.Function]:
    """The held problem and its exact Jacobian, built symbolically (the path small models keep)."""
    m = init.model
    alg = np.flatnonzero(~m.differential)
    t_s, _, ypd, yp_s, p_s = init.problem.symbols()
    ystate, ya = ca.SX.sym("ystate", len(init.diff)), ca.SX.sym("ya", len(alg))
    yfull = ca.SX.zeros(m.n)
    for k, i in enumerate(init.diff):
        yfull[i] = ystate[k]
    for k, i in enumerate(alg):
        yfull[i] = ya[k]
    F = m.sx_function("res")(t_s, yfull, yp_s, p_s)
    w, par = ca.vertcat(ya, ypd), ca.vertcat(t_s, p_s, ystate)
    return ca.Function("g", [w, par], [F]), ca.Function("jg", [w, par], [ca.jacobian(F, w)])


def test_held_problem_matches_the_symbolic_jacobian():
    """Residual equal (same operations) and Jacobian equal to 1e-12 relative to its largest entry, at a perturbed
    point of the contact phase (stiff spring: ∂F/∂y of the held state 1e5 beside ∂F/∂y' = 1, the cancellation
    case)."""
    sim = fl.Simulation(BouncingContact(init={"h": -0.01, "v": -1.0}), use_cache=False)
    m = sim.compiled
    init = Initializer(m)
    alg = np.flatnonzero(~m.differential)
    held = StatesHeld(m, alg, init.diff)
    g, jg = _symbolic_held(init)
    rng = np.random.default_rng(3)
    p = np.concatenate([sim.parameter_vector(), np.ones(m.n_relations)])  # contact branch active
    for _ in range(3):
        w = rng.standard_normal(len(alg) + len(init.diff))
        par = np.concatenate([[0.1], p, rng.standard_normal(len(init.diff)) * 0.01])
        np.testing.assert_array_equal(held(w, par), np.asarray(g(w, par)).ravel())
        J, J_ref = held.jacobian(w, par), sps.csc_matrix(jg(w, par).sparse())
        assert J.shape == J_ref.shape
        # the state columns come from (jac(c) - jac(0))/c, where jac(0) holds the spring's ∂F/∂h = k = 1e5
        t, y, yp, pp = held._point(w, par)
        dF_dy = np.asarray(m.function("jac")(t, y, yp, pp, 0.0).full())
        assert abs(dF_dy[:, init.diff]).max() >= 1e5
        np.testing.assert_allclose(J.toarray(), J_ref.toarray(), rtol=0, atol=1e-12 * abs(J_ref).max())


def test_events_with_the_held_problem_match_the_symbolic_path(monkeypatch):
    """The bouncing contact run with the large-model path forced reproduces the symbolic path's event
    times to 1e-12 s and the trajectory to 1e-9 m (both solve the re-initialisation to 1e-10), and the first
    contact agrees with free fall, t = sqrt(2 h0 / g), to 1e-8 s."""
    runs = []
    for forced in (False, True):
        sim = fl.Simulation(BouncingContact(init={"h": 1.0, "v": 0.0}), use_cache=False)
        if forced:
            monkeypatch.setattr(reinit, "AUTO_C_MIN_UNKNOWNS", 0)
        runs.append(sim.run(1.0, dt_out=0.01, rtol=1e-10, atol=1e-12))
        assert isinstance(sim.initializer._reinit_fns[0], StatesHeld) == forced
    sym, held = runs
    assert held.stats["state_events"] == sym.stats["state_events"] >= 2
    np.testing.assert_allclose([t for t, _ in held.events], [t for t, _ in sym.events], rtol=0, atol=1e-12)
    np.testing.assert_allclose(held["h"], sym["h"], rtol=0, atol=1e-9)
    assert abs(held.events[0][0] - np.sqrt(2 / 9.81)) <= 1e-8
