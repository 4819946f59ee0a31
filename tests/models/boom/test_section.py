"""Bench test of :class:`flexlib.models.boom.BoomSection`: a horizontal section pinned at its root (revolute) and held
at its tip by a roller (a revolute at the tip pin on a horizontal prismatic slider on the ground): zero degrees of
freedom, statically determinate in its plane (out of it the closed loop repeats three rows).

References and tolerances:

* Rigid: moments about the root pin, ``F_tip = g (m x_CM + Σ m_i x_i) / L`` upwards at the tip, root reaction
  ``W − F_tip`` upwards, no horizontal reaction (J. L. Meriam, L. G. Kraige, *Engineering Mechanics: Statics*, ch. 3);
  1e-9 relative (measured 2e-16).
* Flexible (uniform steel box, 24 beam elements, Craig–Bampton with the root, tip and pin stations as interface):
  a vertical tip load ``F`` (``WorldForce``, no gravity) on the section clamped at its root (clamped reduction,
  all in-plane modes kept, so the tip's static constraint mode is in the basis; the cubic beam elements are exact
  for a tip load) gives the Euler–Bernoulli cantilever deflection ``F L³ / (3 E I)`` within 1e-6 relative, as the
  FlexibleBody's own cantilever test (measured 6e-12).
  The pin reactions of the pinned–roller section built flexible (pinned reduction, six in-plane modes) from the
  same arguments are the rigid ones up to the deflected geometry (the centre of mass moves along x by the beam's
  shortening, ~(w/L)² L with the own-weight sag w ~ 1e-3 m): 1e-6 relative (measured 1e-8).
"""

from __future__ import annotations

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics.multibody import FixedTranslation, Prismatic, Revolute, World, WorldForce
from flexlib.errors import ParameterError
from flexlib.fe import beam_mesh, box, modal_data_from_fe, planar_modes
from flexlib.models.boom import BoomSection
from flexlib.models.reference.signal_chain import VectorConstant
from flexlib.units import g_n

G = g_n  # standard gravity: the World's default, as MSL's
L = 10.0
M, R_CM, I_CM = 2000.0, (4.0, 0.2), np.diag([50.0, 1.7e4, 1.7e4])
PINS = {"C": (1.0, -0.5), "P_next": (L + 0.3, 0.35)}
HOSE = (200.0, (L, 0.0))
B, H, T_WALL, E, RHO = 0.4, 0.6, 0.008, 2.1e11, 7850.0


class Cantilever(fl.Model):
    """The section clamped at its root pin, a vertical force ``F`` [N] on its tip pin, no gravity."""

    def __init__(self, section: BoomSection, F: float) -> None:
        super().__init__()
        self.world = World(g=0.0)
        self.section = section
        self.load = VectorConstant(k=[0.0, F, 0.0])
        self.force = WorldForce()
        self.connect(self.world.frame_b, section.frame_root)
        self.connect(self.load.y, self.force.force)
        self.connect(self.force.frame_b, section.frame_tip)


class Bench(fl.Model):
    """Root revolute on the ground; tip pin on a roller (prismatic along world x) at (L, 0)."""

    def __init__(self, section: BoomSection) -> None:
        super().__init__()
        self.world = World()
        self.section = section
        self.pivot = Revolute()
        self.support = FixedTranslation(r=[L, 0.0, 0.0])
        self.slider = Prismatic(n=[1.0, 0.0, 0.0])
        self.tip_pin = Revolute()
        self.connect(self.world.frame_b, self.pivot.frame_a, self.support.frame_a)
        self.connect(self.pivot.frame_b, section.frame_root)
        self.connect(self.support.frame_b, self.slider.frame_a)
        self.connect(self.slider.frame_b, self.tip_pin.frame_a)
        self.connect(self.tip_pin.frame_b, section.frame_tip)


def reactions(res) -> tuple[np.ndarray, np.ndarray]:
    """Forces of the root pin and the tip pin on the section [N], world x–y (section frame horizontal; the pins' frames
    turn about z, so their in-plane components give these: the out-of-plane ones are statically indeterminate, the
    bench's loop being planar)."""
    out = []
    for pin in ("pivot", "tip_pin"):
        T = np.asarray(res[f"{pin}.frame_b.T"][0]).reshape(3, 3, order="F")
        f = np.array([res[f"{pin}.frame_b.f[{i}]"][0] for i in (0, 1)])
        out.append(-T[:2, :2].T @ f)
    return out[0], out[1]


def hand(m_total: float, moment: float) -> tuple[float, float]:
    """Tip force and root reaction [N] upwards: ``F_tip L = g Σ m x``."""
    F_tip = G * moment / L
    return m_total * G - F_tip, F_tip


