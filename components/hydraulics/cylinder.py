"""Double-acting (differential) hydraulic cylinder with translational flanges."""

from __future__ import annotations

import math
from typing import Any

import casadi as ca

from flexlib import Component, Parameter, Variable, der, eq, if_else
from flexlib.components.mechanics.translational.interfaces import Flange
from flexlib.core.options import flag
from flexlib.errors import ParameterError

from ._checks import PositiveParameters, store_fluid
from .fluid import HLP46, Fluid
from .interfaces import Port, chamber_equations, chamber_mass_nominal, check_chamber_form

__all__ = ["DoubleActingCylinder"]


class DoubleActingCylinder(PositiveParameters, Component):
    """Double-acting differential cylinder: two compressible chambers, piston and rod mass, friction,
    internal and external leakage and end-of-stroke contact.

    Geometry: the piston position ``x = flange_b.s - flange_a.s - L0`` runs from 0 (fully retracted,
    piston on the cap-end stop) to ``stroke`` (fully extended); ``L0`` is the distance between the
    flanges at ``x = 0`` (the closed length of a cylinder between pins). Piston area ``A_p = π/4·d_bore²``,
    annulus area ``A_r = A_p − π/4·d_rod²``; chamber volumes ``V_A = V_dead_A + A_p·x``,
    ``V_B = V_dead_B + A_r·(stroke − x)``.

    Chambers (:func:`~.interfaces.chamber_equations`, exact mass balance)::

        der(m_A) = port_A.m_flow − m_flow_int,           m_A = rho(p_A)·V_A
        der(m_B) = port_B.m_flow + m_flow_int − m_flow_ext, m_B = rho(p_B)·V_B
        m_flow_int = rho(p̄)·G_int·(p_A − p_B)            (laminar piston-seal leakage A → B)
        m_flow_ext = rho(p_B)·G_ext·(p_B − p_D)          (laminar rod-seal leakage out of chamber B)
        q_A = port_A.m_flow / rho(p_A),  q_B = port_B.m_flow / rho(p_B)   (port volume flows, into the chamber)

    The states are the compression masses ``mc_A = m_A − rho_0·V_A = (rho(p_A) − rho_0)·V_A`` and ``mc_B``
    (``rho_0`` the density at ``fluid.p_zero``, 0 Pa for a pure liquid), with the displaced mass written through
    the position, ``der(mc_A) + rho_0·A_p·der(x) = port_A.m_flow − m_flow_int``; the stored masses
    ``m_A = rho_0·V_A(x_start) + dm_A``, ``dm_A = rho_0·A_p·(x − x_start) + mc_A`` are linear in the states, so
    the mass balance is exact, and round-off scales with the compression mass, not with the stored or displaced
    mass, in any piston position (:func:`~.interfaces.chamber_equations`; ``chamber_form`` selects another
    formulation).

    ``p_D`` is the drain port pressure (``use_drain``) or the ambient pressure ``p_amb``: without a
    drain the rod-seal leakage leaves the circuit (its mass is ``∫m_flow_ext dt``).

    Rod (piston + rod, mass ``m``, moving with flange_b; the housing is massless — connect a Mass or a
    body to flange_a for it)::

        m·der(v_rod) = F_hyd − F_fric + F_stop + flange_b.f,   v_rod = der(flange_b.s),   flange_a.f = F
        F = m·der(v_rod) − flange_b.f   (= F_hyd − F_fric + F_stop),   F_hyd = p_A·A_p − p_B·A_r − p_amb·(A_p − A_r)

    The net force ``F`` is written through Newton's law rather than as the sum of its parts: the value is the same, but
    ``F``, like the accelerations it drives, is then a derivative-level unknown that stays out of IDA's local error test
    (``docs/engine.md``, "Error-test policy"; why: ``docs/decisions/011-cylinder-force-through-newtons-law.md``).

    (absolute pressures: the ambient pressure ``p_amb`` acts on the rod cross-section ``A_p − A_r`` outside
    the cylinder and pulls the rod in. Its default is the fluid's reference pressure ``fluid.p_ref``
    (atmospheric for HLP46); ``p_amb = 0`` gives the gauge-pressure force balance
    ``F_hyd = p_A·A_p − p_B·A_r`` of data sheets and Simscape's gauge-based actuators, whatever
    ``fluid.p_ref`` is.) Friction, regularised
    Coulomb + Stribeck + viscous (no events; sticking is a slow creep below ``v_reg``)::

        F_fric = F_c·(1 + (stribeck − 1)·exp(−(v/v_s)²))·tanh(v/v_reg) + d·v

    End stops: a stiff spring–damper contact at each end, switched by state events (``if_else``); it
    acts only while the piston is beyond the end (penetration ``−x`` or ``x − stroke``), damps only
    in contact and never pulls (the contact force is clipped at zero)::

        F_stop = max(0, c_stop·(−x) − d_stop·v)     if x < 0
               − max(0, c_stop·(x − stroke) + d_stop·v)   if x > stroke

    The static penetration is ``F/c_stop`` (0.06 mm for 60 kN on the default 1e9 N/m).

    Parameters
    ----------
    x_fixed : bool
        True if ``x(t0) = x_start`` and ``v(t0) = v_start`` are initial conditions (structural; set it
        False when the position follows from the rest of the model, e.g. a 3D linkage).
    p_fixed : bool
        True if ``p_A(t0) = p_A_start`` and ``p_B(t0) = p_B_start`` are initial conditions (structural;
        False to let ``run(steady_state=True)`` or ``init={"p_A": ...}`` decide).
    use_drain : bool
        True if the rod-seal leakage goes to the drain port ``port_D`` (structural); otherwise it
        leaves the circuit at ``fluid.p_ref``.
    fluid : Fluid
        Fluid property record (structural; default HLP46).
    chamber_form : str
        ``"mass"`` (default), ``"pressure"`` or ``"mass_total"`` (structural; see
        :func:`~.interfaces.chamber_equations`).

    Connectors
    ----------
    port_A : Port
        Cap-side chamber (pressure extends the rod); m_flow positive into the cylinder.
    port_B : Port
        Rod-side (annulus) chamber (pressure retracts the rod).
    port_D : Port
        Drain of the rod seal (only if ``use_drain``).
    flange_a : translational Flange
        Cylinder housing (mounting); ``flange_a.f = F``.
    flange_b : translational Flange
        Rod end, moves with the piston mass.

    Notes
    -----
    Nominal values (error weights, ``atol·nominal``): pressures 1e7 Pa; forces 1e4 N (1e3 N end-stop contact,
    which is zero most of the time);
    position ``stroke`` and velocity ``stroke``/s (per instance, from the constructor's stroke); chamber
    mass deviations and compression masses ``rho_ref·V·1e7/beta`` (the mass that 100 bar adds to the chamber at
    mid-stroke, per instance); volumes ``A_p·stroke``; mass flows 1 kg/s. Functions of ``v`` are weighted as ``v``
    is: the port flows ``A_p·stroke`` and ``A_r·stroke`` [m3/s] (the flows at the nominal velocity), the friction
    force its slope at ``v = 0`` times the nominal velocity, ``(F_c·stribeck/v_reg + d)·stroke`` (at least
    1e3 N), so that a holding cylinder's friction force, steep around ``v = 0``, does not set the step size instead of
    ``v`` (``docs/decisions/032-hydraulic-nominals-follow-the-states.md``).

    ``d_bore``, ``d_rod``, ``stroke``, ``V_dead_A``, ``V_dead_B``, ``v_s``, ``v_reg``, ``c_stop``,
    ``p_A_start`` and ``p_B_start`` must be > 0, ``d_rod < d_bore`` and ``x_start`` within the stroke:
    :meth:`check` tests these whenever values are set (on the component, at flatten and for run-time overrides
    ``run(params=...)``), naming the cylinder.

    References
    ----------
    MathWorks Simscape Fluids, *Double-Acting Actuator (IL)* block documentation (chambers, hard stops).
    Hopsan component library, *Piston* (``HydraulicCylinderC``): chambers, leakage, end stops.
    H. E. Merritt, *Hydraulic Control Systems*, Wiley 1967, §5.2 (actuator continuity and load equations).
    H. Olsson et al., "Friction models and friction compensation", *Eur. J. Control* 4 (1998), §2
    (Stribeck friction).
    """

    _positive = ("d_bore", "d_rod", "stroke", "V_dead_A", "V_dead_B", "v_s", "v_reg", "c_stop", "p_A_start",
                 "p_B_start")

    d_bore = Parameter(unit="m", min=0.0, doc="Piston (bore) diameter")
    d_rod = Parameter(unit="m", min=0.0, doc="Rod diameter, < ``d_bore``")
    stroke = Parameter(unit="m", min=0.0, doc="Stroke")
    L0 = Parameter(0.0, unit="m",
                   doc="Distance ``flange_b.s - flange_a.s`` at x = 0 (closed length between the mounting points)")
    V_dead_A = Parameter(1e-5, unit="m3", min=0.0,
                         doc=("Dead volume of the cap-side chamber A at the end of the stroke (ports, hoses inside the "
                              "cylinder)"))
    V_dead_B = Parameter(1e-5, unit="m3", min=0.0,
                         doc=("Dead volume of the rod-side chamber B at the end of the stroke (ports, hoses inside the "
                              "cylinder)"))
    m = Parameter(unit="kg", min=0.0, doc="Mass of piston and rod")
    F_c = Parameter(0.0, unit="N", min=0.0, doc="Coulomb friction force of the seals")
    stribeck = Parameter(1.0, unit="1", min=1.0, doc="Ratio of break-away (static) to Coulomb friction")
    v_s = Parameter(0.01, unit="m/s", min=0.0, doc="Stribeck velocity")
    d = Parameter(0.0, unit="N.s/m", min=0.0, doc="Viscous friction coefficient")
    v_reg = Parameter(1e-4, unit="m/s", min=0.0,
                      doc="Regularisation velocity of the Coulomb friction (``tanh(v/v_reg)``)")
    G_int = Parameter(0.0, unit="m3/(s.Pa)", min=0.0,
                      doc=("Internal (piston seal) laminar leakage coefficient A -> B, volume flow per pressure "
                           "difference"))
    G_ext = Parameter(0.0, unit="m3/(s.Pa)", min=0.0,
                      doc="External (rod seal) laminar leakage coefficient out of chamber B")
    c_stop = Parameter(1e9, unit="N/m", min=0.0, doc="End-stop contact stiffness")
    d_stop = Parameter(1e5, unit="N.s/m", min=0.0, doc="End-stop contact damping")
    x_start = Parameter(0.0, unit="m", doc="Initial piston position, in [0, ``stroke``] (used if ``x_fixed``)")
    v_start = Parameter(0.0, unit="m/s", doc="Initial piston velocity (used if ``x_fixed``)")
    p_A_start = Parameter(1.01325e5, unit="Pa", min=0.0,
                          doc="Initial absolute pressure in chamber A (used if ``p_fixed``)")
    p_B_start = Parameter(1.01325e5, unit="Pa", min=0.0,
                          doc="Initial absolute pressure in chamber B (used if ``p_fixed``)")
    p_amb = Parameter(1.01325e5, unit="Pa", min=0.0,
                      doc=("Ambient absolute pressure around the cylinder: acts on the rod cross-section (``-p_amb "
                           "(A_p - A_r)`` in ``F_hyd``) and receives the rod-seal leakage without a drain; default "
                           "``fluid.p_ref``, 0 for a force balance in gauge terms"))

    x = Variable(unit="m", state_select="prefer", doc="Piston position relative to the housing")
    v = Variable(unit="m/s", state_select="prefer", doc="Piston velocity relative to the housing")
    a = Variable(unit="m/s2", doc="Piston acceleration relative to the housing")
    v_rod = Variable(unit="m/s", state_select="avoid", doc="Absolute velocity of the rod (flange_b)")
    a_rod = Variable(unit="m/s2", doc="Absolute acceleration of the rod (flange_b)")
    p_A = Variable(unit="Pa", nominal=1e7, start=1.01325e5, doc="Pressure in chamber A")
    p_B = Variable(unit="Pa", nominal=1e7, start=1.01325e5, doc="Pressure in chamber B")
    m_A = Variable(unit="kg", nominal=0.1, doc="Fluid mass in chamber A")
    m_B = Variable(unit="kg", nominal=0.1, doc="Fluid mass in chamber B")
    dm_A = Variable(unit="kg", nominal=1e-3, doc="m_A - rho(p_zero)*V_A(x_start)")
    dm_B = Variable(unit="kg", nominal=1e-3, doc="m_B - rho(p_zero)*V_B(x_start)")
    mc_A = Variable(unit="kg", state_select="prefer", nominal=1e-3, doc="Compression mass m_A - rho(p_zero)*V_A")
    mc_B = Variable(unit="kg", state_select="prefer", nominal=1e-3, doc="Compression mass m_B - rho(p_zero)*V_B")
    V_A = Variable(unit="m3", nominal=1e-3, doc="Volume of chamber A")
    V_B = Variable(unit="m3", nominal=1e-3, doc="Volume of chamber B")
    q_A = Variable(unit="m3/s", nominal=1e-3, doc="Volume flow into chamber A at port_A")
    q_B = Variable(unit="m3/s", nominal=1e-3, doc="Volume flow into chamber B at port_B")
    F = Variable(unit="N", nominal=1e4, doc="Net force of housing and fluid on the rod (extending)")
    F_hyd = Variable(unit="N", nominal=1e4, doc="Pressure force on the piston (extending)")
    F_fric = Variable(unit="N", nominal=1e3, doc="Friction force opposing v")
    F_stop = Variable(unit="N", nominal=1e3, doc="End-stop contact force (extending)")
    m_flow_int = Variable(unit="kg/s", nominal=1.0, doc="Internal leakage mass flow A -> B")
    m_flow_ext = Variable(unit="kg/s", nominal=1.0, doc="External leakage mass flow out of chamber B")

    port_A = Port(doc="Cap-side chamber")
    port_B = Port(doc="Rod-side chamber")
    flange_a = Flange(doc="Housing (mounting)")
    flange_b = Flange(doc="Rod end")

    def __init__(self, x_fixed: bool = True, p_fixed: bool = True, use_drain: bool = False,
                 fluid: Fluid = HLP46, chamber_form: str = "mass", **kw: Any) -> None:
        kw.setdefault("p_amb", fluid.p_ref if isinstance(fluid, Fluid) else HLP46.p_ref)
        super().__init__(**kw)
        store_fluid(self, fluid)
        self.chamber_form = check_chamber_form(self, chamber_form)
        self.x_fixed = flag(self, "x_fixed", x_fixed)
        self.p_fixed = flag(self, "p_fixed", p_fixed)
        self.use_drain = flag(self, "use_drain", use_drain, structural=True)
        if self.use_drain:
            self.port_D = Port(doc="Drain of the rod seal")

    def nominals(self) -> dict[str, float]:
        """Nominals from the geometry at the build's values (see ``interfaces.P_NOMINAL``;
        :mod:`flexlib.compile.scaling`): position and speed by the stroke, the port flows and the friction force
        as functions of the speed, the chambers by their volumes."""
        val = {n: self.parameter_value(n) for n in ("d_bore", "d_rod", "stroke", "V_dead_A", "V_dead_B")}
        if any(v is None for v in val.values()):
            return {}
        stroke, a_p = float(val["stroke"]), math.pi / 4.0 * float(val["d_bore"]) ** 2
        a_r = a_p - math.pi / 4.0 * float(val["d_rod"]) ** 2
        rho = float(self.fluid.rho_ref)  # the port mass flows as the volume flows (a port at a node of several lines
        out = {"x": stroke, "v": stroke, "q_A": a_p * stroke, "q_B": a_r * stroke,  # is not an alias of one line's)
               "port_A.m_flow": rho * a_p * stroke, "port_B.m_flow": rho * a_r * stroke}
        fric = {n: self.parameter_value(n) for n in ("F_c", "stribeck", "v_reg", "d")}
        if all(v is not None for v in fric.values()):
            slope = float(fric["F_c"]) * float(fric["stribeck"]) / float(fric["v_reg"]) + float(fric["d"])
            out["F_fric"] = max(self._decls["F_fric"].nominal, slope * stroke)
        V_A, V_B = float(val["V_dead_A"]) + a_p * stroke, float(val["V_dead_B"]) + a_r * stroke
        mid_A = chamber_mass_nominal(self.fluid, float(val["V_dead_A"]) + a_p * stroke / 2)
        mid_B = chamber_mass_nominal(self.fluid, float(val["V_dead_B"]) + a_r * stroke / 2)
        return {**out, "V_A": V_A, "V_B": V_B, "dm_A": mid_A, "dm_B": mid_B, "mc_A": mid_A, "mc_B": mid_B}

    def check(self, values: dict[str, Any]) -> None:
        super().check(values)
        label = self.where
        val = {n: values.get(n) for n in ("d_bore", "d_rod", "stroke", "x_start")}
        if val["d_bore"] is not None and val["d_rod"] is not None and not val["d_rod"] < val["d_bore"]:
            raise ParameterError(f"{label}: rod diameter d_rod = {float(val['d_rod'])!r} m >= bore "
                                 f"d_bore = {float(val['d_bore'])!r} m (no annulus)")
        if val["stroke"] is not None and val["x_start"] is not None and not 0.0 <= val["x_start"] <= val["stroke"]:
            raise ParameterError(f"{label}: x_start = {float(val['x_start'])!r} m is outside the stroke "
                                 f"[0, {float(val['stroke'])!r}] m")

    # -- geometry --------------------------------------------------------------------------------
    @property
    def A_p(self) -> ca.SX:
        """Piston area [m2]."""
        return math.pi / 4.0 * self.d_bore**2

    @property
    def A_r(self) -> ca.SX:
        """Annulus (rod-side) area [m2]."""
        return math.pi / 4.0 * (self.d_bore**2 - self.d_rod**2)

    def friction_force(self) -> ca.SX:
        """Regularised Coulomb–Stribeck–viscous friction force opposing ``v`` [N]."""
        v = self.v
        return (self.F_c * (1.0 + (self.stribeck - 1.0) * ca.exp(-(v / self.v_s) ** 2)) * ca.tanh(v / self.v_reg)
                + self.d * v)

    def stop_force(self) -> ca.SX:
        """End-stop contact force (state events at contact and at zero contact force) [N]."""
        x, v = self.x, self.v
        f_cap = self.c_stop * (-x) - self.d_stop * v
        f_rod = self.c_stop * (x - self.stroke) + self.d_stop * v
        return (if_else(ca.logic_and(x < 0.0, f_cap > 0.0), f_cap, 0.0)
                - if_else(ca.logic_and(x > self.stroke, f_rod > 0.0), f_rod, 0.0))

    def equations(self) -> list:
        fa, fb, fl = self.flange_a, self.flange_b, self.fluid
        p_A, p_B = self.p_A, self.p_B
        p_D = self.port_D.p if self.use_drain else self.p_amb
        rho_AB = fl.density(0.5 * (p_A + p_B))
        eqs = [
            eq(self.x, fb.s - fa.s - self.L0, label="piston position"),
            eq(der(self.x), self.v), eq(der(self.v), self.a),
            eq(der(fb.s), self.v_rod), eq(der(self.v_rod), self.a_rod),
            eq(self.port_A.p, p_A), eq(self.port_B.p, p_B),
            eq(self.V_A, self.V_dead_A + self.A_p * self.x),
            eq(self.V_B, self.V_dead_B + self.A_r * (self.stroke - self.x)),
            eq(self.m_flow_int, rho_AB * self.G_int * (p_A - p_B)),
            eq(self.m_flow_ext, fl.density(p_B) * self.G_ext * (p_B - p_D)),
            *chamber_equations(fl, self.m_A, p_A, self.V_A, self.port_A.m_flow - self.m_flow_int, dm=self.dm_A,
                               mc=self.mc_A, V_ref=self.V_dead_A + self.A_p * self.x_start,
                               dV=self.A_p * (self.x - self.x_start), form=self.chamber_form),
            *chamber_equations(fl, self.m_B, p_B, self.V_B, self.port_B.m_flow + self.m_flow_int - self.m_flow_ext,
                               dm=self.dm_B, mc=self.mc_B,
                               V_ref=self.V_dead_B + self.A_r * (self.stroke - self.x_start),
                               dV=-self.A_r * (self.x - self.x_start), form=self.chamber_form),
            eq(self.q_A, self.port_A.m_flow / fl.density(p_A)), eq(self.q_B, self.port_B.m_flow / fl.density(p_B)),
            eq(self.F_hyd, p_A * self.A_p - p_B * self.A_r - self.p_amb * (self.A_p - self.A_r)),
            eq(self.F_fric, self.friction_force()),
            eq(self.F_stop, self.stop_force()),
            eq(self.m * self.a_rod, self.F_hyd - self.F_fric + self.F_stop + fb.f, label="piston and rod: Newton"),
            eq(self.F, self.m * self.a_rod - fb.f, label="net force on the rod (through Newton's law)"),
            eq(fa.f, self.F, label="massless housing"),
        ]
        if self.use_drain:
            eqs.append(eq(self.port_D.m_flow, -self.m_flow_ext))
        if self.chamber_form != "mass":
            rho_0 = float(fl.density(fl.p_zero))
            eqs += [eq(self.mc_A, self.m_A - rho_0 * self.V_A), eq(self.mc_B, self.m_B - rho_0 * self.V_B),
                    eq(self.dm_A, self.m_A - rho_0 * (self.V_dead_A + self.A_p * self.x_start)),
                    eq(self.dm_B, self.m_B - rho_0 * (self.V_dead_B + self.A_r * (self.stroke - self.x_start)))]
        return eqs

    def initial_equations(self) -> list:
        """``x_fixed``: x = x_start, v = v_start; ``p_fixed``: p_A = p_A_start, p_B = p_B_start."""
        out = []
        if self.x_fixed:
            out += [eq(self.x, self.x_start, label="start position"), eq(self.v, self.v_start, label="start velocity")]
        if self.p_fixed:
            out += [eq(self.p_A, self.p_A_start, label="start pressure A"),
                    eq(self.p_B, self.p_B_start, label="start pressure B")]
        return out
