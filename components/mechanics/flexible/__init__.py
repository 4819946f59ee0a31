"""Modal data for flexible bodies: beam FE mesher, FE matrix files, Craig–Bampton reduction, inertia
invariants, the open HDF5 modal file, mode selection and default modal damping (SI units throughout)."""

from .beam import beam_mesh, beam_stress_modes, element_matrices, section_force_modes
from .fe_model import COMPONENTS, BeamElements, FEModel, MassPoints, read_fe, read_matrix_market
from .geometric import (
    geometric_stiffness_matrix,
    inertial_load_cases,
    interface_load_cases,
    modal_geometric_stiffness,
)
from .importers import read_ansys_full, read_nastran_dmig, read_nastran_op4  # optional extras: ansys, nastran
from .invariants import INVARIANT_NAMES, inertia_invariants
from .modal_data import FORMAT_VERSION, SI_UNITS, ModalData
from .reduction import CraigBamptonResult, craig_bampton, modal_data_from_fe
from .sections import Section, box, circle, i_section, rectangle, tube
from .selection import (
    ParticipationRow,
    ParticipationTable,
    default_damping_ratio,
    modal_damping_matrix,
    modal_participation,
    nodal_generalized_forces,
    select_modes,
)

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
    "beam_mesh",
    "beam_stress_modes",
    "box",
    "circle",
    "craig_bampton",
    "default_damping_ratio",
    "element_matrices",
    "geometric_stiffness_matrix",
    "i_section",
    "inertia_invariants",
    "inertial_load_cases",
    "interface_load_cases",
    "modal_damping_matrix",
    "modal_data_from_fe",
    "modal_geometric_stiffness",
    "modal_participation",
    "nodal_generalized_forces",
    "read_ansys_full",
    "read_fe",
    "read_matrix_market",
    "read_nastran_dmig",
    "read_nastran_op4",
    "rectangle",
    "section_force_modes",
    "select_modes",
    "tube",
]