def beam_data(attachment: str):
    """Uniform steel box root to tip, the pins' stations as interface nodes, reduced ``attachment`` at the root."""
    stations = sorted({0.0, L, *(min(max(p[0], 0.0), L) for p in PINS.values())})
    fe = beam_mesh((0.0, 0.0, 0.0), (L, 0.0, 0.0), 24, box(B, H, T_WALL), E=E, rho=RHO, rotary_inertia=True,
                   nodes_at=stations)
    x = fe.nodes[:, 0]
    nodes = [int(fe.node_ids[np.argmin(np.abs(x - s))]) for s in stations]
    return modal_data_from_fe(fe, nodes, 12, reference_node=nodes[0], attachment=attachment, title="bench section",
                              creator="tests/models/boom/test_section.py")


@pytest.fixture(scope="module")
def data():
    return beam_data("pinned")


@pytest.fixture(scope="module")
def rigid():
    sec = BoomSection(L, m=M, r_CM=R_CM, I=I_CM, pins=PINS, payload=[HOSE])
    return fl.Simulation(Bench(sec), codegen=False).initialize()


def test_rigid_reactions_hand_statics(rigid):
    f_root, f_tip = reactions(rigid)
    R_root, F_tip = hand(M + HOSE[0], M * R_CM[0] + HOSE[0] * HOSE[1][0])
    assert f_tip[1] == pytest.approx(F_tip, rel=1e-9)
    assert f_root[1] == pytest.approx(R_root, rel=1e-9)
    assert abs(f_root[0]) + abs(f_tip[0]) <= 1e-9 * F_tip


def test_rigid_pin_frames_where_the_pins_are(rigid):
    for name, (x, y) in PINS.items():
        r = np.asarray(rigid[f"section.pin_{name}.frame_b.r_0"][0])
        np.testing.assert_allclose(r, [x, y, 0.0], atol=1e-12)


def test_flexible_tip_deflection_euler_bernoulli():
    data = beam_data("clamped")
    F = 1e5
    sec = BoomSection(L, pins=PINS, modal_data=data, modes=len(planar_modes(data, "xy")))
    res = fl.Simulation(Cantilever(sec, F), codegen=False).initialize()
    w = float(np.asarray(res["section.deflection.r_rel"][0])[1])
    assert w == pytest.approx(F * L**3 / (3 * E * box(B, H, T_WALL).Iz), rel=1e-6)


def test_flexible_reactions_equal_rigid(data):
    """The same arguments (the modal data's mass properties, pins, hose) built rigid and flexible: pin reactions."""
    args = {"m": data.mass, "r_CM": data.center_of_mass, "I": data.inertia_cm, "pins": PINS, "payload": [HOSE]}
    rigid = reactions(fl.Simulation(Bench(BoomSection(L, **args)), codegen=False).initialize())
    flexible = reactions(fl.Simulation(Bench(BoomSection(L, **args, modal_data=data, modes=6)),
                                       codegen=False).initialize())
    R_root, F_tip = hand(data.mass + HOSE[0], data.mass * data.center_of_mass[0] + HOSE[0] * HOSE[1][0])
    assert rigid[1][1] == pytest.approx(F_tip, rel=1e-9)
    assert rigid[0][1] == pytest.approx(R_root, rel=1e-9)
    assert flexible[1][1] == pytest.approx(rigid[1][1], rel=1e-6)
    assert flexible[0][1] == pytest.approx(rigid[0][1], rel=1e-6)


@pytest.mark.parametrize(("kwargs", "argument"), [
    ({"length": -1.0, "m": M, "r_CM": R_CM, "I": I_CM}, "length"),
    ({"length": L, "m": 0.0, "r_CM": R_CM, "I": I_CM}, "m"),
    ({"length": L, "m": M, "r_CM": (1.0,), "I": I_CM}, "r_CM"),
    ({"length": L, "m": M, "r_CM": R_CM, "I": np.eye(2)}, "I"),
    ({"length": L, "m": M, "r_CM": R_CM}, "I"),
    ({"length": L, "m": M, "r_CM": R_CM, "I": I_CM, "pins": {"tip": (1.0, 0.0)}}, "pins"),
    ({"length": L, "m": M, "r_CM": R_CM, "I": I_CM, "pins": {"C": "x"}}, "pins['C']"),
    ({"length": L, "m": M, "r_CM": R_CM, "I": I_CM, "payload": [(10.0,)]}, "payload[0]"),
    ({"length": L, "m": M, "r_CM": R_CM, "I": I_CM, "modes": 3}, "modes"),
])
def test_bad_input(kwargs, argument):
    with pytest.raises(ParameterError, match=rf"BoomSection: .*{argument.replace('[', '.').replace(']', '.')}"):
        BoomSection(**kwargs)


def test_flexible_bad_input(data):
    with pytest.raises(ParameterError, match="BoomSection: m = "):
        BoomSection(L, m=2 * data.mass, modal_data=data)
    with pytest.raises(ParameterError, match="BoomSection: length = "):
        BoomSection(L + 1.0, modal_data=data)
    with pytest.raises(ParameterError, match="BoomSection: modal_data has no interface node"):
        BoomSection(L, pins={"D": (5.55, 0.0)}, modal_data=data)
