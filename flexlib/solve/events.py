"""Events, written once for every integrator: relations, the next time event, event iteration, the relation watch.

Events follow Modelica semantics. Relation values are frozen between events (they are the entries of the parameter
vector ``p`` after the ``n_params`` parameters); at a state event (a zero crossing of a relation's indicator) or a
time event (a relation of time and parameters, ``a·t + b``) the relation's value is switched, the algebraic
variables and derivatives are re-initialised with the states held, the remaining relations are re-evaluated until
nothing changes (:func:`event_iteration`), and the integrator is restarted. The run loop
(:mod:`flexlib.solve.loop`) calls these functions; the backends only locate crossings.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib.compile.codegen import CompiledModel
from flexlib.errors import InitializationError, SolverError

__all__ = ["apply_reinit", "check_assertions", "event_iteration", "indeterminate_split", "next_time_event", "off_zero",
           "relation_value", "settled", "state_relations", "time_triggers", "watch", "watched_relations"]


def next_time_event(model: CompiledModel, p: np.ndarray, t: float, t_end: float) -> tuple[float, list[int]]:
    """Earliest time event after ``t`` [s] (at most ``t_end``) and the relations switching there."""
    timed = [k for k, r in enumerate(model.relations) if r.time_event]
    if not timed:
        return t_end, []
    ab = np.asarray(model.function("tev")(p)).reshape(-1, 2)
    best, which = t_end, []
    tol = 1e-13 * max(1.0, abs(t))
    for k in timed:
        a, b = ab[k]
        if a == 0.0:
            continue
        te = -b / a
        if te > t + tol and te <= t_end:
            if te < best - tol:
                best, which = te, [k]
            elif abs(te - best) <= tol:
                which.append(k)
    return best, which


def time_triggers(model: CompiledModel, p: np.ndarray, which: list[int]) -> list[tuple[int, bool]]:
    """The new values of the time-event relations ``which`` once their time has come (``a·t + b`` with ``a > 0``
    becomes true, with ``a < 0`` false)."""
    ab = np.asarray(model.function("tev")(p)).reshape(-1, 2)
    return [(k, bool(ab[k, 0] > 0)) for k in which]


def watched_relations(model: CompiledModel) -> np.ndarray:
    """Indices of the relations that are not time events (the state relations an integrator watches)."""
    return np.array([k for k, r in enumerate(model.relations) if not r.time_event], dtype=int)


def state_relations(model: CompiledModel) -> np.ndarray:
    """Indices of the relations IDA's root finding watches: not time events, and not constant during a run.

    A relation of parameters only (a cylinder's ``x_start >= 0`` asserted for run-time overrides) cannot
    change after the start, where it is evaluated; given to IDA as a root function it is identically zero
    when it holds with equality (``x_start = 0``), and SUNDIALS prints "some root functions identically 0"
    (IDARcheck1) on every run.
    """
    cand = [k for k, r in enumerate(model.relations) if not r.time_event]
    if not cand:
        return np.zeros(0, dtype=int)
    ind = model.sx_function("ind")
    t, y, yp = ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n)
    pp = ca.SX.sym("p", model.n_params + model.n_relations)
    z = ind(t, y, yp, pp)
    txy = ca.vertcat(t, y, yp)
    return np.array([k for k in cand if ca.depends_on(z[k], txy)], dtype=int)


def watch(model: CompiledModel, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray, relations: np.ndarray,
          skip: set[int]) -> list[tuple[int, bool]]:
    """The relations among ``relations`` (not in ``skip``) whose value at ``(t, y, yp)`` differs from the frozen one.

    IDA ignores a root function that is zero at a restart until it leaves zero, so a relation that re-crosses at
    once (sliding) is caught by checking its sign in the first steps after a restart.
    """
    n_par = model.n_params
    z = np.asarray(model.function("ind")(t, y, yp, p)).ravel()
    values = [(int(k), relation_value(model.relations[k], z[k], p[n_par + k])) for k in relations if k not in skip]
    return [(k, bool(v)) for k, v in values if v != p[n_par + k]]


def settled(model: CompiledModel, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray,
            triggered: list[tuple[int, bool]]) -> set[int]:
    """The relations switched at an IDA root whose indicator at the restart point ``(t, y, yp)`` moves towards the
    side of their new value (``dz/dt = ∂z/∂t + ∂z/∂y·y'`` has the sign of that side).

    A root located by IDA lies within its interpolation error (order ``rtol``) of the true crossing: after the
    event iteration the indicator can still be on the old side by that much, and in the first steps after the
    restart its sign follows the Newton corrector's noise. (A limiter at rtol 1e-9: the input was 4e-11 short of
    its limit at the restart, IDA's first step was 1e-15 s, and a re-check by sign switched the relation back,
    after which IDA could not take a step.) Such a relation is still heading across, and IDA's root finding
    watches it from the restart (a root function that is exactly zero there becomes active once it leaves zero).
    A relation whose indicator turns back at once (a contact that bounces, sliding) is left to :func:`watch`.
    """
    n_par = model.n_params
    dz = model._functions.get("ida_native_dzdt")
    if dz is None:
        ind = model.sx_function("ind")
        ts, ys, yps = ca.SX.sym("t"), ca.SX.sym("y", model.n), ca.SX.sym("yp", model.n)
        ps = ca.SX.sym("p", n_par + model.n_relations)
        z = ind(ts, ys, yps, ps)
        rate = ca.jtimes(z, ca.vertcat(ts, ys), ca.vertcat(1.0, yps))
        dz = ca.Function("flexlib_dzdt", [ts, ys, yps, ps], [rate])
        model._functions["ida_native_dzdt"] = dz  # type: ignore[assignment]
    with np.errstate(all="ignore"):
        rate = np.asarray(dz(t, y, yp, p)).ravel()
    out = set()
    for k, _ in triggered:
        rel = model.relations[k]
        if np.isfinite(rate[k]) and rate[k] != 0.0 and float(rel.value(rate[k])) == p[n_par + k]:
            out.add(k)
    return out


#: An indicator smaller than this in magnitude (not exactly zero) leaves its relation's value as it is
#: (:func:`relation_value`, :func:`off_zero`): the sign noise a Newton update leaves on an unknown that is zero by
#: construction (a brake's normal force 100·(1 − 1) came out ±1e-27 … 1e-50 N, each sign change an event that engaged
#: the released brake with a 1e-48 N m breakaway torque and made the friction modes cycle). No SI quantity a model
#: compares is meaningful below it.
INDICATOR_NOISE = 1e-20


def event_iteration(model: CompiledModel, init: Any, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray,
                    triggered: list[tuple[int, bool]], max_iter: int = 20,
                    ties: set[int] | frozenset[int] = frozenset()) -> tuple[np.ndarray, np.ndarray]:
    """Switch the triggered relations, re-initialise (``init.reinit``), re-evaluate the others until consistent.

    Each pass re-evaluates every relation at the point of the pass before and switches all that changed (Modelica's
    event iteration, ``pre()`` the values of the pass before). Coupled switches can cycle there: two stuck friction
    elements on one shaft (MSL's ``LossyGearDemo2``) each see the other hold the shaft and break away in turn, never
    together. When a set of relation values comes round again, the iteration switches one relation at a time instead,
    the first whose switch leads to a set not tried yet and whose re-initialisation has a solution, until the values
    agree with the point (or every way out is tried).

    Parameters
    ----------
    model : CompiledModel
        The model.
    init : Initializer
        Re-initialisation with the states held.
    p : ndarray
        Parameters followed by relation values (updated in place).
    t : float
        Event time [s].
    y, yp : ndarray
        The point before the event.
    triggered : list of (int, bool)
        Relations and their new values.
    max_iter : int
        Passes before the iteration switches one relation at a time.
    ties : set of int
        Relations that keep their value while their indicator is exactly zero (put on their limit by
        :func:`indeterminate_split`).

    Returns
    -------
    y, yp : ndarray
        The consistent point after the event.

    Raises
    ------
    SolverError
        The iteration does not converge, or an assertion (:func:`check_assertions`) fails.
    """
    n_par = model.n_params
    before = p[n_par:].copy()
    fixed = {k for k, _ in triggered}
    for k, v in triggered:
        p[n_par + k] = float(v)
    ind = model.function("ind")
    free = [k for k, rel in enumerate(model.relations) if k not in fixed and not rel.time_event]
    seen: set[bytes] = set()
    one_at_a_time = False
    reinitialised: set[int] = set()
    at_trigger = p.copy()  # the discrete values the triggered relations were switched with
    for _ in range(max_iter + 2 * len(free)):
        seen.add(p[n_par:].tobytes())
        y1, yp1 = init.reinit(t, y, yp, p)
        z = np.asarray(ind(t, y1, yp1, p)).ravel()
        if fixed and not np.array_equal(p, at_trigger):
            free += _reading_switched(ind, t, y1, yp1, z, at_trigger, fixed)
        values = [(k, relation_value(model.relations[k], z[k], p[n_par + k], k in ties)) for k in free]
        changed = [(k, v) for k, v in values if v != p[n_par + k]]
        if not changed:
            fired = [k for k, rel in enumerate(model.relations) if rel.reinit and k not in reinitialised
                     and before[k] == 0.0 and p[n_par + k] == 1.0]
            if fired:  # reinit(): the states set, then the iteration goes on from them (each edge once), every
                # relation re-evaluated there (the triggered ones too: the state they crossed on has moved)
                y = apply_reinit(model, p, t, y1, yp1, fired)
                yp = yp1
                reinitialised.update(fired)
                free = [k for k, rel in enumerate(model.relations) if not rel.time_event]
                continue
            check_assertions(model, p, t)
            return y1, yp1
        trial = p.copy()
        for k, v in changed:
            trial[n_par + k] = v
        if not one_at_a_time and trial[n_par:].tobytes() not in seen:
            p[:] = trial
        else:
            one_at_a_time = True
            if not _switch_one(init, p, t, y1, yp1, changed, seen):
                break
        y, yp = y1, yp1
    raise SolverError(f"event iteration did not converge at t = {t:.10g} s")


def _reading_switched(ind: Any, t: float, y: np.ndarray, yp: np.ndarray, z: np.ndarray, at_trigger: np.ndarray,
                      fixed: set[int]) -> list[int]:
    """The triggered relations (``fixed``, removed from it) whose indicator ``z`` at ``(t, y, yp)`` differs from the
    one with the discrete values they were switched with (``at_trigger``): they read discrete values that have
    switched since (a friction element's start flag, released once it slides) and are evaluated again."""
    z0 = np.asarray(ind(t, y, yp, at_trigger)).ravel()
    reads = [k for k in sorted(fixed) if z[k] != z0[k]]
    fixed.difference_update(reads)
    return reads


def indeterminate_split(model: CompiledModel, init: Any, p: np.ndarray, t: float, y: np.ndarray,
                        yp: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """A consistent point at ``t`` [s] whose event problem is regular, reached by switching one relation, when the
    point ``(y, yp)`` leaves some unknowns undetermined (``p`` updated in place); None if it is regular or no single
    switch makes it so.

    Two friction elements stuck on one shaft (MSL's ``LossyGearDemo2``: "if both friction models are stuck, there is
    no unique solution") each hold it with a torque of its own whose split nothing in the model decides: the event
    problem with the states held is singular and the integrator cannot take a step. Modelica leaves the choice to the
    tool. Here one element takes the limit of its stuck phase (its relation to start sliding switched, the speed still
    zero: its torque is then its breakaway torque) and the other holds the rest. Each relation of the components the
    singularity names (their dependent equations, their undetermined unknowns) is tried, held while the event
    iteration settles the others; of those whose point is regular, the one that switches the fewest
    relations is taken, the last declared of equals — on ``LossyGearDemo2`` the bearing friction's start forward, as
    in Dymola's reference result.
    """
    from flexlib.solve.diagnose import rank_deficiency

    J, nominal = init.held_jacobian(t, y, yp, p)
    rows, cols = rank_deficiency(J, nominal)
    if not rows and not cols:
        return None
    # the candidates: relations of the components whose equations or unknowns the deficiency names
    alg, diff = np.flatnonzero(~model.differential), np.flatnonzero(model.differential)
    held = np.concatenate([alg, diff])
    owners = {model.row_labels[i].split(":")[0] for i in rows} | {model.y_owners[int(held[j])] for j in cols}
    n_par = model.n_params
    best: tuple[int, np.ndarray, np.ndarray, np.ndarray] | None = None
    for k in reversed(range(model.n_relations)):
        rel = model.relations[k]
        if rel.time_event or rel.initial or rel.assertion:
            continue
        if not any(o == rel.owner or o.startswith(rel.owner + ".") for o in owners):
            continue
        trial = p.copy()
        try:
            y1, yp1 = event_iteration(model, init, trial, t, y, yp, [(k, trial[n_par + k] == 0.0)])
        except (InitializationError, SolverError):
            continue
        J, _ = init.held_jacobian(t, y1, yp1, trial)
        switched = int(np.count_nonzero(trial[n_par:] != p[n_par:]))
        if (best is None or switched < best[0]) and not any(rank_deficiency(J, nominal)):
            best = (switched, trial, y1, yp1)
    if best is not None:
        p[:] = best[1]
        return best[2], best[3]
    return None


def apply_reinit(model: CompiledModel, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray,
                 fired: list[int]) -> np.ndarray:
    """``y`` with the states of the relations ``fired`` set by their :func:`flexlib.reinit` actions (each value a
    number or a variable's value at ``(t, y, yp)``)."""
    y = y.copy()
    values: dict[str, float] | None = None
    for k in fired:
        for target, value in model.relations[k].reinit:
            if isinstance(value, str):
                if values is None:
                    out = np.asarray(model.function("out")(t, y, yp, p)).ravel()
                    values = {v.name: float(x) for v, x in zip(model.variables, out, strict=True)}
                value = values[value]
            y[model.y_names.index(target)] = float(value)
    return y


def _switch_one(init: Any, p: np.ndarray, t: float, y: np.ndarray, yp: np.ndarray,
                changed: list[tuple[int, float]], seen: set[bytes]) -> bool:
    """Switch the first of ``changed`` that leads to relation values not in ``seen`` and whose re-initialisation has
    a solution (``p`` updated in place); False if none does."""
    n_par = init.model.n_params
    for k, v in changed:
        trial = p.copy()
        trial[n_par + k] = v
        if trial[n_par:].tobytes() in seen:
            continue
        try:
            init.reinit(t, y, yp, trial)
        except (InitializationError, SolverError):
            seen.add(trial[n_par:].tobytes())  # no solution with these values: not a way out
            continue
        p[:] = trial
        return True
    return False


def check_assertions(model: CompiledModel, p: np.ndarray, t: float) -> None:
    """Raise :class:`SolverError` if a relation declared with :func:`flexlib.assert_` is false."""
    n_par = model.n_params
    failed = [r for k, r in enumerate(model.relations) if r.assertion and p[n_par + k] != 1.0]
    if failed:
        lines = "\n".join(f"  {r.text}: {r.assertion}" for r in failed)
        raise SolverError(f"assertion failed at t = {t:.10g} s:\n{lines}")


def off_zero(z: ca.SX, strict: bool, current: ca.SX) -> ca.SX:
    """The indicator ``z`` for IDA's root finding, with an exact zero replaced by ±1e-300: the side of the
    relation's value at zero (``z > 0`` is false there, ``z >= 0`` true); an indicator within
    :data:`INDICATOR_NOISE` of zero is held on the side of the relation's ``current`` value (its discrete symbol).

    IDA only needs a sign change where the relation's value changes. An exact zero gives it nothing more, but
    one that stays zero over the first step (a body at rest on its contact, x = 0) makes SUNDIALS print "some
    root functions identically 0" (IDARcheck1; ``IDASetNoInactiveRootWarn`` is not exposed by
    scikit-sundae), and one that reaches exactly zero and stays there (a contact at rest on its boundary, its
    positions moving below round-off: MSL's ``Translational.Examples.PreLoad``) is a root IDA reports and then
    "found at and very near t" (IDA_ILL_INPUT). With the sign of the value at zero, an indicator reaching zero
    from the other side is still a sign change (the relation switches there), one leaving zero to the same side is
    none — exactly the relation's events. An indicator that is zero by construction but computed by IDA's Newton
    iteration (a brake's normal force ``100·(1 − ramp)`` once the ramp has ended) carries sign noise of 1e-27 to
    1e-50, each sign change a root: held on its side, only a real crossing, out of the noise, is one. Part of the
    compiled event function: no cost per call in Python.
    """
    out = ca.if_else(z == 0, -1e-300 if strict else 1e-300, z)
    return ca.if_else(ca.logic_and(ca.fabs(z) < INDICATOR_NOISE, z != 0), ca.if_else(current, 1e-300, -1e-300), out)


def relation_value(rel: Any, z: float, current: float, tie: bool = False) -> float:
    """The value of relation ``rel`` at indicator ``z``: as its strictness says at an exact zero (``current`` for a
    ``tie``), ``current`` (its value so far) within :data:`INDICATOR_NOISE` of zero, the indicator's sign
    otherwise."""
    if (z != 0.0 or tie) and abs(z) < INDICATOR_NOISE:
        return current
    return float(rel.value(z))
