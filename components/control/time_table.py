"""Signal interpolated in a table of time points."""

from __future__ import annotations

from typing import Any

import numpy as np

from flexlib import Parameter, eq, if_else, time
from flexlib.core.values import numeric_array
from flexlib.errors import ParameterError

from .interfaces import PartialSO, check_choice

__all__ = ["TimeTable"]

SMOOTHNESS = ("linear", "constant", "akima", "modified_akima", "monotone")


def _akima_slopes(h: np.ndarray, m: np.ndarray, modified: bool) -> np.ndarray:
    """Knot derivatives of Akima's spline (1970); ``modified``: Akima's weights plus |m_i + m_i+1|/2."""
    ext = np.concatenate([[3 * m[0] - 2 * m[1], 2 * m[0] - m[1]], m, [2 * m[-1] - m[-2], 3 * m[-1] - 2 * m[-2]]])
    dm = np.abs(np.diff(ext))
    if modified:
        dm = dm + 0.5 * np.abs(ext[1:] + ext[:-1])
    w_left, w_right = dm[2:], dm[:-2]  # weights of m_{i-1} (left) and m_i (right) at knot i
    total = w_left + w_right
    average = 0.5 * (ext[1:-2] + ext[2:-1])  # both weights zero: mean of the adjacent slopes
    defined = total > 1e-9 * total.max() if total.size and total.max() > 0 else np.zeros(total.shape, bool)
    safe = np.where(defined, total, 1.0)
    return np.where(defined, (w_left * ext[1:-2] + w_right * ext[2:-1]) / safe, average)


def _monotone_slopes(h: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Knot derivatives preserving monotonicity: Fritsch & Butland (1984) weighted harmonic mean."""
    d = np.zeros(len(h) + 1)
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    same = (np.sign(m[1:]) == np.sign(m[:-1])) & (m[1:] != 0) & (m[:-1] != 0)
    with np.errstate(divide="ignore"):
        d[1:-1] = np.where(same, (w1 + w2) / (w1 / np.where(same, m[:-1], 1) + w2 / np.where(same, m[1:], 1)), 0.0)

    def end(h0: float, h1: float, m0: float, m1: float) -> float:  # three-point end formula, shape-preserving
        s = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        if np.sign(s) != np.sign(m0):
            return 0.0
        if np.sign(m0) != np.sign(m1) and abs(s) > abs(3 * m0):
            return 3 * m0
        return s

    d[0], d[-1] = end(h[0], h[1], m[0], m[1]), end(h[-1], h[-2], m[-1], m[-2])
    return d


class TimeTable(PartialSO):
    """Output interpolated in a table ``(t, y)``; end values held outside the table.

    Between the time points the output is linear (``"linear"``, default), the value of the
    previous point (``"constant"``) or a cubic Hermite polynomial with a continuous first
    derivative: Akima's spline (``"akima"``, MSL ContinuousDerivative), the modified Akima
    spline (``"modified_akima"``, MSL ModifiedContinuousDerivative) or the monotonicity-
    preserving Fritsch–Butland spline (``"monotone"``, MSL MonotoneContinuousDerivative1).
    Every time point is a time event, so the integrator never steps across a kink. Tables
    of two points are linear for every smooth option.

    Parameters
    ----------
    t : array_like
        Time points [s], strictly increasing (structural: one time event each).
    y : array_like
        Output values at the time points [1], as many as ``t``.
    smoothness : str
        ``"linear"``, ``"constant"``, ``"akima"``, ``"modified_akima"`` or ``"monotone"``.

    Connectors
    ----------
    y : Output [1]
        Interpolated signal.

    Notes
    -----
    The table is data of the structure (a new table recompiles; ``offset`` and
    ``shift_time`` are run-time parameters). Outside the table the first and last values
    are held (MSL HoldLastPoint; MSL's default extrapolation is LastTwoPoints). One output
    column (MSL CombiTimeTable has several).

    References
    ----------
    Modelica Standard Library 4.0, ``Modelica.Blocks.Sources.CombiTimeTable``; H. Akima,
    *J. ACM* 17(4), 1970, 589–602; F. N. Fritsch, J. Butland, *SIAM J. Sci. Stat. Comput.*
    5(2), 1984, 300–304.
    """

    offset = Parameter(0.0, unit="1", doc="Offset of the output signal")
    shift_time = Parameter(0.0, unit="s",
                           doc=("Shift of the table's time points: the output at ``time`` is the table at ``time - "
                                "shift_time``"))

    def __init__(self, t: Any, y: Any, smoothness: str = "linear", **kw: Any) -> None:
        name = type(self).__name__
        t_arr, y_arr = (numeric_array(v, f"{name}: {k}", f"a vector of real numbers [{u}]", ParameterError)
                        for k, v, u in (("t", t, "s"), ("y", y, "1")))
        if t_arr.ndim != 1 or y_arr.ndim != 1 or t_arr.size == 0:
            raise ParameterError(f"{name}: t and y must be non-empty vectors, got shapes {t_arr.shape}, {y_arr.shape}")
        if t_arr.size != y_arr.size:
            raise ParameterError(f"{name}: t has {t_arr.size} points but y has {y_arr.size}")
        for k, arr in (("t", t_arr), ("y", y_arr)):
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise ParameterError(f"{name}: t and y must be finite, but {k}[{int(bad[0])}] = {arr[bad[0]]}")
        bad = np.flatnonzero(np.diff(t_arr) <= 0)
        if bad.size:
            i = int(bad[0])
            raise ParameterError(f"{name}: time points must be strictly increasing, but t[{i}] = {t_arr[i]:g} "
                                 f">= t[{i + 1}] = {t_arr[i + 1]:g}")
        super().__init__(**kw)
        self.smoothness = check_choice(self, "smoothness", smoothness, SMOOTHNESS)
        self.table_t, self.table_y = t_arr, y_arr

    def coefficients(self) -> np.ndarray:
        """Polynomial coefficients ``c[k] = (c0, c1, c2, c3)`` of segment k in ``s = t - t[k]``."""
        t, y = self.table_t, self.table_y
        h, m = np.diff(t), np.diff(y) / np.diff(t)
        c = np.zeros((len(h), 4))
        c[:, 0] = y[:-1]
        if self.smoothness == "constant" or len(h) == 0:
            return c
        if self.smoothness == "linear" or len(h) == 1:
            c[:, 1] = m
            return c
        if self.smoothness == "monotone":
            d = _monotone_slopes(h, m)
        else:
            d = _akima_slopes(h, m, modified=self.smoothness == "modified_akima")
        c[:, 1] = d[:-1]
        c[:, 2] = (3 * m - 2 * d[:-1] - d[1:]) / h
        c[:, 3] = (d[:-1] + d[1:] - 2 * m) / h**2
        return c

    def equations(self) -> list:
        t, y = self.table_t, self.table_y
        tau = time - self.shift_time
        value: Any = float(y[-1])  # held after the last point
        for k, (c0, c1, c2, c3) in reversed(list(enumerate(self.coefficients()))):
            s = tau - float(t[k])
            value = if_else(tau < float(t[k + 1]), c0 + s * (c1 + s * (c2 + s * c3)), value)
        value = if_else(tau < float(t[0]), float(y[0]), value)
        return [eq(self.y, self.offset + value)]
