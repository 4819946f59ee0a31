"""Pinned-free flexible beam of seed 001: flexlib beside Exudyn's ``ObjectFFRFreducedOrder``.

The beam (density 8000 kg/m³, E = 2e11 Pa, L = 1.5 m, A = 1e-4 m², I = 1e-10 m⁴, no gravity) is pinned to the
world at one end (rotation about z free), at rest along world x, and driven by a torque about z on the pin:
+1.4 N·m for 0 ≤ t ≤ 1 s, −1.4 N·m for 1 < t ≤ 2 s. Each runner simulates 2 s with n dynamic modes and returns the
seed's outputs at its 201 samples (every 10 ms): the tip's world y [m], the tip deflection from the pin tangent
[m] and the mid-span bending moment averaged over ±5 ms [N·m]; the table compares them with the geometrically
exact reference (``tests/data/pinned_free_beam_reference.npz``) by the seed's error, eq. (2):
``100 · mean|z − z*| / max|z*|`` [%].

Exudyn is fed the same FE model and modes as flexlib: the beam mesher's 32 Euler–Bernoulli frame elements
(``beam_mesh``), held in the x-y plane, and the first n eigenmodes with the pin node clamped (the fixed-interface
modes of a Craig–Bampton reduction with the pin as the one interface node; the pin's own constraint modes are the
rigid-body motions, carried by the floating frame). The body frame is the pin tangent frame, so the deflection is
measured from the pin tangent as in the seed. ``ObjectFFRFreducedOrder`` takes translational node coordinates
only (no nodal rotations), so its inertia terms are built from flexlib's mass description: the elements' Gauss
points with their masses and the modes interpolated there (which integrates the consistent mass exactly, checked
below); the modal stiffness is ``Φᵀ K Φ`` of the frame elements. The mid-span moment is the modal coordinates
times the section-force modes of the frame elements (``section_force_modes``).

Exudyn's step size is chosen by convergence: the largest step of a halving sequence whose three series are all
within 1 % (seed metric) of the same model's converged run (a step 4× smaller than the finest tried). Wall time
and process CPU time are for ``exu.SolveDynamic`` alone; the setup (mesh, modes, system assembly) is reported
separately.

Run ``python benchmarks/flexible_beam.py [--quick]`` (``pip install -e .[bench]`` for Exudyn). Flexlib's runner is
added to :data:`FLEXLIB_RUNNER` (``{name: callable(n_modes) -> dict}``); every runner returns the keys of
:data:`SERIES` plus ``t``, ``wall_time``, ``cpu_time``, ``setup_time`` and ``info``.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

os.environ.setdefault("OMP_NUM_THREADS", "1")  # before numpy: one thread, as the other benchmarks
import numpy as np
import scipy.sparse as sp

ROOT = Path(__file__).resolve().parents[1]

from references.pinned_free_beam import (  # noqa: E402  (the reference's constants and metrics)
    AREA,
    AVERAGE_HALF_WIDTH,
    DENSITY,
    LENGTH,
    REFERENCE_FILE,
    SAMPLE_DT,
    SECOND_MOMENT,
    T_END,
    T_SWITCH,
    TORQUE,
    YOUNG,
    seed_error,
    window_average,
)

from flexlib.fe import FEModel, Section, beam_mesh, craig_bampton, section_force_modes  # noqa: E402

#: Output series of every runner (201 samples each), compared with the reference.
SERIES = ("tip_y", "tip_deflection", "moment_mid_avg")
#: Modes of the table rows.
MODES = (1, 2, 4)
#: Runners beside Exudyn: ``{name: callable(n_modes) -> dict}`` (flexlib's FlexibleBody is added by the lead).
FLEXLIB_RUNNER: dict[str, Callable[[int], dict[str, Any]]] = {}
_FLEXLIB_DATA: dict[str, Any] = {}


def run_flexlib(n_modes: int, *, attachment: str = "pinned", geometric_stiffening: bool = True,
                rtol: float = 1e-5, dt_out: float = 1e-3, recovered: bool = False, step: float | None = None
                ) -> dict[str, Any]:
    """flexlib's FlexibleBody (``models/pinned_free_beam.py``) with the ``n_modes`` lowest in-plane bending modes of
    the same 32-element mesh: ``attachment="pinned"`` the hinged beam's modes, ``"clamped"`` the pin-clamped
    modes Exudyn gets. Timed with the compiled (C) model, as after a first run; IDA at ``rtol``, atol 1e-2·rtol,
    output every ``dt_out`` (the ±5 ms moment average is taken over these samples, as Exudyn's sensors every
    step). The errors are the same at rtol 1e-4…1e-7: the modes, not the integrator, limit the accuracy.
    ``recovered``: the deflection and moment by mode-acceleration recovery (same run). ``step``: fixed steps of
    that size instead of IDA (``fl.FixedStep``, BDF2 in C: the real-time integrator, issue 32)."""
    import flexlib as fl
    from flexlib.models.pinned_free_beam import beam_modal_data, simulate

    c0 = time.process_time()
    data = _FLEXLIB_DATA.get(attachment)
    if data is None:
        data = _FLEXLIB_DATA[attachment] = beam_modal_data(attachment=attachment)
    prep = time.process_time() - c0
    solver = "ida" if step is None else fl.FixedStep(h=step)
    run = simulate(n_modes, data=data, geometric_stiffening=geometric_stiffening, rtol=rtol, atol=1e-2 * rtol,
                   dt_fine=dt_out, compiled=True, solver=solver)
    if recovered:  # mode-acceleration recovery of deflection and moment from the same run
        return {"t": run.t, "tip_y": run.tip_y, "tip_deflection": run.tip_deflection_ma,
                "moment_mid_avg": run.moment_mid_avg_ma, "wall_time": run.run_wall, "cpu_time": run.run_time,
                "setup_time": prep + run.build_time, "info": {"solver": f"IDA rtol {rtol:g}, mode acceleration"}}
    return {"t": run.t, "tip_y": run.tip_y, "tip_deflection": run.tip_deflection,
            "moment_mid_avg": run.moment_mid_avg, "wall_time": run.run_wall, "cpu_time": run.run_time,
            "setup_time": prep + run.build_time,
            "info": {"solver": f"IDA rtol {rtol:g}" if step is None else f"fixed step {step:g} s (BDF2)"}}


FLEXLIB_RUNNER["flexlib"] = run_flexlib
FLEXLIB_RUNNER["flexlib fixed 1 ms"] = lambda n: run_flexlib(n, step=1e-3)
FLEXLIB_RUNNER["flexlib MA"] = lambda n: run_flexlib(n, recovered=True)
FLEXLIB_RUNNER["flexlib clamped"] = lambda n: run_flexlib(n, attachment="clamped", geometric_stiffening=False)
#: Step sizes [s] of Exudyn's convergence study, largest first (each divides the 10 ms sampling and the 1 s switch).
STEPS = tuple(1e-2 / 2**k for k in range(9))  # 10 ms … 39 µs
#: Steps chosen by that study on this machine (used by ``--quick``); see docs/decisions/116.
QUICK_STEPS = {1: 1.25e-3, 2: 6.25e-4, 4: 7.8125e-5}


def sample_times() -> np.ndarray:
    """The seed's 201 sampling instants 0, 0.01, …, 2 s."""
    return SAMPLE_DT * np.arange(round(T_END / SAMPLE_DT) + 1)


