"""Tests of ``TimeTable`` (MSL ``Modelica.Blocks.Sources.CombiTimeTable``, one column, end values held).

References (independent of flexlib): ``numpy.interp`` (linear), ``numpy.searchsorted`` (constant
segments), ``scipy.interpolate.Akima1DInterpolator`` (``method="akima"`` / ``"makima"``) and
``PchipInterpolator`` (Fritsch–Butland monotone cubic), held constant outside the table. The
output is an algebraic function of time and every time point is a time event, so it matches to
1e-12 on the output grid (dyadic times: breakpoints exact in floating point). Integrated by a mass,
the position matches the second antiderivative of the same interpolant (1e-9 relative at rtol 1e-10).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import Akima1DInterpolator, PchipInterpolator, PPoly

import flexlib as fl
from flexlib.components.control import TimeTable
from flexlib.components.mechanics.translational import Force, Mass

TOL = {"rtol": 1e-8, "atol": 1e-10}
DT = 1.0 / 64.0
T_TAB = np.array([0.0, 0.25, 0.5, 1.0, 1.25, 1.75, 2.0])
Y_TAB = np.array([0.0, 1.0, 0.5, 0.75, 2.0, 2.0, -0.5])
SHIFT, OFFSET = 0.25, 0.125


def interpolant(smoothness: str):
    """Reference interpolant for a smoothness option, as a callable of table time."""
    if smoothness == "linear":
        return lambda x: np.interp(x, T_TAB, Y_TAB)
    if smoothness == "constant":
        return lambda x: Y_TAB[np.clip(np.searchsorted(T_TAB, x, side="right") - 1, 0, len(T_TAB) - 1)]
    if smoothness == "monotone":
        return PchipInterpolator(T_TAB, Y_TAB)
    return Akima1DInterpolator(T_TAB, Y_TAB, method="makima" if smoothness == "modified_akima" else "akima")


def reference(smoothness: str, t: np.ndarray) -> np.ndarray:
    """Table at time − shift_time, end values held outside, plus the offset."""
    x = np.clip(t - SHIFT, T_TAB[0], T_TAB[-1])
    return OFFSET + np.asarray(interpolant(smoothness)(x), dtype=float)


OPTIONS = ["linear", "constant", "akima", "modified_akima", "monotone"]


class Tables(fl.Model):
    def __init__(self) -> None:
        super().__init__()
        for option in OPTIONS:
            setattr(self, option, TimeTable(T_TAB, Y_TAB, smoothness=option, offset=OFFSET, shift_time=SHIFT))


@pytest.fixture(scope="module")
def result() -> fl.Result:
    return fl.Simulation(Tables(), use_cache=False).run(2.5, dt_out=DT, **TOL)


def right_values(res: fl.Result, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Time points and values, keeping the right (post-event) value at an event time."""
    keep = np.ones(len(res.t), dtype=bool)
    keep[:-1] = res.t[1:] != res.t[:-1]
    return res.t[keep], res[name][keep]


@pytest.mark.parametrize("option", OPTIONS)
def test_table_matches_reference_interpolant(result, option):
    """Output = reference interpolant at time − shift_time (held outside) + offset, to 1e-12."""
    t, y = right_values(result, f"{option}.y")
    np.testing.assert_allclose(y, reference(option, t), rtol=0, atol=1e-12)
    assert y[0] == OFFSET + Y_TAB[0] and y[-1] == OFFSET + Y_TAB[-1]  # held before and after the table


def test_smooth_options_have_continuous_slope_and_linear_has_kinks(result):
    """At a breakpoint the one-sided slopes agree for the cubic options and differ for linear.

    Reference: one-sided difference quotients of the output over 1e-4 s at t = 1.0 + shift (slopes
    of the linear table there are 0.5 and 5.0 per second). For the cubics they differ by
    y''·1e-4 (measured ≤ 5.3e-3): tolerance 1e-2, against a kink of 4.5 for the linear table."""
    tb, h = 1.0 + SHIFT, 1e-4
    fine = fl.Simulation(Tables(), use_cache=False).run(2.5, output_times=[0.0, tb - h, tb, tb + h, 2.5], **TOL)
    for option in OPTIONS[2:]:
        left, mid, right = fine.value(f"{option}.y", [tb - h, tb, tb + h])
        assert (mid - left) / h == pytest.approx((right - mid) / h, abs=1e-2)
    left, mid, right = fine.value("linear.y", [tb - h, tb, tb + h])
    assert ((mid - left) / h, (right - mid) / h) == pytest.approx((0.5, 5.0), abs=1e-6)


