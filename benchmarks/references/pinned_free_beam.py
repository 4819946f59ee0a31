"""Independent, geometrically exact reference for the pinned-free beam of seed 001 (issue 10).

The seed's beam (density 8000 kg/m³, E = 2e11 Pa, L = 1.5 m, A = 1e-4 m², I = 1e-10 m⁴, no gravity) is pinned at
one end to the world (translations fixed, rotation about the world z axis free), starts at rest along the world
x axis and is driven by a torque about z on the pin: +1.4 N·m for 0 ≤ t < 1 s and −1.4 N·m for 1 ≤ t ≤ 2 s.
The seed's own reference was COSMOS/M's nonlinear module with 64 elements; this module is ours: the mechanics and
numerics use numpy/scipy only and are independent of flexlib (from flexlib it imports only the atomic file
writer; nothing of its flexible-body code).

Model
-----
Planar Euler–Bernoulli beam in the absolute nodal coordinate formulation (ANCF) with the *elastic line*
approach: gradient-deficient cubic elements with the nodal coordinates ``e = [r(0), r'(0), r(h), r'(h)]`` (world
position of the centre line and its derivative with respect to the undeformed arc length ``x``), interpolated by
cubic Hermite polynomials, ``r(x) = S(x) e``. The strain energy

    U = ½ ∫ (EA ε² + EI κ²) dx,   ε = ½ (r'·r' − 1),   κ = (r' × r'')·e_z / |r'|³

uses the Green–Lagrange strain of the centre line and the *exact* curvature of the deformed centre line, so
rotations and deflections are unrestricted (geometrically exact); only the strains are assumed small (here
|ε| < 1e-6, where Green–Lagrange and engineering strain agree to 1e-12). The kinetic energy
``T = ½ ∫ ρA ṙ·ṙ dx`` gives a constant consistent mass matrix and no velocity-dependent inertia terms. The
rotary inertia of the cross-sections (ρI = 8e-7 kg·m per metre, 1e-6 of the beam's inertia about the pin) is
neglected, as in Euler–Bernoulli theory. Integrals use 5-point Gauss–Legendre quadrature per element (exact for
the mass matrix). The pin fixes the first node's position; its slope ``r'(0)`` stays free, and the torque τ
acts on the pin angle θ = atan2(r'_y(0), r'_x(0)) through the virtual work τ δθ (a conservative load, so the
tangent matrix stays symmetric).

Time integration: generalised-α (Chung & Hulbert 1993) on the constant-mass system
``M a + f(q) = τ ∂θ/∂q`` with Newton iterations on the positions (analytic tangent, banded LU). The internal and
external forces are weighted at ``n + 1 − α_f`` as ``(1 − α_f) g(q_{n+1}) + α_f g(q_n)``. ρ∞ = 1 is the
non-dissipative average-acceleration (trapezoidal) Newmark rule; ρ∞ < 1 damps the modes that the step does not
resolve. The torque is piecewise constant and its switching times lie on the step grid: each step uses the value
on its interval, and the integrator restarts at each switch with the acceleration recomputed from the
equations of motion (as at t = 0), so the step change costs no order of accuracy.

Outputs and sign conventions (all SI)
-------------------------------------
- ``tip_y`` [m]: world y of the free end.
- ``pin_angle`` [rad]: angle of the pin tangent ``r'(0)`` from the world x axis, counter-clockwise positive,
  continuous (unwrapped).
- ``tip_x_local``, ``tip_deflection`` [m]: the free end's coordinates in the pin-tangent frame (origin at the pin,
  local x along the pin tangent, local y that tangent rotated by +90° about z): the deflection is the signed
  distance of the tip from the pin tangent line, positive on the +local-y side.
- ``moment_mid`` [N·m]: bending moment EI κ at mid-span, κ = dφ/ds the rate of the tangent angle φ along the
  deformed arc length: positive when the beam curves towards +local y (counter-clockwise turning tangent). The
  cubic element's curvature is discontinuous across nodes; the mid-span value is the mean of the two elements
  meeting there (``n_elements`` must be even).
- ``moment_mid_avg`` [N·m]: ``moment_mid`` averaged over the window [t − 5 ms, t + 5 ms] intersected with
  [0, 2] s (so at t = 0 and t = 2 s the window is one-sided), see :func:`window_average`.
- ``tip_deflection_avg`` [m]: ``tip_deflection`` averaged the same way (not in the seed; it filters the pin
  slope's fast oscillation, see below, and converges faster than the instantaneous deflection).

References
----------
- J. Gerstmayr, H. Irschik, "On the correct representation of bending and axial deformation in the absolute
  nodal coordinate formulation with an elastic line approach", J. Sound Vib. 318 (2008) 461–487 (the element).
- C. Berzeri, A. A. Shabana, "Development of simple models for the elastic forces in the absolute nodal
  co-ordinate formulation", J. Sound Vib. 235 (2000) 539–565.
- J. Chung, G. M. Hulbert, "A time integration algorithm for structural dynamics with improved numerical
  dissipation: the generalized-α method", J. Appl. Mech. 60 (1993) 371–375 (eqs. 17, 25 for α_m, α_f, β, γ).
- Seed 001, eq. (2), for :func:`seed_error`.

Run ``python benchmarks/references/pinned_free_beam.py --jobs 2`` for the convergence study (730–915 s of CPU on
the shared 2-core machine; the finest run, 128 elements at dt = 3.125e-5 s, 207–264 s); it writes the finest
run's series to ``tests/data/pinned_free_beam_reference.npz`` (atomically). Measured (seed error, eq. 2,
between the two finest meshes / the two finest steps): tip y 0.0002 / 0.0011 %, tip deflection 0.27 / 0.72 %,
averaged tip deflection 0.005 / 0.04 %, averaged moment 0.10 / 0.37 %; ρ∞ = 0.9 instead of 1 changes them by
0.0001, 0.16, 0.001 and 0.04 %. The tip deflection converges slowly in dt because it is measured from the pin
tangent, whose slope carries a small fast oscillation of many modes excited by the step torque at the pin
(4e-4 rad of pin angle moves the tip 0.6 mm across the tangent). The instantaneous mid-span moment does not
converge (5–8 % between refinements): each added mode adds a jagged component of amplitude ~1/k, hence the
±5 ms average.
"""

