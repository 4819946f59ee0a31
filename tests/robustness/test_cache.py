"""The disk cache heals and cannot be abused (issue 8, deliverables 2 and 5).

Every damaged, planted or misconfigured cache item below must give one ``CacheWarning`` naming the file or
directory, never a crash, never executed code and never a different answer: the reference of each test is
the same model built and run without the cache (``use_cache=False``), compared to 1e-12 (both runs do the
same arithmetic; only the cache handling differs).
"""

from __future__ import annotations

import hashlib
import json
import os
import pickle
import subprocess
import sys
import textwrap
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest

import flexlib as fl
from flexlib import CacheWarning, Parameter, Variable, der, eq
from flexlib.compile import cache, cache_key, pipeline

ROOT = Path(__file__).resolve().parents[2]
#: This directory: the subprocesses import this module (its Oscillator) from it.
HERE = Path(__file__).resolve().parent


class CachedOscillator(fl.Model):
    """Damped oscillator m x'' + c x' + k x = 0 written as raw equations."""

    m = Parameter(1.0, unit="kg", doc="Mass")
    c = Parameter(0.3, unit="N.s/m", doc="Damping")
    k = Parameter(40.0, unit="N/m", doc="Stiffness")
    x = Variable(unit="m", doc="Position", start=0.1, fixed=True)
    v = Variable(unit="m/s", doc="Velocity", start=0.0, fixed=True)

    def equations(self):
        return [eq(der(self.x), self.v), eq(self.m * der(self.v), -self.c * self.v - self.k * self.x)]


def _reference() -> np.ndarray:
    return fl.Simulation(CachedOscillator(), use_cache=False, codegen=False).run(1.0, dt_out=0.1).values


def _run(codegen: bool = False, **kw) -> fl.Simulation:
    sim = fl.Simulation(CachedOscillator(), codegen=codegen, **kw)
    sim.last = sim.run(1.0, dt_out=0.1)
    return sim


@pytest.fixture
def cdir(tmp_path, monkeypatch) -> Path:
    d = tmp_path / "cache"
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(d))
    return d


def _prime(cdir: Path) -> None:
    """Build and run with C code in another process, so this one never maps the library that a test then
    damages (truncating a library a process has loaded crashes that process, whatever it checks)."""
    subprocess.run([sys.executable, "-c", "import test_cache; test_cache._run(codegen=True)"],
                   env=dict(os.environ, FLEXLIB_CACHE_DIR=str(cdir), PYTHONPATH=str(HERE)), cwd=ROOT, check=True,
                   timeout=300)


def _entry(cdir: Path) -> Path:
    (entry,) = [p for p in cdir.iterdir() if p.is_dir() and p.name.startswith("CachedOscillator-")]
    return entry


@contextmanager
def _metadata(cdir: Path) -> Iterator[dict]:
    """The ``model.json`` document of the cache entry, written back when the block ends (to damage it)."""
    meta = _entry(cdir) / "model.json"
    doc = json.loads(meta.read_text())
    yield doc
    meta.write_text(json.dumps(doc))


def _library(cdir: Path) -> Path:
    (lib,) = (cdir / "lib").glob("flexlib_*.so")
    return lib


def _init_file(cdir: Path) -> Path:
    (f,) = cdir.glob("CachedOscillator-*-init-*.npz")
    return f


def _heals(cdir: Path, culprit: str, codegen: bool = False) -> None:
    """The next build warns once naming ``culprit``, rebuilds, gives the reference answer, and the one after
    that is a clean cache hit."""
    with pytest.warns(CacheWarning, match=culprit) as rec:
        sim = _run(codegen)
    assert len([w for w in rec if issubclass(w.category, CacheWarning)]) == 1
    assert not sim.build.cached
    np.testing.assert_allclose(sim.last.values, _reference(), rtol=0, atol=1e-12)
    again = _run(codegen)  # no warning (pytest turns any warning into an error)
    assert again.build.cached and again.init_cached


# -- a damaged compiled library ----------------------------------------------------------------------------
def test_truncated_library_is_rebuilt_not_crashing(cdir):
    """A truncated .so (today SIGBUS at dlopen) is caught by the manifest's size and SHA-256."""
    _prime(cdir)
    lib = _library(cdir)
    lib.write_bytes(lib.read_bytes()[:1000])
    _heals(cdir, lib.name, codegen=True)


