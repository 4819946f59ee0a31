"""The reference-model catalogue: each canonical small system with its default instance, a short run and the
invariants or closed-form reference it must satisfy.

:data:`CASES` maps a case name to a :class:`ReferenceCase`. ``case.check(res)`` returns the largest error of each
named invariant or reference (in the unit given by the case); ``case.tolerances`` holds the bound each must stay
under for the case's run (``case.run``). The models live in the modules beside this one; the closed forms in
:mod:`flexlib.models.reference.closed_form` (numpy/scipy only).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.models.n_link_pendulum import NLinkPendulum
from flexlib.models.n_mass_chain import NMassChain
from flexlib.models.reference import closed_form as cf
from flexlib.models.reference.blow_up import BlowUp
from flexlib.models.reference.cartesian_pendulum import CartesianPendulum
from flexlib.models.reference.events import BangBang, FallingBall
from flexlib.models.reference.four_bar import A, B, C, D, FourBar, loop_residual
from flexlib.models.reference.hydraulic_circuit import PumpValveCylinder, mass_balance_error
from flexlib.models.reference.hydraulic_cylinder import A_P, A_R, BAR, P_ATM, STROKE, PressureDriven
from flexlib.models.reference.mass_spring_damper import DampedOscillator, MassSpringDamper, Oscillator
from flexlib.models.reference.rigid_pendulum import G, RigidPendulum
from flexlib.models.reference.signal_chain import LimitedSine
from flexlib.models.reference.slider_crank import SliderCrank
from flexlib.units import g_n

__all__ = ["CASES", "ReferenceCase"]


@dataclass(frozen=True)
class ReferenceCase:
    """One catalogue entry.

    Parameters
    ----------
    name : str
        Case name (also its registry name, ``flexlib run NAME``).
    doc : str
        One line: the system and what is checked.
    build : callable
        ``build() -> Model``: the default instance.
    check : callable
        ``check(model, res) -> {name: largest error}`` of the invariants and references.
    tolerances : mapping
        ``{name: bound}`` for each key of ``check``'s answer.
    run : mapping
        Keyword arguments of :meth:`flexlib.Simulation.run` (``t_end``, ``dt_out``, ``rtol``, ``atol``).
    """

    name: str
    doc: str
    build: Callable[[], fl.Model]
    check: Callable[[Any, fl.Result], dict[str, float]]
    tolerances: Mapping[str, float]
    run: Mapping[str, Any] = field(default_factory=dict)


def _max(x: Any) -> float:
    return float(np.max(np.abs(np.asarray(x, dtype=float))))


def _drift(x: np.ndarray) -> float:
    return _max(np.asarray(x) - np.asarray(x)[0])


# -- checks ---------------------------------------------------------------------------------------------------------
CARTESIAN_THETA0 = 0.5
RIGID = {"L": 0.5, "m": 1.0, "inertia": np.diag([1e-3, 2e-3, 2e-3]), "phi0": 0.3}


def _cartesian(model: CartesianPendulum, res: fl.Result) -> dict[str, float]:
    g0, g1 = CartesianPendulum.constraint_residuals(res)
    theta = cf.pendulum_angle(res.t, 1.0, 9.81, CARTESIAN_THETA0)
    return {"position constraint [m2]": _max(g0), "velocity constraint [m2/s]": _max(g1),
            "energy drift [J]": _drift(CartesianPendulum.energy(res)),
            "x vs closed form [m]": _max(res["x"] - np.sin(theta))}


def _rigid(model: RigidPendulum, res: fl.Result) -> dict[str, float]:
    L, m, I_zz = RIGID["L"], RIGID["m"], RIGID["inertia"][2, 2]
    L_eq = (m * L**2 + I_zz) / (m * L)  # equivalent simple pendulum (parallel-axis theorem)
    theta = cf.pendulum_angle(res.t, L_eq, G, RIGID["phi0"] + np.pi / 2)  # phi = 0 is horizontal
    return {"energy drift [J]": _drift(RigidPendulum.energy(res, L, m, I_zz)),
            "angle vs closed form [rad]": _max(res["rev.phi"] - (theta - np.pi / 2))}


def _four_bar(model: FourBar, res: fl.Result) -> dict[str, float]:
    _, th4 = cf.fourbar_angles(A, B, C, D, res["rev1.phi"], "open")
    return {"loop closure [m]": _max(loop_residual(res)),
            "rocker angle vs closed form [rad]": _max(np.angle(np.exp(1j * (res["rev4.phi"] - th4))))}


def _slider_crank(model: SliderCrank, res: fl.Result) -> dict[str, float]:
    return {"piston position vs closed form [m]": _max(res["slide.s"] - cf.slider_position(res["crank_joint.phi"],
                                                                                            0.1, 0.35))}


def _oscillator(model: Oscillator, res: fl.Result) -> dict[str, float]:
    return {"x vs cos t [m]": _max(res["x"] - Oscillator.exact(res.t)),
            "energy drift [J]": _drift(Oscillator.energy(res))}


def _damped(model: DampedOscillator, res: fl.Result) -> dict[str, float]:
    return {"x vs closed form [m]": _max(res["x"] - DampedOscillator.exact(res.t))}


def _blow_up(model: BlowUp, res: fl.Result) -> dict[str, float]:
    return {"x vs 1/(1 - t), relative [1]": _max(res["x"] / BlowUp.exact(res.t) - 1.0)}


def _bang_bang(model: BangBang, res: fl.Result) -> dict[str, float]:
    t, J, T, t1, t2 = res.t, 2.0, 1.0, 1.0, 2.5
    w = T / J * np.where(t < t1, t, np.where(t < t2, 2 * t1 - t, 2 * t1 - 2 * t2 + t))
    return {"w vs piecewise-linear closed form [rad/s]": _max(res["w"] - w)}


def _falling(model: FallingBall, res: fl.Result) -> dict[str, float]:
    return {"h vs free fall [m]": _max(res["h"] - (1.0 - 0.5 * 9.81 * res.t**2))}


def _msd(model: MassSpringDamper, res: fl.Result) -> dict[str, float]:
    e = model.energy(res)
    return {"position vs closed form [m]": _max(res["mass.s"] - model.exact(res.t)),
            "energy increase [J]": max(0.0, float(np.max(np.diff(e))))}


def _cylinder(model: PressureDriven, res: fl.Result) -> dict[str, float]:
    p_s = 100 * BAR
    out = (res.t > 1.5) & (res.t < 2.0)
    f_out = p_s * A_P - P_ATM * A_R - P_ATM * (A_P - A_R)
    pen = f_out / 1e9  # stop stiffness 1e9 N/m
    return {"rod-end stop penetration vs force / stiffness [1]": _max((res["cylinder.x"][out] - STROKE) / pen - 1.0)}


def _circuit(model: PumpValveCylinder, res: fl.Result) -> dict[str, float]:
    return {"mass balance [1]": mass_balance_error(res)}


def _n_link(model: NLinkPendulum, res: fl.Result) -> dict[str, float]:
    L, m = 0.5, 1.0
    I_zz = m * L**2 / 12
    energy = 0.0
    for k in range(1, model.n + 1):
        v, w, r = res[f"body{k}.v_0"], res[f"body{k}.w_a"], res[f"body{k}.r_0"]
        energy = energy + 0.5 * m * np.sum(v**2, axis=-1) + 0.5 * I_zz * w[:, 2] ** 2 + m * g_n * r[:, 1]
    return {"energy drift [J]": _drift(energy)}


def _chain(model: NMassChain, res: fl.Result) -> dict[str, float]:
    return {"first mass start offset [m]": abs(float(res["mass0.s"][0]) - 1.0)}


def _limited(model: LimitedSine, res: fl.Result) -> dict[str, float]:
    y = res["limiter.y"]
    return {"limiter output beyond its limits [1]": max(0.0, float(np.max(y)) - 1.0, -0.5 - float(np.min(y)))}


CASES: dict[str, ReferenceCase] = {case.name: case for case in [
    ReferenceCase("cartesian-pendulum", "index-3 planar pendulum released at 0.5 rad: constraints, energy, "
                  "elliptic-function angle", lambda: CartesianPendulum.released_at(CARTESIAN_THETA0), _cartesian,
                  {"position constraint [m2]": 1e-8, "velocity constraint [m2/s]": 1e-6, "energy drift [J]": 1e-6,
                   "x vs closed form [m]": 1e-6}, {"t_end": 1.0, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("rigid-pendulum", "3D body on a revolute about z: energy, elliptic-function angle",
                  lambda: RigidPendulum(**RIGID), _rigid,
                  {"energy drift [J]": 1e-6, "angle vs closed form [rad]": 1e-6},
                  {"t_end": 1.0, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("four-bar", "crank-rocker of four Revolutes from 6 rad/s: loop closure, Freudenstein position",
                  FourBar, _four_bar, {"loop closure [m]": 1e-8, "rocker angle vs closed form [rad]": 1e-6},
                  {"t_end": 0.3, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("slider-crank", "crank, rod and piston from 5 rad/s: piston position in closed form",
                  lambda: SliderCrank(0.5, w0=5.0), _slider_crank, {"piston position vs closed form [m]": 1e-7},
                  {"t_end": 0.3, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("oscillator", "x'' = -x from x = 1: x = cos t, energy",
                  lambda: Oscillator(init={"x": 1.0, "v": 0.0}), _oscillator,
                  {"x vs cos t [m]": 1e-6, "energy drift [J]": 1e-6},
                  {"t_end": 1.0, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("damped-oscillator", "m x'' + d x' + k x = 0 from x = 1: the underdamped closed form",
                  lambda: DampedOscillator(init={"x": 1.0, "v": 0.0}), _damped, {"x vs closed form [m]": 1e-6},
                  {"t_end": 2.0, "dt_out": 0.02, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("blow-up", "x' = x² from x = 1 up to t = 0.9 s: x = 1/(1 - t)", lambda: BlowUp(init={"x": 1.0}),
                  _blow_up, {"x vs 1/(1 - t), relative [1]": 1e-5},
                  {"t_end": 0.9, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("bang-bang", "inertia under +T, -T, +T switched at 1 s and 2.5 s (time events): w piecewise linear",
                  lambda: BangBang(init={"w": 0.0}), _bang_bang,
                  {"w vs piecewise-linear closed form [rad/s]": 1e-9},
                  {"t_end": 4.0, "dt_out": 0.05, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("falling-ball", "ball released 1 m above a contact spring, before the contact: free fall",
                  lambda: FallingBall(init={"h": 1.0, "v": 0.0}), _falling, {"h vs free fall [m]": 1e-8},
                  {"t_end": 0.4, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("mass-spring-damper", "wall, spring-damper and mass from 0.1 m: damped response, energy decreasing",
                  MassSpringDamper, _msd, {"position vs closed form [m]": 1e-6, "energy increase [J]": 1e-9},
                  {"t_end": 0.5, "dt_out": 0.005, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("hydraulic-cylinder", "cylinder driven into its rod-end stop at 100 bar: stop penetration",
                  lambda: PressureDriven(100 * BAR, t_switch=2.0), _cylinder,
                  {"rod-end stop penetration vs force / stiffness [1]": 1e-6},
                  {"t_end": 2.0, "dt_out": 0.001, "rtol": 1e-7, "atol": 1e-9}),
    ReferenceCase("hydraulic-circuit", "pump, relief valve, 4/3 valve, leaking cylinder, mass counters: mass balance",
                  PumpValveCylinder, _circuit, {"mass balance [1]": 1e-9}, {"t_end": 0.5, "dt_out": 0.01}),
    ReferenceCase("n-link-pendulum", "3 links released at -0.8 rad: energy", lambda: NLinkPendulum(3), _n_link,
                  {"energy drift [J]": 1e-4}, {"t_end": 0.5, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10}),
    ReferenceCase("n-mass-chain", "5 masses on nonlinear springs driven by a sine force: start at rest in place",
                  lambda: NMassChain(5), _chain, {"first mass start offset [m]": 1e-12},
                  {"t_end": 1.0, "dt_out": 0.1}),
    ReferenceCase("limited-sine", "sine through limiter, rate limiter and lag: the limits hold", LimitedSine, _limited,
                  {"limiter output beyond its limits [1]": 1e-6}, {"t_end": 1.0, "dt_out": 0.01}),
]}