from __future__ import annotations

import argparse
import itertools
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from scipy.linalg.lapack import dgbsv as _gbsv

from flexlib.compile.cache import store_init
from flexlib.errors import RunArgumentError

DENSITY = 8000.0  # kg/m³
YOUNG = 2e11  # Pa
LENGTH = 1.5  # m
AREA = 1e-4  # m²
SECOND_MOMENT = 1e-10  # m⁴
TORQUE = 1.4  # N·m
T_SWITCH = 1.0  # s
T_END = 2.0  # s
SAMPLE_DT = 0.01  # s, the seed's 1 cs sampling (201 samples)
AVERAGE_HALF_WIDTH = 5e-3  # s
TABLE_SERIES = ("tip_y", "tip_deflection", "tip_deflection_avg", "moment_mid_avg", "moment_mid", "pin_angle")
BANG_BANG: tuple[tuple[float, float], ...] = ((0.0, TORQUE), (T_SWITCH, -TORQUE))
REFERENCE_FILE = Path(__file__).resolve().parents[2] / "tests" / "data" / "pinned_free_beam_reference.npz"
SERIES = ("tip_y", "tip_deflection", "tip_x_local", "moment_mid", "moment_mid_avg", "pin_angle", "tip_deflection_avg")

_GAUSS_S, _GAUSS_W = np.polynomial.legendre.leggauss(5)
_P = np.array([[0.0, 1.0], [-1.0, 0.0]])  # aᵀ P b = a × b (z component)