def test_garbage_library_same_size_is_rebuilt(cdir):
    """Random bytes of the right size: only the SHA-256 tells, and it does."""
    _prime(cdir)
    lib = _library(cdir)
    lib.write_bytes(np.random.default_rng(1).bytes(lib.stat().st_size))
    _heals(cdir, "SHA-256 differs", codegen=True)


def test_missing_library_is_rebuilt(cdir):
    _prime(cdir)
    lib = _library(cdir)
    lib.unlink()
    _heals(cdir, lib.name, codegen=True)


def test_library_replaced_after_load_is_not_dlopened(cdir):
    """The library is checked again right before ``casadi.external`` loads it: replaced between the build and
    the first run, it is not loaded (CacheWarning naming it) and the symbolic functions give the answer."""
    _prime(cdir)
    sim = fl.Simulation(CachedOscillator(), codegen=True)
    assert sim.build.cached
    lib = Path(sim.compiled.library)
    lib.write_bytes(b"\x7fELF" + bytes(lib.stat().st_size - 4))
    with pytest.warns(CacheWarning, match=lib.name):
        res = sim.run(1.0, dt_out=0.1)
    np.testing.assert_allclose(res.values, _reference(), rtol=0, atol=1e-12)


def test_group_writable_library_is_refused(cdir):
    _prime(cdir)
    lib = _library(cdir)
    lib.chmod(0o775)
    _heals(cdir, "writable by other users", codegen=True)


def test_library_outside_the_cache_is_refused(cdir):
    """Metadata naming a library outside ``lib/`` (path traversal) is a damaged entry, never loaded."""
    _prime(cdir)
    with _metadata(cdir) as doc:
        lib = doc["model"]["library"]
        doc["model"]["library"] = "lib/../../evil/" + lib.split("/")[-1]
        doc["manifest"][doc["model"]["library"]] = doc["manifest"].pop(lib)
    _heals(cdir, "not a compiled-model library of this cache", codegen=True)


# -- damaged metadata and arrays -------------------------------------------------------------------------------
def test_truncated_metadata_is_rebuilt(cdir):
    _run()
    meta = _entry(cdir) / "model.json"
    meta.write_bytes(meta.read_bytes()[:500])
    _heals(cdir, "model.json")


def test_garbage_metadata_is_rebuilt(cdir):
    _run()
    meta = _entry(cdir) / "model.json"
    meta.write_bytes(np.random.default_rng(2).bytes(4000))
    _heals(cdir, "model.json")


def test_metadata_of_another_format_is_rebuilt(cdir):
    _run()
    with _metadata(cdir) as doc:
        doc["format"] = 999
    _heals(cdir, "format 999")


def test_metadata_with_wrong_types_is_rebuilt(cdir):
    _run()
    with _metadata(cdir) as doc:
        doc["model"]["n"] = "2; import os"
    _heals(cdir, "invalid metadata")


def test_swapped_functions_are_rebuilt(cdir):
    """The residual stream replaced by the output function's: the name/signature check catches it."""
    _run()
    with _metadata(cdir) as doc:
        doc["model"]["serialized"]["res"] = doc["model"]["serialized"]["out"]
    _heals(cdir, "model.json.*(SHA-256 differs from the manifest|another function)")


def test_swapped_functions_with_consistent_manifest_are_rebuilt(cdir):
    """The same, with the manifest updated to match: the stream's name check catches it."""
    _run()
    with _metadata(cdir) as doc:
        doc["model"]["serialized"]["res"] = doc["model"]["serialized"]["out"]
        doc["manifest"]["functions"]["res"] = doc["manifest"]["functions"]["out"]
    _heals(cdir, "another function")


def test_truncated_arrays_are_rebuilt(cdir):
    _run()
    arrays = _entry(cdir) / "arrays.npz"
    arrays.write_bytes(arrays.read_bytes()[:100])
    _heals(cdir, "arrays.npz")