def beam_modes(n_modes: int, n_elements: int = 32) -> tuple[FEModel, np.ndarray, np.ndarray]:
    """The seed beam's FE model held in the x-y plane and clamped at the pin (node 0), with its first ``n_modes``
    eigenmodes (mass-normalised, the fixed-interface modes of Craig–Bampton with the pin as interface).

    Returns
    -------
    fe : FEModel
        ``n_elements`` frame elements along the body x axis, DOFs ``ux, uy, rz`` of nodes 1..N.
    modes : ndarray (n_dofs, n_modes)
        Mode shapes [m, rad per unit modal coordinate].
    omega : ndarray (n_modes,)
        Natural frequencies [rad/s].
    """
    section = Section(A=AREA, Iy=SECOND_MOMENT, Iz=SECOND_MOMENT, J=2 * SECOND_MOMENT, name="seed-001 solid")
    fe = beam_mesh((0.0, 0.0, 0.0), (LENGTH, 0.0, 0.0), n_elements, section, E=YOUNG, rho=DENSITY)
    fe = fe.constrained(fe.node_ids, ("uz", "rx", "ry")).constrained([0])
    cb = craig_bampton(fe.M, fe.K, [], n_modes)
    return fe, cb.modes, cb.omega


def mid_moment_modes(fe: FEModel, modes: np.ndarray) -> np.ndarray:
    """Bending moment about z at mid-span per unit modal coordinate [N·m]: the mean of the two elements meeting
    at the middle node (their section forces on the positive face; positive when the beam curves towards +y)."""
    sf = section_force_modes(fe, modes)  # (n_modes, E, 2, 6): N, Vy, Vz, T, My, Mz
    k = sf.shape[1] // 2
    return 0.5 * (sf[:, k - 1, 1, 5] + sf[:, k, 0, 5])


