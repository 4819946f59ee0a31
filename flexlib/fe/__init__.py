"""The finite-element toolkit behind flexible bodies (SI units throughout): the FE model record and matrix files
(Matrix Market, ``.npz``, ANSYS and Nastran importers), the beam mesher and cross-sections, Craig–Bampton
reduction, inertia invariants, the open HDF5 modal file, mode selection and default modal damping, geometric
stiffening data, and deformation/stress output and drawing. The component that uses them is
:class:`flexlib.components.mechanics.flexible.FlexibleBody`.

The names below load their module on first use, so that the component, which needs only the modal data record,
mode selection and load cases, does not import the readers, writers and drawing it does not use.
"""

import importlib
from typing import Any

#: Module (in this package) of each public name.
_MODULES: dict[str, tuple[str, ...]] = {
    "arguments": ("COMPONENTS",),
    "assembly": ("join_models",),
    "beam": ("beam_mesh", "beam_stress_modes", "element_matrices", "section_force_modes"),
    "drawing": ("animate", "plot_frame"),
    "fe_model": ("BeamElements", "FEModel", "MassPoints"),
    "geometric": ("geometric_stiffness_matrix", "inertial_load_amplitudes", "inertial_load_cases",
                  "interface_load_cases", "modal_geometric_stiffness"),
    "importers": ("read_ansys_full", "read_nastran_dmig", "read_nastran_op4"),
    "invariants": ("INVARIANT_NAMES", "inertia_invariants"),
    "matrix_files": ("read_fe", "read_matrix_market"),
    "modal_data": ("ModalData",),
    "modal_from_fe": ("modal_data_from_fe",),
    "modal_schema": ("FORMAT_VERSION", "SI_UNITS"),
    "output": ("deformed_positions", "energies", "nodal_stress", "node_displacements", "node_rotations",
               "section_forces", "von_mises"),
    "reduction": ("craig_bampton", "CraigBamptonResult", "elastic_static_responses"),
    "sections": ("box", "circle", "i_section", "rectangle", "Section", "tube"),
    "selection": ("default_damping_ratio", "modal_damping_matrix", "modal_participation",
                  "nodal_generalized_forces", "participation_from_load_cases", "ParticipationRow",
                  "ParticipationTable", "planar_modes", "select_modes"),
    "vtk_series": ("write_model_vtk", "write_vtk_series"),
}
_WHERE = {name: module for module, names in _MODULES.items() for name in names}

__all__ = sorted(_WHERE)


def __getattr__(name: str) -> Any:
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