class _Evil:
    """Unpickling this writes a marker file (stands for arbitrary code)."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self):
        return (Path.write_text, (self.marker, "pwned"))


def test_pickled_arrays_never_unpickled(cdir, tmp_path):
    """An ``arrays.npz`` carrying a pickled object, with a manifest updated to match it, is refused by
    ``allow_pickle=False``: the payload (which would write a marker file) never runs."""
    _run()
    entry = _entry(cdir)
    marker = tmp_path / "marker"
    arrays = entry / "arrays.npz"
    with np.load(arrays) as data:
        content = {k: data[k] for k in data.files}
    evil = np.empty(1, dtype=object)
    evil[0] = _Evil(marker)
    content["differential"] = evil
    np.savez(arrays, **content)
    meta = entry / "model.json"
    doc = json.loads(meta.read_text())
    raw = arrays.read_bytes()
    doc["manifest"]["arrays.npz"] = {"sha256": hashlib.sha256(raw).hexdigest(), "size": len(raw)}
    meta.write_text(json.dumps(doc))
    _heals(cdir, "arrays.npz")
    assert not marker.exists()


def test_planted_pickle_cache_file_is_never_loaded(cdir, tmp_path):
    """Old-format ``.pkl`` entries (and any pickle planted in the cache dir) are never unpickled."""
    _run()
    marker = tmp_path / "marker"
    key = _entry(cdir).name
    (cdir / f"{key}.pkl").write_bytes(pickle.dumps(_Evil(marker)))
    sim = _run()
    assert sim.build.cached and not marker.exists()


def test_external_function_stream_is_refused_before_deserializing(cdir, tmp_path):
    """A serialized *External* function (deserializing it would dlopen a library whose constructor runs code)
    is refused from the stream's header, before CasADi reads it: the constructor's marker file never appears."""
    import casadi as ca

    marker = tmp_path / "marker"
    src = tmp_path / "evil.c"
    lib = tmp_path / "evil.so"
    x = ca.SX.sym("x")
    gen = ca.CodeGenerator("evil.c")
    gen.add(ca.Function("flexlib_res", [x], [2 * x]))
    gen.generate(str(tmp_path) + os.sep)
    subprocess.run(["gcc", "-shared", "-fPIC", str(src), "-o", str(lib), "-lm"], check=True)
    stream = ca.external("flexlib_res", str(lib)).serialize()
    src.write_text(src.read_text() + textwrap.dedent(f"""
        #include <stdio.h>
        __attribute__((constructor)) static void evil(void) {{
            FILE *f = fopen("{marker}", "w"); if (f) {{ fputs("pwned", f); fclose(f); }}
        }}
    """))
    subprocess.run(["gcc", "-shared", "-fPIC", str(src), "-o", str(lib), "-lm"], check=True)
    _run()
    with _metadata(cdir) as doc:
        doc["model"]["serialized"]["res"] = stream
        doc["manifest"]["functions"]["res"] = hashlib.sha256(stream.encode()).hexdigest()  # a consistent planting
    with pytest.warns(CacheWarning, match="not an SXFunction"):
        sim = _run()
    assert not marker.exists()
    np.testing.assert_allclose(sim.last.values, _reference(), rtol=0, atol=1e-12)


# -- cached initial values ---------------------------------------------------------------------------------
def test_truncated_initial_values_are_recomputed(cdir):
    """Today a truncated init .npz gives BadZipFile on every run; now it is reported once and replaced."""
    _run()
    init = _init_file(cdir)
    init.write_bytes(init.read_bytes()[:50])
    with pytest.warns(CacheWarning, match=init.name) as rec:
        sim = _run()
    assert sim.build.cached and not sim.init_cached and len(rec) == 1
    np.testing.assert_allclose(sim.last.values, _reference(), rtol=0, atol=1e-12)
    assert _run().init_cached


def test_cached_initial_values_with_wrong_residual_are_not_used(cdir):
    """Initial values that do not satisfy the DAE at the run's parameters are replaced by a fresh start."""
    _run()
    init = _init_file(cdir)
    with np.load(init) as data:
        arrays = {k: data[k].copy() for k in data.files}
    arrays["yp"] = arrays["yp"] + 1.0  # x' no longer equals v
    np.savez(init, **arrays)
    with pytest.warns(CacheWarning, match="largest residual"):
        sim = _run()
    assert not sim.init_cached
    np.testing.assert_allclose(sim.last.values, _reference(), rtol=0, atol=1e-12)


def test_cached_initial_values_with_wrong_size_are_not_used(cdir):
    _run()
    init = _init_file(cdir)
    np.savez(init, y=np.zeros(7), yp=np.zeros(7), p=np.zeros(3), residual=np.zeros(1))
    with pytest.warns(CacheWarning, match="sizes do not match"):
        sim = _run()
    np.testing.assert_allclose(sim.last.values, _reference(), rtol=0, atol=1e-12)


# -- the cache directory -----------------------------------------------------------------------------------
def _no_cache_build(culprit: str) -> None:
    with pytest.warns(CacheWarning, match=culprit):
        sim = _run()
    assert not sim.build.cached and sim.build.key is None
    np.testing.assert_allclose(sim.last.values, _reference(), rtol=0, atol=1e-12)


