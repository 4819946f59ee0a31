"""Scenarios of the pump-truck boom as data, and its registration as ``pump-truck``.

A scenario is a :class:`flexlib.registry.Scenario` (a frozen dataclass): ``data`` holds the start ``pose`` [deg],
the joint ``targets`` (a time table in degrees, see :class:`~models.pump_truck.model.PumpTruck`) and open-loop
valve ``commands``; ``options`` the pipe state (``filled``) and the variant (``flexible``); ``run`` the solver
settings. ``flexlib run pump-truck --scenario expand-fold`` runs one; a user writes their own as JSON (see
``docs/cli.md``) or in Python with :func:`expand_targets`.

Timing of the unfolding: as an operator does, several joints move at once: each joint's move starts when the one
before it is half done (``OVERLAP``), at ``W_REF`` (1.4°/s) in a jerk-limited profile (the model smooths each
stretch of the table's constant speed, :class:`~models.pump_truck.model.PumpTruck`). Joint 4 passes its load
reversal (the gravity moment changes sign, the holding chamber changes side) in ``expand``, ``fold`` and
``expand-fold`` while joint 5 moves too (seed 000, Fig. 14).
"""

from __future__ import annotations

import numpy as np

from flexlib.errors import ParameterError
from flexlib.registry import Scenario, register_model

from .arguments import OPTIONS
from .model import EXTENDED_POSE_DEG, JOINTS, TRANSPORT_POSE_DEG, WORKING_POSE_DEG, PumpTruck
from .plots import figures

__all__ = ["OVERLAP", "SCENARIOS", "W_REF", "expand_targets", "reverse_after", "summary_signals"]

W_REF = 0.025  # joint speed of the reference moves [rad/s]
OVERLAP = 0.5  # each joint starts when the one before it is half done
# BDF order 2 (A-stable): the sections' elastic modes (and the oil springs) are lightly damped and fast; at
# orders 3-5 IDA rang them at the tolerance level (a spurious 106 Hz oscillation of section 2 at rtol 1e-5, gone at
# rtol 1e-7 or order 2) and needed up to 20 times more steps. The rigid boom is as fast at order 2.
RUN = {"rtol": 1e-5, "atol": 1e-7, "dt_out": 0.05, "max_order": 2}


def expand_targets(start: tuple[float, ...], end: tuple[float, ...], t0: float = 1.0, w: float = W_REF,
                   order: tuple[int, ...] = (1, 2, 3, 4, 5), overlap: float = 0.0) -> dict[str, list]:
    """Time table [s, deg] moving joints from ``start`` to ``end`` (6 angles: slew, q1 … q5) in ``order``.

    Joint ``order[i]`` ramps linearly at ``w`` [rad/s] (at least 10 s), starting when ``order[i-1]`` has covered
    ``1 − overlap`` of its move (the first at ``t0``; ``overlap = 0``: one after another, ``0.5``: each starts
    halfway through the one before); a joint not in ``order`` keeps ``start``.
    """
    if not 0.0 <= overlap < 1.0:
        raise ParameterError(f"expand_targets: overlap must be in [0, 1), got {overlap!r}")
    spans, t = {}, t0
    for j in order:
        T = max(abs(np.radians(end[j] - start[j])) / w, 10.0)
        spans[j] = (t, t + T)
        t += (1.0 - overlap) * T
    knots = sorted({0.0, *(a for a, _ in spans.values()), *(b for _, b in spans.values())})
    t_last = max(b for _, b in spans.values())
    knots = [k for k in knots if k <= t_last]
    table: dict[str, list] = {"t": knots}
    for j, name in enumerate(JOINTS):
        if j in spans:
            table[name] = [float(np.interp(tk, spans[j], [start[j], end[j]])) for tk in knots]
    return table


def _end(table: dict[str, list]) -> float:
    return float(table["t"][-1])


def reverse_after(table: dict[str, list], shift: float) -> dict[str, list]:
    """``table`` followed, ``shift`` seconds later, by the same moves backwards in reverse joint order."""
    t = np.asarray(table["t"])
    T = t[-1]
    back_t = T + shift + (T - t[::-1])
    out = {"t": [*t.tolist(), *back_t.tolist()]}
    for name, col in table.items():
        if name != "t":
            out[name] = [*col, *col[::-1]]
    return out


