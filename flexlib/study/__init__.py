"""Studies: many runs of one registered model with other values, on Dask (issue 33).

A study is a list of **variants** of a registered scenario (parameter values: a grid, a list, a Latin hypercube or a
Monte Carlo sample) and the **reductions** each run is judged by (the peak of a signal, its value at the end, any
function of the result). :func:`run_study` runs the variants on a Dask cluster — by default a ``LocalCluster`` on this
machine (one process per core, :func:`local_cluster`; start one yourself to serve several studies), or
``scheduler="tcp://host:8786"`` — each worker building the model once (from the
disk cache when it is there) and running many variants; only the reductions come back. The table (one row per
variant: its inputs, the reductions, the status, the error of a failed run and the run time) is written as Parquet and
a study started again skips the rows it has.
"""

from flexlib.study.reductions import Final, Maximum, Minimum, Peak, Reduction
from flexlib.study.run import StudyResult, local_cluster, run_study
from flexlib.study.variants import grid, latin_hypercube, monte_carlo, start_pose

__all__ = ["Final", "Maximum", "Minimum", "Peak", "Reduction", "StudyResult", "grid", "latin_hypercube",
           "local_cluster", "monte_carlo", "run_study", "start_pose"]
