"""Statically indeterminate reactions of over-constrained rigid loops: found at build time, marked in results.

Mechanism: the catalogue's four-bar (flexlib.models.reference.four_bar: crank A, coupler B, rocker C, ground D,
every joint axis along z) with its crank locked at θ2 (a 0-DOF structure) and gravity tilted out of its plane,
``g·(0, −0.6, −0.8)``. By hand: each of the three moving links has three in-plane (F_x, F_y, M_z) and three
out-of-plane (F_z, M_x, M_y) equilibrium equations. In the plane the four pins (two force components each) and the
lock torque are 9 unknowns for 9 equations: the in-plane pin forces, every ``t[2]`` about a pin axis and the lock
torque ``rev1.tau`` are determined. Out of the plane the four revolutes carry ``f_z, t_x, t_y`` each, 12 unknowns
for 9 equations: 3 self-stresses (the 3 loop rows the build drops), so every out-of-plane pin reaction and cut force
of the loop (``f[2]``, ``t[0]``, ``t[1]`` of every frame the loop passes through) is indeterminate; the bodies'
own frames carry their weight and inertia (determined by their motion).

Physical check (the reference of the mark): the out-of-plane weight splits between the two ground pins as the loop
is cut — the rigid model sets the reactions at its cut joint to zero — so cutting the loop at rev2 instead of rev3
changes every marked reaction and none of the others; a Bushing in place of the cut joint (stiff in translation and
tilt, free about the hinge) gives the split of the rigid model cut there (it carries no out-of-plane load between
two rigid cantilevers, up to its deflection), and with a Bushing nothing is dropped and nothing is marked.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import flexlib as fl
from flexlib.components.mechanics import rotational
from flexlib.components.mechanics.multibody import Bushing, Fixed, FixedTranslation, Revolute, World
from flexlib.models.reference import closed_form as ref
from flexlib.models.reference.four_bar import A, B, C, D, link_body

THETA2 = 0.9  # locked crank angle [rad]
G_DIR = [0.0, -0.6, -0.8]  # gravity direction: in the plane (−y) and out of it (−z)
C_BUSH = 1e6  # bushing stiffness [N/m] and [N.m/rad]


class LockedFourBar(fl.Model):
    """The four-bar with its crank locked at ``THETA2``; the loop is closed at ``cut`` ("rev3", coupler–rocker, or
    "rev2", crank–coupler: the connection declared last), which is a Revolute, or with ``bushing`` a Bushing in its
    place (free about z)."""

    def __init__(self, cut: str = "rev3", bushing: bool = False) -> None:
        super().__init__()
        th3, th4 = (float(x) for x in ref.fourbar_angles(A, B, C, D, THETA2, "open"))
        self.world = World(g=9.81, n=G_DIR)
        self.ground4 = Fixed(r=[D, 0, 0])
        self.rev1 = Revolute(use_axis_flange=True, guess={"phi": THETA2})
        self.lock = rotational.Fixed(phi0=THETA2)
        self.crank = FixedTranslation(r=[A, 0, 0])
        self.crank_mass = link_body(1.0, A)
        self.coupler = FixedTranslation(r=[B, 0, 0])
        self.coupler_mass = link_body(2.0, B)
        self.rev4 = Revolute(guess={"phi": th4})
        self.rocker = FixedTranslation(r=[C, 0, 0])
        self.rocker_mass = link_body(1.5, C)
        joints = {"rev2": th3 - THETA2, "rev3": th4 - th3}
        for name, phi in joints.items():
            if bushing and name == cut:
                joint = Bushing(c_trans=[C_BUSH] * 3, d_trans=[1e3] * 3, c_rot=[C_BUSH, C_BUSH, 0.0],
                                d_rot=[1e3, 1e3, 0.0], guess={"phi_rel": [0.0, 0.0, phi]})
            else:
                joint = Revolute(guess={"phi": phi})
            setattr(self, name, joint)
        self.connect(self.rev1.axis, self.lock.flange)
        self.connect(self.world.frame_b, self.rev1.frame_a)
        self.connect(self.rev1.frame_b, self.crank.frame_a)
        self.connect(self.crank.frame_b, self.crank_mass.frame_a, self.rev2.frame_a)
        self.connect(self.coupler.frame_b, self.coupler_mass.frame_a, self.rev3.frame_a)
        self.connect(self.ground4.frame_b, self.rev4.frame_a)
        self.connect(self.rev4.frame_b, self.rocker.frame_a)
        self.connect(self.rocker.frame_b, self.rocker_mass.frame_a)
        # the connection declared last closes the loop; its first frame's cut force is what a dropped row zeroes
        closing = [(self.rev2.frame_b, self.coupler.frame_a), (self.rev3.frame_b, self.rocker.frame_b)]
        for frames in closing if cut == "rev3" else closing[::-1]:
            self.connect(*frames)


#: Reactions by hand (module docstring): in-plane ones determined, out-of-plane ones indeterminate.
DETERMINED = ["rev1.tau", "rev1.frame_a.f[0]", "rev1.frame_a.f[1]", "rev1.frame_a.t[2]", "rev4.frame_a.f[0]",
              "rev4.frame_a.f[1]", "rev2.frame_b.f[0]", "rev2.frame_b.f[1]", "crank.frame_a.t[2]",
              "coupler_mass.frame_a.f[2]", "rocker_mass.frame_a.t[0]"]
INDETERMINATE = ["rev1.frame_a.f[2]", "rev1.frame_a.t[0]", "rev1.frame_a.t[1]", "rev4.frame_a.f[2]",
                 "rev4.frame_b.t[0]", "world.frame_b.f[2]", "ground4.frame_b.t[1]", "crank.frame_a.t[0]",
                 "coupler.frame_b.f[2]"]


def _run(model: fl.Model) -> fl.Result:
    return fl.Simulation(model).run(0.01, dt_out=0.01, steady_state=True, rtol=1e-10, atol=1e-12, progress=False)


def _reactions(res: fl.Result) -> dict[str, float]:
    """Every force and torque of the result at its start (the structure is at rest), read without warnings."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fl.IndeterminateReactionWarning)
        return {n: float(res[n][0]) for n in res.names if n.rsplit(".", 1)[-1].startswith(("f[", "t[", "tau"))}


