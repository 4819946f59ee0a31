"""The Modelica Association's reference results of MSL examples (``tests/data/msl``) and the comparison the MSL
example tests make: each signal's largest deviation over its range at the reference's output times."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import flexlib as fl

DATA = Path(__file__).resolve().parents[1] / "data" / "msl"


def reference(name: str) -> dict[str, np.ndarray]:
    """The reference's signals at its distinct output times (an event's second row, the value after it)."""
    with np.load(DATA / f"{name}.npz") as f:
        ref = {k: f[k] for k in f.files}
    t = ref["time"]
    last = np.r_[t[1:] != t[:-1], True]
    return {k: v[last] for k, v in ref.items()}


def worst_deviation(res: fl.Result, ref: dict[str, np.ndarray]) -> dict[str, float]:
    """Per comparison signal: the largest deviation from the reference over the reference's range."""
    t = ref["time"]
    out = {}
    for name, values in ref.items():
        if name == "time":
            continue
        mine = res.value(name, t, side="right")
        out[name] = float(np.max(np.abs(mine - values)) / np.ptp(values))
    return out


def switches(t: np.ndarray, x: np.ndarray) -> list[tuple[float, float]]:
    """The instants where a discrete signal changes and its value from then on."""
    k = np.nonzero(np.diff(x))[0] + 1
    return [(float(t[i]), float(x[i])) for i in k]


def reference_switches(name: str, signal: str, until: float = np.inf) -> list[tuple[float, float]]:
    """A discrete comparison signal's switches in the reference (every row kept: a pulse within one event instant,
    MSL's ``startForward``, is in the rows an event writes)."""
    with np.load(DATA / f"{name}.npz") as f:
        return [(t, v) for t, v in switches(f["time"], f[signal]) if t < until]


def without_pulses(sw: list[tuple[float, float]], start: float) -> list[tuple[float, float]]:
    """A discrete signal's switches without the pulses shorter than :data:`SWITCH_TIME` (a value taken and left
    within it, ``start`` the value before the first switch).

    A start flag raised at breakaway falls once the element slides. Whether that is within the event instant (the
    reference writes no pulse) or at the next event, an instant later (it writes one), follows the sign of the
    relative speed's round-off while the element was stuck: MSL's ``Rotational.Examples.Friction`` has a 3e-7 s pulse
    where ``LossyGearDemo2`` has none. Either is MSL's semantics; such pulses are compared as one instant."""
    out: list[tuple[float, float]] = []
    for t, v in sw:
        before = out[-2][1] if len(out) > 1 else start
        if out and t - out[-1][0] < SWITCH_TIME and v == before:
            out.pop()
        else:
            out.append((t, v))
    return out


def switch_mismatch(res: fl.Result, ref_name: str, signal: str, mine: str | None = None,
                    until: float = np.inf) -> float:
    """The largest distance in time between a discrete signal's switches in ``res`` and in the reference [s]; infinite
    if the sequences of values differ (a switch missing, added or to another value; pulses shorter than
    :data:`SWITCH_TIME` are dropped from both, :func:`without_pulses`)."""
    with np.load(DATA / f"{ref_name}.npz") as f:
        start = float(f[signal][0])
    expected = without_pulses(reference_switches(ref_name, signal, until), start)
    values = np.asarray(res[mine or signal])
    got = without_pulses([(t, v) for t, v in switches(res.t, values) if t < until], float(values[0]))
    if [v for _, v in got] != [v for _, v in expected]:
        return float("inf")
    return max((abs(a - b) for (a, _), (b, _) in zip(got, expected, strict=True)), default=0.0)


#: Discrete comparison signals (a friction element's mode and its start flags) are compared by their switches: the
#: same sequence of values, each switch within this time of the reference's [s]. (A sample taken at an event instant
#: compares the sides of one event, 1e-10 s apart in the reference, and means nothing.)
SWITCH_TIME = 1e-5


def is_discrete(signal: str) -> bool:
    return signal.endswith((".mode", ".startForward", ".startBackward"))


def flexlib_name(signal: str) -> str:
    return signal.replace(".startForward", ".start_forward").replace(".startBackward", ".start_backward")


def check_friction_example(res: fl.Result, name: str, until: float = np.inf) -> None:
    """Continuous signals within 1e-3 of their range; the modes and start flags switch as the reference's do (both
    before ``until`` [s] only, if given)."""
    ref = reference(name)
    keep = ref["time"] < until
    continuous = {k: v[keep] for k, v in ref.items() if not is_discrete(k)}
    worst = worst_deviation(res, continuous)
    assert max(worst.values()) < 1e-3, worst
    late = {k: switch_mismatch(res, name, k, flexlib_name(k), until) for k in ref if is_discrete(k)}
    assert max(late.values()) < SWITCH_TIME, late