def test_world_writable_cache_dir_is_refused(cdir):
    cdir.mkdir()
    cdir.chmod(0o777)
    _no_cache_build(f"{cdir}.*writable by other users")
    assert list(cdir.iterdir()) == []  # nothing written where others could tamper with it


def test_group_writable_cache_dir_is_refused(cdir):
    cdir.mkdir()
    cdir.chmod(0o770)
    _no_cache_build("writable by other users")


def test_sticky_world_writable_cache_dir_is_accepted(cdir):
    """Like /tmp: others may create files but not replace ours; ours are checked file by file."""
    cdir.mkdir()
    cdir.chmod(0o1777)
    _run()
    assert _run().build.cached


def test_group_writable_lib_dir_is_refused(cdir):
    _run()
    (cdir / "lib").chmod(0o777)
    _no_cache_build("lib is writable by other users")


@pytest.mark.skipif(not hasattr(os, "getuid") or os.getuid() != 0, reason="chown needs root")
def test_cache_dir_owned_by_another_user_is_refused(cdir):
    cdir.mkdir()
    os.chown(cdir, 65534, 65534)
    _no_cache_build("owned by uid 65534")


@pytest.mark.skipif(not hasattr(os, "getuid") or os.getuid() != 0, reason="chown needs root")
def test_entry_owned_by_another_user_is_refused(cdir):
    _run()
    meta = _entry(cdir) / "model.json"
    os.chown(meta, 65534, 65534)
    _heals(cdir, "owned by uid 65534")


def test_cache_dir_is_a_file(cdir):
    cdir.write_text("not a directory")
    _no_cache_build(f"{cdir}.*(not a directory|cannot be created)")


def test_cache_dir_under_a_file_cannot_be_created(cdir, monkeypatch):
    cdir.write_text("a file")
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(cdir / "sub" / "dir"))
    _no_cache_build("cannot be created")


def test_unwritable_cache_dir(tmp_path, monkeypatch):
    """A cache dir this user cannot write: one warning naming the dir, and the model still builds and runs.
    (Root may write any ordinary directory, so as root a read-only kernel directory stands in.)"""
    if hasattr(os, "getuid") and os.getuid() == 0:
        cdir = Path("/proc/sys")
        if not cdir.is_dir() or os.access(cdir, os.W_OK):
            pytest.skip("no directory that root cannot write")
    else:
        cdir = tmp_path / "ro"
        cdir.mkdir(mode=0o555)
    monkeypatch.setenv("FLEXLIB_CACHE_DIR", str(cdir))
    _no_cache_build(f"{cdir}.*not writable")


def test_symlinked_cache_dir_is_followed(cdir, tmp_path):
    """A cache dir that is a symbolic link to a private directory (another disk) is fine."""
    real = tmp_path / "real"
    real.mkdir(mode=0o700)
    cdir.symlink_to(real)
    _run()
    assert _run().build.cached