def test_rigid_four_bar_marks_its_out_of_plane_reactions_and_reading_one_warns():
    """The 3 dropped rows leave exactly the out-of-plane reactions of the loop indeterminate (hand count in the
    module docstring): every marked variable is an out-of-plane component (``f[2]``, ``t[0]``, ``t[1]``), the
    listed ones are marked, the in-plane ones and the lock torque are not. Reading a marked one warns once per
    variable, naming it, the dropped row and the Bushing alternative; reading a determined one does not warn."""
    sim = fl.Simulation(LockedFourBar())
    assert len(sim.report.redundant) == 3
    res = _run(LockedFourBar())
    assert res.indeterminate
    assert all(n.endswith(("f[2]", "t[0]", "t[1]")) for n in res.indeterminate), sorted(res.indeterminate)
    assert not [n for n in INDETERMINATE if n not in res.indeterminate]
    assert not [n for n in DETERMINED if n in res.indeterminate]
    assert all("dropped redundant constraint" in row for rows in res.indeterminate.values() for row in rows)
    with warnings.catch_warnings():
        warnings.simplefilter("error", fl.IndeterminateReactionWarning)
        tau = res["rev1.tau"]  # the lock torque: determined
        f_plane = res["rev1.frame_a.f[1]"]
    assert np.abs(tau).max() > 0.1 and np.abs(f_plane).max() > 1.0  # real loads, not zeros
    with pytest.warns(fl.IndeterminateReactionWarning) as caught:
        res["rev1.frame_a.f"]  # the vector: its out-of-plane element is marked
    text = str(caught[0].message)
    assert "rev1.frame_a.f[2] is statically indeterminate" in text and "rev1.frame_a.f[0]" not in text
    assert "dropped redundant constraint" in text and "Bushing" in text and "FlexibleBody" in text
    with warnings.catch_warnings():  # once per variable and result
        warnings.simplefilter("error", fl.IndeterminateReactionWarning)
        res.value("rev1.frame_a.f[2]", 0.0)
    with pytest.warns(fl.IndeterminateReactionWarning, match=r"rev4\.frame_a\.f\[2\]"):
        frame = res.to_dataframe("rev4.frame_a.f")
    assert frame.attrs["indeterminate"] == ["rev4.frame_a.f[2]"]
    with pytest.warns(fl.IndeterminateReactionWarning, match="ground4"):
        table = res.summary("ground4.frame_b.t", "rev1.tau")
    lines = table.splitlines()
    marked = [line.split()[0] for line in lines if line.endswith("(indeterminate)")]
    assert marked == ["ground4.frame_b.t[0]", "ground4.frame_b.t[1]"]
    assert lines[-1].startswith("(indeterminate): statically indeterminate")
    import matplotlib.pyplot as plt

    ax = res.plot("rev1.frame_a.f", "rev1.tau", "ground4.frame_b.t[1]")  # each already warned about: no warning
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        "rev1.frame_a.f[0] [N]", "rev1.frame_a.f[1] [N]", "rev1.frame_a.f[2] [N] (indeterminate)", "rev1.tau [N.m]",
        "ground4.frame_b.t[1] [N.m] (indeterminate)"]
    plt.close(ax.figure)


