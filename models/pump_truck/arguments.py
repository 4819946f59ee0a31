"""Checks of :class:`~models.pump_truck.model.PumpTruck`'s arguments: the model options (declared once, in
:data:`OPTIONS`, for the registry and the class), the start pose, time tables and flexible-section modes.

The checks serve any machine on a :class:`~models.pump_truck.parameters.PumpTruckParameters` record of N = 4 … 6
sections (``flexlib.models.boom32``): the joints are the record's (:func:`joint_names`), the messages name the
machine (``model``, default ``"PumpTruck"``); for the 42 m record they are the 42 m machine's."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from functools import partial
from typing import Any

import numpy as np

from flexlib.errors import ParameterError
from flexlib.registry import ModelOption

from .geometry import LINK_PLATE
from .parameters import PumpTruckParameters

__all__ = ["JOINTS", "OPTIONS", "check_commands", "check_modes", "check_modes_form", "check_pose", "check_sources",
           "check_table", "check_targets", "joint_names", "model_options", "option"]

#: Joint names of the 42 m machine: the slewing joint and the five boom joints (:func:`joint_names` of any record).
JOINTS = ("slew", "joint1", "joint2", "joint3", "joint4", "joint5")


def joint_names(record: PumpTruckParameters) -> tuple[str, ...]:
    """The joint names of a machine on ``record``: ``"slew"``, then ``"joint1"`` … ``"joint<N>"``."""
    return ("slew", *(f"joint{n}" for n in range(1, record.n_sections + 1)))


def check_modes_form(modes: Any, n_sections: int = 5) -> str | int | dict[int, list[int]]:
    """The form of ``modes`` (``"mpf"``, a count >= 1, or a list of mode indices for every section 1–N), normalised;
    ``ValueError`` completing "modes ..." otherwise (the check of the ``modes`` option's declaration).

    A mapping gives every section 1–N (``n_sections``, default the 42 m boom's 5) once (``1`` and ``"01"`` are the
    same section) a non-empty list of distinct mode indices >= 0; whether an index exists is the modal data's check
    (:class:`FlexibleBody`)."""
    if isinstance(modes, str) and modes == "mpf":
        return modes
    if isinstance(modes, int | np.integer) and not isinstance(modes, bool | np.bool_):
        if modes < 1:
            raise ValueError(f"must be at least 1 per section, got {modes!r}")
        return int(modes)
    if not isinstance(modes, Mapping):
        raise ValueError(f"must be 'mpf', a count or a mapping of section to mode indices, got {modes!r}")
    out: dict[int, list[int]] = {}
    keys: dict[int, Any] = {}
    for k, v in modes.items():
        try:
            if isinstance(v, str | bytes | Mapping) or isinstance(k, bool) \
                    or any(isinstance(i, bool | float) for i in v):
                raise TypeError
            section, indices = int(k), [int(i) for i in v]
        except (TypeError, ValueError):
            raise ValueError(f"must map section numbers 1-{n_sections} to lists of mode indices, got "
                             f"{modes!r}") from None
        if section in out:
            raise ValueError(f"must give section {section} once, got it twice (keys {keys[section]!r} and {k!r})")
        if not indices:
            raise ValueError(f"must give section {section} at least one mode index, got an empty list")
        if min(indices) < 0 or len(set(indices)) != len(indices):
            raise ValueError(f"of section {section} must be distinct mode indices >= 0, got {list(v)!r}")
        out[section], keys[section] = indices, k
    every = list(range(1, n_sections + 1))
    if sorted(out) != every:
        missing = sorted(set(every) - set(out))
        extra = sorted(set(out) - set(every))
        raise ValueError(f"must give every section 1-{n_sections} (missing {missing}, unknown {extra})")
    return out


def model_options(n_sections: int = 5) -> tuple[ModelOption, ...]:
    """The model options of a machine of ``n_sections`` sections: type, default, accepted values, doc
    (:data:`OPTIONS`: the 42 m ``PumpTruck``'s, and the registered ``pump-truck``'s)."""
    return (
        ModelOption("filled", bool, None, "delivery pipe filled with concrete (default: the record's pipe.filled)",
                    allow_none=True),
        ModelOption("flexible", bool, False, "each section a FlexibleBody (beam mesh, Craig-Bampton reduction)"),
        ModelOption("modes", None, "mpf", "modes of the flexible sections",
                    check=check_modes_form if n_sections == 5 else partial(check_modes_form, n_sections=n_sections),
                    accepts=f"'mpf', a count >= 1 or a mapping of every section 1-{n_sections} to its mode indices"),
        ModelOption("slewing", bool, True, "the slewing bearing and its drive (false: the turret fixed to the ground)"),
        ModelOption("link_plate", float, LINK_PLATE, "cross-section of levers and links at joint scale 3", low=0.0,
                    low_open=True, unit="m2", accepts="a positive area [m2] (a finite number > 0)"),
    )


#: The model options of ``PumpTruck`` (and of the registered ``pump-truck``): type, default, accepted values, doc.
OPTIONS = model_options(5)
_OPTIONS = {o.name: o for o in OPTIONS}


def option(name: str, value: Any, model: str = "PumpTruck", options: Sequence[ModelOption] = OPTIONS) -> Any:
    """``model``'s keyword ``name`` checked by its declaration in ``options`` (default :data:`OPTIONS`;
    ``ParameterError`` naming the machine, the keyword, the value and what is accepted)."""
    declared = _OPTIONS if options is OPTIONS else {o.name: o for o in options}
    return declared[name].validate(value, f"{model}: ", error=ParameterError)


def check_modes(modes: Any, record: PumpTruckParameters, model: str = "PumpTruck",
                select: Callable[[PumpTruckParameters], dict[int, list[int]]] | None = None
                ) -> int | dict[int, list[int]]:
    """``PumpTruck(modes=...)`` of a flexible boom: ``"mpf"`` (the machine's modal participation factor selection
    ``select(record)``, default :func:`~models.pump_truck.flexible.mpf_modes` on the rigid ``PumpTruck``), a count
    >= 1, or a list of mode indices for every section 1–N of ``record``."""
    modes = option("modes", modes, model, OPTIONS if record.n_sections == 5 else model_options(record.n_sections))
    if modes == "mpf":
        if select is None:
            from .flexible import mpf_modes as select
        return select(record)
    return modes


def check_pose(pose: Any, record: PumpTruckParameters, model: str = "PumpTruck") -> np.ndarray:
    """The start pose [deg] (slew, q1 … qN: N + 1 angles, N the record's sections) as angles [rad], each boom
    joint inside its range."""
    N = record.n_sections
    if isinstance(pose, str | bytes | Mapping) or not hasattr(pose, "__len__"):
        raise ParameterError(f"{model}: pose must be a sequence of {N + 1} angles [deg] (slew, q1 ... q{N}), got "
                             f"{type(pose).__name__} {pose!r}")
    try:
        q0 = np.radians(np.asarray(pose, dtype=float))
    except (TypeError, ValueError):
        q0 = np.full(1, np.nan)
    if q0.shape != (N + 1,) or not np.all(np.isfinite(q0)) or any(isinstance(v, bool | np.bool_) for v in pose):
        raise ParameterError(f"{model}: pose needs {N + 1} finite angles [deg] (slew, q1 ... q{N}), got {pose!r}")
    for k in range(N):
        drive = record.drive(k + 1)
        if not drive.q_min - 1e-9 <= q0[k + 1] <= drive.q_max + 1e-9:
            raise ParameterError(
                f"{model}: pose joint{k + 1} = {math.degrees(q0[k + 1]):.2f} deg is outside its range "
                f"{math.degrees(drive.q_min):.1f} ... {math.degrees(drive.q_max):.1f} deg")
    return q0


def check_sources(ref_cols: Mapping[str, Any], cmd_cols: Mapping[str, Any], model: str = "PumpTruck",
                  joints: Sequence[str] = JOINTS) -> None:
    """A joint is either controlled (a column in ``targets``) or open loop (a column in ``commands``), not both
    (``joints``: the machine's joint names in order, default :data:`JOINTS`)."""
    both = [name for name in joints if name in ref_cols and name in cmd_cols]
    if both:
        raise ParameterError(f"{model}: {', '.join(both)} {'is' if len(both) == 1 else 'are'} given in both "
                             "targets and commands; give either a target (closed loop) or a command (open loop) "
                             "per joint")


def check_commands(cmd_cols: Mapping[str, np.ndarray], model: str = "PumpTruck") -> None:
    """Valve commands stay within −1 … 1."""
    for name, col in cmd_cols.items():
        if np.any(np.abs(col) > 1.0):
            raise ParameterError(f"{model}: commands[{name!r}] must stay within -1 ... 1 (valve command)")


def check_targets(ref_cols: Mapping[str, np.ndarray], record: PumpTruckParameters, model: str = "PumpTruck") -> None:
    """Each boom joint's waypoints [deg] inside its range."""
    joints = joint_names(record)
    for name, col in ref_cols.items():
        k = joints.index(name)
        if k > 0:
            drive = record.drive(k)
            lo, hi = math.degrees(drive.q_min), math.degrees(drive.q_max)
            if np.any(col < lo - 1e-9) or np.any(col > hi + 1e-9):
                raise ParameterError(f"{model}: targets[{name!r}] leaves the joint's range {lo:.1f} ... "
                                     f"{hi:.1f} deg")


def check_table(owner: str, spec: Any, n_values: int | None = None, model: str = "PumpTruck",
                joints: Sequence[str] = JOINTS) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Check a time table ``{"t": [...], "<joint>": [...], ...}`` (``joints``: the machine's joint names, default
    :data:`JOINTS`) and return ``t`` and the columns."""
    if not isinstance(spec, Mapping) or "t" not in spec:
        raise ParameterError(f"{model}: {owner} must be a mapping with a time column 't' and one column per joint")
    t = _numbers(spec["t"])
    if t.ndim != 1 or t.size < 1 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise ParameterError(f"{model}: {owner}['t'] must be finite, strictly increasing times [s], got "
                             f"{spec['t']!r}")
    cols = {}
    for name, col in spec.items():
        if name == "t":
            continue
        if name not in joints:
            import difflib

            close = difflib.get_close_matches(str(name), joints, n=1, cutoff=0.6)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ParameterError(f"{model}: {owner} has unknown joint {name!r}{hint}; joints are "
                                 f"{', '.join(joints)}")
        y = _numbers(col)
        if y.shape != t.shape or not np.all(np.isfinite(y)):
            raise ParameterError(f"{model}: {owner}[{name!r}] needs {t.size} finite values (one per time point)")
        cols[name] = y
    return t, cols


def _numbers(values: Any) -> np.ndarray:
    """``values`` as a float array; NaN (refused by the caller) for text, mappings, bools or anything else that is
    not a sequence of numbers."""
    if isinstance(values, str | bytes | Mapping) or isinstance(values, bool | np.bool_):
        return np.full(1, np.nan)
    try:
        seq = list(values) if not isinstance(values, np.ndarray) else values
        if any(isinstance(v, str | bytes | bool | np.bool_) for v in np.ravel(np.asarray(seq, dtype=object))):
            return np.full(1, np.nan)
        return np.asarray(seq, dtype=float)
    except (TypeError, ValueError):
        return np.full(1, np.nan)
