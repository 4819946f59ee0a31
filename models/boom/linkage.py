"""The lever-and-link four-bar that drives a boom joint (joints 2–5 of a truck-mounted concrete-pump boom).

What ``PumpTruck._fourbar`` builds today, as a part; the closed-form kinematics it starts from are those of
:mod:`models.pump_truck.kinematics` (:func:`~models.pump_truck.kinematics.fourbar_state`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

import flexlib as fl
from flexlib.components.mechanics.multibody import FixedTranslation, Revolute
from flexlib.components.mechanics.multibody.interfaces import Frame
from flexlib.errors import ParameterError
from flexlib.models.boom_proxy import link_body
from flexlib.models.pump_truck.kinematics import fourbar_state

from ._checks import positive

__all__ = ["LeverLink"]

PART = "LeverLink"


class LeverLink(fl.Model):
    """Lever (rocker) and link of a lever-and-link joint drive, closed by three revolutes about ``z``.

    Diagram (section k−1 carries the joint at its tip; the cylinder pushes the lever tip)::

        frame_pivot ── pivot (Revolute) ── lever (Body) ── lever_end (r along x) ── frame_tip (T)
                                                                 └── hinge (Revolute) ── link (Body)
                                                                       ── link_end (s along x) ── bracket (Revolute)
                                                                       ── frame_bracket (C)

    The lever's frame has ``x`` from the pivot ``P`` to its tip ``T``, the link's from ``T`` to the bracket ``C``;
    each body is a slender bar (:func:`flexlib.models.boom_proxy.link_body`: centre of mass at mid-length, inertia
    ``m L²/12``), left out when its mass is zero (the massless-linkage limit). With the joint between the sections
    the loop is a planar four-bar (Norton ch. 4); the engine drops its out-of-plane redundant rows. The revolute
    angles ``pivot.phi`` (lever from section k−1), ``hinge.phi`` (link from lever), ``bracket.phi`` (section k
    from link) start from ``guess``; :meth:`start_angles` gives them for a joint angle from the closed-form circle
    intersection, :meth:`at_pose` builds the part with them.

    Parameters
    ----------
    r : float
        Lever length, pivot ``P`` to tip ``T`` [m].
    s : float
        Link length, ``T`` to bracket ``C`` [m].
    m_lever, m_link : float
        Masses of lever and link [kg] (0: massless).
    guess : 3 floats
        Start guesses of ``pivot.phi``, ``hinge.phi``, ``bracket.phi`` [rad].

    Connectors
    ----------
    frame_pivot : Frame
        The lever pivot, to section k−1's pin ``P`` (a frame with section k−1's orientation).
    frame_tip : Frame
        The lever tip ``T`` (where the cylinder rod attaches), lever orientation.
    frame_bracket : Frame
        The link's end, to section k's bracket pin ``C`` (a frame with section k's orientation).

    References
    ----------
    R. L. Norton, *Design of Machinery*, 5th ed., McGraw-Hill 2012, ch. 4 (four-bar position analysis).
    Modelica Standard Library 4.0, ``MultiBody.Joints.Revolute``, ``MultiBody.Parts.BodyShape``.
    """

    def __init__(self, r: float, s: float, m_lever: float = 0.0, m_link: float = 0.0,
                 guess: Sequence[float] = (0.0, 0.0, 0.0)) -> None:
        super().__init__()
        self.r, self.s = positive(PART, "r", r, "m"), positive(PART, "s", s, "m")
        m_lever = positive(PART, "m_lever", m_lever, "kg", allow_zero=True)
        m_link = positive(PART, "m_link", m_link, "kg", allow_zero=True)
        g = np.asarray(guess, dtype=float) if not isinstance(guess, str) else np.array([])
        if g.shape != (3,) or not np.all(np.isfinite(g)):
            raise ParameterError(f"LeverLink: guess must be 3 finite angles [rad] (pivot, hinge, bracket), "
                                 f"got {guess!r}")
        self.frame_pivot = Frame(doc="Lever pivot P (on section k-1)")
        self.frame_tip = Frame(doc="Lever tip T (cylinder rod end)")
        self.frame_bracket = Frame(doc="Link end at the bracket C (on section k)")
        self.pivot = Revolute(guess={"phi": float(g[0])})
        self.lever_end = FixedTranslation(r=[self.r, 0.0, 0.0])
        self.hinge = Revolute(guess={"phi": float(g[1])})
        self.link_end = FixedTranslation(r=[self.s, 0.0, 0.0])
        self.bracket = Revolute(guess={"phi": float(g[2])})
        self.connect(self.frame_pivot, self.pivot.frame_a)
        self.connect(self.pivot.frame_b, self.lever_end.frame_a)
        self.connect(self.lever_end.frame_b, self.hinge.frame_a, self.frame_tip)
        self.connect(self.hinge.frame_b, self.link_end.frame_a)
        self.connect(self.link_end.frame_b, self.bracket.frame_a)
        self.connect(self.bracket.frame_b, self.frame_bracket)
        if m_lever > 0.0:
            self.lever = link_body(m_lever, self.r)
            self.connect(self.pivot.frame_b, self.lever.frame_a)
        if m_link > 0.0:
            self.link = link_body(m_link, self.s)
            self.connect(self.hinge.frame_b, self.link.frame_a)

    @staticmethod
    def start_angles(q: float, P: Sequence[float], c: Sequence[float], r: float, s: float,
                     sigma: int) -> tuple[float, float, float]:
        """The three revolute angles [rad] at joint angle ``q`` [rad].

        ``P`` is the lever pivot in the joint frame of section k−1 (origin at the joint pin) [m], ``c`` the bracket
        in section k's frame [m], ``sigma`` the branch (``+1``: ``T`` left of ``P → C``), as
        :func:`models.pump_truck.kinematics.fourbar_state` takes them (its circle intersection gives ``T``).
        Returns ``(pivot.phi, hinge.phi, bracket.phi)``: lever from section k−1, link from lever, section k from
        link (they sum to ``q`` modulo 2π).
        """
        st = fourbar_state(q, P, P, c, r, s, sigma)
        P = np.asarray(P, dtype=float)
        th_lever = math.atan2(st.T[1] - P[1], st.T[0] - P[0])
        th_link = math.atan2(st.C[1] - st.T[1], st.C[0] - st.T[0])
        return th_lever, th_link - th_lever, q - th_link

    @classmethod
    def at_pose(cls, q: float, P: Sequence[float], c: Sequence[float], r: float, s: float, sigma: int,
                m_lever: float = 0.0, m_link: float = 0.0) -> LeverLink:
        """A LeverLink whose revolutes start from :meth:`start_angles` at joint angle ``q`` [rad]."""
        r, s = positive(PART, "r", r, "m"), positive(PART, "s", s, "m")
        try:
            guess = cls.start_angles(q, P, c, r, s, sigma)
        except ValueError as err:
            raise ParameterError(f"LeverLink: q = {q!r}: {err}") from None
        return cls(r, s, m_lever, m_link, guess)
