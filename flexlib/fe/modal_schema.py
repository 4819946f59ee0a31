"""The schema of the HDF5 modal file (``docs/modal_file.md``) and its checks: format version, SI units, the dataset
paths of every field, the grammar of the unit load case names, and the validation of a
:class:`~.modal_data.ModalData` (shapes, dtypes, finite values, symmetric and definite matrices, frequencies
consistent with the generalised matrices, invariants consistent with the body properties)."""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import Any

import numpy as np

from .invariants import invariant_shapes

__all__ = ["DATASETS", "FORMAT", "FORMAT_VERSION", "LOAD_CASE_NAMES", "SI_UNITS", "InvalidDataset",
           "is_load_case_name", "validate"]

FORMAT = "flexlib-modal"


FORMAT_VERSION = 1


#: Units of every quantity in the file (fixed: the file is SI only).
SI_UNITS: dict[str, str] = {"length": "m", "mass": "kg", "time": "s", "force": "N", "angle": "rad",
                            "frequency": "Hz", "stress": "Pa"}


# attribute -> (dataset path, required, integer?)
DATASETS: dict[str, tuple[str, bool, bool]] = {
    "mass": ("body/mass", True, False),
    "center_of_mass": ("body/center_of_mass", True, False),
    "inertia": ("body/inertia", True, False),
    "node_ids": ("nodes/ids", True, True),
    "coordinates": ("nodes/coordinates", True, False),
    "elements": ("nodes/elements", True, True),
    "faces": ("nodes/faces", False, True),
    "interface_nodes": ("interface/node_ids", True, True),
    "translational_modes": ("modes/translational", True, False),
    "rotational_modes": ("modes/rotational", True, False),
    "generalized_mass": ("modes/generalized_mass", True, False),
    "generalized_stiffness": ("modes/generalized_stiffness", True, False),
    "frequencies": ("modes/frequencies", True, False),
    "damping_ratio": ("modes/damping_ratio", False, False),
    "stress_modes": ("modes/stress", False, False),
    "section_forces": ("modes/section_forces", False, False),
    "static_translations": ("static_loads/translations", False, False),
    "static_rotations": ("static_loads/rotations", False, False),
    "static_modal_loads": ("static_loads/modal_loads", False, False),
    "static_section_forces": ("static_loads/section_forces", False, False),
    "static_stress": ("static_loads/stress", False, False),
}


#: The unit load cases a flexible body knows (geometric stiffness and static responses): the grammar of their names.
LOAD_CASE_NAMES = ("acc_x|y|z, alpha_x|y|z, omega_xx|yy|zz|xy|yz|zx, F<node id>_ux|uy|uz|rx|ry|rz "
                   "(a node of '/nodes/ids')")


_CASE = re.compile(r"(acc|alpha)_[xyz]|omega_(xx|yy|zz|xy|yz|zx)|F(-?\d+)_(ux|uy|uz|rx|ry|rz)")


def is_load_case_name(name: Any, node_ids: Sequence[int] | np.ndarray) -> bool:
    """True if ``name`` is a unit load case a flexible body applies (:data:`LOAD_CASE_NAMES`): an inertial case or a
    load ``F<node>_<component>`` at one of ``node_ids``."""
    match = _CASE.fullmatch(name) if isinstance(name, str) else None
    if match is None:
        return False
    return match.group(3) is None or int(match.group(3)) in {int(k) for k in node_ids}


def _unknown_cases(dataset: str, what: str, names: Sequence[Any], node_ids: np.ndarray) -> None:
    unknown = [k for k in names if not is_load_case_name(k, node_ids)]
    if unknown:
        raise InvalidDataset(dataset, f"{what} {unknown} unknown: a flexible body applies only the load cases "
                                f"{LOAD_CASE_NAMES}; no term of theirs would enter its equations")


_STATIC = ("static_translations", "static_rotations", "static_modal_loads", "static_section_forces", "static_stress")


_REL = 1e-9  # relative tolerance of the symmetry and consistency checks


class InvalidDataset(Exception):
    """A field of modal data that breaks the schema; ``dataset`` is its path in the file."""

    def __init__(self, dataset: str, message: str) -> None:
        super().__init__(message)
        self.dataset = dataset


def _freeze(a: np.ndarray) -> np.ndarray:
    """A read-only copy of ``a``."""
    a = np.array(a, copy=True)
    a.setflags(write=False)
    return a


