"""Scenarios of the 32 m boom as data, and its registration as ``boom-32``.

Scenarios are :class:`flexlib.registry.Scenario` records as the 42 m machine's (:mod:`models.pump_truck.scenarios`,
whose timing they share: :func:`~models.pump_truck.scenarios.expand_targets` at ``W_REF``, each joint starting when
the one before it is half done, and the solver settings ``RUN``):

* ``hold``: fully extended, horizontal, pipe filled, every valve closed for 30 s (the hold drift);
* ``expand``: transport fold → working pose, pipe empty, joints 1–4 moving together;
* ``expand-fold``: the expand, 2 s at rest, and the same moves backwards in the reverse joint order;
* ``slew``: the turret slewed 90° in the working pose, pipe filled.

``flexlib run boom-32 --scenario expand-fold``; the goldens of ``hold`` and ``expand-fold`` are
``tests/models/goldens/boom32-*.h5`` (:mod:`.goldens`).
"""

from __future__ import annotations

from flexlib.models.pump_truck.plots import figures
from flexlib.models.pump_truck.scenarios import OVERLAP, RUN, expand_targets, reverse_after
from flexlib.registry import Scenario, register_model

from .model import EXTENDED_POSE_DEG, JOINTS, OPTIONS, TRANSPORT_POSE_DEG, WORKING_POSE_DEG, Boom32

__all__ = ["DATA_KEYS", "SCENARIOS", "summary_signals"]

_ORDER = (1, 2, 3, 4)
_EXPAND = expand_targets(TRANSPORT_POSE_DEG, WORKING_POSE_DEG, order=_ORDER, overlap=OVERLAP)
_EXPAND_FOLD = reverse_after(_EXPAND, 2.0)
_CLOSED = {"t": [0.0], **{name: [0.0] for name in JOINTS}}
_SLEW = expand_targets(WORKING_POSE_DEG, (90.0, *WORKING_POSE_DEG[1:]), w=0.06, order=(0,))

SCENARIOS = (
    Scenario("hold", "fully extended, horizontal, pipe filled, valves closed for 30 s (hold drift)", t_end=30.0,
             options={"filled": True}, data={"pose": list(EXTENDED_POSE_DEG), "commands": _CLOSED},
             run={"rtol": 1e-6, "atol": 1e-8, "dt_out": 0.05}),
    Scenario("expand", "transport fold -> working pose, each joint starting when the one before is half done",
             t_end=_EXPAND["t"][-1] + 5.0, options={"filled": False},
             data={"pose": list(TRANSPORT_POSE_DEG), "targets": _EXPAND}, run=RUN),
    Scenario("expand-fold", "a full cycle: expand, 2 s pause, fold back (the reverse order)",
             t_end=_EXPAND_FOLD["t"][-1] + 5.0, options={"filled": False},
             data={"pose": list(TRANSPORT_POSE_DEG), "targets": _EXPAND_FOLD}, run=RUN),
    Scenario("slew", "turret slewed 90 deg in the working pose, pipe filled", t_end=_SLEW["t"][-1] + 5.0,
             options={"filled": True}, data={"pose": list(WORKING_POSE_DEG), "targets": _SLEW}, run=RUN),
)

#: The keys of ``Scenario.data`` the factory reads (arguments of :class:`Boom32`).
DATA_KEYS = ("pose", "targets", "commands")


def summary_signals(model: Boom32) -> list[str]:
    """Per joint ``n``: its cylinder's pressures and port flows, the hinge force on section ``n`` (its frame) and
    the joint angle; the slew angle if the turret slews (``flexlib run``'s table of peaks)."""
    out = []
    for n in range(1, model.record.n_sections + 1):
        out += [f"axis{n}.cylinder.cylinder.{v}" for v in ("p_A", "p_B", "q_A", "q_B")]
        out += [f"joint{n}.frame_b.f[0]", f"joint{n}.frame_b.f[1]", f"joint{n}.phi"]
    return out + (["turret.slew.phi"] if model.slewing else [])


register_model(
    "boom-32", lambda scenario: Boom32(**scenario.options, **scenario.data),
    doc="32 m four-section Z-fold boom composed from the boom parts (issue 28's second machine)",
    scenarios=list(SCENARIOS), summary_signals=summary_signals, options=OPTIONS, data=DATA_KEYS, plots=figures,
)
