"""Models defined where engineers work: ``python -c``, an interactive interpreter, a Jupyter notebook.

Such classes have no source file; the cache keys them by their code (``flexlib.compile.cache_key.code_digest``).
Each test runs the real thing in a subprocess with its own cache dir and checks: the model builds and runs
(x' = −a·x, x(1) = exp(−a) to 1e-6), a second build of the same class is a cache hit, and a class changed
in the session is *not* a cache hit (its result follows the new code).
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

MODEL = """\
import flexlib as fl
from flexlib import Parameter, Variable, der, eq
class Decay(fl.Model):
    a = Parameter(2.0, unit="1/s", doc="Rate")
    x = Variable(unit="1", doc="Amount", start=1.0, fixed=True)
    def equations(self):
        return [eq(der(self.x), -self.a * self.x)]

"""
RUN = """\
sim = fl.Simulation(Decay(), codegen=False)
res = sim.run(1.0, rtol=1e-10, atol=1e-12)
print("RESULT", sim.build.cached, repr(float(res["x"][-1])))

"""
CHANGED = MODEL.replace("-self.a * self.x", "-2.0 * self.a * self.x")  # x(1) = exp(-4)


def _results(text: str) -> list[tuple[bool, float]]:
    rows = [line.split()[1:] for line in text.splitlines() if line.startswith("RESULT ")]
    return [(cached == "True", float(value)) for cached, value in rows]


def _env(tmp_path: Path) -> dict[str, str]:
    return dict(os.environ, FLEXLIB_CACHE_DIR=str(tmp_path / "cache"), OMP_NUM_THREADS="1",
                PYTHONWARNINGS="error::UserWarning")


def _check(results: list[tuple[bool, float]]) -> None:
    """Build + run, cache hit for the same class, miss for the changed class."""
    assert [c for c, _ in results] == [False, True, False]
    assert [v for _, v in results] == pytest.approx([math.exp(-2), math.exp(-2), math.exp(-4)], rel=1e-6)


def test_model_defined_in_python_c(tmp_path):
    code = MODEL + RUN + RUN + CHANGED + RUN
    proc = subprocess.run([sys.executable, "-c", code], env=_env(tmp_path), cwd=tmp_path, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    _check(_results(proc.stdout))
    again = subprocess.run([sys.executable, "-c", MODEL + RUN], env=_env(tmp_path), cwd=tmp_path,
                           capture_output=True, text=True, timeout=120)
    assert _results(again.stdout) == [(True, pytest.approx(math.exp(-2), rel=1e-6))], again.stderr


def test_model_defined_in_interactive_interpreter(tmp_path):
    """``python -i`` fed through stdin: every line goes through the interactive compiler (``<stdin>``)."""
    session = MODEL + RUN + RUN + CHANGED + RUN
    proc = subprocess.run([sys.executable, "-i", "-q"], input=session, env=_env(tmp_path), cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)
    assert "Traceback" not in proc.stderr, proc.stderr
    _check(_results(proc.stdout))


def test_model_defined_in_jupyter_notebook(tmp_path):
    """A real notebook executed by a Jupyter kernel (nbclient + ipykernel of this environment); the class is
    defined in one cell and defined again, unchanged, in a later cell (a cache hit), then changed."""
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    cells = [MODEL + RUN, RUN, MODEL + RUN, CHANGED + RUN]
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(textwrap.dedent(c)) for c in cells]
    path = tmp_path / "interactive.ipynb"
    nbformat.write(nb, path)
    old = dict(os.environ)
    os.environ.update(_env(tmp_path))
    os.environ.pop("PYTHONWARNINGS")
    try:
        client = nbclient.NotebookClient(nb, kernel_name="python3", timeout=60, startup_timeout=60,
                                         resources={"metadata": {"path": str(tmp_path)}})
        client.execute()
    finally:
        os.environ.clear()
        os.environ.update(old)
    streams = [o for cell in nb.cells for o in cell.get("outputs", []) if o.get("output_type") == "stream"]
    out = "".join(o["text"] for o in streams if o.get("name") == "stdout")
    err = "".join(o["text"] for o in streams if o.get("name") == "stderr")
    assert "Warning" not in err, err
    results = _results(out)
    assert [c for c, _ in results] == [False, True, True, False], out
    assert [v for _, v in results] == pytest.approx([math.exp(-2)] * 3 + [math.exp(-4)], rel=1e-6)