def _numeric(dataset: str, value: Any, shape: tuple[int, ...] | None, integer: bool = False) -> np.ndarray:
    try:
        a = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InvalidDataset(dataset, f"not an array: {exc}") from None
    if not np.issubdtype(a.dtype, np.number) or np.issubdtype(a.dtype, np.complexfloating):
        raise InvalidDataset(dataset, f"must be real numbers, got dtype {a.dtype}")
    if shape is not None and a.shape != shape:
        raise InvalidDataset(dataset, f"wrong shape {a.shape}, expected {shape}")
    if integer:
        if not np.issubdtype(a.dtype, np.integer):
            if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
                raise InvalidDataset(dataset, "must be integers")
        return _freeze(a.astype(np.int64))
    a = a.astype(np.float64)
    bad = ~np.isfinite(a)
    if bad.any():
        where = tuple(int(x) for x in np.argwhere(bad)[0])
        raise InvalidDataset(dataset, f"non-finite value {a[where]} at index {where}")
    return _freeze(a)


def _symmetric(dataset: str, A: np.ndarray, definite: bool | None) -> None:
    """Symmetry; with ``definite`` True/False also positive definiteness/semidefiniteness (None: symmetry only)."""
    scale = max(np.abs(A).max(initial=0.0), 1e-300)
    asym = np.abs(A - A.T).max(initial=0.0)
    if asym > _REL * scale:
        raise InvalidDataset(dataset, f"not symmetric: max |A - A^T| = {asym:.3g} (max |A| = {scale:.3g})")
    if A.size == 0 or definite is None:
        return
    eig = np.linalg.eigvalsh((A + A.T) / 2)
    if definite and eig.min() <= _REL * scale:
        raise InvalidDataset(dataset, f"not positive definite: smallest eigenvalue {eig.min():.3g}")
    if not definite and eig.min() < -_REL * scale:
        raise InvalidDataset(dataset, f"not positive semidefinite: smallest eigenvalue {eig.min():.3g}")


def _close(dataset: str, a: np.ndarray, b: np.ndarray, what: str, scale: float) -> None:
    err = np.abs(np.asarray(a) - np.asarray(b)).max(initial=0.0)
    if err > 1e-9 * max(scale, 1e-300):
        raise InvalidDataset(dataset, f"contradicts {what} (difference {err:.3g})")


def validate(d: Any) -> dict[str, Any]:
    """Check every field of a :class:`~.modal_data.ModalData`; return the normalised (float64/int64, read-only)
    arrays. Raises :class:`InvalidDataset` naming the dataset at fault."""
    _check_header(d)
    p = {attr: path for attr, (path, _, _) in DATASETS.items()}
    out = _body_and_nodes(d, p)
    N = out["coordinates"].shape[0]
    out.update(_modes(d, p, N))
    m = out["frequencies"].shape[0]
    n_el = out["elements"].shape[0]
    out["section_forces"] = (None if d.section_forces is None
                             else _numeric(p["section_forces"], d.section_forces, (m, n_el, 2, 6)))
    out["geometric_stiffness"] = _geometric_stiffness(d, m, out["node_ids"])
    out.update(_validate_static(d, p, m, N, n_el, out["node_ids"]))
    out["invariants"] = _invariants(d, m, out)
    try:
        out["provenance"] = MappingProxyType(json.loads(json.dumps(dict(d.provenance), sort_keys=True, default=str)))
    except (TypeError, ValueError) as exc:
        raise InvalidDataset("", f"attribute 'provenance' is not JSON-serialisable: {exc}") from None
    out["units"] = MappingProxyType(dict(d.units))
    out["format_version"] = int(d.format_version)
    return out


def _check_header(d: Any) -> None:
    """Format version, SI units, header strings and the mass description."""
    if not isinstance(d.format_version, int | np.integer) or not 1 <= d.format_version <= FORMAT_VERSION:
        raise InvalidDataset("", f"attribute 'format_version' {d.format_version!r} is not supported "
                                 f"(1..{FORMAT_VERSION})")
    if dict(d.units) != SI_UNITS:
        wrong = {k: v for k, v in dict(d.units).items() if SI_UNITS.get(k) != v}
        missing = sorted(set(SI_UNITS) - set(d.units))
        raise InvalidDataset("units", f"must be SI {SI_UNITS}; wrong {wrong}, missing {missing}")
    for key in ("title", "creator", "date", "mass_description"):
        if not isinstance(getattr(d, key), str):
            raise InvalidDataset("header", f"attribute {key!r} must be a string")
    if d.mass_description not in ("consistent", "lumped"):
        raise InvalidDataset("invariants", f"attribute 'mass_description' must be 'consistent' or 'lumped', "
                                           f"got {d.mass_description!r}")


