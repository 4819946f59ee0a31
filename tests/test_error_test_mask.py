"""Which unknowns IDA's local error test sees with recursive kinematics (``structure.derivative_level``).

Frames carry their acceleration less gravity ``a`` and angular acceleration ``z`` along the tree, marked untested by
the multibody compile pass (``flexlib/compile/passes/multibody/kinematics.py``): what a joint's acceleration reaches
is kept out of the test with the reactions it determines, while a frame acceleration that positions and velocities
alone give (gravity carried out from the World) is tested like any algebraic unknown. Both halves were measured
wrong on their own (``docs/engine.md``, "Error-test policy"); the physics tests that caught them are the bearing
friction curve (``test_friction.py``) and the universal-joint conical pendulum (``test_parts_joints.py``). Here the
marks themselves.
"""

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, Revolute, World


class FrictionRotor(fl.Model):
    """A disk with its centre of mass on a horizontal frictional revolute axis."""

    def __init__(self) -> None:
        super().__init__()
        self.world = World(g=9.81)
        self.bearing = Revolute(n=[0, 0, 1], use_friction=True, tau_c0=0.3, init={"phi": 0.0, "w": 3.0})
        self.disk = Body(m=4.0, I=np.diag([0.05, 0.05, 0.05]))
        self.connect(self.world.frame_b, self.bearing.frame_a)
        self.connect(self.bearing.frame_b, self.disk.frame_a)


def _marks(sim: fl.Simulation) -> dict[str, bool]:
    m = sim.compiled
    return dict(zip(m.y_names, np.asarray(m.derivative_level, dtype=bool), strict=True))


def test_gravity_only_frame_acceleration_is_tested_reaction_is_not(monkeypatch):
    """The disk's frame acceleration is gravity turned by the joint angle (tested); the bearing reaction, which
    the disk's angular acceleration enters through its centre-of-mass offset, is not, nor is the friction torque
    computed from it; the states are always tested. Built without the explicit-elimination stage, which would
    otherwise remove the frame acceleration (a kinematic intermediate) from the unknowns."""
    monkeypatch.setenv("FLEXLIB_EXPLICIT", "0")
    marks = _marks(fl.Simulation(FrictionRotor(), use_cache=False))
    frame_a = [n for n in marks if n.startswith("disk.frame_a.a[")]
    assert frame_a and not any(marks[n] for n in frame_a)
    assert marks["disk.frame_a.f[0]"] and marks["disk.frame_a.f[1]"] and marks["bearing.tau_f"]
    assert not marks["bearing.phi"] and not marks["bearing.w"]


def test_without_the_declaration_the_point_mass_accelerations_would_be_tested(monkeypatch):
    """The mark is what excludes the point mass's angular acceleration about the rod's swing axis on a
    universal joint (the one that a joint acceleration reaches): with ``Frame.a`` and ``Frame.z`` marked tested,
    the mask loses it, which took the conical-pendulum test 22 000 steps instead of 1 040."""
    from flexlib.models.reference.rigid_pendulum import PointOnRod, UniversalPendulum

    def build():
        init = {"phi_a": 0.5, "phi_b": 0.0, "w_a": 0.0, "w_b": 3.0}
        return _marks(fl.Simulation(UniversalPendulum(PointOnRod(0.8, 1.2), init), use_cache=False))

    declared = build()
    assert declared["link.mass.z_a[0]"] and declared["link.mass.z_a[1]"]
    from flexlib.compile.passes.multibody import kinematics

    for name in ("a", "z"):
        monkeypatch.setitem(kinematics.FRAME_MARKS, name, (True, True))
    undeclared = build()
    assert not undeclared["link.mass.z_a[0]"]
