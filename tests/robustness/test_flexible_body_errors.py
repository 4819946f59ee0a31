"""FlexibleBody given bad input: each a clear error naming the body, the argument or parameter and the file."""

from __future__ import annotations

import numpy as np
import pytest

from flexlib import ModalFileError, ModelError, ParameterError
from flexlib.components.mechanics.flexible import FlexibleBody
from flexlib.fe import beam_mesh, modal_data_from_fe, rectangle


@pytest.fixture(scope="module")
def data():
    fe = beam_mesh((0, 0, 0), (1.0, 0, 0), 6, rectangle(0.02, 0.03), E=2.1e11, rho=7850.0)
    return modal_data_from_fe(fe, [6], 2, reference_node=0, title="six-element beam")


def test_missing_file_names_the_file(tmp_path):
    path = tmp_path / "absent.h5"
    with pytest.raises(ModalFileError, match=r"absent\.h5"):
        FlexibleBody(path)


def test_frame_at_unknown_node(data):
    with pytest.raises(ModelError, match=r"frames: node 99 is not in the modal data"):
        FlexibleBody(data, frames=[0, 99])


def test_frame_named_twice(data):
    with pytest.raises(ModelError, match=r"frames \[0, 0\] name a node twice"):
        FlexibleBody(data, frames=[0, 0])


def test_geometric_stiffening_without_data(data):
    with pytest.raises(ModelError, match=r"geometric_stiffening=True.*'/geometric_stiffness'"):
        FlexibleBody(data, geometric_stiffening=True)


@pytest.mark.parametrize(("modes", "pattern"), [([0, 50], r"modes \[50\] are not in the modal data"),
                                                (-1, r"modes must be >= 0, got -1")])
def test_bad_mode_selection(data, modes, pattern):
    with pytest.raises(ModelError, match=pattern):
        FlexibleBody(data, modes=modes)


def test_damping_for_a_mode_not_kept(data):
    with pytest.raises(ModelError, match=r"damping given for mode 12, but 8 modes are kept"):
        FlexibleBody(data, damping={12: 0.05})


def test_negative_damping_ratio_names_the_parameter(data):
    with pytest.raises(ParameterError, match=r"FlexibleBody: zeta = .* is below its minimum 0"):
        FlexibleBody(data, zeta=np.full(data.n_modes, -0.1))


def test_zeta_of_wrong_length(data):
    with pytest.raises(ParameterError, match="zeta"):
        FlexibleBody(data, zeta=[0.01, 0.02])


def test_frame_at_lookup(data):
    body = FlexibleBody(data)
    assert body.frame_at(6) is body.frame_b
    with pytest.raises(ModelError, match=r"node 3 has no frame \(frames at nodes \[0, 6\]\)"):
        body.frame_at(3)