def _exudyn() -> Any:
    """The ``exudyn`` module, or None when it is not installed."""
    if importlib.util.find_spec("exudyn") is None:
        return None
    import exudyn

    return exudyn


def run_exudyn(n_modes: int, *, n_elements: int = 32, dt: float = 1e-3, solver: str = "trapezoidal",
               spectral_radius: float = 1.0, rtol: float = 1e-8, atol: float = 1e-10) -> dict[str, Any]:
    """Simulate the pinned-free beam with Exudyn's ``ObjectFFRFreducedOrder`` on flexlib's FE model and modes.

    Parameters
    ----------
    n_modes : int
        Dynamic (pin-clamped) modes.
    n_elements : int
        Frame elements of the FE mesh (even: the mid-span moment is taken at a node).
    dt : float
        Fixed time step [s]; must divide the 10 ms sampling period.
    solver : {"trapezoidal", "generalized-alpha"}
        Exudyn's ``TrapezoidalIndex2`` (non-dissipative, velocity-level constraints) or ``GeneralizedAlpha``
        (index 3) with ``spectral_radius``.
    spectral_radius : float
        ρ∞ of generalised-α (ignored for the trapezoidal rule).
    rtol, atol : float
        Newton's relative and absolute residual tolerances (Exudyn's defaults 1e-8, 1e-10).

    Returns
    -------
    dict
        ``t`` (201 samples [s]), ``tip_y`` [m], ``tip_deflection`` [m], ``moment_mid_avg`` [N·m], ``wall_time`` and
        ``cpu_time`` of the solve [s], ``setup_time`` [s] (mesh, modes, system assembly), ``info``.
    """
    exu = _exudyn()
    if exu is None:
        raise ModuleNotFoundError("run_exudyn needs Exudyn: pip install exudyn (or pip install -e '.[bench]')")
    eii = importlib.import_module("exudyn.itemInterface")
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface

    per_sample = SAMPLE_DT / dt
    if abs(per_sample - round(per_sample)) > 1e-9 or n_elements % 2:
        raise ValueError(f"run_exudyn: dt={dt!r} must divide {SAMPLE_DT} s and n_elements={n_elements!r} be even")
    start = time.perf_counter()
    fe, modes, omega = beam_modes(n_modes, n_elements)
    points = fe.mass_points
    at_points = (points.Nt @ modes)  # (3 P, n_modes) Gauss-point translations
    # Exudyn's nodes: the FE nodes (massless, for output) and the mass points; translations only
    fem = FEMinterface()
    fem.nodes = {"Position": np.vstack([fe.nodes, points.positions])}
    n_fe = fe.nodes.shape[0]
    lumped = np.concatenate([np.zeros(3 * n_fe), np.repeat(points.masses, 3)])
    fem.massMatrix = sp.diags(lumped).tocsr()
    fem.stiffnessMatrix = sp.csr_matrix((lumped.size, lumped.size))  # replaced by the frame elements' Φᵀ K Φ below
    node_shapes = fe.nodal_fields(modes)[0].transpose(1, 2, 0).reshape(-1, modes.shape[1])  # (3 N, n_modes)
    fem.modeBasis = {"matrix": np.vstack([node_shapes, at_points]), "type": "NormalModes"}
    cms = ObjectFFRFreducedOrderInterface(fem)
    generalized_mass = modes.T @ (fe.M @ modes)
    if not np.allclose(cms.massMatrixReduced, generalized_mass, rtol=0, atol=1e-9):
        raise RuntimeError("run_exudyn: the mass points do not reproduce the consistent modal mass")
    cms.stiffnessMatrixReduced = modes.T @ (fe.K @ modes)

    mbs = exu.SystemContainer().AddSystem()
    body = cms.AddObjectFFRFreducedOrder(mbs, positionRef=[0, 0, 0])
    ground = mbs.AddObject(eii.ObjectGround())
    m_ground = mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=ground, localPosition=[0, 0, 0]))
    m_pin = mbs.AddMarker(eii.MarkerNodeRigid(nodeNumber=body["nRigidBody"]))
    mbs.AddObject(eii.GenericJoint(markerNumbers=[m_ground, m_pin], constrainedAxes=[1, 1, 1, 1, 1, 0],
                                   visualization=eii.VGenericJoint(show=False)))

    def torque(mbs: Any, t: float, load: Sequence[float]) -> list[float]:
        return [0.0, 0.0, TORQUE if t <= T_SWITCH + 1e-9 else -TORQUE]

    mbs.AddLoad(eii.LoadTorqueVector(markerNumber=m_pin, loadVector=[0, 0, TORQUE], loadVectorUserFunction=torque))
    s_rot = mbs.AddSensor(eii.SensorNode(nodeNumber=body["nRigidBody"], storeInternal=True, writeToFile=False,
                                         outputVariableType=exu.OutputVariableType.RotationMatrix))
    s_modal = mbs.AddSensor(eii.SensorNode(nodeNumber=body["nGenericODE2"], storeInternal=True, writeToFile=False,
                                           outputVariableType=exu.OutputVariableType.Coordinates))
    mbs.Assemble()

    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = T_END
    settings.timeIntegration.numberOfSteps = round(T_END / dt)
    settings.timeIntegration.verboseMode = 0
    settings.timeIntegration.adaptiveStep = False  # a fixed step: Exudyn would otherwise shrink it silently
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = 0.5 * dt  # every step (a period of dt skips steps by round-off)
    settings.timeIntegration.generalizedAlpha.spectralRadius = spectral_radius
    settings.timeIntegration.newton.relativeTolerance = rtol
    settings.timeIntegration.newton.absoluteTolerance = atol
    kind = {"trapezoidal": exu.DynamicSolverType.TrapezoidalIndex2,
            "generalized-alpha": exu.DynamicSolverType.GeneralizedAlpha}[solver]
    setup_time = time.perf_counter() - start

    wall, cpu = time.perf_counter(), time.process_time()
    exu.SolveDynamic(mbs, settings, solverType=kind, showHints=False)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu

    rot = mbs.GetSensorStoredData(s_rot)
    q = mbs.GetSensorStoredData(s_modal)[:, 1:]
    t = rot[:, 0]
    R = rot[:, 1:].reshape(-1, 3, 3)
    tip = fe.nodal_fields(modes)[0][:, n_fe - 1, :].T @ q.T  # (3, steps) in the body frame
    local = fe.nodes[-1][:, None] + tip
    tip_y = np.einsum("sj,js->s", R[:, 1, :], local)
    moment = q @ mid_moment_modes(fe, modes)
    ts = sample_times()
    idx = np.minimum(np.searchsorted(t, ts - 0.5 * dt), t.size - 1)
    if np.max(np.abs(t[idx] - ts)) > 1e-3 * dt:
        raise RuntimeError(f"run_exudyn: the sensor samples miss the 10 ms grid (n={n_modes}, dt={dt}, "
                           f"{t.size} samples, last t={t[-1]})")
    return {"t": ts, "tip_y": tip_y[idx], "tip_deflection": tip[1, idx],
            "moment_mid_avg": window_average(t, moment, ts, AVERAGE_HALF_WIDTH),
            "modal_coordinates": q[idx], "wall_time": wall, "cpu_time": cpu, "setup_time": setup_time,
            "info": {"dt": dt, "steps": round(T_END / dt), "solver": solver, "n_elements": n_elements,
                     "frequencies_Hz": omega / (2 * np.pi), "exudyn": exu.__version__}}