def _body_and_nodes(d: Any, p: dict[str, str]) -> dict[str, Any]:
    """Body properties (mass, centre of mass, inertia), nodes, their connectivity and the interface nodes."""
    out: dict[str, Any] = {}
    mass = _numeric(p["mass"], d.mass, ())
    if mass <= 0:
        raise InvalidDataset(p["mass"], f"must be positive, got {float(mass)!r} kg")
    out["mass"] = float(mass)
    out["center_of_mass"] = _numeric(p["center_of_mass"], d.center_of_mass, (3,))
    out["inertia"] = _numeric(p["inertia"], d.inertia, (3, 3))
    _symmetric(p["inertia"], out["inertia"], definite=False)
    coords = _numeric(p["coordinates"], d.coordinates, None)
    if coords.ndim != 2 or coords.shape[1] != 3:
        raise InvalidDataset(p["coordinates"], f"wrong shape {coords.shape}, expected (N, 3)")
    out["coordinates"] = coords
    N = coords.shape[0]
    ids = _numeric(p["node_ids"], d.node_ids, (N,), integer=True)
    if len(np.unique(ids)) != N:
        raise InvalidDataset(p["node_ids"], "node ids must be distinct")
    out["node_ids"] = ids
    for attr in ("elements", "faces"):
        value = getattr(d, attr)
        if value is None:
            if attr == "elements":
                raise InvalidDataset(p[attr], "is missing")
            out[attr] = None
            continue
        conn = _numeric(p[attr], value, None, integer=True)
        if conn.ndim != 2:
            raise InvalidDataset(p[attr], f"wrong shape {conn.shape}, expected (count, nodes per {attr[:-1]})")
        if conn.size and (conn.min() < 0 or conn.max() >= N):
            raise InvalidDataset(p[attr], f"node index out of range 0..{N - 1}")
        out[attr] = conn
    iface = _numeric(p["interface_nodes"], d.interface_nodes, None, integer=True)
    if iface.ndim != 1:
        raise InvalidDataset(p["interface_nodes"], f"wrong shape {iface.shape}, expected (B,)")
    unknown = sorted(set(iface.tolist()) - set(ids.tolist()))
    if unknown:
        raise InvalidDataset(p["interface_nodes"], f"node ids {unknown} are not in '/nodes/ids'")
    if len(np.unique(iface)) != iface.size:
        twice = sorted({int(k) for k in iface.tolist() if iface.tolist().count(k) > 1})
        raise InvalidDataset(p["interface_nodes"], f"node {twice[0]} is given twice ({iface.tolist()}): each "
                                                   "interface node is one frame of the body")
    out["interface_nodes"] = iface
    return out


def _modes(d: Any, p: dict[str, str], N: int) -> dict[str, Any]:
    """Frequencies, mode shapes, generalised matrices (consistent with the frequencies), damping ratios and stress
    modes."""
    out: dict[str, Any] = {}
    freq = _numeric(p["frequencies"], d.frequencies, None)
    if freq.ndim != 1:
        raise InvalidDataset(p["frequencies"], f"wrong shape {freq.shape}, expected (M,)")
    m = freq.shape[0]
    out["frequencies"] = freq
    for attr in ("translational_modes", "rotational_modes"):
        out[attr] = _numeric(p[attr], getattr(d, attr), (m, N, 3))
    Mg = _numeric(p["generalized_mass"], d.generalized_mass, (m, m))
    Kg = _numeric(p["generalized_stiffness"], d.generalized_stiffness, (m, m))
    _symmetric(p["generalized_mass"], Mg, definite=True)
    _symmetric(p["generalized_stiffness"], Kg, definite=False)
    out["generalized_mass"], out["generalized_stiffness"] = Mg, Kg
    if m:
        expected = np.sqrt(np.maximum(np.diag(Kg), 0.0) / np.diag(Mg)) / (2 * math.pi)
        err = np.abs(freq - expected)
        if np.any(err > 1e-6 * np.maximum(expected, expected.max() * 1e-6)):
            j = int(np.argmax(err))
            raise InvalidDataset(p["frequencies"], f"mode {j}: {freq[j]:.6g} Hz contradicts sqrt(K_jj/M_jj)/(2 pi) "
                                                   f"= {expected[j]:.6g} Hz from the generalised matrices")
    if d.damping_ratio is None:
        out["damping_ratio"] = None
    else:
        zeta = _numeric(p["damping_ratio"], d.damping_ratio, (m,))
        if np.any(zeta < 0):
            raise InvalidDataset(p["damping_ratio"], f"negative damping ratio at mode {int(np.argmin(zeta))}")
        if np.any(zeta > 1):
            j = int(np.argmax(zeta))
            raise InvalidDataset(p["damping_ratio"], f"damping ratio {zeta[j]:g} at mode {j} is above 1: ratios "
                                                     "are fractions of critical damping in [0, 1] (0.02 for 2 %)")
        out["damping_ratio"] = zeta
    out["stress_modes"] = None if d.stress_modes is None else _numeric(p["stress_modes"], d.stress_modes, (m, N, 6))
    return out