def _hermite(s: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Shape matrices ``S``, ``dS/dx``, ``d²S/dx²`` (each ``(len(s), 2, 8)``) of the cubic element of length
    ``h`` [m] at the local coordinates ``s = x / h``; element coordinates ``[r0, r0', r1, r1']`` (2 each)."""
    s = np.asarray(s, dtype=float)
    one = np.ones_like(s)
    n = np.stack([1 - 3 * s**2 + 2 * s**3, h * (s - 2 * s**2 + s**3), 3 * s**2 - 2 * s**3, h * (s**3 - s**2)], -1)
    dn = np.stack([(6 * s**2 - 6 * s) / h, 1 - 4 * s + 3 * s**2, (6 * s - 6 * s**2) / h, 3 * s**2 - 2 * s], -1)
    ddn = np.stack([(12 * s - 6) / h**2, (6 * s - 4) / h, (6 - 12 * s) / h**2, (6 * s - 2) / h], -1)
    eye = np.eye(2)

    def expand(values: np.ndarray) -> np.ndarray:
        return np.einsum("gk,ij->gikj", values, eye).reshape(len(s), 2, 8) * one[:, None, None]

    return expand(n), expand(dn), expand(ddn)


class Beam:
    """Discretised pinned-free ANCF beam: constant mass, internal forces, tangent, strain energy, pin torque.

    Parameters
    ----------
    n_elements : int
        Number of equal elements (even, ≥ 2, so that mid-span is a node).
    young, density, length, area, second_moment : float
        E [Pa], ρ [kg/m³], L [m], A [m²], I [m⁴].

    Notes
    -----
    Global coordinates are node-wise ``[r_x, r_y, r'_x, r'_y]``; the pin removes the first node's two position
    coordinates, leaving ``4 n_elements + 2`` unknowns. Matrices are kept in LAPACK band storage (7 sub- and
    super-diagonals).
    """

    BAND = 7

    def __init__(
        self,
        n_elements: int,
        young: float = YOUNG,
        density: float = DENSITY,
        length: float = LENGTH,
        area: float = AREA,
        second_moment: float = SECOND_MOMENT,
    ) -> None:
        if isinstance(n_elements, bool) or not isinstance(n_elements, (int, np.integer)):
            raise ValueError(f"pinned-free beam: n_elements must be an int, got {n_elements!r}")
        if n_elements < 2 or n_elements % 2:
            raise ValueError(f"pinned-free beam: n_elements must be even and >= 2 (mid-span node), got {n_elements}")
        for name, value in (
            ("young", young),
            ("density", density),
            ("length", length),
            ("area", area),
            ("second_moment", second_moment),
        ):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"pinned-free beam: {name} must be finite and > 0, got {value!r}")
        self.n = int(n_elements)
        self.h = length / self.n
        self.length = length
        self.EA = young * area
        self.EI = young * second_moment
        self.rhoA = density * area
        s = 0.5 * (_GAUSS_S + 1.0)
        self.w = 0.5 * self.h * _GAUSS_W
        S, self.Sx, self.Sxx = _hermite(s, self.h)
        self.nx, self.nxx = self.Sx[:, 0, 0::2], self.Sxx[:, 0, 0::2]  # scalar shape functions (g, 4)
        # n_p[k] n_q[l] for (p, q) = (r', r'), (r', r''), (r'', r'): (g·3, 16)
        self._outer = np.stack(
            [
                np.einsum("gk,gl->gkl", u1, u2)
                for u1, u2 in ((self.nx, self.nx), (self.nx, self.nxx), (self.nxx, self.nx))
            ],
            axis=1,
        ).reshape(-1, 16)
        self.size = 4 * (self.n + 1)
        self.elem_dofs = 4 * np.arange(self.n)[:, None] + np.arange(8)[None, :]
        u = self.BAND
        i, j = np.meshgrid(np.arange(8), np.arange(8), indexing="ij")
        rows = (u + i - j)[None, :, :]
        cols = self.elem_dofs[:, None, :] + 0 * i[None]
        self._band_index = (rows * self.size + cols).ravel()
        m_el = self.rhoA * np.einsum("g,gik,gil->kl", self.w, S, S)
        self.mass_band = self._assemble_band(np.broadcast_to(m_el, (self.n, 8, 8)))
        rr = np.broadcast_to(self.elem_dofs[:, :, None], (self.n, 8, 8)).ravel()
        cc = np.broadcast_to(self.elem_dofs[:, None, :], (self.n, 8, 8)).ravel()
        mass = sp.coo_matrix((np.broadcast_to(m_el, (self.n, 8, 8)).ravel(), (rr, cc)), (self.size,) * 2).tocsr()
        self.mass = mass[2:, 2:]
        _, sx_end, sxx_end = _hermite(np.array([1.0, 0.0]), self.h)
        self._mid_shapes = (sx_end, sxx_end)

    def _assemble_band(self, blocks: np.ndarray) -> np.ndarray:
        """Band storage ``(15, size)`` of the sum of the element blocks ``(n, 8, 8)``."""
        flat = np.bincount(self._band_index, weights=blocks.ravel(), minlength=(2 * self.BAND + 1) * self.size)
        return flat.reshape(2 * self.BAND + 1, self.size)

    def initial(self) -> np.ndarray:
        """Full coordinate vector of the straight, undeformed beam along the world x axis."""
        q = np.zeros(self.size)
        q[0::4] = np.linspace(0.0, self.length, self.n + 1)
        q[2::4] = 1.0
        return q

    def internal(self, q: np.ndarray, tangent: bool = True) -> tuple[np.ndarray, np.ndarray | None, float]:
        """Internal force ``∂U/∂q`` (full size), tangent ``∂²U/∂q²`` in band storage (or None), strain energy
        ``U`` [J] at the full coordinates ``q``.

        With ``a = r'``, ``b = r''``, ``g = a·a``, ``c = aᵀ P b`` (P the 90° rotation, so c = a × b):
        ``∂κ/∂a = g^-3/2 P b − 3 c g^-5/2 a``, ``∂κ/∂b = g^-3/2 Pᵀ a``, and the second derivatives
        ``∂²κ/∂a² = −3 g^-5/2 (P b aᵀ + a bᵀ Pᵀ) + 15 c g^-7/2 a aᵀ − 3 c g^-5/2 I``,
        ``∂²κ/∂a∂b = g^-3/2 P − 3 g^-5/2 a aᵀ P``, ``∂²κ/∂b² = 0``. Shape functions act per coordinate
        (``S = N ⊗ I₂``), so element blocks are Kronecker products of shape-function and 2×2 factors.
        """
        e = q[self.elem_dofs].reshape(self.n, 4, 2)
        a = np.einsum("gk,eki->egi", self.nx, e)
        b = np.einsum("gk,eki->egi", self.nxx, e)
        g = np.einsum("egi,egi->eg", a, a)
        eps = 0.5 * (g - 1.0)
        c = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
        g32, g52 = g**-1.5, g**-2.5
        kappa = c * g32
        pb = np.stack([b[..., 1], -b[..., 0]], -1)  # P b
        pta = np.stack([-a[..., 1], a[..., 0]], -1)  # Pᵀ a
        k_a = g32[..., None] * pb - 3.0 * (c * g52)[..., None] * a
        k_b = g32[..., None] * pta
        axial = self.EA * self.w * eps  # (e, g): EA ε times the quadrature weight
        bend = self.EI * self.w * kappa
        f_el = np.einsum("gk,egi->eki", self.nx, axial[..., None] * a + bend[..., None] * k_a) + np.einsum(
            "gk,egi->eki", self.nxx, bend[..., None] * k_b
        )
        f = np.bincount(self.elem_dofs.ravel(), weights=f_el.ravel(), minlength=self.size)
        energy = float(np.sum(0.5 * self.w * (self.EA * eps**2 + self.EI * kappa**2)))
        if not tangent:
            return f, None, energy
        # first-order part: Σ_g EA w dε dεᵀ + EI w dκ dκᵀ as Dᵀ D
        d_eps = (self.nx[None, :, :, None] * a[:, :, None, :]).reshape(self.n, -1, 8)
        d_kap = self.nx[None, :, :, None] * k_a[:, :, None, :] + self.nxx[None, :, :, None] * k_b[:, :, None, :]
        d_all = np.concatenate(
            [
                np.sqrt(self.EA * self.w)[None, :, None] * d_eps,
                np.sqrt(self.EI * self.w)[None, :, None] * d_kap.reshape(self.n, -1, 8),
            ],
            axis=1,
        )
        k_el = np.matmul(d_all.transpose(0, 2, 1), d_all)
        # second-order part: blocks B_pq (p, q ∈ {r', r''}) of 2×2 matrices, contracted with n_p n_q over g
        aa = a[..., :, None] * a[..., None, :]
        h_aa = (
            -3.0 * g52[..., None, None] * (pb[..., :, None] * a[..., None, :] + a[..., :, None] * pb[..., None, :])
            + 15.0 * (c * g**-3.5)[..., None, None] * aa
            - 3.0 * (c * g52)[..., None, None] * np.eye(2)
        )
        h_ab = g32[..., None, None] * _P - 3.0 * g52[..., None, None] * a[..., :, None] * pta[..., None, :]
        blocks = np.zeros((self.n, len(self.w), 3, 2, 2))
        blocks[:, :, 0] = axial[..., None, None] * np.eye(2) + bend[..., None, None] * h_aa
        blocks[:, :, 1] = bend[..., None, None] * h_ab
        blocks[:, :, 2] = bend[..., None, None] * h_ab.transpose(0, 1, 3, 2)
        geo = np.matmul(blocks.reshape(self.n, -1, 4).transpose(0, 2, 1), self._outer)  # (e, ij, kl)
        k_el += geo.reshape(self.n, 2, 2, 4, 4).transpose(0, 3, 1, 4, 2).reshape(self.n, 8, 8)
        return f, self._assemble_band(k_el), energy

    @staticmethod
    def pin_angle(q: np.ndarray) -> float:
        """Angle θ [rad] of the pin tangent r'(0) from the world x axis, in (−π, π]."""
        return float(np.arctan2(q[3], q[2]))

    @staticmethod
    def pin_torque(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``∂θ/∂r'(0)`` (2,) and ``∂²θ/∂r'(0)²`` (2, 2) of the pin angle, for the torque's generalised force."""
        a0, a1 = q[2], q[3]
        g = a0 * a0 + a1 * a1
        grad = np.array([-a1, a0]) / g
        hess = np.array([[2 * a0 * a1, a1 * a1 - a0 * a0], [a1 * a1 - a0 * a0, -2 * a0 * a1]]) / g**2
        return grad, hess

    def moment_mid(self, q: np.ndarray) -> float:
        """Bending moment EI κ [N·m] at mid-span: mean of the two adjacent elements' end values."""
        sx, sxx = self._mid_shapes
        k = self.n // 2
        values = []
        for elem, point in ((k - 1, 0), (k, 1)):
            e = q[self.elem_dofs[elem]]
            a, b = sx[point] @ e, sxx[point] @ e
            values.append((a[0] * b[1] - a[1] * b[0]) / (a @ a) ** 1.5)
        return self.EI * 0.5 * (values[0] + values[1])


@dataclass(frozen=True)
class Solution:
    """Every-step series of one run (all SI). ``energy`` is kinetic plus strain energy [J]; ``work`` the torque's
    work ∫ τ dθ [J] since t = 0; ``newton_iterations`` the total number of tangent solves."""

    t: np.ndarray
    tip: np.ndarray
    pin_angle: np.ndarray
    moment_mid: np.ndarray
    energy: np.ndarray
    work: np.ndarray
    n_elements: int
    dt: float
    rho_inf: float
    newton_iterations: int
    cpu_time: float

    @property
    def tip_y(self) -> np.ndarray:
        return self.tip[:, 1]

    @property
    def tip_x_local(self) -> np.ndarray:
        return self.tip[:, 0] * np.cos(self.pin_angle) + self.tip[:, 1] * np.sin(self.pin_angle)

    @property
    def tip_deflection(self) -> np.ndarray:
        return -self.tip[:, 0] * np.sin(self.pin_angle) + self.tip[:, 1] * np.cos(self.pin_angle)

    def sampled(self, sample_dt: float = SAMPLE_DT, half_width: float = AVERAGE_HALF_WIDTH) -> dict[str, np.ndarray]:
        """The output series at ``0, sample_dt, …, t_end`` (``t`` plus :data:`SERIES`)."""
        t_s = sample_dt * np.arange(round(self.t[-1] / sample_dt) + 1)
        idx = np.rint(t_s / self.dt).astype(int)
        if np.max(np.abs(self.t[idx] - t_s)) > 1e-9 * sample_dt:
            raise ValueError(f"pinned-free beam: sample_dt={sample_dt} is not a multiple of dt={self.dt}")
        out = {"t": t_s}
        for name in ("tip_y", "tip_deflection", "tip_x_local", "moment_mid", "pin_angle"):
            out[name] = getattr(self, name)[idx]
        out["moment_mid_avg"] = window_average(self.t, self.moment_mid, t_s, half_width)
        out["tip_deflection_avg"] = window_average(self.t, self.tip_deflection, t_s, half_width)
        return out


def window_average(t: np.ndarray, z: np.ndarray, at: np.ndarray, half_width: float = AVERAGE_HALF_WIDTH) -> np.ndarray:
    """Mean of the piecewise-linear signal ``z(t)`` over ``[s − half_width, s + half_width] ∩ [t[0], t[-1]]`` for
    each ``s`` in ``at`` (trapezoidal integral; exact for the piecewise-linear interpolant of the samples).

    Use this on any simulated series (the samples need not be uniform, but dense: every step) to compare with
    ``moment_mid_avg``.
    """
    t = np.asarray(t, dtype=float)
    z = np.asarray(z, dtype=float)
    if t.ndim != 1 or t.shape != z.shape or len(t) < 2 or np.any(np.diff(t) <= 0):
        raise ValueError("window_average: t must be increasing and z the same 1-D shape")
    if not half_width > 0:
        raise ValueError(f"window_average: half_width must be > 0, got {half_width!r}")
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (z[1:] + z[:-1]))])
    at = np.asarray(at, dtype=float)
    lo = np.clip(at - half_width, t[0], t[-1])
    hi = np.clip(at + half_width, t[0], t[-1])

    def integral(x: np.ndarray) -> np.ndarray:
        k = np.clip(np.searchsorted(t, x, side="right") - 1, 0, len(t) - 2)
        dx = x - t[k]
        slope = (z[k + 1] - z[k]) / (t[k + 1] - t[k])
        return cumulative[k] + dx * (z[k] + 0.5 * slope * dx)

    return (integral(hi) - integral(lo)) / (hi - lo)


