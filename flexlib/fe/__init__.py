"""The finite-element toolkit behind flexible bodies (SI units throughout): the FE model record and matrix files
(Matrix Market, ``.npz``, ANSYS and Nastran importers), the beam mesher and cross-sections, Craig–Bampton
reduction, inertia invariants, the open HDF5 modal file, mode selection and default modal damping, geometric
stiffening data, and deformation/stress output and drawing. The component that uses them is
:class:`flexlib.components.mechanics.flexible.FlexibleBody`."""

from .arguments import COMPONENTS
from .beam import beam_mesh, beam_stress_modes, element_matrices, section_force_modes
from .drawing import animate, plot_frame
from .fe_model import BeamElements, FEModel, MassPoints
from .geometric import (
    geometric_stiffness_matrix,
    inertial_load_amplitudes,
    inertial_load_cases,
    interface_load_cases,
    modal_geometric_stiffness,
)
from .importers import read_ansys_full, read_nastran_dmig, read_nastran_op4  # optional extras: ansys, nastran
from .invariants import INVARIANT_NAMES, inertia_invariants
from .matrix_files import read_fe, read_matrix_market
from .modal_data import ModalData
from .modal_from_fe import modal_data_from_fe
from .modal_schema import FORMAT_VERSION, SI_UNITS
from .output import (
    deformed_positions,
    energies,
    nodal_stress,
    node_displacements,
    node_rotations,
    section_forces,
    von_mises,
)
from .reduction import CraigBamptonResult, craig_bampton, elastic_static_responses
from .sections import Section, box, circle, i_section, rectangle, tube
from .selection import (
    ParticipationRow,
    ParticipationTable,
    default_damping_ratio,
    modal_damping_matrix,
    modal_participation,
    nodal_generalized_forces,
    participation_from_load_cases,
    select_modes,
)
from .vtk_series import write_model_vtk, write_vtk_series

__all__ = [
    "COMPONENTS",
    "FORMAT_VERSION",
    "INVARIANT_NAMES",
    "SI_UNITS",
    "BeamElements",
    "CraigBamptonResult",
    "FEModel",
    "MassPoints",
    "ModalData",
    "ParticipationRow",
    "ParticipationTable",
    "Section",
    "animate",
    "beam_mesh",
    "beam_stress_modes",
    "box",
    "circle",
    "craig_bampton",
    "default_damping_ratio",
    "deformed_positions",
    "elastic_static_responses",
    "element_matrices",
    "energies",
    "geometric_stiffness_matrix",
    "i_section",
    "inertia_invariants",
    "inertial_load_amplitudes",
    "inertial_load_cases",
    "interface_load_cases",
    "modal_damping_matrix",
    "modal_data_from_fe",
    "modal_geometric_stiffness",
    "modal_participation",
    "nodal_generalized_forces",
    "nodal_stress",
    "node_displacements",
    "node_rotations",
    "participation_from_load_cases",
    "plot_frame",
    "read_ansys_full",
    "read_fe",
    "read_matrix_market",
    "read_nastran_dmig",
    "read_nastran_op4",
    "rectangle",
    "section_force_modes",
    "section_forces",
    "select_modes",
    "tube",
    "von_mises",
    "write_model_vtk",
    "write_vtk_series",
]