_EXPAND = expand_targets(TRANSPORT_POSE_DEG, WORKING_POSE_DEG, overlap=OVERLAP)
_FOLD = expand_targets(WORKING_POSE_DEG, TRANSPORT_POSE_DEG, order=(5, 4, 3, 2, 1), overlap=OVERLAP)
_EXPAND_FOLD = reverse_after(_EXPAND, 2.0)
_ZERO = {"t": [0.0], **{name: [0.0] for name in JOINTS}}
# emergency stop: joints 1 and 2 lowered on open-loop commands, all valves closed abruptly at 4 s
_ESTOP = {"t": [0.0, 0.5, 1.0, 4.0, 4.02], "slew": [0.0] * 5, "joint1": [0.0, 0.0, -0.5, -0.5, 0.0],
          "joint2": [0.0, 0.0, 0.5, 0.5, 0.0], "joint3": [0.0] * 5, "joint4": [0.0] * 5, "joint5": [0.0] * 5}
_SLEW = expand_targets(WORKING_POSE_DEG, (90.0, *WORKING_POSE_DEG[1:]), w=0.06, order=(0,))

SCENARIOS = (
    Scenario("expand", "transport fold -> working pose, each joint starting when the one before is half done",
             t_end=_end(_EXPAND) + 5.0, options={"filled": False},
             data={"pose": list(TRANSPORT_POSE_DEG), "targets": _EXPAND}, run=RUN),
    Scenario("fold", "working pose -> transport fold (the reverse order, overlapping)", t_end=_end(_FOLD) + 5.0,
             options={"filled": False}, data={"pose": list(WORKING_POSE_DEG), "targets": _FOLD}, run=RUN),
    Scenario("expand-fold", "a full cycle: expand, 2 s pause, fold back (a reversal)",
             t_end=_end(_EXPAND_FOLD) + 5.0, options={"filled": False},
             data={"pose": list(TRANSPORT_POSE_DEG), "targets": _EXPAND_FOLD}, run=RUN),
    Scenario("hold", "fully extended, horizontal, pipe filled, valves closed for 30 s (hold drift)", t_end=30.0,
             options={"filled": True}, data={"pose": list(EXTENDED_POSE_DEG), "commands": _ZERO},
             run={"rtol": 1e-6, "atol": 1e-8, "dt_out": 0.05}),
    Scenario("emergency-stop", "working pose, filled: joints 1 and 2 moving on open-loop commands, all valves "
             "closed abruptly at 4 s", t_end=8.0, options={"filled": True},
             data={"pose": list(WORKING_POSE_DEG), "commands": _ESTOP},
             run={"rtol": 1e-6, "atol": 1e-8, "dt_out": 0.005}),
    Scenario("slew", "turret slewed 90 deg in the working pose, pipe filled", t_end=_end(_SLEW) + 5.0,
             options={"filled": True}, data={"pose": list(WORKING_POSE_DEG), "targets": _SLEW}, run=RUN),
)


def summary_signals(model: PumpTruck) -> list[str]:
    """Peak pressures and flows per cylinder, hinge-force components per joint (on section n, in its frame),
    joint angles, the slew angle and, flexible, each section's tip deflection (for ``flexlib run``'s table)."""
    sig = [f"axis{n}.cylinder.cylinder.{v}" for n in range(1, 6) for v in ("p_A", "p_B", "q_A", "q_B")]
    sig += [f"joint{n}.frame_b.f[{i}]" for n in range(1, 6) for i in (0, 1)]
    sig += [f"joint{n}.phi" for n in range(1, 6)]
    if model.flexible:  # each section's tip deflection from its root pin's tangent
        sig += [f"section{n}.deflection.r_rel[1]" for n in range(1, 6)]
    if model.slewing:
        sig.append("turret.slew.phi")
    return sig


#: The keys of ``Scenario.data`` the factory reads (arguments of :class:`PumpTruck`).
DATA_KEYS = ("pose", "targets", "commands")


def _factory(scenario: Scenario) -> PumpTruck:
    unknown = sorted(set(scenario.data) - set(DATA_KEYS))
    if unknown:
        raise ParameterError(f"pump-truck scenario {scenario.name!r}: unknown data {', '.join(unknown)}; "
                             f"known: {', '.join(DATA_KEYS)}")
    return PumpTruck(**scenario.options, **scenario.data)


register_model(
    "pump-truck", _factory,
    doc="42 m five-section boom, lever-and-link joints, counterbalance valves, PID joint control (issue 11)",
    scenarios=list(SCENARIOS), summary_signals=summary_signals,
    options=OPTIONS, data=DATA_KEYS, plots=figures,
)