def test_the_mark_is_what_another_cut_or_a_bushing_changes():
    """Reference of the mark: the rigid structure cut at rev2 instead of rev3 gives the same in-plane reactions and
    lock torque (1e-9 of the weight) and a different split of the out-of-plane ones. Every reaction that differs is
    marked (by 1 % of the weight or more: no round-off), and a marked one that does not differ is zero in both (the
    coupler's torsion, which neither cut loads). A Bushing (1e6 N/m, N.m/rad) in place of the cut joint drops
    nothing and marks nothing, and gives the rigid split of that cut: 1e-3 of the weight (its deflection)."""
    weight = 9.81 * (1.0 + 2.0 + 1.5)
    rigid = {cut: _run(LockedFourBar(cut)) for cut in ("rev3", "rev2")}
    r3, r2 = (_reactions(rigid[cut]) for cut in ("rev3", "rev2"))
    changed = {n for n in r3 if abs(r3[n] - r2[n]) > 1e-9 * weight}
    assert changed, "the two cuts split the out-of-plane weight alike"
    assert min(abs(r3[n] - r2[n]) for n in changed) > 0.01 * weight
    for res in rigid.values():
        assert changed <= set(res.indeterminate), sorted(changed - set(res.indeterminate))
    assert {n for n in changed if n.startswith(("rev1.", "rev4.", "world.", "ground4."))} >= {
        "rev1.frame_a.f[2]", "rev4.frame_a.f[2]", "world.frame_b.f[2]", "ground4.frame_b.f[2]"}
    same = [n for n in rigid["rev3"].indeterminate if n in r2 and n not in changed]
    assert all(abs(r3[n]) < 1e-9 * weight for n in same), same  # unchanged only where both cuts leave zero
    for cut, res in rigid.items():
        bushed = fl.Simulation(LockedFourBar(cut, bushing=True))
        assert bushed.report.redundant == []
        soft = _run(LockedFourBar(cut, bushing=True))
        assert soft.indeterminate == {}
        with warnings.catch_warnings():
            warnings.simplefilter("error", fl.IndeterminateReactionWarning)
            values = _reactions(soft)
        stiff = _reactions(res)
        for name in ("rev1.frame_a.f[2]", "rev1.frame_a.t[0]", "rev4.frame_a.f[2]", "rev4.frame_a.t[1]",
                     "rev1.frame_a.f[1]", "rev1.tau"):
            assert values[name] == pytest.approx(stiff[name], abs=1e-3 * weight), (cut, name)


def test_cached_build_and_result_file_keep_the_mark(tmp_path):
    """A build loaded from the cache carries the same mark as the fresh one; a result saved and loaded keeps it
    (and a file without it reads as none); ``flexlib show --signals`` marks it in its table instead of warning."""
    fresh = fl.build(LockedFourBar(), use_cache=False)
    fl.build(LockedFourBar())
    cached = fl.build(LockedFourBar())
    assert cached.cached and not fresh.cached
    assert cached.compiled.indeterminate == fresh.compiled.indeterminate != {}
    res = _run(LockedFourBar())
    path = tmp_path / "four_bar.h5"
    res.save(path)
    loaded = fl.load_result(path)
    assert loaded.indeterminate == res.indeterminate
    with pytest.warns(fl.IndeterminateReactionWarning, match=r"rev1\.frame_a\.t\[0\]"):
        loaded["rev1.frame_a.t[0]"]
    from click.testing import CliRunner

    from flexlib.cli import cli

    shown = CliRunner().invoke(cli, ["show", str(path), "--signals", "rev1.frame_a.f"], env={"COLUMNS": "200"},
                               catch_exceptions=False)
    assert shown.exit_code == 0
    assert "rev1.frame_a.f[2] (indeterminate)" in shown.output and "rev1.frame_a.f[0] (" not in shown.output
    import h5py

    older = tmp_path / "older.h5"
    res.save(older)
    with h5py.File(older, "a") as f:
        del f.attrs["indeterminate"]  # as written before the mark
    assert fl.load_result(older).indeterminate == {}