def _geometric_stiffness(d: Any, m: int, ids: np.ndarray) -> MappingProxyType | None:
    """The modal geometric stiffness of known unit load cases: symmetric (m, m) matrices."""
    if d.geometric_stiffness is None:
        return None
    geo = {}
    for k, v in dict(d.geometric_stiffness).items():
        if not isinstance(k, str) or not k or "/" in k:
            raise InvalidDataset("geometric_stiffness", f"load case names must be non-empty strings without '/', "
                                                        f"got {k!r}")
        geo[k] = _numeric(f"geometric_stiffness/{k}", v, (m, m))
        _symmetric(f"geometric_stiffness/{k}", geo[k], definite=None)
    _unknown_cases("geometric_stiffness", "load cases", sorted(geo), ids)
    return MappingProxyType(geo)


def _invariants(d: Any, m: int, out: dict[str, Any]) -> MappingProxyType:
    """The nine inertia invariants, of the right shapes and consistent with the body properties in ``out``."""
    if not isinstance(d.invariants, Mapping):
        raise InvalidDataset("invariants", "must map I1..I9 to arrays")
    inv = {}
    for k, shape in invariant_shapes(m).items():
        if k not in d.invariants:
            raise InvalidDataset(f"invariants/{k}", "is missing")
        inv[k] = _numeric(f"invariants/{k}", d.invariants[k], shape)
    _symmetric("invariants/I6", inv["I6"], definite=False)
    _symmetric("invariants/I7", inv["I7"], definite=False)
    mass, com, coords = out["mass"], out["center_of_mass"], out["coordinates"]
    _close("invariants/I1", inv["I1"], mass, "'/body/mass'", mass)
    _close("invariants/I2", inv["I2"], mass * com, "'/body/mass' x '/body/center_of_mass'",
           mass * max(np.abs(com).max(), np.abs(coords).max(initial=0.0), 1e-300))
    _close("invariants/I7", inv["I7"], out["inertia"], "'/body/inertia'", np.abs(out["inertia"]).max())
    return MappingProxyType(inv)


def _validate_static(d: Any, p: dict[str, str], m: int, N: int, n_el: int,
                     out_ids: np.ndarray) -> dict[str, Any]:
    """The static load responses: all or none, names unique, shapes consistent with the cases and modes."""
    out: dict[str, Any] = {attr: None for attr in _STATIC}
    cases = d.load_cases
    if cases is None:
        present = [p[a] for a in _STATIC if getattr(d, a) is not None]
        if present:
            raise InvalidDataset(present[0], "is given without the load case names (attribute 'cases' of "
                                       "'/static_loads')")
        out["load_cases"] = None
        return out
    if (isinstance(cases, str) or not isinstance(cases, Sequence)
            or not all(isinstance(c, str) and c and "/" not in c for c in cases)):
        raise InvalidDataset("static_loads", f"attribute 'cases' must be a list of non-empty names without '/', "
                                       f"got {cases!r}")
    if len(set(cases)) != len(cases):
        raise InvalidDataset("static_loads", "attribute 'cases' names a load case twice")
    _unknown_cases("static_loads", "attribute 'cases': load cases", list(cases), out_ids)
    C = len(cases)
    out["load_cases"] = tuple(cases)
    shapes = {"static_translations": (C, N, 3), "static_rotations": (C, N, 3), "static_modal_loads": (C, m),
              "static_section_forces": (C, n_el, 2, 6), "static_stress": (C, N, 6)}
    for attr, shape in shapes.items():
        value = getattr(d, attr)
        if value is None:
            if attr in ("static_translations", "static_rotations", "static_modal_loads"):
                raise InvalidDataset(p[attr], "is missing (the file has '/static_loads' cases)")
            continue
        out[attr] = _numeric(p[attr], value, shape)
    return out