def seed_error(z: np.ndarray, z_ref: np.ndarray) -> float:
    """Seed 001, eq. (2): ``100 · mean(|z − z*|) / max|z*|`` [%] over the samples (201 in the seed), with the
    maximum taken over the reference ``z_ref``."""
    z = np.asarray(z, dtype=float)
    z_ref = np.asarray(z_ref, dtype=float)
    if z.shape != z_ref.shape or z.ndim != 1 or z.size == 0:
        raise RunArgumentError(f"seed_error: z {z.shape} and z_ref {z_ref.shape} must be equal 1-D shapes")
    scale = np.max(np.abs(z_ref))
    if not scale > 0:
        raise RunArgumentError("seed_error: the reference z_ref is identically zero")
    return float(100.0 * np.mean(np.abs(z - z_ref)) / scale)


def _torque_steps(schedule: Sequence[tuple[float, float]], dt: float, n_steps: int) -> tuple[np.ndarray, set[int]]:
    """Torque per step [N·m] and the step indices at which it switches (restarts)."""
    times = [float(t0) for t0, _ in schedule]
    if not schedule or times[0] != 0.0 or np.any(np.diff(times) <= 0):
        raise ValueError(f"pinned-free beam: torque schedule must start at t=0 with increasing times, got {schedule!r}")
    tau = np.empty(n_steps)
    restarts: set[int] = set()
    for i, (t0, value) in enumerate(schedule):
        k0 = round(t0 / dt)
        if abs(k0 * dt - t0) > 1e-9 * dt:
            raise ValueError(f"pinned-free beam: torque switch at t={t0} s is not on the step grid (dt={dt} s)")
        if not np.isfinite(value):
            raise ValueError(f"pinned-free beam: torque value {value!r} at t={t0} s is not finite")
        k1 = n_steps if i + 1 == len(schedule) else round(times[i + 1] / dt)
        tau[k0:k1] = value
        if 0 < k0 < n_steps:
            restarts.add(k0)
    return tau, restarts