def errors(run: dict[str, Any], reference: dict[str, np.ndarray]) -> dict[str, float]:
    """Seed errors [%] of a run's series against the reference's."""
    return {name: seed_error(run[name], reference[name]) for name in SERIES}


def converged_step(n_modes: int, steps: Sequence[float] = STEPS, tolerance: float = 1.0,
                   **kwargs: Any) -> tuple[float, dict[str, Any], dict[str, Any]]:
    """Largest of ``steps`` whose series are all within ``tolerance`` % (seed metric) of the same model's run at a
    step 4× smaller than the smallest of ``steps``; returns that step, its run and the converged run."""
    converged = run_exudyn(n_modes, dt=min(steps) / 4, **kwargs)
    for dt in steps:
        try:
            run = run_exudyn(n_modes, dt=dt, **kwargs)
        except _exudyn().SolverError:  # Newton failed at this fixed step (Exudyn prints the failure)
            continue
        if max(errors(run, converged).values()) <= tolerance:
            return dt, run, converged
    raise RuntimeError(f"Exudyn n={n_modes}: no step in {steps} within {tolerance} % of the converged run")


def load_reference(path: Path = REFERENCE_FILE) -> tuple[dict[str, np.ndarray] | None, str]:
    """The geometrically exact reference series (``t`` and :data:`SERIES`), or None with the reason."""
    if not path.exists():
        return None, f"{path} not found"
    with np.load(path) as data:
        missing = [name for name in ("t", *SERIES) if name not in data]
        if missing:
            raise ValueError(f"{path}: missing arrays {missing}")
        ref = {name: np.asarray(data[name], dtype=float) for name in ("t", *SERIES)}
    if ref["t"].shape != sample_times().shape or not np.allclose(ref["t"], sample_times()):
        raise ValueError(f"{path}: t must be the 201 samples 0, 0.01, …, 2 s")
    return ref, f"the geometrically exact reference {path}"


