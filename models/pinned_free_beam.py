"""The pinned-free beam of seed 001: a slender beam pinned at one end, driven by a bang-bang torque.

Density 8000 kg/m³, Young's modulus 2e11 Pa, length 1.5 m, area 1e-4 m², second moment 1e-10 m⁴ (in-plane
bending), no gravity; the pin is fixed in the world and turns about the world z axis; the beam starts at rest along
world x; the torque is +1.4 N·m for 0 ≤ t < 1 s and −1.4 N·m for 1 ≤ t ≤ 2 s. The beam is a
:class:`~flexlib.components.mechanics.flexible.FlexibleBody` built from the beam mesher and Craig–Bampton with
*pinned* attachment at the pin node: its modes are the hinged beam's own (first 5.45 Hz), mass-orthogonal to the
rotation about the pin, so the reference frame turns with the beam's mean rotation and the pin node turns
elastically (``modal_data_from_fe(..., reference_node=0, attachment="pinned")``); the tip is an interface node.
Geometric stiffening (centrifugal, energy-consistent) is on by default.

Outputs sampled as in the seed (201 samples, every 10 ms): the tip's world y coordinate, the tip deflection from
the pin tangent (the tip's y in the pin node's frame, with the node's exact elastic rotation) and the mid-span
bending moment (modal section forces), plus its average over ±5 ms. The deflection and the moment come twice from
the same run: by plain modal superposition, and by the mode-acceleration method, which adds the left-out modes'
static response to the run's loads (here the pin torque). The pin tangent is the slope where the torque acts, and
in plain superposition each left-out mode ``k`` still contributes about ``1/k²`` of it (12.6 → 8.7 → 5.05 % error
for 1, 2, 4 modes); the recovery restores that static part (4.9, 2.9, 1.6 %).

References
----------
- J. Cuadrado, R. Gutiérrez, M. A. Naya, P. Morer, "A comparison in terms of accuracy and efficiency between a MBS
  dynamic formulation with stress analysis and a non-linear FEA code", *Int. J. Numer. Meth. Eng.* 51 (2001)
  1033–1052 (the beam and its error measure; seed 001 of this project).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.components.control import Step
from flexlib.components.mechanics.flexible import FlexibleBody, cayley_rotation
from flexlib.components.mechanics.multibody import Revolute, World
from flexlib.components.mechanics.rotational import Torque
from flexlib.errors import ModelError, RunArgumentError
from flexlib.fe import (
    ModalData,
    ParticipationTable,
    Section,
    beam_mesh,
    inertial_load_cases,
    modal_data_from_fe,
    modal_participation,
    node_displacements,
    node_rotations,
    planar_modes,
    section_forces,
)
from flexlib.registry import ModelOption, Scenario, register_model

__all__ = ["DENSITY", "LENGTH", "N_BENDING_MODES", "OPTIONS", "TORQUE", "BeamRun", "PinnedFreeBeam", "beam_fe",
           "beam_modal_data", "bending_modes", "participation_table", "seed_error", "simulate", "simulate_modes"]

DENSITY = 8000.0      #: [kg/m3]
YOUNG = 2e11          #: [Pa]
LENGTH = 1.5          #: [m]
AREA = 1e-4           #: [m2]
I_BENDING = 1e-10     #: in-plane second moment of area [m4]
TORQUE = 1.4          #: [N m]
T_END = 2.0           #: [s]
SAMPLES = np.linspace(0.0, T_END, 201)  #: the seed's output instants [s]


def section() -> Section:
    """The seed's section: A = 1e-4 m², Iz = 1e-10 m⁴ (in-plane, x–y). Out of plane and in torsion the beam is
    stiffer (10×): those motions are never excited in the planar problem, and distinct frequencies keep the
    in-plane modes pure."""
    return Section(A=AREA, Iy=10 * I_BENDING, Iz=I_BENDING, J=20 * I_BENDING, name="seed-001 beam")


def beam_fe(n_elements: int = 32):
    """Euler–Bernoulli FE model of the beam along body x from the pin (node 0) to the tip (node ``n_elements``)."""
    return beam_mesh((0.0, 0.0, 0.0), (LENGTH, 0.0, 0.0), n_elements, section(), E=YOUNG, rho=DENSITY)


def beam_modal_data(n_elements: int = 32, n_fixed_modes: int = 16, geometric_stiffening: bool = True,
                    attachment: str = "pinned") -> ModalData:
    """Modal data of the beam: reference frame attached at the pin node (``"pinned"``: hinged-beam modes;
    ``"clamped"``: the seed's tangent frame with cantilever modes), tip as interface node, with section-force
    modes and, by default, the geometric stiffness of the unit load cases (held at the pin)."""
    return modal_data_from_fe(beam_fe(n_elements), [n_elements], n_fixed_modes, reference_node=0,
                              attachment=attachment, geometric_stiffening=geometric_stiffening,
                              title="seed-001 pinned-free beam")


def _modal_data(what: str, data: Any) -> ModalData:
    """``data`` checked to be a ModalData (a path or an FE model is named, with how to get modal data)."""
    if not isinstance(data, ModalData):
        raise RunArgumentError(f"{what}: argument 'data' must be the beam's ModalData (beam_modal_data(), or "
                               f"ModalData.read(path) for a file), got {type(data).__name__} {data!r:.60}")
    return data


def bending_modes(data: ModalData) -> list[int]:
    """Indices of the in-plane (x–y) bending modes, lowest frequency first: the modes in the beam's plane
    (:func:`flexlib.fe.planar_modes`) that move it more transversely than axially.

    Raises
    ------
    RunArgumentError
        ``data`` is not a ModalData.
    """
    data = _modal_data("bending_modes", data)
    T = data.translational_modes
    return [k for k in planar_modes(data, "xy") if np.abs(T[k, :, 1]).max() > np.abs(T[k, :, 0]).max()]


class PinnedFreeBeam(fl.Model):
    """World, a revolute pin about z driven by the bang-bang torque, and the flexible beam (undamped).

    Parameters
    ----------
    data : ModalData
        The beam's modal data (:func:`beam_modal_data`).
    modes : list of int
        Modes to keep (indices into ``data``; or, as for :class:`FlexibleBody`, an int count of the lowest).
    geometric_stiffening : bool
        Include the geometric stiffness terms.
    frames : list of int, optional
        Node ids of the beam's frames (default: the data's interface nodes); the first is pinned.

    Raises
    ------
    ModelError
        Bad ``modes``, ``frames`` or ``geometric_stiffening`` (from :class:`FlexibleBody`, naming the argument).
    """

    def __init__(self, data: ModalData, modes: list[int], geometric_stiffening: bool = True,
                 frames: list[int] | None = None) -> None:
        super().__init__()
        self.world = World(g=0.0)
        self.pin = Revolute(n=[0, 0, 1], use_axis_flange=True, init={"phi": 0.0, "w": 0.0})
        self.torque = Torque()
        self.profile = Step(offset=TORQUE, height=-2 * TORQUE, start_time=1.0)
        self.beam = FlexibleBody(data, modes=modes, damping=0.0, frames=frames,
                                 geometric_stiffening=geometric_stiffening)
        self.connect(self.world.frame_b, self.pin.frame_a)
        self.connect(self.pin.frame_b, self.beam.frame_a)
        self.connect(self.profile.y, self.torque.tau)
        self.connect(self.torque.flange, self.pin.axis)


@dataclass
class BeamRun:
    """One simulation of the beam, sampled at :data:`SAMPLES`.

    Attributes
    ----------
    t : ndarray [s]; tip_y : ndarray [m]; tip_deflection : ndarray [m]; moment_mid, moment_mid_avg : ndarray [N m]
    build_time, run_time : float [s] (process CPU time); n_modes : int; run_wall : float [s] (wall time of the run)
    tip_deflection_ma : ndarray [m]; moment_mid_ma, moment_mid_avg_ma : ndarray [N m]
        The same outputs recovered by the mode-acceleration method (the left-out modes' static response to the
        run's loads added to the modal superposition: :mod:`flexlib.fe.output`) from
        the same run; ``None`` if the modal data hold no static load responses.
    """

    t: np.ndarray
    tip_y: np.ndarray
    tip_deflection: np.ndarray
    moment_mid: np.ndarray
    moment_mid_avg: np.ndarray
    build_time: float
    run_time: float
    n_modes: int
    run_wall: float = 0.0
    tip_deflection_ma: np.ndarray | None = None
    moment_mid_ma: np.ndarray | None = None
    moment_mid_avg_ma: np.ndarray | None = None


def _window_average(t: np.ndarray, x: np.ndarray, at: np.ndarray, half: float) -> np.ndarray:
    """Mean of the piecewise-linear ``x(t)`` over ``[τ − half, τ + half] ∩ [t0, t_end]`` for each τ in ``at``."""
    cum = np.concatenate([[0.0], np.cumsum(np.diff(t) * (x[1:] + x[:-1]) / 2)])
    lo, hi = np.clip(at - half, t[0], t[-1]), np.clip(at + half, t[0], t[-1])
    return (np.interp(hi, t, cum) - np.interp(lo, t, cum)) / (hi - lo)


def simulate(n_modes: int, *, data: ModalData | None = None, geometric_stiffening: bool = True,
             rtol: float = 1e-7, atol: float = 1e-9, dt_fine: float = 2.5e-4, compiled: bool = False,
             solver: Any = "ida") -> BeamRun:
    """Run the beam with the ``n_modes`` lowest in-plane bending modes (0: rigid).

    Parameters
    ----------
    n_modes : int
        Number of in-plane bending modes kept.
    data : ModalData, optional
        Modal data (default :func:`beam_modal_data`).
    geometric_stiffening : bool
        Include the geometric stiffness terms.
    rtol, atol : float
        Integrator tolerances [1], [units of each unknown].
    dt_fine : float
        Output step [s] of the fine series the ±5 ms moment average is taken over.
    compiled : bool
        Wait for the generated C code before the run (timings of the compiled model, as after a first run).
    solver : str or Solver
        The run's solver (``fl.FixedStep(h=...)`` for the real-time comparison of ``benchmarks/flexible_beam.py``).

    Raises
    ------
    RunArgumentError
        ``n_modes`` not an int, negative, or more than the data's in-plane bending modes; ``data`` not a ModalData;
        ``compiled`` not a bool (a ``ValueError``).
    """
    _check_count("simulate: n_modes", n_modes, RunArgumentError)
    data = beam_modal_data() if data is None else _modal_data("simulate", data)
    modes = _bending_subset("simulate: n_modes", n_modes, data, RunArgumentError)
    return simulate_modes(modes, data=data, geometric_stiffening=geometric_stiffening, rtol=rtol, atol=atol,
                          dt_fine=dt_fine, compiled=compiled, solver=solver)


def simulate_modes(modes: list[int], *, data: ModalData, geometric_stiffening: bool = True, rtol: float = 1e-7,
                   atol: float = 1e-9, dt_fine: float = 2.5e-4, compiled: bool = False,
                   solver: Any = "ida") -> BeamRun:
    """Run the beam with the given modes (indices into ``data``); arguments as :func:`simulate`."""
    data = _modal_data("simulate_modes", data)
    if not isinstance(compiled, bool | np.bool_):
        raise RunArgumentError(f"simulate_modes: argument 'compiled' must be True or False, got {compiled!r}")
    tip = int(data.node_ids[np.argmax(data.coordinates[:, 0])])
    pin = int(data.node_ids[np.argmin(data.coordinates[:, 0])])
    c0 = time.process_time()
    model = PinnedFreeBeam(data, modes, geometric_stiffening, frames=[pin, tip])
    sim = fl.Simulation(model)
    c1 = time.process_time()
    if compiled:
        sim.compiled.wait_for_library(120.0)
        c1 = time.process_time()
    w1 = time.perf_counter()
    res = sim.run(T_END, dt_out=dt_fine, rtol=rtol, atol=atol, progress=False, solver=solver)
    c2, w2 = time.process_time(), time.perf_counter()
    t = res.t
    sel = model.beam.modal_data
    q = res["beam.q"].reshape(len(t), -1) if modes else np.zeros((len(t), 0))

    def deflection_and_moment(loads: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        # the tip in the pin node's frame: x_tip - x_pin (body axes) turned by the pin node's exact elastic rotation
        x = sel.coordinates[[sel.node_index(pin), sel.node_index(tip)]] + node_displacements(
            sel, q, [pin, tip], loads=loads)
        local = np.einsum("kij,kj->ki", cayley_rotation(node_rotations(sel, q, [pin], loads=loads)[:, 0]),
                          x[:, 1] - x[:, 0])
        n_el = sel.elements.shape[0]
        forces = section_forces(sel, q, loads=loads)
        return local[:, 1], 0.5 * (forces[:, n_el // 2 - 1, 1, 5] + forces[:, n_el // 2, 0, 5])

    deflection, moment = deflection_and_moment(None)
    recovered = None
    if sel.load_cases is not None:
        d_ma, m_ma = deflection_and_moment(model.beam.load_amplitudes(res))
        recovered = (np.interp(SAMPLES, t, d_ma), np.interp(SAMPLES, t, m_ma), _window_average(t, m_ma, SAMPLES, 5e-3))
    return BeamRun(t=SAMPLES.copy(), tip_y=np.interp(SAMPLES, t, res["beam.frame_b.r_0"][:, 1]),
                   tip_deflection=np.interp(SAMPLES, t, deflection), moment_mid=np.interp(SAMPLES, t, moment),
                   moment_mid_avg=_window_average(t, moment, SAMPLES, 5e-3),
                   build_time=c1 - c0, run_time=c2 - c1, n_modes=len(modes), run_wall=w2 - w1,
                   tip_deflection_ma=None if recovered is None else recovered[0],
                   moment_mid_ma=None if recovered is None else recovered[1],
                   moment_mid_avg_ma=None if recovered is None else recovered[2])


def seed_error(z: np.ndarray, z_ref: np.ndarray) -> float:
    """The seed's error [%]: mean of ``|z − z*|`` over the samples divided by ``max |z*|``, × 100 (its eq. 2).

    Raises
    ------
    RunArgumentError
        ``z`` or ``z_ref`` not finite real numbers (text is refused), not equal non-empty 1-D shapes, or a
        reference that is identically zero (the error has no scale).
    """
    arrays = []
    for name, value in (("z", z), ("z_ref", z_ref)):
        try:
            kind = "U" if isinstance(value, str | bytes) else np.asarray(value).dtype.kind
        except (TypeError, ValueError):
            kind = "O"
        if kind not in "iuf":
            raise RunArgumentError(f"seed_error: {name} must be an array of real numbers, got {value!r:.60}")
        a = np.asarray(value, dtype=float)
        if not np.all(np.isfinite(a)):
            raise RunArgumentError(f"seed_error: {name} has a non-finite value at sample "
                                   f"{int(np.flatnonzero(~np.isfinite(a.ravel()))[0])}")
        arrays.append(a)
    z, z_ref = arrays
    if z.shape != z_ref.shape or z.ndim != 1 or z.size == 0:
        raise RunArgumentError(f"seed_error: z {z.shape} and z_ref {z_ref.shape} must be equal non-empty 1-D shapes "
                               "(the same samples)")
    scale = float(np.abs(z_ref).max())
    if not scale > 0:
        raise RunArgumentError("seed_error: the reference z_ref is identically zero: the error has no scale")
    return float(np.mean(np.abs(z - z_ref)) / scale * 100.0)


def participation_table(data: ModalData | None = None, n_elements: int | None = None, threshold: float = 0.01,
                        ) -> tuple[ParticipationTable, float]:
    """The MPF method of seed 001 on the in-plane bending modes: a rigid-body run (analytic here: the pinned rigid
    beam, ``α = ±τ/J``, ``J = ρAL³/3``), its most critical instant (largest load, t = 1 s where the angular
    velocity peaks), the loads there on the FE DOFs — the d'Alembert forces of the rigid motion and the pin torque,
    in equilibrium — their static modal amplitudes and shares.

    Parameters
    ----------
    data : ModalData, optional
        The beam's modal data (default :func:`beam_modal_data` of ``n_elements``).
    n_elements : int, optional
        Elements of the beam's mesh: the FE model the loads are applied on; default that of ``data`` (its nodes
        less one), else 32.
    threshold : float
        Keep modes whose share reaches this fraction of the largest [1] (0.01 for 1 %).

    Returns
    -------
    (ParticipationTable, float)
        The table (rows in :func:`bending_modes` order) and the critical instant [s].

    Raises
    ------
    RunArgumentError
        ``data`` not a ModalData, ``n_elements`` not the mesh of ``data``, ``threshold`` not in ``[0, 1]``.
    """
    if data is None:
        n_elements = 32 if n_elements is None else n_elements
        data = beam_modal_data(n_elements)
    else:
        data = _modal_data("participation_table", data)
        if n_elements is None:
            n_elements = data.n_nodes - 1
        elif n_elements != data.n_nodes - 1:
            raise RunArgumentError(f"participation_table: n_elements={n_elements!r}, but the modal data "
                                   f"{data.title!r} are of a mesh of {data.n_nodes - 1} elements ({data.n_nodes} "
                                   "nodes): leave n_elements out, or pass the data of that mesh")
    attachment = data.provenance.get("attachment") or "clamped"
    held = ("ux", "uy", "uz") if attachment == "pinned" else ("ux", "uy", "uz", "rx", "ry", "rz")
    fe = beam_fe(n_elements).constrained([0], held)
    J = DENSITY * AREA * LENGTH**3 / 3
    t = np.linspace(0.0, T_END, 2001)
    tau = np.where(t < 1.0, TORQUE, -TORQUE)
    omega = np.where(t < 1.0, TORQUE / J * t, TORQUE / J * (2.0 - t))
    cases = inertial_load_cases(fe)
    loads = np.outer(cases["alpha_z"], tau / J) + np.outer(cases["omega_zz"], omega**2)
    pin_rz = fe.dofs([0], ["rz"])
    if pin_rz.size:
        loads[pin_rz] += tau
    critical = int(np.argmax(np.linalg.norm(loads, axis=0)))
    modes = bending_modes(data)
    shapes = fe.dof_fields(data.translational_modes[modes], data.rotational_modes[modes])
    K = np.diag(data.generalized_stiffness)[modes]
    table = modal_participation(shapes, K, loads[:, critical], frequencies=data.frequencies[modes],
                                threshold=threshold)
    return table, float(t[critical])


# -- registration (flexlib list / flexlib run) ------------------------------------------------------------------
def _bending_subset(what: str, n_modes: Any, data: ModalData, error: type[Exception]) -> list[int]:
    """The ``n_modes`` lowest in-plane bending modes of ``data``: ``n_modes`` an int in 0..available."""
    available = bending_modes(data)
    _check_count(what, n_modes, error, len(available))
    return available[:int(n_modes)]


def _check_count(what: str, n_modes: Any, error: type[Exception], available: int | None = None) -> None:
    """``n_modes`` an int (not a bool) in 0..available (no upper bound if ``available`` is None)."""
    if (isinstance(n_modes, bool | np.bool_) or not isinstance(n_modes, int | np.integer) or n_modes < 0
            or (available is not None and n_modes > available)):
        bound = ">= 0" if available is None else f"in 0..{available} (the modal data has {available})"
        raise error(f"{what} must be an int {bound}: the number of lowest in-plane bending modes kept, 0 for a "
                    f"rigid beam; got {n_modes!r} ({type(n_modes).__name__})")


#: In-plane bending modes of :func:`beam_modal_data` (with or without geometric stiffening): the upper bound of the
#: ``n_modes`` option.
N_BENDING_MODES = 13
#: The model options of ``pinned-free-beam`` (checked by the registry, for a registered scenario, a JSON file and
#: ``flexlib run -O NAME=VALUE``, before the factory runs). The upper bound of ``n_modes`` depends on the modal data,
#: so the factory checks it, with the data.
OPTIONS = (
    ModelOption("n_modes", int, 4, f"lowest in-plane bending modes kept (0: rigid beam; at most the "
                f"{N_BENDING_MODES} of the beam's modal data)", low=0),
    ModelOption("geometric_stiffening", bool, True, "geometric stiffness of the unit load cases (centrifugal "
                "stiffening; false: the linear modal beam)"),
)
_OPTIONS = {o.name: o for o in OPTIONS}


def _beam_factory(scenario: Scenario) -> PinnedFreeBeam:
    """``options`` (declared in :data:`OPTIONS`, checked by the registry before the factory runs): ``n_modes``
    (lowest in-plane bending modes kept, an int from 0 to the modal data's in-plane bending modes — that bound is
    checked here, with the data), ``geometric_stiffening`` (True or False). A direct call with an unchecked
    scenario gets the same checks, as :class:`~flexlib.errors.ModelError`."""
    where = f"model 'pinned-free-beam', scenario {scenario.name!r}: option"
    stiffening = _OPTIONS["geometric_stiffening"].validate(
        scenario.options.get("geometric_stiffening", _OPTIONS["geometric_stiffening"].default), f"{where} ",
        error=ModelError)
    n_modes = scenario.options.get("n_modes", _OPTIONS["n_modes"].default)
    _check_count(f"{where} n_modes", n_modes, ModelError)  # before the reduction: a direct call fails at once
    data = beam_modal_data(geometric_stiffening=stiffening)
    modes = _bending_subset(f"{where} n_modes", n_modes, data, ModelError)  # the upper bound: the data's modes
    return PinnedFreeBeam(data, modes, geometric_stiffening=stiffening)


register_model(
    "pinned-free-beam", _beam_factory,
    doc="seed-001 flexible beam (1.5 m steel, FlexibleBody) on a pin, bang-bang torque 1.4 N m",
    scenarios=[
        Scenario("seed", "the seed's 2 s run with 4 bending modes", t_end=T_END, options={"n_modes": 4},
                 run={"dt_out": 0.01, "rtol": 1e-7, "atol": 1e-9}),
        Scenario("rigid", "the same with no elastic mode (rigid beam)", t_end=T_END, options={"n_modes": 0},
                 run={"dt_out": 0.01, "rtol": 1e-7, "atol": 1e-9}),
    ],
    summary_signals=["pin.phi", "pin.w", "torque.tau"],
    options=OPTIONS, data=(),
)