def solve(
    n_elements: int,
    dt: float,
    *,
    rho_inf: float = 1.0,
    t_end: float = T_END,
    schedule: Sequence[tuple[float, float]] = BANG_BANG,
    young: float = YOUNG,
    tol: float = 1e-10,
    max_iterations: int = 20,
) -> Solution:
    """Integrate the pinned-free beam from rest.

    Parameters
    ----------
    n_elements : int
        Number of equal ANCF elements (even, ≥ 2).
    dt : float
        Fixed time step [s]; ``t_end`` and every torque switch must be multiples of it.
    rho_inf : float
        Generalised-α spectral radius at infinite frequency, 0 ≤ ρ∞ ≤ 1 (1: average-acceleration Newmark,
        no numerical damping).
    t_end : float
        Simulated time [s].
    schedule : sequence of (t_start [s], torque [N·m])
        Piecewise-constant pin torque about world z; the default is the seed's bang-bang load.
    young : float
        Young's modulus [Pa] (scaled for the rigid-limit check).
    tol : float
        Newton stops when the largest position/slope update is below ``tol`` (m, or dimensionless for slopes).
    max_iterations : int
        Newton iterations per step before giving up (``RuntimeError``).

    Returns
    -------
    Solution
        The series at every step, ``t = 0, dt, …, t_end``.
    """
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"pinned-free beam: dt must be finite and > 0, got {dt!r}")
    n_steps = round(t_end / dt)
    if n_steps < 1 or abs(n_steps * dt - t_end) > 1e-9 * dt:
        raise ValueError(f"pinned-free beam: t_end={t_end} s is not a positive multiple of dt={dt} s")
    if not 0.0 <= rho_inf <= 1.0:
        raise ValueError(f"pinned-free beam: rho_inf must lie in [0, 1], got {rho_inf!r}")
    cpu0 = time.process_time()
    beam = Beam(n_elements, young=young)
    tau_steps, restarts = _torque_steps(schedule, dt, n_steps)
    alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    alpha_f = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 - alpha_m + alpha_f
    beta = 0.25 * (1.0 - alpha_m + alpha_f) ** 2
    u = Beam.BAND
    mass_band = beam.mass_band[:, 2:]
    mass = beam.mass

    q = beam.initial()
    v = np.zeros(beam.size - 2)
    f_int, _, strain = beam.internal(q, tangent=False)

    def generalised(q_full: np.ndarray, f_full: np.ndarray, tau: float) -> np.ndarray:
        """Internal minus external generalised force on the free coordinates."""
        g = f_full[2:].copy()
        grad, _ = Beam.pin_torque(q_full)
        g[0:2] -= tau * grad
        return g

    def acceleration(q_full: np.ndarray, f_full: np.ndarray, tau: float) -> np.ndarray:
        return sla.solve_banded((u, u), mass_band, -generalised(q_full, f_full, tau), check_finite=False)

    a = acceleration(q, f_int, tau_steps[0])
    t = dt * np.arange(n_steps + 1)
    tip = np.empty((n_steps + 1, 2))
    angle = np.empty(n_steps + 1)
    moment = np.empty(n_steps + 1)
    energy = np.empty(n_steps + 1)
    work = np.zeros(n_steps + 1)
    tip[0], angle[0], moment[0], energy[0] = q[-4:-2], Beam.pin_angle(q), beam.moment_mid(q), strain
    c_mass = (1.0 - alpha_m) / (beta * dt * dt)
    iterations = 0
    for k in range(n_steps):
        tau = tau_steps[k]
        if k in restarts:
            a = acceleration(q, f_int, tau)
        g_old = generalised(q, f_int, tau)
        a_new = -(0.5 - beta) / beta * a  # predictor q_{n+1} = q_n + dt v_n (robust with stiff modes)
        q_new = q.copy()
        q_new[2:] = q[2:] + dt * v + dt * dt * ((0.5 - beta) * a + beta * a_new)
        for it in range(max_iterations + 1):
            f_new, k_band, _ = beam.internal(q_new)
            residual = (
                mass @ ((1.0 - alpha_m) * a_new + alpha_m * a)
                + (1.0 - alpha_f) * generalised(q_new, f_new, tau)
                + alpha_f * g_old
            )
            jac = np.empty((3 * u + 1, beam.size - 2))  # LAPACK gbsv layout: u extra rows for the LU fill-in
            np.add(c_mass * mass_band, (1.0 - alpha_f) * k_band[:, 2:], out=jac[u:])
            _, hess = Beam.pin_torque(q_new)
            for i in range(2):
                for j in range(2):
                    jac[2 * u + i - j, j] -= (1.0 - alpha_f) * tau * hess[i, j]
            *_, dq, info = _gbsv(u, u, jac, -residual, overwrite_ab=1, overwrite_b=1)
            if info != 0:
                raise RuntimeError(f"pinned-free beam: singular Newton matrix at t={t[k + 1]:.6g} s (info {info})")
            iterations += 1
            q_new[2:] += dq
            a_new += dq / (beta * dt * dt)
            if not np.all(np.isfinite(dq)):
                raise RuntimeError(f"pinned-free beam: Newton diverged at t={t[k + 1]:.6g} s (dt={dt}, n={n_elements})")
            if np.max(np.abs(dq)) < tol:
                break
            if it == max_iterations:
                raise RuntimeError(
                    f"pinned-free beam: Newton did not converge in {max_iterations} iterations at t={t[k + 1]:.6g} s "
                    f"(last update {np.max(np.abs(dq)):.3g}, dt={dt}, n={n_elements})"
                )
        v = v + dt * ((1.0 - gamma) * a + gamma * a_new)
        a = a_new
        theta_old = Beam.pin_angle(q)
        q = q_new
        f_int, _, strain = beam.internal(q, tangent=False)
        i = k + 1
        tip[i] = q[-4:-2]
        angle[i] = Beam.pin_angle(q)
        moment[i] = beam.moment_mid(q)
        energy[i] = strain + 0.5 * float(v @ (mass @ v))
        work[i] = work[k] + tau * float(np.angle(np.exp(1j * (angle[i] - theta_old))))
    return Solution(
        t=t,
        tip=tip,
        pin_angle=np.unwrap(angle),
        moment_mid=moment,
        energy=energy,
        work=work,
        n_elements=int(n_elements),
        dt=float(dt),
        rho_inf=float(rho_inf),
        newton_iterations=iterations,
        cpu_time=time.process_time() - cpu0,
    )