# -- concurrency -------------------------------------------------------------------------------------------
def test_concurrent_processes_share_one_cache_dir(cdir):
    """Two processes building (with C code) and running the same model at once, three times each, with one
    cache dir: no warning, no error, identical answers; afterwards the entry is a clean cache hit."""
    code = textwrap.dedent("""
        import sys, warnings
        warnings.simplefilter("error")
        import flexlib as fl
        from test_cache import CachedOscillator
        for _ in range(3):
            res = fl.Simulation(CachedOscillator(), codegen=True).run(1.0, dt_out=0.1)
        print(repr(float(res["x"][-1])))
    """)
    env = dict(os.environ, FLEXLIB_CACHE_DIR=str(cdir), PYTHONPATH=str(HERE))
    procs = [subprocess.Popen([sys.executable, "-c", code], env=env, cwd=ROOT, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    outs = [p.communicate(timeout=300) for p in procs]
    for p, (_out, err) in zip(procs, outs, strict=True):
        assert p.returncode == 0, err
    ref = _reference()[-1][0]
    assert [float(o) for o, _ in outs] == pytest.approx([ref, ref], abs=1e-12)
    assert _run(codegen=True).build.cached
    assert not list(cdir.glob(".*.tmp")) and not list((cdir / "lib").glob(".*.tmp"))


# -- the key -----------------------------------------------------------------------------------------------
class FileDriven(fl.Model):
    """Equations chosen from a file's contents (as a modal body reads its modes): x' = -a x for each line."""

    def __init__(self, table: str) -> None:
        super().__init__()
        self.table = table
        rates = [float(v) for v in Path(table).read_text().split()]
        for k, _ in enumerate(rates):
            setattr(self, f"x{k}", Variable(unit="1", start=1.0, fixed=True))
        self._rates = rates  # private: not seen by the key

    def structure_key(self):
        return Path(self.table).read_bytes()

    def equations(self):
        return [eq(der(getattr(self, f"x{k}")), -a * getattr(self, f"x{k}")) for k, a in enumerate(self._rates)]


def test_structure_key_sees_file_contents(cdir, tmp_path):
    """A ``str`` attribute naming a file: after the file changes, the cache is not hit (the key includes
    ``structure_key()``); x(1) = exp(-a) to 1e-6."""
    table = tmp_path / "rates.txt"
    table.write_text("1.0")
    first = fl.Simulation(FileDriven(str(table)), codegen=False)
    assert not first.build.cached and fl.Simulation(FileDriven(str(table)), codegen=False).build.cached
    table.write_text("2.5")  # same variables, another equation: only structure_key() tells
    second = fl.Simulation(FileDriven(str(table)), codegen=False)
    assert not second.build.cached
    res = second.run(1.0, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(res["x0"][-1], np.exp(-2.5), rtol=1e-6)


def test_structure_key_must_be_plain_data(cdir):
    class BadKey(CachedOscillator):
        def structure_key(self):
            return object()

    class BadHolder(fl.Model):
        def __init__(self):
            super().__init__()
            self.osc = BadKey()

    with pytest.raises(fl.ModelError, match=r"osc\.structure_key\(\) must return plain data"):
        fl.Simulation(BadHolder())


def test_unrepresentable_attribute_disables_the_cache_not_a_wrong_hit(cdir):
    """An attribute the key cannot represent (an arbitrary object in a list) means no caching, never a hit
    on another model's entry."""

    class WithObject(CachedOscillator):
        def __init__(self):
            super().__init__()
            self.helpers = [object()]

    assert not fl.Simulation(WithObject(), codegen=False).build.cached
    assert not fl.Simulation(WithObject(), codegen=False).build.cached


def test_code_digest_follows_code_not_lines():
    """Classes without a source file are keyed by their code: the same code (even at other lines) gives the
    same digest; a changed constant, method body, default or REPL helper changes it."""

    def make(src: str) -> type:
        ns = {"__name__": "flexlib_repl_test", "fl": fl, "eq": eq, "der": der, "Variable": Variable}
        exec(compile(src, "<stdin>", "exec"), ns)
        return ns["M"]

    base = """
def helper(x):
    return 2.0 * x
class M(fl.Model):
    x = Variable(start=1.0, fixed=True)
    def equations(self, k=1.0):
        return [eq(der(self.x), -helper(k) * self.x)]
"""
    d0 = cache_key.code_digest(make(base))
    assert d0 is not None
    assert cache_key.code_digest(make("\n\n\n" + base)) == d0
    assert cache_key.code_digest(make(base.replace("2.0 * x", "3.0 * x"))) != d0  # helper changed
    assert cache_key.code_digest(make(base.replace("k=1.0", "k=1.5"))) != d0  # default changed
    assert cache_key.code_digest(make(base.replace("-helper(k)", "helper(k)"))) != d0  # body changed


# -- the pipeline ------------------------------------------------------------------------------------------
def test_pipeline_stages_are_inspectable(cdir):
    """``build`` returns every stage's product; a cached build runs stages 1–3 again on request; the old
    ``model, timings = fl.build(root)`` still works."""
    b = pipeline.build(CachedOscillator(), codegen=False)
    assert [v.name for v in b.flat.variables] == ["x", "v"]
    assert b.simple is not None and b.dae.report.states == b.compiled.report.states
    assert {"flatten", "simplify", "index_reduction", "compile", "total"} <= set(b.timings)
    cached = fl.build(CachedOscillator(), codegen=False)
    assert cached.cached and cached.flat is None
    assert cached.analyse(CachedOscillator()).flat is not None
    model, timings = fl.build(CachedOscillator(), codegen=False)
    assert timings["cached"] and model.n == b.compiled.n
    assert fl.build(CachedOscillator(), codegen=False)[1]["cached"]
    sim = fl.Simulation(CachedOscillator(), codegen=False)
    assert sim.build.compiled is sim.compiled and sim.build_info is sim.build.timings


def triple_rocker() -> fl.Model:
    """A planar four-bar of four Revolutes whose links cannot turn fully (non-Grashof: a = 0.5, b = 0.7,
    c = 0.9, d = 0.6 m, S + L = 1.4 > P + Q = 1.3): the crank swings into a toggle position where its angle
    stops being a usable state and the states must be re-selected mid-run (the catalogue's ``FourBar``)."""

    from flexlib.models.reference import closed_form as ref
    from flexlib.models.reference.four_bar import FourBar

    a, b, c, d = 0.5, 0.7, 0.9, 0.6
    th2 = 1.5
    th3, th4 = (float(x) for x in ref.fourbar_angles(a, b, c, d, th2, "open"))  # start guesses (Norton §4.5)
    return FourBar(th2, th3, th4, -3.0, lengths=(a, b, c, d))


def test_cached_loop_model_switches_states_mid_run(cdir):
    """Formerly the monitor's private pipeline flattened with the balance check on, so the *cached* four-bar
    failed with StructuralSingularityError at its state switch. Now it re-runs the build's own stages: fresh
    and cached runs both switch states, agree to 1e-9 rad, keep the loop closed to 1e-8 m, and the crank
    stops at the toggle angle acos((a² + d² − (c − b)²)/(2ad)) = 0.3176 rad (to 1e-3 rad, the output grid)."""
    fresh = fl.Simulation(triple_rocker(), codegen=False)
    cached = fl.Simulation(triple_rocker(), codegen=False)
    assert not fresh.build.cached and cached.build.cached and cached.compiled._structure is None
    runs = [s.run(1.0, dt_out=0.005, rtol=1e-8, atol=1e-10) for s in (fresh, cached)]
    for res in runs:
        assert res.stats["state_switches"] >= 1
        np.testing.assert_allclose(res["coupler.frame_b.r_0"], res["rocker.frame_b.r_0"], atol=1e-8)
    np.testing.assert_allclose(runs[1]["rev1.phi"], runs[0]["rev1.phi"], atol=1e-9)
    toggle = np.arccos((0.5**2 + 0.6**2 - (0.9 - 0.7) ** 2) / (2 * 0.5 * 0.6))
    assert runs[1]["rev1.phi"].min() == pytest.approx(toggle, abs=1e-3)
    assert cached.build.flat is not None  # stages 1-3 were run again by the same pipeline, and kept


def test_leftovers_of_killed_writers_are_removed(cdir):
    """Temporary entries, libraries and gcc directories of a process killed while writing are removed once
    older than an hour; a live writer's (new) items are left alone."""
    _run()
    old, new = cdir / ".Oscillator-x.abc.tmp", cdir / "lib" / ".flexlib-gcc-def.tmp"
    stale_lib = cdir / "lib" / ".flexlib_0.so.123.tmp"
    for d in (old, new):
        d.mkdir()
        (d / "model.json").write_text("{")
    stale_lib.write_bytes(b"\x7fELF")
    for item in (old, stale_lib):
        os.utime(item, (0, 0))
    cache.remove_stale(cdir)
    assert not old.exists() and not stale_lib.exists() and new.exists()
    assert _run().build.cached


def test_entry_replaced_by_a_symlink_is_refused(cdir, tmp_path):
    """An entry directory that is a symbolic link (to a directory someone else controls) is not followed."""
    _run()
    entry = _entry(cdir)
    elsewhere = tmp_path / "elsewhere"
    entry.rename(elsewhere)
    entry.symlink_to(elsewhere)
    _heals(cdir, f"{entry.name}.*symbolic link")


def test_library_symlink_is_refused(cdir, tmp_path):
    """A library replaced by a symbolic link to a file with the right bytes elsewhere is not loaded."""
    _prime(cdir)
    lib = _library(cdir)
    elsewhere = tmp_path / "elsewhere.so"
    lib.rename(elsewhere)
    lib.symlink_to(elsewhere)
    _heals(cdir, f"{lib.name}.*not a regular file", codegen=True)


def test_pickled_initial_values_never_unpickled(cdir, tmp_path):
    """Cached initial values carrying a pickled object are refused (``allow_pickle=False``); the payload never
    runs and a fresh initialisation gives the reference answer."""
    _run()
    init = _init_file(cdir)
    marker = tmp_path / "marker"
    evil = np.empty(1, dtype=object)
    evil[0] = _Evil(marker)
    np.savez(init, y=evil, yp=np.zeros(2), p=np.zeros(3), residual=np.zeros(1))
    with pytest.warns(CacheWarning, match=init.name):
        sim = _run()
    assert not marker.exists() and not sim.init_cached
    np.testing.assert_allclose(sim.last.values, _reference(), rtol=0, atol=1e-12)
