"""Design record of the pump-truck boom (issue 11): mass properties, linkage kinematics, statics and sizing.

References: hand formulas for a uniform box beam (m = rho A L, I = m L²/12 + rho L I_section; parallel-axis
theorem for the pipe) at 1e-9; finite differences and a brute-force loop closure (scipy ``fsolve``) for the
linkage kinematics; virtual work (central differences of the potential energy through the forward kinematics)
for the statics at 1e-6.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import brentq

from flexlib.models.pump_truck.kinematics import rot
from flexlib.models.pump_truck.parameters import PumpTruckParameters
from flexlib.models.pump_truck.statics import cylinder_forces, joint_torques, mass_properties, point_masses, sizing

REC = PumpTruckParameters()


@pytest.mark.parametrize("k", range(5))
def test_section_mass_matches_target(k):
    mp = mass_properties(REC, k, pipe=False)
    assert mp["m"] == pytest.approx(REC.sections[k].mass, rel=0.01)


@pytest.mark.parametrize("filled", [True, False])
@pytest.mark.parametrize("k", [0, 4])
def test_mass_properties_against_hand_box_plus_pipe(k, filled):
    rec = replace(REC, pipe=replace(REC.pipe, filled=filled))
    sec = rec.sections[k]
    rho, L, b, h = rec.steel.rho, sec.length, sec.b, sec.h
    t = sec.t(rho)
    bi, hi = b - 2 * t, h - 2 * t
    A = b * h - bi * hi
    Iz_s, Iy_s = (b * h**3 - bi * hi**3) / 12, (h * b**3 - hi * bi**3) / 12
    mb = rho * A * L
    mu = 10.5 + (2400 * math.pi / 4 * 0.125**2 if filled else 0.0)
    mpipe, yp = mu * L, h / 2 + 0.15
    m = mb + mpipe
    yc = mpipe * yp / m
    Ixx = rho * L * (Iy_s + Iz_s) + mb * yc**2 + mpipe * (yp - yc) ** 2
    Iyy = mb * L**2 / 12 + rho * L * Iy_s + mpipe * L**2 / 12
    Izz = mb * L**2 / 12 + rho * L * Iz_s + mb * yc**2 + mpipe * L**2 / 12 + mpipe * (yp - yc) ** 2
    mp = mass_properties(rec, k)
    assert mp["m"] == pytest.approx(m, rel=1e-9)
    np.testing.assert_allclose(mp["com"], [L / 2, yc, 0.0], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(mp["I"], np.diag([Ixx, Iyy, Izz]), rtol=1e-9, atol=1e-9 * Izz)
    assert mb == pytest.approx(sec.mass, rel=1e-12)


def test_pipe_mass_per_metre_filled_and_empty():
    assert REC.pipe.mass_per_m == pytest.approx(40.0, rel=0.01)  # issue 11: about 40 kg/m filled
    assert replace(REC.pipe, filled=False).mass_per_m == 10.5


@pytest.mark.parametrize("k", range(1, 6))
def test_joint_reaches_range_with_transmission_above_minimum(k):
    drive = REC.drive(k)
    span = math.degrees(drive.q_max - drive.q_min)
    assert span >= (180.0 if k > 1 else 84.9)  # joints 2-5 fold through 180 deg; joint 1 -5..80 deg
    worst = min(min(drive.state(q).transmission.values()) for q in np.linspace(drive.q_min, drive.q_max, 721))
    assert worst > REC.min_transmission_deg
    arms = [drive.state(q).lever_arm for q in np.linspace(drive.q_min, drive.q_max, 721)]
    assert np.all(np.sign(arms) == np.sign(arms[0]))  # no dead centre inside the range


@pytest.mark.parametrize("k", range(1, 6))
def test_lever_arm_against_finite_differences(k):
    drive = REC.drive(k)
    hstep = 1e-6
    for q in np.linspace(drive.q_min + 0.01, drive.q_max - 0.01, 9):
        fd = (drive.state(q + hstep).length - drive.state(q - hstep).length) / (2 * hstep)
        assert drive.state(q).lever_arm == pytest.approx(fd, rel=1e-7, abs=1e-9)


@pytest.mark.parametrize("k", range(2, 6))
def test_cylinder_length_against_brute_force_closure(k):
    d = REC.drive(k)
    P, H, c = (np.array(v) for v in (d.P, d.H, d.c))
    for q in np.radians([1.0, 60.0, 120.0, 170.0]) * np.sign(d.q_max + d.q_min):
        C = rot(q) @ c
        st = d.state(q)

        # brute force: walk the lever angle round the pivot, bracket |T - C| = s, refine by bisection (brentq)
        def gap(phi, C=C):
            return np.linalg.norm(P + d.r * np.array([math.cos(phi), math.sin(phi)]) - C) - d.s

        grid = np.linspace(0.0, 2 * math.pi, 3601)
        vals = [gap(p) for p in grid]
        roots = [brentq(gap, grid[i], grid[i + 1], xtol=1e-15) for i in range(3600) if vals[i] * vals[i + 1] < 0]
        assert len(roots) == 2  # two assembly branches
        tips = [P + d.r * np.array([math.cos(p), math.sin(p)]) for p in roots]
        T = min(tips, key=lambda tip: np.linalg.norm(tip - st.T))
        assert np.linalg.norm(T - st.T) < 1e-9
        assert np.linalg.norm(T - H) == pytest.approx(st.length, rel=1e-9)


def test_joint1_length_brute_force():
    d = REC.joint1
    for q in np.radians([-5.0, 30.0, 80.0]):
        C = np.array([math.cos(q) * d.c[0] - math.sin(q) * d.c[1], math.sin(q) * d.c[0] + math.cos(q) * d.c[1]])
        assert math.dist(C, d.H) == pytest.approx(d.state(q).length, rel=1e-12)


def test_holding_pressures_extended_horizontal_filled():
    rows = sizing(REC)
    limit = 0.8 * 35e6
    for row in rows:
        assert row["sized"]
        assert 0 < row["p"] <= limit
        assert row["p_worst"] <= limit
        assert row["min_transmission_deg"] > 20.0


@pytest.mark.parametrize("q_deg", [(0, 0, 0, 0, 0), (40, -30, 60, -45, 20), (10, 120, -90, 150, -60)])
def test_statics_against_virtual_work(q_deg):
    q = np.radians(q_deg)

    def V(qq):
        _, m, x = point_masses(REC, qq)
        return REC.g * float(m @ x[:, 1])

    F, _ = cylinder_forces(REC, q)
    tau = joint_torques(REC, q)
    hstep = 1e-5
    for k in range(5):
        e = np.zeros(5)
        e[k] = hstep
        dV = (V(q + e) - V(q - e)) / (2 * hstep)
        dl = (REC.drive(k + 1).state(q[k] + hstep).length - REC.drive(k + 1).state(q[k] - hstep).length) / (2 * hstep)
        assert tau[k] == pytest.approx(dV, rel=1e-6)
        assert F[k] == pytest.approx(dV / dl, rel=1e-6)  # Q + F dl/dq = 0 with Q = -dV/dq


def test_design_bores_strokes_and_flows():
    """Issue 28 item 3 (design test: the numbers of this record's geometry): every bore 100–280 mm at 80 % of
    p_system <= 350 bar, retracted length >= stroke + dead length, flow <= 150 L/min at the design joint speed."""
    assert REC.p_system <= 35e6
    for row in sizing(REC):
        assert 0.1 <= row["bore"] <= 0.28, row
        assert row["fits"] and row["l_min"] >= row["stroke"] + row["dead"]
        assert row["flow"] * 6e4 <= 150.0
    assert [round(r["bore"] * 1e3) for r in sizing(REC)] == [250, 220, 220, 125, 100]  # joint 1: levers, links counted


def test_machine_sized_once_on_its_worst_case():
    """The empty-pipe record is the same machine: same cylinders (sized with the pipe filled)."""
    empty = replace(REC, pipe=replace(REC.pipe, filled=False))
    keys = ("bore", "rod", "stroke", "m_housing", "m_rod", "p_worst_A", "p_worst_B")
    assert [[r[k] for k in keys] for r in sizing(empty)] == [[r[k] for k in keys] for r in sizing(REC)]
    # the load does change with the pipe state
    assert joint_torques(empty, np.zeros(5))[0] < joint_torques(REC, np.zeros(5))[0]


def test_cylinder_masses_in_the_load():
    """Cylinder housing and rod weigh in the gravity torque: at joint 1, extended, the torque with them minus without
    them is g Σ m_i x_i over cylinders 2–5 (rigid with joint 1) plus d(g Σ m_i y_i)/dq1 of cylinder 1's own points
    (central differences, 1e-6 rad), to 1e-6."""
    q = np.zeros(5)
    with_c, bare = joint_torques(REC, q), joint_torques(REC, q, cylinders=False)
    _, m, x = point_masses(REC, q)
    # masses: section 1, housing 1, rod 1, then per section k = 2..5: section, housing, rod, lever, link; the hose
    rigid = [4, 5, 9, 10, 14, 15, 19, 20]  # housing and rod of cylinders 2–5
    own = [1, 2]
    h = 1e-6
    e = np.array([h, 0, 0, 0, 0])
    dV = (point_masses(REC, q + e)[2][own, 1] - point_masses(REC, q - e)[2][own, 1]) / (2 * h) @ m[own]
    assert with_c[0] - bare[0] == pytest.approx(REC.g * (float(m[rigid] @ x[rigid, 0]) + dV), rel=1e-6)
    assert with_c[0] / bare[0] > 1.1  # issue 28: the rods alone add ~15 % at hinge 1


def test_the_design_sizing_is_kept_and_read_back_exactly(tmp_path, monkeypatch):
    """The sizing is kept on disk per record and code: read back equal to ``sizing()`` value for value; a damaged
    file is sized again and replaced; another record has its own file."""
    from flexlib.models.pump_truck import statics
    from flexlib.models.pump_truck.parameters import PumpTruckParameters

    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(tmp_path))
    design = statics.worst_case(PumpTruckParameters())
    fresh = statics.sizing(design)
    first = statics._stored_sizing(design)
    (kept,) = (tmp_path / "pump_truck").glob("sizing-*.json")
    again = statics._stored_sizing(design)
    kept.write_text("{not json")
    healed = statics._stored_sizing(design)
    for rows in (first, again, healed):
        assert [sorted(r) for r in rows] == [sorted(r) for r in fresh]
        assert all(float(r[k]) == float(f[k]) for r, f in zip(rows, fresh, strict=True) for k in f
                   if not isinstance(f[k], bool | str))
    statics._stored_sizing(replace(design, g=9.80))
    assert len(list((tmp_path / "pump_truck").glob("sizing-*.json"))) == 2