def test_breakpoints_are_time_events(result):
    """Every table point (shifted) is a time event, at its exact time."""
    times = {t for t, text in result.events if "linear:" in text}
    assert times == set(T_TAB + SHIFT)


def test_monotone_option_preserves_monotonicity(result):
    """The Fritsch–Butland spline stays between the end values of every segment (no overshoot);
    the Akima spline on the same table overshoots (by 0.42 on [1.25, 1.75]), so the check can fail."""
    overshoot = {}
    for option in ("monotone", "akima"):
        t, y = right_values(result, f"{option}.y")
        worst = 0.0
        for k in range(len(T_TAB) - 1):
            inside = (t - SHIFT >= T_TAB[k]) & (t - SHIFT <= T_TAB[k + 1])
            lo, hi = sorted((Y_TAB[k], Y_TAB[k + 1]))
            worst = max(worst, np.max(y[inside] - OFFSET - hi), np.max(lo - (y[inside] - OFFSET)))
        overshoot[option] = worst
    assert overshoot["monotone"] <= 1e-12
    assert overshoot["akima"] > 0.1


class TablePush(fl.Model):
    """Force from a table on a free mass."""

    def __init__(self, smoothness: str, m: float) -> None:
        super().__init__()
        self.table = TimeTable(T_TAB, Y_TAB, smoothness=smoothness)
        self.force = Force()
        self.mass = Mass(m=m, init={"s": 0.0, "v": 0.0})
        self.connect(self.table.y, self.force.f)
        self.connect(self.force.flange, self.mass.flange_a)


@pytest.mark.parametrize("option", ["linear", "akima"])
@pytest.mark.parametrize("solver", ["ida", "casadi-idas"])
def test_table_force_integrates_exactly(option, solver):
    """Mass pushed by the table force: s(t) = P''(t)/m with P'' the second antiderivative of the
    piecewise-polynomial reference (scipy PPoly). The breakpoints are time events, so the integrator
    never steps across a kink: tolerance 1e-9 relative to s(2) at rtol 1e-10, on both solvers."""
    m = 2.0
    if option == "linear":
        pp = PPoly.from_spline((np.r_[T_TAB[0], T_TAB, T_TAB[-1]], np.r_[Y_TAB, 0.0, 0.0], 1))
    else:
        pp = interpolant(option)
    s_ref = pp.antiderivative(2)
    run_kw = {"solver": solver} if solver != "ida" else {}
    res = fl.Simulation(TablePush(option, m), use_cache=False).run(2.0, dt_out=DT, rtol=1e-10, atol=1e-12, **run_kw)
    t = np.linspace(0.0, 2.0, 17)
    expected = s_ref(t) / m
    np.testing.assert_allclose(res.value("mass.s", t), expected, rtol=0, atol=1e-9 * abs(expected[-1]))


def test_bad_tables_are_rejected():
    """Bad input: non-increasing or repeated times, mismatched lengths, unknown smoothness."""
    with pytest.raises(fl.ParameterError, match=r"strictly increasing, but t\[1\] = 1 >= t\[2\] = 0\.5"):
        TimeTable([0.0, 1.0, 0.5], [0.0, 1.0, 2.0])
    with pytest.raises(fl.ParameterError, match=r"strictly increasing"):
        TimeTable([0.0, 1.0, 1.0], [0.0, 1.0, 2.0])
    with pytest.raises(fl.ParameterError, match=r"t has 3 points but y has 2"):
        TimeTable([0.0, 1.0, 2.0], [0.0, 1.0])
    with pytest.raises(fl.ParameterError, match=r"non-empty"):
        TimeTable([], [])
    with pytest.raises(fl.ModelError, match=r"smoothness='spline'"):
        TimeTable([0.0, 1.0], [0.0, 1.0], smoothness="spline")
