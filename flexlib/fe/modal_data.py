"""``ModalData``: the open HDF5 modal file of a flexible body (schema in ``docs/modal_file.md``).

The file plays the role of the modal neutral file (MNF) of commercial codes, whose binary format has no public
specification: header, body properties, nodes, interface nodes, translational and rotational mode shapes,
generalised mass and stiffness, frequencies, the nine inertia invariants, optional damping ratios and stress
modes, and the reduction's provenance. Everything is SI: m, kg, s, N, rad, Hz.

References
----------
- The HDF Group, *HDF5 File Format Specification* (read and written with h5py).
- MSC Software, *Adams/Flex*: "The Modal Neutral File (MNF)" (content, not format, of the commercial file).
- A. A. Shabana, *Dynamics of Multibody Systems*, 3rd ed., 2005, ch. 5 (inertia invariants).
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import os
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from flexlib.errors import ModalFileError, RunArgumentError

from .fe_model import UnknownNodeError, node_id_list
from .invariants import INVARIANT_NAMES
from .modal_schema import DATASETS, FORMAT, FORMAT_VERSION, SI_UNITS, InvalidDataset, validate

__all__ = ["ModalData"]


@dataclass(frozen=True, eq=False)
class ModalData:
    """Modal data of one flexible body (immutable: arrays read-only, mappings read-only views). All SI.

    Parameters
    ----------
    title, creator, date : str
        Header text; ``date`` ISO 8601 (default: now, UTC).
    mass : float
        Total mass [kg].
    center_of_mass : ndarray (3,)
        Centre of mass in the body frame [m].
    inertia : ndarray (3, 3)
        Inertia tensor about the body-frame origin, body axes [kg m2] (undeformed body).
    node_ids : ndarray of int (N,)
        Node numbers (as in the FE model).
    coordinates : ndarray (N, 3)
        Undeformed node coordinates in the body frame [m].
    elements : ndarray of int (E, k)
        Element connectivity as indices into ``coordinates`` (drawing; ``(0, 2)`` if none).
    interface_nodes : ndarray of int (B,)
        Node ids of the interface (frames of the flexible body).
    translational_modes, rotational_modes : ndarray (M, N, 3)
        Mode shapes per mode and node: translation [m] and small rotation [rad] per unit modal coordinate.
    generalized_mass, generalized_stiffness : ndarray (M, M)
        Modal mass [kg] (symmetric positive definite) and stiffness [N/m] (symmetric positive semidefinite)
        per unit modal coordinate.
    frequencies : ndarray (M,)
        ``sqrt(K_jj / M_jj) / (2 pi)`` of each mode [Hz] (its natural frequency for orthogonal modes).
    invariants : mapping of str to ndarray
        The nine inertia invariants ``I1`` .. ``I9`` (see :mod:`.invariants`).
    mass_description : str
        ``"consistent"`` or ``"lumped"``: how the invariants were computed.
    damping_ratio : ndarray (M,), optional
        Modal damping ratios [1], each in ``[0, 1]`` (fractions of critical); ``None``: the frequency rule of
        :func:`~flexlib.fe.selection.default_damping_ratio`.
    stress_modes : ndarray (M, N, 6), optional
        Stress per unit modal coordinate at each node [Pa] (sxx, syy, szz, sxy, syz, szx).
    faces : ndarray of int (F, k), optional
        Surface faces for drawing, as indices into ``coordinates``.
    section_forces : ndarray (M, E, 2, 6), optional
        Beam models: section forces ``(N, Vy, Vz, T, My, Mz)`` [N, N m per unit modal coordinate] in element
        axes at both ends of each element of ``elements``.
    geometric_stiffness : mapping of str to ndarray (M, M), optional
        Modal geometric stiffness per unit load case [N/m per unit coordinate and unit load] (see
        :mod:`.geometric`): ``acc_x..z``, ``alpha_x..z``, ``omega_xx..zx``, ``F{node}_{ux..rz}`` (a node of
        ``node_ids``); other names are refused (:data:`~.modal_schema.LOAD_CASE_NAMES`: a flexible body would
        apply none of them).
    load_cases : tuple of str, optional
        Names of the unit load cases of the static responses (as for ``geometric_stiffness``, the same names
        only); stored as the JSON attribute ``cases`` of the group ``/static_loads``.
    static_translations, static_rotations : ndarray (C, N, 3), optional
        The body's exact elastic static response to each unit load case (all FE modes, with inertia relief for
        the rigid-body modes the reference frame carries) [m, rad per unit load].
    static_modal_loads : ndarray (C, M), optional
        Modal loads ``Phi^T f`` of each unit load case [N per unit load].
    static_section_forces : ndarray (C, E, 2, 6), optional; static_stress : ndarray (C, N, 6), optional
        Section forces and stresses of the static responses (as ``section_forces`` and ``stress_modes``).
    provenance : dict
        How the data were made (reduction, FE source, settings); JSON-serialisable.
    units : dict
        Must equal :data:`~.modal_schema.SI_UNITS`.
    format_version : int
        File format version (:data:`~.modal_schema.FORMAT_VERSION`).

    Raises
    ------
    ModalFileError
        Any inconsistency (shapes, symmetry, definiteness, finiteness, units, invariants vs body properties);
        the message names the dataset of the file layout.
    """

    title: str
    creator: str
    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray
    node_ids: np.ndarray
    coordinates: np.ndarray
    elements: np.ndarray
    interface_nodes: np.ndarray
    translational_modes: np.ndarray
    rotational_modes: np.ndarray
    generalized_mass: np.ndarray
    generalized_stiffness: np.ndarray
    frequencies: np.ndarray
    invariants: Mapping[str, np.ndarray]
    mass_description: str = "consistent"
    damping_ratio: np.ndarray | None = None
    stress_modes: np.ndarray | None = None
    faces: np.ndarray | None = None
    section_forces: np.ndarray | None = None
    geometric_stiffness: Mapping[str, np.ndarray] | None = None
    load_cases: tuple[str, ...] | None = None
    static_translations: np.ndarray | None = None
    static_rotations: np.ndarray | None = None
    static_modal_loads: np.ndarray | None = None
    static_section_forces: np.ndarray | None = None
    static_stress: np.ndarray | None = None
    provenance: Mapping[str, Any] = field(default_factory=dict)
    date: str = field(default_factory=lambda: _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"))
    units: Mapping[str, str] = field(default_factory=lambda: dict(SI_UNITS))
    format_version: int = FORMAT_VERSION

    def __post_init__(self) -> None:
        self._check("ModalData")

    def _check(self, source: str) -> None:
        try:
            values = validate(self)
        except InvalidDataset as exc:
            raise ModalFileError(f"{source}: dataset '/{exc.dataset}': {exc}") from None
        for name, value in values.items():
            object.__setattr__(self, name, value)

    # ------------------------------------------------------------------ properties
    @property
    def n_modes(self) -> int:
        """Number of modes ``M``."""
        return int(self.frequencies.shape[0])

    @property
    def n_nodes(self) -> int:
        """Number of nodes ``N``."""
        return int(self.coordinates.shape[0])

    @property
    def inertia_cm(self) -> np.ndarray:
        """Inertia tensor about the centre of mass [kg m2] (parallel-axis theorem)."""
        c = self.center_of_mass
        return self.inertia - self.mass * (float(c @ c) * np.eye(3) - np.outer(c, c))

    def damping_ratios(self) -> np.ndarray:
        """Modal damping ratios [1]: the stored ones, else the default frequency rule."""
        from .selection import default_damping_ratio

        return self.damping_ratio if self.damping_ratio is not None else default_damping_ratio(self.frequencies)

    def node_index(self, node_id: int) -> int:
        """Index into ``coordinates`` of a node id.

        Raises
        ------
        UnknownNodeError
            (a :class:`~flexlib.errors.RunArgumentError` and a ``KeyError``) A node id the data do not have, or not
            a node id (text, a bool, a fractional number); the message names it and the data's ids.
        """
        where = f"modal data {self.title!r}" if self.title else "modal data (untitled)"
        if isinstance(node_id, str | bytes) or np.ndim(node_id) != 0:
            raise UnknownNodeError(f"{where}: a node id is one whole number, got {node_id!r}")
        (node,) = node_id_list(node_id, where)
        hits = np.flatnonzero(self.node_ids == node)
        if hits.size != 1:
            raise UnknownNodeError(f"{where}: no node with id {node} (ids {int(self.node_ids.min())}.."
                                   f"{int(self.node_ids.max())}, {self.n_nodes} nodes)")
        return int(hits[0])

    # ------------------------------------------------------------------ mode subsets
    def select(self, modes: Sequence[int] | np.ndarray) -> ModalData:
        """The same body with a subset of its modes (indices into the current modes, in the given order).

        Raises
        ------
        RunArgumentError
            (a ``ValueError``) ``modes`` not a list of distinct integer indices in ``0 .. n_modes - 1`` (a bool, a
            float or text is refused, not read as an index).
        """
        where = f"modal data {self.title!r}" if self.title else "modal data (untitled)"
        items = [modes] if isinstance(modes, str | bytes) or np.ndim(modes) == 0 else np.asarray(
            modes, dtype=object).ravel().tolist()
        bad = [v for v in items if isinstance(v, bool | np.bool_) or not isinstance(v, int | np.integer)]
        if bad or np.ndim(modes) != 1:
            item = f" (an item {bad[0]!r} of type {type(bad[0]).__name__})" if bad else ""
            raise RunArgumentError(f"{where}.select: modes must be a list of mode indices (ints) in "
                                   f"0..{self.n_modes - 1}, got {modes!r}{item}")
        idx = np.asarray(items, dtype=np.int64)
        if idx.size and (idx.min() < 0 or idx.max() >= self.n_modes or len(np.unique(idx)) != idx.size):
            raise RunArgumentError(f"{where}.select: mode indices must be distinct in 0..{self.n_modes - 1}, got "
                                   f"{idx.tolist()}")
        inv = dict(self.invariants)
        inv["I3"] = inv["I3"][:, idx]
        inv["I4"] = inv["I4"][:, idx]
        inv["I5"] = inv["I5"][idx][:, :, idx]
        inv["I6"] = inv["I6"][np.ix_(idx, idx)]
        inv["I8"] = inv["I8"][idx]
        inv["I9"] = inv["I9"][np.ix_(idx, idx)]
        prov = dict(self.provenance)
        before = prov.get("selected_modes", list(range(self.n_modes)))  # indices into the producer's modes
        prov["selected_modes"] = [int(before[i]) for i in idx]
        return replace(
            self, translational_modes=self.translational_modes[idx], rotational_modes=self.rotational_modes[idx],
            generalized_mass=self.generalized_mass[np.ix_(idx, idx)],
            generalized_stiffness=self.generalized_stiffness[np.ix_(idx, idx)], frequencies=self.frequencies[idx],
            invariants=inv, damping_ratio=None if self.damping_ratio is None else self.damping_ratio[idx],
            stress_modes=None if self.stress_modes is None else self.stress_modes[idx],
            section_forces=None if self.section_forces is None else self.section_forces[idx],
            geometric_stiffness=None if self.geometric_stiffness is None else
            {k: v[np.ix_(idx, idx)] for k, v in self.geometric_stiffness.items()},
            static_modal_loads=None if self.static_modal_loads is None else self.static_modal_loads[:, idx],
            provenance=prov)

    # ------------------------------------------------------------------ mode-acceleration recovery
    def residual_fields(self) -> dict[str, np.ndarray]:
        """Residual (truncated-mode) static responses of the unit load cases for the current modes.

        ``R_c = u_c - Phi K^-1 Phi^T f_c``: the part of the exact static response ``u_c`` to load case ``c``
        that the kept modes ``Phi`` (generalised stiffness ``K``) leave out. An output recovered as
        ``Phi q + sum_c R_c l_c(t)`` with the load amplitudes ``l_c(t)`` is the mode-acceleration method
        (Craig & Kurdila 2006, §10.4): the truncated modes respond quasi-statically.

        Returns
        -------
        dict
            ``cases`` (tuple of str) and, per stored field, ``translations``, ``rotations`` (C, N, 3) [m, rad per
            unit load], ``section_forces`` (C, E, 2, 6) and ``stress`` (C, N, 6) when present.

        Raises
        ------
        ModalFileError
            The data hold no static load responses (made with ``static_loads=False`` or by another producer); a
            ``ValueError``.
        """
        if self.load_cases is None:
            raise ModalFileError(f"modal data {self.title!r}: no static load responses (dataset '/static_loads'); "
                                 "make the data with modal_data_from_fe(..., static_loads=True)")
        K = self.generalized_stiffness
        if self.n_modes:
            coef = np.linalg.lstsq(K, self.static_modal_loads.T, rcond=None)[0]  # (M, C)
        else:
            coef = np.zeros((0, len(self.load_cases)))
        out: dict[str, Any] = {"cases": self.load_cases}
        pairs = (("translations", "static_translations", self.translational_modes),
                 ("rotations", "static_rotations", self.rotational_modes),
                 ("section_forces", "static_section_forces", self.section_forces),
                 ("stress", "static_stress", self.stress_modes))
        for key, attr, modes in pairs:
            full = getattr(self, attr)
            if full is None or (modes is None and self.n_modes):
                continue
            kept = np.zeros_like(full) if modes is None else np.tensordot(coef.T, modes, axes=(1, 0))
            out[key] = full - kept
        return out

    # ------------------------------------------------------------------ hashing
    def content_hash(self) -> str:
        """SHA-256 (hex) of everything the equations of a flexible body depend on: every array (name, dtype,
        shape, little-endian bytes, in a fixed order), the units, the format version and the mass
        description. Header text (title, creator, date) and provenance are left out, so the same data
        written again, or under another name, hashes the same: the compiled-model cache keys on content."""
        h = hashlib.sha256()
        h.update(json.dumps({"format": FORMAT, "format_version": int(self.format_version), "units": dict(self.units),
                             "mass_description": self.mass_description,
                             "load_cases": None if self.load_cases is None else list(self.load_cases)},
                            sort_keys=True).encode())
        for name, array in self._arrays():
            h.update(name.encode() + b"\0")
            if array is None:
                h.update(b"none\0")
                continue
            a = np.array(array, order="C")
            a = a.astype(a.dtype.newbyteorder("<"), copy=False)
            h.update(f"{a.dtype.str}{a.shape}".encode() + b"\0")
            h.update(a.tobytes())
        return h.hexdigest()

    def _arrays(self) -> list[tuple[str, np.ndarray | None]]:
        out: list[tuple[str, np.ndarray | None]] = [
            (path, np.asarray(self.mass, dtype=np.float64) if attr == "mass" else getattr(self, attr))
            for attr, (path, _, _) in DATASETS.items()]
        out += [(f"invariants/{k}", self.invariants[k]) for k in INVARIANT_NAMES]
        if self.geometric_stiffness is not None:
            out += [(f"geometric_stiffness/{k}", v) for k, v in sorted(self.geometric_stiffness.items())]
        return out

    # ------------------------------------------------------------------ files
    def write(self, path: str | os.PathLike[str]) -> Path:
        """Write the HDF5 modal file atomically (temporary file in the same directory, then ``os.replace``).

        Returns
        -------
        Path
            The written file.

        Raises
        ------
        ModalFileError
            The file could not be written (the previous file, if any, is left untouched), or ``path`` is not a
            str or os.PathLike.
        """
        if not isinstance(path, str | os.PathLike):
            raise ModalFileError(f"ModalData.write: path must be the path of the modal file to write (str or Path), "
                                 f"got {path!r} ({type(path).__name__})")
        path = Path(path)
        try:
            fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=path.parent)
        except OSError as exc:
            raise ModalFileError(f"{path}: cannot write the modal file: {exc}") from None
        os.close(fd)
        try:
            with h5py.File(tmp, "w") as f:
                f.attrs["format"] = FORMAT
                f.attrs["format_version"] = int(self.format_version)
                header = f.create_group("header")
                header.attrs["title"] = self.title
                header.attrs["creator"] = self.creator
                header.attrs["date"] = self.date
                units = f.create_group("units")
                for k, v in self.units.items():
                    units.attrs[k] = v
                for name, array in self._arrays():
                    if array is not None:
                        f.create_dataset(name, data=array)
                f["invariants"].attrs["mass_description"] = self.mass_description
                if self.load_cases is not None:
                    f["static_loads"].attrs["cases"] = json.dumps(list(self.load_cases))
                f.attrs["provenance"] = json.dumps(dict(self.provenance), sort_keys=True, default=str)
            os.replace(tmp, path)
        except (OSError, TypeError, ValueError) as exc:
            raise ModalFileError(f"{path}: cannot write the modal file: {exc}") from None
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
        return path

    @classmethod
    def read(cls, path: str | os.PathLike[str]) -> ModalData:
        """Read and validate a modal file.

        Raises
        ------
        ModalFileError
            Missing or truncated file, not a flexlib modal file, a future format version, a missing dataset,
            a wrong dtype (e.g. a string where a number belongs), shape, non-finite value, non-symmetric or
            indefinite mass/stiffness, units other than SI, invariants that contradict the body properties,
            damping ratios outside [0, 1], load-case names a flexible body does not know
            (:data:`~.modal_schema.LOAD_CASE_NAMES`), a directory or a path that is not a str/PathLike. The
            message names the file and the dataset.
        """
        if not isinstance(path, str | os.PathLike):
            raise ModalFileError(f"ModalData.read: path must be the path of a modal file (str or Path), got "
                                 f"{path!r} ({type(path).__name__})")
        name = os.fspath(path)
        if os.path.isdir(name):
            raise ModalFileError(f"{name}: is a directory, not a modal file: give the path of the HDF5 modal file "
                                 "(.h5) in it")
        if not os.path.isfile(name):
            raise ModalFileError(f"{name}: no such modal file")
        try:
            f = h5py.File(name, "r")
        except OSError as exc:
            raise ModalFileError(f"{name}: not a readable HDF5 modal file (truncated or damaged?): {exc}") from None
        try:
            with f:
                kwargs = _read_all(f, name)
        except ModalFileError:
            raise
        except (OSError, KeyError, RuntimeError) as exc:  # damaged data blocks inside a readable header
            raise ModalFileError(f"{name}: damaged modal file: {exc}") from None
        data = cls.__new__(cls)
        for key, value in kwargs.items():
            object.__setattr__(data, key, value)
        data._check(name)
        return data


def _read_all(f: h5py.File, name: str) -> dict[str, Any]:
    fmt = f.attrs.get("format")
    if isinstance(fmt, bytes):
        fmt = fmt.decode()
    if fmt != FORMAT:
        raise ModalFileError(f"{name}: dataset '/' attribute 'format' is {fmt!r}, not {FORMAT!r}: not a flexlib "
                             "modal file")
    version = f.attrs.get("format_version")
    if not isinstance(version, int | np.integer):
        raise ModalFileError(f"{name}: dataset '/' attribute 'format_version' must be an integer, got {version!r}")
    if version > FORMAT_VERSION:
        raise ModalFileError(f"{name}: dataset '/' attribute 'format_version' is {int(version)}, newer than the "
                             f"supported {FORMAT_VERSION}: update flexlib to read this file")
    if version < 1:
        raise ModalFileError(f"{name}: dataset '/' attribute 'format_version' {int(version)} is invalid")

    def text(group: str, key: str) -> str:
        if group not in f:
            raise ModalFileError(f"{name}: group '/{group}' is missing")
        value = f[group].attrs.get(key)
        if isinstance(value, bytes):
            value = value.decode()
        if not isinstance(value, str):
            raise ModalFileError(f"{name}: dataset '/{group}' attribute {key!r} must be a string, got {value!r}")
        return value

    out: dict[str, Any] = {"title": text("header", "title"), "creator": text("header", "creator"),
                           "date": text("header", "date"), "format_version": int(version)}
    if "units" not in f:
        raise ModalFileError(f"{name}: group '/units' is missing")
    out["units"] = {k: text("units", k) for k in f["units"].attrs}

    def array(path: str, required: bool) -> np.ndarray | None:
        if path not in f:
            if required:
                raise ModalFileError(f"{name}: dataset '/{path}' is missing")
            return None
        node = f[path]
        if not isinstance(node, h5py.Dataset):
            raise ModalFileError(f"{name}: '/{path}' must be a dataset, found a group")
        value = node[()]
        if not isinstance(value, np.ndarray):
            value = np.asarray(value)
        if not np.issubdtype(value.dtype, np.number) or np.issubdtype(value.dtype, np.complexfloating):
            raise ModalFileError(f"{name}: dataset '/{path}' must be real numbers, got dtype {value.dtype} "
                                 f"({value.ravel()[:1]!r}...)")
        return value

    for attr, (path, required, _) in DATASETS.items():
        out[attr] = array(path, required)
    out["invariants"] = {k: array(f"invariants/{k}", True) for k in INVARIANT_NAMES}
    if "geometric_stiffness" in f:
        group = f["geometric_stiffness"]
        if not isinstance(group, h5py.Group):
            raise ModalFileError(f"{name}: '/geometric_stiffness' must be a group of datasets")
        out["geometric_stiffness"] = {k: array(f"geometric_stiffness/{k}", True) for k in group}
    else:
        out["geometric_stiffness"] = None
    out["mass_description"] = text("invariants", "mass_description")
    out["load_cases"] = None
    if "static_loads" in f:
        cases = text("static_loads", "cases")
        try:
            out["load_cases"] = json.loads(cases)
        except ValueError as exc:
            raise ModalFileError(f"{name}: dataset '/static_loads' attribute 'cases' is not JSON: {exc}") from None
    prov = f.attrs.get("provenance", "{}")
    try:
        out["provenance"] = json.loads(prov.decode() if isinstance(prov, bytes) else prov)
    except (TypeError, ValueError) as exc:
        raise ModalFileError(f"{name}: dataset '/' attribute 'provenance' is not JSON: {exc}") from None
    if not isinstance(out["provenance"], dict):
        raise ModalFileError(f"{name}: dataset '/' attribute 'provenance' must be a JSON object ({{...}}: how the "
                             f"data were made), got {type(out['provenance']).__name__} {out['provenance']!r:.60}")
    return out