def table(runners: dict[str, Callable[[int], dict[str, Any]]], reference: dict[str, np.ndarray],
          modes: Sequence[int] = MODES, rows: list[tuple] | None = None) -> list[str]:
    """One row per runner and mode count: wall/CPU time of the solve, setup time, seed errors [%].

    The same figures are appended to ``rows`` (when given) as tuples for the results file.
    """
    lines = [f"{'runner':<12}{'n':>3}{'wall s':>9}{'cpu s':>9}{'setup s':>9}{'tip y %':>9}{'defl %':>9}"
             f"{'M avg %':>9}  info"]
    for n in modes:
        for name, runner in runners.items():
            try:
                run = runner(n)
            except Exception as exc:  # a failed run is a row of the table (as in the seed's Table 1), not the end
                lines.append(f"{name:<12}{n:>3}  failed: {type(exc).__name__}: {exc}")
                continue
            e = errors(run, reference)
            info = run.get("info", {})
            detail = ", ".join(f"{k}={v}" for k, v in info.items() if k in ("dt", "steps", "solver"))
            lines.append(f"{name:<12}{n:>3}{run['wall_time']:>9.3f}{run['cpu_time']:>9.3f}{run['setup_time']:>9.3f}"
                         f"{e['tip_y']:>9.2f}{e['tip_deflection']:>9.2f}{e['moment_mid_avg']:>9.2f}  {detail}")
            if rows is not None:
                rows.append((name, n, run["wall_time"], run["cpu_time"], run["setup_time"], e["tip_y"],
                             e["tip_deflection"], e["moment_mid_avg"], detail))
    return lines


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="Exudyn at the recorded steps, no convergence study")
    parser.add_argument("--reference", type=Path, default=REFERENCE_FILE, help="reference series (.npz)")
    args = parser.parse_args(argv)
    runners = dict(FLEXLIB_RUNNER)
    exu = _exudyn()
    reference, source = load_reference(args.reference)
    if exu is None:
        print("Exudyn is not installed (pip install exudyn, or pip install -e '.[bench]'): only flexlib's runners.")
    else:
        print(f"Exudyn {exu.__version__}, ObjectFFRFreducedOrder, TrapezoidalIndex2, fixed step")
        steps = dict(QUICK_STEPS)
        if not args.quick:
            for n in MODES:
                dt, _, converged = converged_step(n)
                steps[n] = dt
                print(f"  n={n}: largest step within 1 % of its converged run (dt={min(STEPS) / 4:g} s): {dt:g} s")
                if reference is None and n == max(MODES):
                    reference = converged
                    source = f"Exudyn's own converged run (n={n}, dt={min(STEPS) / 4:g} s), NOT the exact reference"
        runners["exudyn"] = lambda n: run_exudyn(n, dt=steps[n])
        runners["exudyn 1ms"] = lambda n: run_exudyn(n, dt=1e-3)  # the seed's own step
    if reference is None:
        if exu is None:
            print(f"no reference ({source}) and no Exudyn: nothing to compare")
            return 0
        reference = run_exudyn(max(MODES), dt=min(STEPS))
        source = f"Exudyn's own run (n={max(MODES)}, dt={min(STEPS):g} s), NOT the exact reference"
    if not runners:
        print("no runners: flexlib's runner is not registered yet (FLEXLIB_RUNNER) and Exudyn is missing")
        return 0
    print(f"errors (seed 001 eq. 2, 201 samples) against {source}")
    rows: list[tuple] = []
    print("\n".join(table(runners, reference, rows=rows)))

    import report  # sibling module: benchmarks/ is on sys.path when this file runs as a script

    wall = {(r[0], r[1]): r[2] for r in rows}
    figures = [(f"{name}, n = 4: wall", wall[name, 4], "s") for name in runners if (name, 4) in wall]
    figures += [(f"{name}, n = 4: tip deflection", r[6], "%") for r in rows for name in runners
                if r[:2] == (name, 4)]
    report.write_results(__file__, figures, tables=[report.table(
        f"Pinned-free beam, 2 s; errors (seed eq. 2, 201 samples) against {source}",
        ["runner", "n", "wall [s]", "CPU [s]", "setup [s]", "tip y [%]", "tip deflection [%]", "moment avg [%]",
         "info"], rows)])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
