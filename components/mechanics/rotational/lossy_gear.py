"""Gear with mesh efficiency and bearing friction, stuck phases included (MSL ``LossyGear``)."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from flexlib import Parameter, ParameterError, Variable, define_latch, der, eq, if_else, initial, latch, no_event

from ..friction import BACKWARD, FORWARD, FREE, STUCK, characteristic, check_table
from .interfaces import PartialTwoFlangesAndSupport

__all__ = ["LossyGear"]

#: MSL compares efficiencies with 1 and the table with the ideal one to ``Modelica.Constants.eps``
EPS = float(np.finfo(float).eps)


class LossyGear(PartialTwoFlangesAndSupport):
    """Ideal gear ``phi_a = ratio phi_b`` with the mesh efficiency and bearing friction of ``loss_table``, and the
    stuck phase where the torque cannot overcome the losses.

    ``loss_table`` rows ``[|w_a|, eta_mf1, eta_mf2, tau_bf1, tau_bf2]`` give, against the speed of flange_a, the mesh
    efficiency when flange_a drives (``eta_mf1``) and when flange_b drives (``eta_mf2``) and the bearing friction
    torques in those cases (at flange_a). With the torque loss ``tau_loss``::

        0 = flange_b.tau + ratio (flange_a.tau − tau_loss)
        tau_loss = sa                                        stuck (a_a = 0)
                 = (1 − eta_mf1) flange_a.tau + tau_bf1      rolling forward, flange_a driving (quadrant 1)
                 = (1 − 1/eta_mf2) flange_a.tau + tau_bf2    rolling forward, flange_b driving (quadrant 2)
                 (and quadrants 3, 4 mirrored for backward rolling);  a_a = sa − tau_loss rolling

    It breaks away forward when ``sa`` exceeds the loss at ``w = 0`` (``tau_loss_max_p``), backward likewise; the
    modes (forward, backward, stuck; free for the ideal table ``[[0, 1, 1, 0, 0]]``) switch by state events as in
    :mod:`components.mechanics.friction`, here without a breakaway peak (MSL's ``LossyGear``).

    Parameters
    ----------
    loss_table : array_like
        Rows ``[w, eta_mf1, eta_mf2, tau_bf1, tau_bf2]`` ([rad/s], [1], [1], [N.m], [N.m]) with ``w ≥ 0`` rising,
        linear in between and extrapolated; default ideal ``[[0, 1, 1, 0, 0]]``.
    use_support : bool
        True: the housing is the ``support`` flange (it takes the reaction); False: grounded.

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Mechanics.Rotational.Components.LossyGear`` (without the heat port);
    F. Pelchen, C. Schweiger, M. Otter: Modeling and Simulating the Efficiency of Gearboxes and of Planetary
    Gearboxes. 2nd International Modelica Conference, 2002. Validated against the reference results of MSL's
    ``Rotational.Examples.LossyGearDemo1`` and ``LossyGearDemo2``.
    """

    ratio = Parameter(1.0, unit="1", doc="Transmission ratio flange_a.phi / flange_b.phi (≠ 0)")
    phi_a = Variable(unit="rad", doc="Angle of flange_a relative to the support")
    phi_b = Variable(unit="rad", doc="Angle of flange_b relative to the support")
    w_a = Variable(unit="rad/s", doc="Angular velocity of flange_a relative to the support")
    a_a = Variable(unit="rad/s2", doc="Angular acceleration of flange_a relative to the support")
    sa = Variable(unit="1", doc="Path parameter of the loss characteristic (torque [N.m] stuck, else a_a + tau_loss)")
    tau_loss = Variable(unit="N.m", doc="Torque loss at flange_a")
    tau_eta = Variable(unit="N.m", doc="flange_a.tau less the bearing friction: its sign says which side drives")
    mode = Variable(unit="1", doc="Mode: 2 ideal (free), 1 rolling forward, 0 stuck, -1 rolling backward (MSL mode)")
    start_forward = Variable(unit="1", doc="1 while starting to roll forward from stuck (MSL startForward)")
    start_backward = Variable(unit="1", doc="1 while starting to roll backward from stuck (MSL startBackward)")
    locked = Variable(unit="1", doc="1 while stuck (w_a held at zero)")

    def __init__(self, loss_table: Any = ((0.0, 1.0, 1.0, 0.0, 0.0),), use_support: bool = False, **kw: Any) -> None:
        super().__init__(use_support=use_support, **kw)
        arr = self._table(loss_table)
        self.loss_table = Parameter(unit="1", shape=arr.shape,
                                    doc="Rows [w, eta_mf1, eta_mf2, tau_bf1, tau_bf2]: speed [rad/s], efficiencies "
                                        "[1], bearing friction [N.m]")
        self.loss_table = arr

    def _table(self, value: Any) -> np.ndarray:
        arr = check_table(self, "loss_table", value, 5, "[w, eta_mf1, eta_mf2, tau_bf1, tau_bf2]")
        if np.any(arr[:, 1:3] <= 0):
            raise self._bad("the efficiencies eta_mf1, eta_mf2 (columns 2, 3) must be > 0", arr[:, 1:3])
        return arr

    def _bad(self, what: str, values: Any) -> Exception:
        return ParameterError(f"{type(self).__name__}: loss_table: {what}, got {np.asarray(values).tolist()}")

    def check(self, values: dict) -> None:
        super().check(values)
        if values.get("ratio") is not None and float(values["ratio"]) == 0.0:
            raise self._bad("ratio must not be zero", values["ratio"])
        if values.get("loss_table") is not None:
            self._table(values["loss_table"])

    def _losses(self, w: Any) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX]:
        """``eta_mf1, eta_mf2, |tau_bf1|, |tau_bf2|`` at speed ``|w|`` (without events, as MSL's ``noEvent``)."""
        tab = self.loss_table
        speed = no_event(w >= 0, w, -w)
        eta1, eta2, bf1, bf2 = (characteristic(ca.horzcat(tab[:, 0], tab[:, k]), speed) for k in range(1, 5))
        return eta1, eta2, no_event(bf1 >= 0, bf1, -bf1), no_event(bf2 >= 0, bf2, -bf2)

    @staticmethod
    def _bearing_a(eta1: Any, eta2: Any, bf1: Any, bf2: Any) -> ca.SX:
        """The bearing friction on flange_a's side: from ``tau_bf1 = eta_mf1 tau_bf_a + …`` and ``tau_bf2 =
        tau_bf_a/eta_mf2 + …``; half of ``tau_bf1`` when both efficiencies are 1 (not separable)."""
        both_one = ca.logic_and(ca.fabs(eta1 - 1.0) <= EPS, ca.fabs(eta2 - 1.0) <= EPS)
        return no_event(both_one, bf1 / 2, (bf1 - bf2) / (eta1 - 1.0 / eta2 + no_event(both_one, 1.0, 0.0)))

    def equations(self) -> list:
        fa, fb, tab = self.flange_a, self.flange_b, self.loss_table
        ideal = ca.SX(0.0)  # the ideal table [[0, 1, 1, 0, 0]] (parameters: decided at the start, no event)
        if tab.shape[0] == 1:
            exact = ca.SX(1.0)
            for k, value in enumerate((0.0, 1.0, 1.0, 0.0, 0.0)):
                exact = ca.logic_and(exact, ca.fabs(tab[0, k] - value) <= EPS)
            ideal = if_else(exact, 1.0, 0.0)
        eta1, eta2, bf1, bf2 = self._losses(self.w_a)
        eta1_0, eta2_0, bf1_0, bf2_0 = self._losses(ca.SX(0.0))
        bf_a, bf_a_0 = self._bearing_a(eta1, eta2, bf1, bf2), self._bearing_a(eta1_0, eta2_0, bf1_0, bf2_0)
        tau_a = fa.tau
        # the losses at w = 0 decide breakaway (MSL: quadrants at w = 0, the driving side assumed by the sign)
        loss_max_p = no_event(tau_a - bf_a_0 > 0, (1 - eta1_0) * tau_a + bf1_0, (1 - 1 / eta2_0) * tau_a + bf2_0)
        loss_min_m = no_event(tau_a + bf_a_0 > 0, (1 - 1 / eta2_0) * tau_a - bf2_0, (1 - eta1_0) * tau_a - bf1_0)

        fw, bw = latch(name="rolling forward"), latch(name="rolling backward")
        sf, sb = latch(name="start forward"), latch(name="start backward")
        is_ideal = ideal > 0.5
        stuck = ca.logic_and(ca.logic_not(is_ideal), ca.logic_and(ca.logic_not(fw), ca.logic_not(bw)))
        first = initial()
        start_fw = ca.logic_or(ca.logic_and(stuck, self.sa > loss_max_p), ca.logic_and(first, self.w_a > 0))
        start_bw = ca.logic_or(ca.logic_and(stuck, self.sa < loss_min_m), ca.logic_and(first, self.w_a < 0))
        define_latch(sf, start_fw, start_fw)
        define_latch(sb, start_bw, start_bw)
        define_latch(fw, ca.logic_and(sf, self.w_a > 0), self.w_a > 0)
        define_latch(bw, ca.logic_and(sb, self.w_a < 0), self.w_a < 0)
        free = ideal > 0.5
        locked = ca.logic_not(ca.logic_or(ca.logic_or(free, ca.logic_or(fw, sf)), ca.logic_or(bw, sb)))
        forward = ca.logic_or(sf, fw)
        driving_a = if_else(self.tau_eta >= 0, 1.0, 0.0)  # flange_a drives (an event where it changes)
        loss_max = driving_a * ((1 - eta1) * tau_a + bf1) + (1 - driving_a) * ((1 - 1 / eta2) * tau_a + bf2)
        loss_min = driving_a * ((1 - 1 / eta2) * tau_a - bf2) + (1 - driving_a) * ((1 - eta1) * tau_a - bf1)
        rolling = ca.if_else(forward, loss_max, loss_min)
        sliding_mode = ca.if_else(fw, FORWARD, ca.if_else(bw, BACKWARD, STUCK))
        return [*self.support_equations(),
                eq(self.phi_a, fa.phi - self.phi_support), eq(self.phi_b, fb.phi - self.phi_support),
                eq(self.phi_a, self.ratio * self.phi_b),
                eq(0.0, fb.tau + self.ratio * (fa.tau - self.tau_loss)),
                eq(self.w_a, der(self.phi_a)), eq(self.a_a, der(self.w_a)),
                eq(self.tau_eta, ca.if_else(ca.logic_or(free, locked), tau_a,
                                            ca.if_else(forward, tau_a - bf_a, tau_a + bf_a))),
                eq(self.tau_loss, ca.if_else(free, 0.0, ca.if_else(locked, self.sa, rolling))),
                eq(self.a_a, ca.if_else(locked, 0.0, self.sa - self.tau_loss)),
                eq(self.mode, ca.if_else(free, FREE, sliding_mode)),
                eq(self.start_forward, ca.if_else(sf, 1.0, 0.0)), eq(self.start_backward, ca.if_else(sb, 1.0, 0.0)),
                eq(self.locked, ca.if_else(locked, 1.0, 0.0))]
