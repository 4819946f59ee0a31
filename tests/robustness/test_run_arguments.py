"""Bad arguments of ``Simulation.run`` fail before any work with a RunArgumentError (a ValueError) naming the
argument, the value and what is allowed (issue 8: before, ``dt_out=0`` gave ZeroDivisionError, ``dt_out=1e-9``
a MemoryError, ``t_end=inf`` an OverflowError, output times after t_end were dropped silently, ``params`` as a
list an AttributeError, ``max_step=1e-9`` ran for minutes)."""

import numpy as np
import pytest

import flexlib as fl
from flexlib.models.reference.mass_spring_damper import Oscillator


@pytest.fixture(scope="module")
def sim():
    return fl.Simulation(Oscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)


# (arguments of run(), regular expression the message must match: argument name and what is wrong)
BAD = {
    "t_end_inf": (dict(t_end=np.inf), r"t_end = inf.*finite"),
    "t_end_nan": (dict(t_end=np.nan), r"t_end = nan.*finite"),
    "t_end_before_start": (dict(t_end=-1.0), r"t_end = -1\.0.*greater than t_start \(0\)"),
    "t_end_equals_start": (dict(t_end=0.5, t_start=0.5), r"t_end = 0\.5.*greater than t_start"),
    "t_end_span_underflows": (dict(t_end=1e-300), r"t_end = 1e-300.*span.*too short.*at least 1e-100 s"),
    "t_end_span_below_resolution": (dict(t_start=1e6, t_end=1e6 + 1e-7),
                                    r"span t_end - t_start = 1\.0+1e-07 s is too short.*t_start = 1e\+06 s.*at least "
                                    r"1e-06 s"),
    "t_end_string": (dict(t_end="10"), r"t_end = '10'.*finite time.*str"),
    "t_end_bool": (dict(t_end=True), r"t_end = True.*bool"),
    "t_start_nan": (dict(t_end=1.0, t_start=np.nan), r"t_start = nan.*finite"),
    "t_start_minus_inf": (dict(t_end=1.0, t_start=-np.inf), r"t_start = -inf.*finite"),
    "dt_out_zero": (dict(t_end=1.0, dt_out=0.0), r"dt_out = 0\.0.*positive"),
    "dt_out_negative": (dict(t_end=1.0, dt_out=-0.1), r"dt_out = -0\.1.*positive"),
    "dt_out_nan": (dict(t_end=1.0, dt_out=np.nan), r"dt_out = nan.*positive"),
    "dt_out_inf": (dict(t_end=1.0, dt_out=np.inf), r"dt_out = inf.*finite"),
    "dt_out_tiny": (dict(t_end=1.0, dt_out=1e-9),
                    r"dt_out = 1e-09.*1000000001 output points.*more than 10000000.*output_times"),
    "dt_out_list": (dict(t_end=1.0, dt_out=[0.1]), r"dt_out = \[0\.1\].*list"),
    "dt_out_and_output_times": (dict(t_end=1.0, dt_out=0.1, output_times=[0.5]), r"dt_out.*not both"),
    "output_times_2d": (dict(t_end=1.0, output_times=[[0.1, 0.2]]), r"output_times.*1-D.*\(1, 2\)"),
    "output_times_nan": (dict(t_end=1.0, output_times=[0.1, np.nan]), r"output_times\[1\] = nan"),
    "output_times_unsorted": (dict(t_end=1.0, output_times=[0.5, 0.2]), r"strictly increasing.*\[0\] = 0\.5"),
    "output_times_duplicate": (dict(t_end=1.0, output_times=[0.2, 0.2]), r"strictly increasing"),
    "output_times_before_start": (dict(t_end=1.0, t_start=0.5, output_times=[0.1, 0.6]),
                                  r"output_times\[0\] = 0\.1 s is before t_start = 0\.5"),
    "output_times_after_end": (dict(t_end=1.0, output_times=[0.5, 1.5, 2.0]),
                               r"2 time\(s\) after t_end = 1 s.*last is 2 s"),
    "output_times_empty": (dict(t_end=1.0, output_times=[]), r"output_times.*at least one"),
    "output_times_text": (dict(t_end=1.0, output_times=["a", "b"]), r"output_times.*1-D sequence of times"),
    "rtol_zero": (dict(t_end=1.0, rtol=0.0), r"rtol = 0\.0.*0 < rtol < 1"),
    "rtol_negative": (dict(t_end=1.0, rtol=-1e-6), r"rtol = -1e-06.*0 < rtol < 1"),
    "rtol_one": (dict(t_end=1.0, rtol=1.0), r"rtol = 1\.0.*0 < rtol < 1"),
    "rtol_nan": (dict(t_end=1.0, rtol=np.nan), r"rtol = nan"),
    "rtol_string": (dict(t_end=1.0, rtol="1e-6"), r"rtol = '1e-6'.*str"),
    "atol_zero": (dict(t_end=1.0, atol=0.0), r"atol = 0\.0.*positive"),
    "atol_negative": (dict(t_end=1.0, atol=-1e-8), r"atol = -1e-08.*positive"),
    "atol_inf": (dict(t_end=1.0, atol=np.inf), r"atol = inf.*finite"),
    "max_step_negative": (dict(t_end=1.0, max_step=-0.1), r"max_step = -0\.1.*>= 0"),
    "max_step_nan": (dict(t_end=1.0, max_step=np.nan), r"max_step = nan"),
    "max_step_inf": (dict(t_end=1.0, max_step=np.inf), r"max_step = inf.*finite"),
    "max_step_too_small": (dict(t_end=1.0, max_step=1e-9),
                           r"max_step = 1e-09.*1e\+09 steps.*max_steps = 5000000.*raise max_step or max_steps"),
    "max_step_vs_max_steps": (dict(t_end=10.0, max_step=0.1, max_steps=50), r"100 steps.*max_steps = 50"),
    "max_steps_zero": (dict(t_end=1.0, max_steps=0), r"max_steps = 0.*positive integer"),
    "max_steps_negative": (dict(t_end=1.0, max_steps=-5), r"max_steps = -5.*positive integer"),
    "max_steps_fraction": (dict(t_end=1.0, max_steps=10.5), r"max_steps = 10\.5.*positive integer"),
    "max_order_zero": (dict(t_end=1.0, max_order=0), r"max_order = 0.*integer 1 \.\.\. 5"),
    "max_order_six": (dict(t_end=1.0, max_order=6), r"max_order = 6.*integer 1 \.\.\. 5"),
    "max_order_fraction": (dict(t_end=1.0, max_order=2.5), r"max_order = 2\.5.*integer"),
    "max_order_bool": (dict(t_end=1.0, max_order=True), r"max_order = True"),
    "max_steps_string": (dict(t_end=1.0, max_steps="1000"), r"max_steps = '1000'.*positive integer"),
    "max_steps_bool": (dict(t_end=1.0, max_steps=True), r"max_steps = True.*positive integer"),
    "params_list": (dict(t_end=1.0, params=[("x", 1.0)]), r"params = \[\('x', 1\.0\)\].*dict.*list"),
    "params_string": (dict(t_end=1.0, params="mass.m=2"), r"params = 'mass\.m=2'.*dict.*str"),
    "params_int_key": (dict(t_end=1.0, params={1: 2.0}), r"params.*keys must be parameter names.*got 1"),
    "steady_state_string": (dict(t_end=1.0, steady_state="yes"), r"steady_state = 'yes'.*True or False"),
    "steady_state_int": (dict(t_end=1.0, steady_state=1), r"steady_state = 1.*True or False.*int"),
    "dynamic_states_none": (dict(t_end=1.0, dynamic_states=None), r"dynamic_states = None.*True or False"),
    "progress_string": (dict(t_end=1.0, progress="no"), r"progress = 'no'.*True, False or None"),
    "solver_upper_case": (dict(t_end=1.0, solver="IDA"), r"solver = 'IDA'.*'ida', 'casadi-idas'.*did you mean 'ida'"),
    "solver_unknown": (dict(t_end=1.0, solver="cvode"), r"solver = 'cvode'.*one of 'ida', 'casadi-idas'"),
    "solver_none": (dict(t_end=1.0, solver=None), r"solver = None.*one of"),
    "result_file_int": (dict(t_end=1.0, result_file=123), r"result_file = 123.*str or os\.PathLike.*int"),
    "result_file_bytes": (dict(t_end=1.0, result_file=b"run.h5"), r"result_file = b'run\.h5'.*bytes"),
    "result_file_empty": (dict(t_end=1.0, result_file=""), r"result_file = ''.*empty"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_argument_fails_before_any_work(no_work, case):
    kwargs, pattern = BAD[case]
    with pytest.raises(fl.RunArgumentError, match=pattern) as err:
        no_work.run(**kwargs)
    assert isinstance(err.value, ValueError) and isinstance(err.value, fl.FlexlibError)
    assert str(err.value).startswith("run(): ")


def test_result_file_is_a_directory(no_work, tmp_path):
    with pytest.raises(fl.RunArgumentError, match=rf"result_file = .*{tmp_path.name}.*is a directory"):
        no_work.run(1.0, result_file=tmp_path)


def test_result_file_under_a_file(no_work, tmp_path):
    """The directory of the result file cannot be created because a file has its name."""
    blocker = tmp_path / "data"
    blocker.write_text("not a directory")
    with pytest.raises(fl.RunArgumentError, match=r"result_file = .*cannot be created.*data is a file"):
        no_work.run(1.0, result_file=blocker / "sub" / "run.h5")


def test_result_file_in_a_directory_that_refuses_files(no_work):
    """sysfs refuses new files even for root: the probe write fails before the run, with the OS reason."""
    with pytest.raises(fl.RunArgumentError, match=r"result_file = '/sys/run\.h5'.*cannot write in /sys: Permission"):
        no_work.run(1.0, result_file="/sys/run.h5")


def test_older_callers_catching_value_error_still_work(no_work):
    with pytest.raises(ValueError, match="t_end"):
        no_work.run(0.0)


def test_unknown_parameter_is_still_a_parameter_error(sim):
    with pytest.raises(fl.ParameterError, match=r"unknown parameter 'mass\.m'"):
        sim.run(1.0, params={"mass.m": 2.0})


def test_accepted_edge_cases_run(sim, tmp_path):
    """Values at the edges of what is allowed: output times exactly at t_start and t_end, t_end with round-off
    (1e-15), a dt_out longer than the run, an integral float max_steps, a result file in a directory that does
    not exist yet. Reference: x = cos t, |error| < 1e-5 at rtol 1e-8."""
    res = sim.run(1.0, output_times=[0.0, 0.5, 1.0 + 1e-15], rtol=1e-8, atol=1e-10)
    np.testing.assert_array_equal(res.t, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-5)
    res = sim.run(1.0, dt_out=5.0, max_steps=1e5)
    np.testing.assert_array_equal(res.t, [0.0, 1.0])
    path = tmp_path / "new" / "dir" / "run.h5"
    res = sim.run(1.0, dt_out=0.25, result_file=path, max_step=0.01, max_steps=np.int64(200))
    assert fl.load_result(path).t.tolist() == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert not [p for p in path.parent.iterdir() if p.name != "run.h5"]  # no probe or temporary file left


def test_bad_value_from_the_models_experiment_names_it():
    """A run without arguments takes t_end, dt_out and tolerances from the model's ``experiment``: a bad value
    there is named as coming from it."""

    class TimedOscillator(Oscillator):
        experiment = fl.Experiment(t_end=2.0, dt_out=0.0)

    sim = fl.Simulation(TimedOscillator(init={"x": 1.0, "v": 0.0}), use_cache=False)
    with pytest.raises(fl.RunArgumentError, match=r"dt_out = 0\.0 is invalid.*comes from TimedOscillator\.experiment"):
        sim.run()
    res = sim.run(1.0)  # an explicit t_end: the experiment's dt_out is not used, every step is recorded
    assert res.success and len(res.t) > 2


@pytest.mark.parametrize("solver", ["ida", "ida-sksundae", "casadi-idas"])
def test_max_order_caps_the_bdf_order_and_is_recorded(sim, solver):
    """x = cos t to 1e-5 with the order capped at 2 and at 5; at the same tolerance order 2 needs more than twice
    the residual evaluations of order 5 (the cap is applied)."""
    evals = {}
    for order in (2, 5):
        res = sim.run(5.0, dt_out=0.1, rtol=1e-8, atol=1e-10, max_order=order, solver=solver, progress=False)
        np.testing.assert_allclose(res["x"], np.cos(res.t), atol=1e-5)
        assert res.stats["max_order"] == order
        evals[order] = res.stats["nfev"]
    assert evals[2] > 2 * evals[5]
