"""One boom section, rigid or flexible, behind the same named frames.

A section of a truck-mounted concrete-pump boom is a steel box between two joint pins with brackets on it: the
bracket ``C`` its own joint's drive pushes on, and (on all but the last section) the next joint's lever pivot and
cylinder housing. :class:`BoomSection` gives each of them a frame, so drives, levers and the next section attach to
the same connectors whether the section is a rigid ``Body`` or a Craig–Bampton ``FlexibleBody``.

The pump truck's and the 28 m boom's sections are these (:func:`models.pump_truck.machine.boom_section`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import Body, FixedTranslation, RelativePosition
from flexlib.components.mechanics.multibody.interfaces import Frame
from flexlib.errors import ParameterError
from flexlib.fe import ModalData

from ._checks import positive

__all__ = ["BoomSection"]

#: Connector names a pin may not take (they are the section's own frames).
RESERVED = ("root", "tip", "a", "b")


def _vector(part: str, name: str, value: Any, sizes: tuple[int, ...] = (2, 3)) -> np.ndarray:
    """``value`` as a finite 3-vector (a 2-vector gets ``z = 0``); ``ParameterError`` naming ``part.name``."""
    v = np.asarray(value, dtype=float) if not isinstance(value, str) else np.array([])
    if v.ndim != 1 or v.size not in sizes or not np.all(np.isfinite(v)):
        raise ParameterError(f"{part}: {name} must be {' or '.join(map(str, sizes))} finite numbers [m], got {value!r}")
    return np.append(v, 0.0) if v.size == 2 else v


def lumped(m: float, com: np.ndarray, inertia: np.ndarray,
           masses: Sequence[tuple[float, np.ndarray]]) -> tuple[float, np.ndarray, np.ndarray]:
    """A body's mass [kg], centre of mass [m] and inertia at it [kg.m2] with point masses ``(m_i, r_i)`` added
    (parallel-axis theorem; as ``geometry.section_mass_properties`` lumps the end hose)."""
    pts = [(m, com), *masses]
    total = sum(mi for mi, _ in pts)
    c = sum(mi * ri for mi, ri in pts) / total
    out = np.array(inertia, dtype=float)
    for mi, ri in pts:
        d = ri - c
        out = out + mi * (d @ d * np.eye(3) - np.outer(d, d))
    return total, c, out


class BoomSection(fl.Model):
    """A boom section between its root pin and its tip pin, with a frame at each named pin.

    Section frame: origin at the root pin, ``x`` along the section to the tip pin (at ``x = length``), ``y`` up when
    the section is horizontal, ``z`` the joint axis. Diagram::

        frame_root ── body (Body, or FlexibleBody at its beam nodes) ── tip ── frame_tip
              └── pin_<name> (FixedTranslation to the pin) ── frame_<name>     (one per pin)

    *Rigid* (``modal_data`` not given): one ``Body`` with the mass properties ``m``, ``r_CM``, ``I`` plus the
    ``payload`` point masses lumped into it (parallel-axis theorem), and a ``FixedTranslation`` from the root pin to
    the tip and to each pin. *Flexible* (``modal_data`` given): a ``FlexibleBody`` of that modal data (its
    reference frame at the root pin, pinned attachment: the section's own modes), with frames at the nodes of the
    root, the tip and each pin's and payload's station (the nearest node along ``x``, which must be an interface
    node of the reduction); an off-axis pin or payload is reached by a rigid ``FixedTranslation`` (a stiff
    bracket), a payload is a point-mass ``Body`` there. Its mass properties are the modal data's; given ``m`` and
    ``r_CM`` are checked against them (0.1 %), so the same arguments build either variant. The flexible variant also
    carries ``deflection``, a ``RelativePosition`` from the root pin to the tip pin (``deflection.r_rel[1]``: the
    tip's deflection from the root tangent, as ``PumpTruck`` reads it).

    Parameters
    ----------
    length : float
        Root pin to tip pin [m].
    m : float
        Mass of the section (box, pipe) [kg]; required when rigid.
    r_CM : 2 or 3 floats
        Centre of mass in the section frame [m]; required when rigid.
    I : 3x3 floats
        Inertia at the centre of mass, section frame [kg.m2]; required when rigid.
    pins : mapping of str to 2 or 3 floats
        Pin points in the section frame [m], e.g. ``{"C": (0.9, -0.4), "P_next": (L + 0.3, 0.3)}``; each name
        becomes the connector ``frame_<name>`` (a Python identifier, not ``root``/``tip``/``a``/``b``).
    payload : sequence of (float, 2 or 3 floats)
        Point masses ``(m [kg], position [m])`` carried by the section (end hose, pipe clamps).
    modal_data : ModalData, optional
        Craig–Bampton modal data of the section (nodes along ``x`` from the root pin, reference at the root):
        makes the section flexible. :func:`models.pump_truck.flexible.section_modal_data` gives the truck's.
    modes : int or sequence of int, optional
        Flexible only: the lowest ``modes`` modes in the section's plane (:func:`flexlib.fe.planar_modes`,
        ``"xy"``; default 8) or mode indices into ``modal_data``.

    Connectors
    ----------
    frame_root : Frame
        The root pin (the section's joint).
    frame_tip : Frame
        The tip pin (the next joint, or the hose hanger).
    frame_<name> : Frame
        One per pin of ``pins``.

    References
    ----------
    Modelica Standard Library 4.0, ``MultiBody.Parts.BodyShape`` (body with two frames); R. R. Craig,
    M. C. C. Bampton, *AIAA J.* 6 (1968) 1313–1319 (the flexible variant's reduction).
    """

    def __init__(self, length: float, m: float | None = None, r_CM: Sequence[float] | None = None,
                 I: Any = None, pins: Mapping[str, Sequence[float]] | None = None,  # noqa: E741
                 payload: Sequence[tuple[float, Sequence[float]]] = (), modal_data: ModalData | None = None,
                 modes: int | Sequence[int] | None = None) -> None:
        super().__init__()
        part = "BoomSection"
        self.length = positive(part, "length", length, "m")
        self.pins = self._check_pins(part, pins)
        self.payload = [(positive(part, f"payload[{i}] mass", p[0], "kg"),
                         _vector(part, f"payload[{i}] position", p[1]))
                        if isinstance(p, Sequence) and len(p) == 2 else self._bad_payload(part, i, p)
                        for i, p in enumerate(payload)]
        self.flexible = modal_data is not None
        self.frame_root = Frame(doc="Root pin (the section's joint)")
        self.frame_tip = Frame(doc="Tip pin (the next joint)")
        for name in self.pins:
            setattr(self, f"frame_{name}", Frame(doc=f"Pin {name}"))
        if self.flexible:
            self._flexible(part, modal_data, modes, m, r_CM)
            return
        if modes is not None:
            raise ParameterError(f"{part}: modes = {modes!r} selects the modes of a flexible section; give "
                                 "modal_data as well, or leave modes out")
        if m is None or r_CM is None or I is None:
            raise ParameterError(f"{part}: a rigid section needs m, r_CM and I (missing: "
                                 f"{', '.join(k for k, v in (('m', m), ('r_CM', r_CM), ('I', I)) if v is None)})")
        inertia = np.asarray(I, dtype=float)
        if inertia.shape != (3, 3) or not np.all(np.isfinite(inertia)):
            raise ParameterError(f"{part}: I must be a 3x3 inertia tensor [kg.m2], got {I!r}")
        mass, com, inertia = lumped(positive(part, "m", m, "kg"), _vector(part, "r_CM", r_CM), inertia, self.payload)
        self.body = Body(m=mass, r_CM=[float(v) for v in com], I=inertia)
        self.tip = FixedTranslation(r=[self.length, 0.0, 0.0])
        self.connect(self.frame_root, self.body.frame_a, self.tip.frame_a)
        self.connect(self.tip.frame_b, self.frame_tip)
        for name, point in self.pins.items():
            pin = FixedTranslation(r=[float(v) for v in point])
            setattr(self, f"pin_{name}", pin)
            self.connect(self.frame_root, pin.frame_a)
            self.connect(pin.frame_b, self.frame(name))

    def frame(self, name: str) -> Frame:
        """The connector of pin ``name`` (or ``"root"``, ``"tip"``)."""
        if name not in (*self.pins, "root", "tip"):
            raise ParameterError(f"BoomSection: no pin {name!r}; pins: {sorted(self.pins)} (and root, tip)")
        return getattr(self, f"frame_{name}")

    @staticmethod
    def _check_pins(part: str, pins: Mapping[str, Sequence[float]] | None) -> dict[str, np.ndarray]:
        if pins is None:
            return {}
        if not isinstance(pins, Mapping):
            raise ParameterError(f"{part}: pins must be a mapping {{name: (x, y)}} [m], got {pins!r}")
        out = {}
        for name, point in pins.items():
            if not isinstance(name, str) or not name.isidentifier() or name in RESERVED:
                raise ParameterError(f"{part}: pins: name {name!r} must be a Python identifier other than "
                                     f"{', '.join(RESERVED)} (it becomes the connector frame_<name>)")
            out[name] = _vector(part, f"pins[{name!r}]", point)
        return out

    @staticmethod
    def _bad_payload(part: str, i: int, p: Any) -> Any:
        raise ParameterError(f"{part}: payload[{i}] must be (mass [kg], (x, y) [m]), got {p!r}")

    def _flexible(self, part: str, data: ModalData, modes: Any, m: float | None, r_CM: Any) -> None:
        """The FlexibleBody variant (class docstring)."""
        from flexlib.components.mechanics.flexible import FlexibleBody
        from flexlib.fe import planar_modes
        from flexlib.models.pump_truck.flexible import station_node

        if not isinstance(data, ModalData):
            raise ParameterError(f"{part}: modal_data must be a ModalData, got {type(data).__name__}")
        if m is not None and abs(positive(part, "m", m, "kg") - data.mass) > 1e-3 * data.mass:
            raise ParameterError(f"{part}: m = {m!r} kg differs from the modal data's mass {data.mass:.6g} kg")
        if r_CM is not None and np.abs(_vector(part, "r_CM", r_CM) - data.center_of_mass).max() > 1e-3 * self.length:
            raise ParameterError(f"{part}: r_CM = {r_CM!r} m differs from the modal data's centre of mass "
                                 f"{data.center_of_mass.tolist()}")
        modes = 8 if modes is None else modes
        kept = planar_modes(data, "xy")[:modes] if isinstance(modes, int) else [int(k) for k in modes]
        x, ids = data.coordinates[:, 0], data.node_ids
        if abs(float(x.max()) - self.length) > 1e-9 * self.length or abs(float(x.min())) > 1e-9 * self.length:
            raise ParameterError(f"{part}: length = {self.length} m, but the modal data's nodes span "
                                 f"{x.min():.6g} ... {x.max():.6g} m along x")
        places = {"root": np.zeros(3), "tip": np.array([self.length, 0.0, 0.0]), **self.pins,
                  **{f"payload{i}": r for i, (_, r) in enumerate(self.payload)}}
        at = {name: station_node(x, ids, float(p[0]), self.length) for name, p in places.items()}
        interface = set(data.interface_nodes.tolist())
        missing = sorted(name for name, node in at.items() if node not in interface)
        if missing:
            raise ParameterError(f"{part}: modal_data has no interface node at the stations of {missing} (give "
                                 "those stations to the mesh and the reduction as interface nodes)")
        self.body = FlexibleBody(data, modes=kept, frames=list(dict.fromkeys(at.values())))
        # the static start: at rest with zero modal accelerations; the deflection follows from the loads
        self.body.set_start("qd", np.zeros(len(kept)), fixed=True)
        self.body.set_start("qdd", np.zeros(len(kept)), fixed=True)
        self.tip = FixedTranslation(r=[0.0, 0.0, 0.0])
        self.deflection = RelativePosition()
        self.connect(self.frame_root, self.body.frame_at(at["root"]), self.deflection.frame_a)
        self.connect(self.body.frame_at(at["tip"]), self.tip.frame_a)
        self.connect(self.tip.frame_b, self.frame_tip, self.deflection.frame_b)
        for name, point in places.items():
            if name in ("root", "tip"):
                continue
            pin = FixedTranslation(r=[float(v) for v in point - data.coordinates[data.node_index(at[name])]])
            setattr(self, f"pin_{name}" if name in self.pins else name, pin)
            self.connect(self.body.frame_at(at[name]), pin.frame_a)
            if name in self.pins:
                self.connect(pin.frame_b, self.frame(name))
            else:
                mass = Body(m=self.payload[int(name[7:])][0], r_CM=[0.0, 0.0, 0.0], I=np.zeros((3, 3)))
                setattr(self, f"{name}_mass", mass)
                self.connect(pin.frame_b, mass.frame_a)