def write_reference(path: Path, data: dict[str, np.ndarray | float | int | str]) -> None:
    """Write ``data`` to the ``.npz`` file ``path`` atomically (flexlib's cache writer: a temporary file in the
    same folder renamed into place; flexlib's file plumbing only, none of its flexible-body code)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    store_init(path, **data)


def _run(args: tuple[int, float, float]) -> Solution:
    n, dt, rho = args
    return solve(n, dt, rho_inf=rho)


def study(
    elements: Sequence[int], dts: Sequence[float], rho_inf: float, compare_rho: float | None, jobs: int = 1
) -> dict[str, object]:
    """Convergence study: element refinement at the finest step, step refinement at the finest mesh, and the
    second-finest mesh at the finest step repeated with ``compare_rho`` (if given). Returns the runs keyed by
    ``(n, dt, ρ∞)`` and the table rows ``(label, {series: seed error [%]})`` between successive refinements."""
    elements = sorted(elements)
    dts = sorted(dts, reverse=True)
    n_fine, dt_fine = elements[-1], dts[-1]
    keys = [(n, dt_fine, rho_inf) for n in elements] + [(n_fine, dt, rho_inf) for dt in dts[:-1]]
    n_rho = elements[-2] if len(elements) > 1 else n_fine  # the damping check on the second-finest mesh
    if compare_rho is not None:
        keys.append((n_rho, dt_fine, compare_rho))
    keys = sorted(set(keys), key=lambda k: k[0] / k[1], reverse=True)  # the costliest first
    if jobs > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(jobs) as pool:
            runs = dict(zip(keys, pool.map(_run, keys)))
    else:
        runs = {key: _run(key) for key in keys}
    sampled = {key: run.sampled() for key, run in runs.items()}
    rows: list[tuple[str, dict[str, float]]] = []
    names = TABLE_SERIES

    def compare(coarse: tuple, fine: tuple, label: str) -> dict[str, float]:
        errors = {name: seed_error(sampled[coarse][name], sampled[fine][name]) for name in names}
        rows.append((label, errors))
        return errors

    last_n = last_dt = {}
    for n0, n1 in itertools.pairwise(elements):
        last_n = compare((n0, dt_fine, rho_inf), (n1, dt_fine, rho_inf), f"n {n0:>4} -> {n1:<4} dt {dt_fine:.4g}")
    for d0, d1 in itertools.pairwise(dts):
        last_dt = compare((n_fine, d0, rho_inf), (n_fine, d1, rho_inf), f"dt {d0:.4g} -> {d1:.4g} n {n_fine}")
    rho_effect = {}
    if compare_rho is not None:
        rho_effect = compare(
            (n_rho, dt_fine, compare_rho), (n_rho, dt_fine, rho_inf), f"rho_inf {compare_rho} vs {rho_inf} n {n_rho}"
        )
    convergence = {name: max(last_n.get(name, 0.0), last_dt.get(name, 0.0)) for name in names}
    return {
        "runs": runs,
        "sampled": sampled,
        "rows": rows,
        "finest": (n_fine, dt_fine, rho_inf),
        "convergence": convergence,
        "rho_effect": rho_effect,
    }


def format_table(rows: Sequence[tuple[str, dict[str, float]]]) -> str:
    """The convergence table: seed error [%] (eq. 2) of each coarser run against the next finer one."""
    names = TABLE_SERIES
    lines = [f"{'refinement':<34}" + "".join(f"{name:>20}" for name in names)]
    lines += [f"{label:<34}" + "".join(f"{errors[name]:>19.4f}%" for name in names) for label, errors in rows]
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the convergence study, print the table, write the finest run to :data:`REFERENCE_FILE`."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[32, 64, 128])
    parser.add_argument("--dts", type=float, nargs="+", default=[2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5])
    parser.add_argument("--rho-inf", type=float, default=1.0, help="generalised-α ρ∞ of the reference runs")
    parser.add_argument("--compare-rho", type=float, default=0.9, help="ρ∞ of the damping check (negative: none)")
    parser.add_argument("--jobs", type=int, default=1, help="runs in parallel processes")
    parser.add_argument("--output", type=Path, default=REFERENCE_FILE)
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args(argv)
    compare_rho = args.compare_rho if args.compare_rho >= 0 else None
    wall0 = time.perf_counter()
    result = study(args.elements, args.dts, args.rho_inf, compare_rho, args.jobs)
    runs: dict = result["runs"]
    print(f"{'n':>5} {'dt [s]':>10} {'rho_inf':>8} {'CPU [s]':>9} {'Newton/step':>12}")
    for (n, dt, rho), run in sorted(runs.items()):
        print(f"{n:>5} {dt:>10.4g} {rho:>8.2f} {run.cpu_time:>9.1f} {run.newton_iterations / (len(run.t) - 1):>12.2f}")
    table = format_table(result["rows"])
    print("\nSeed error (eq. 2, %) between successive refinements:\n" + table)
    finest = runs[result["finest"]]
    series = result["sampled"][result["finest"]]
    print(
        f"\nfinest run n={finest.n_elements} dt={finest.dt:.4g} s rho_inf={finest.rho_inf}: "
        f"CPU {finest.cpu_time:.1f} s; "
        f"max|tip_y| {np.max(np.abs(series['tip_y'])):.6f} m, max|tip_deflection| "
        f"{np.max(np.abs(series['tip_deflection'])):.6f} m, max|moment_mid_avg| "
        f"{np.max(np.abs(series['moment_mid_avg'])):.5f} N·m (study wall time {time.perf_counter() - wall0:.0f} s)"
    )
    if args.no_write:
        return 0
    t_dense = 1e-3 * np.arange(round(T_END / 1e-3) + 1)
    data: dict[str, np.ndarray | float | int | str] = {name: np.asarray(value) for name, value in series.items()}
    data["t_dense"] = t_dense
    data["moment_mid_avg_dense"] = window_average(finest.t, finest.moment_mid, t_dense)
    data["n_elements"] = finest.n_elements
    data["dt"] = finest.dt
    data["rho_inf"] = finest.rho_inf
    data["cpu_time"] = finest.cpu_time
    for name, value in result["convergence"].items():
        data[f"convergence_error_{name}"] = value
    for name, value in result["rho_effect"].items():
        data[f"rho_inf_effect_{name}"] = value
    data["provenance"] = (
        "benchmarks/references/pinned_free_beam.py (flexlib issue 10): seed-001 pinned-free beam, planar ANCF "
        "elastic-line Euler-Bernoulli elements (exact curvature, Green axial strain, consistent mass, no rotary "
        f"inertia), generalised-alpha (Chung & Hulbert 1993) rho_inf={finest.rho_inf}, n_elements="
        f"{finest.n_elements}, dt={finest.dt:g} s, Newton tol 1e-10. moment_mid = EI*kappa at mid-span, positive "
        "when the beam curves towards +local y; moment_mid_avg, tip_deflection_avg = means over [t-5ms, t+5ms] "
        "within [0, 2] s. "
        "convergence_error_* = max seed error (eq. 2, %) between the two finest meshes and the two finest steps.\n"
        + table
    )
    write_reference(args.output, data)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
