"""Test helpers on the independent free-body statics of a pump-truck boom
(:mod:`models.pump_truck.free_body`, free-body equilibrium, not virtual work and nothing of the engine's multibody
formulation): a composed boom's static start checked against it, and static starts on one build.

Issue 28's check "independent hand statics, including cylinder housing and rod masses: cylinder forces and hinge
forces within 1 %".
"""

from __future__ import annotations

import numpy as np

from flexlib.models.pump_truck.free_body import free_body_statics as hand_statics
from flexlib.models.pump_truck.free_body import total_weight

__all__ = ["check_static_start", "hand_statics", "static_starts", "total_weight"]


def check_static_start(model, result, q_deg, p_tank: float, rel: float = 1e-2, label: str = "") -> None:
    """Assert that a composed boom's static start (``result``'s first row; ``model.cylinders`` its bores and rods,
    ``model.record`` its record) holds joint angles ``q_deg`` [deg] with this module's forces, within ``rel``: each
    cylinder force ``(p_A − p_T) A_p − (p_B − p_T) A_r`` (``axis{n}.cylinder.cylinder``, no seal friction at rest)
    against ``F_cyl``; each hinge force on section ``n`` (``−joint{n}.frame_b.f``, section ``n``'s frame) in
    magnitude against ``F_hinge_abs`` and in each component against ``F_hinge_section`` (within ``rel`` of the
    magnitude)."""
    hand = hand_statics(model.record, np.radians(q_deg))
    for n, cyl in enumerate(model.cylinders, start=1):
        A_p = np.pi / 4 * cyl["bore"] ** 2
        A_r = A_p - np.pi / 4 * cyl["rod"] ** 2
        c = f"axis{n}.cylinder.cylinder"
        F = (result[f"{c}.p_A"][0] - p_tank) * A_p - (result[f"{c}.p_B"][0] - p_tank) * A_r
        assert abs(F - hand["F_cyl"][n - 1]) <= rel * abs(hand["F_cyl"][n - 1]), (label, f"cylinder {n}", F, hand)
        f = -np.array([result[f"joint{n}.frame_b.f[{i}]"][0] for i in range(2)])
        scale = hand["F_hinge_abs"][n - 1]
        assert abs(np.linalg.norm(f) - scale) <= rel * scale, (label, f"joint {n} |F|", f, scale)
        assert np.allclose(f, hand["F_hinge_section"][n - 1], rtol=0.0, atol=rel * scale), (label, f"joint {n}", f)


def static_starts(make, poses: dict) -> tuple[object, dict]:
    """The static start (``Simulation.initialize``, no integration) of ``make(q)`` for every pose ``q`` of
    ``poses`` (name to joint angles [deg]) on one build (the pose is a start value): the last model and the
    one-row results by name."""
    import flexlib as fl

    sim, out, model = None, {}, None
    for name, q in poses.items():
        model = make(q)
        sim = fl.Simulation(model, codegen=False) if sim is None else sim.with_model(model)
        out[name] = sim.initialize()
    return model, out
