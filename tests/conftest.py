import functools
import json
import os
import subprocess
import zlib
from pathlib import Path

import jax
import pytest

# Figures are drawn headless, as the CLI draws them (the library itself chooses no backend).
os.environ.setdefault("MPLBACKEND", "Agg")

# Float64 is enabled here explicitly; importing jaxdamp never changes JAX's configuration.
jax.config.update("jax_enable_x64", True)
# XLA compiles the suite's programs as the CLI's one-design commands do, fast rather than
# optimised (runtime.compile_for_latency, before anything compiles; inherited by the notebooks'
# kernels and the CLI subprocesses): the suite is mostly XLA compilation, and its default tier ran
# in 5 min 47 s instead of 10.5-11.5 min on 2 cores, every test passing either way. What XLA
# optimises changes no result beyond rounding (tests/test_runtime.py compares the two); the
# benchmarks, which measure speed and accuracy, compile optimised.
from jaxdamp.runtime import compile_for_latency  # noqa: E402

compile_for_latency()
# No persistent compilation cache in tests, and calls run on the calling thread. With the cache,
# jaxlib (0.10.2 and 0.9.2 alike) segfaulted about once per suite run while serialising an
# executable for it (`executable.serialize()` in compilation_cache.put_executable_and_time) or
# reading one back; a crashed worker fails the run, and a crash is never rerun away
# (docs/performance.md, "Worker crashes"). The cache only shared compiled programs between the
# two workers and carried them from one run to the next; the CLI keeps it for users.
jax.config.update("jax_cpu_enable_async_dispatch", False)
# In-process CLI calls run their programs as plain calls (JAXDAMP_CACHE_DIR=off): a saved export
# (jaxdamp.cli.exported) is a second compiled form of a program the Python API tests compile
# anyway, and its folder (~/.cache/jaxdamp) would carry state from one run to the next.
# tests/test_cli_exported.py and tests/test_cli.py test the cache with folders of their own.
os.environ["JAXDAMP_CACHE_DIR"] = "off"
# Implicit rank promotion hides shape bugs (a (3,) meeting a (n, 3) by accident): make it an error.
jax.config.update("jax_numpy_rank_promotion", "raise")


@pytest.fixture(autouse=True, scope="module")
def _no_persistent_compilation_cache():
    """Fails the file whose tests left JAX's persistent compilation cache on (the CLI's
    configure_runtime turns it on where JAXDAMP_CACHE_DIR names a folder): every later file in
    that worker would write and read cache entries, where jaxlib crashed."""
    yield
    leaked = jax.config.jax_compilation_cache_dir
    jax.config.update("jax_compilation_cache_dir", None)
    assert not leaked, f"a test turned on the persistent compilation cache at {leaked}"


@pytest.fixture(scope="session")
def paper():
    from jaxdamp import paper_tables

    return paper_tables()


# The heaviest test files of the default tier first (worker-seconds of the run of 2026-11-25).
# What this order decides under `--dist loadfile` is small: pytest-xdist hands the files out by
# their number of tests (its --loadscope-reorder default), so this order only breaks its ties. Its
# own order, tried with --no-loadscope-reorder and the files sorted by measured worker-seconds
# (2026-11-27), ran the default tier in 10 min 32 s against 10 min 17 s: a file's cost depends on
# which programs its worker has compiled for earlier files (the same tests took 1212 instead of
# 1135 worker-seconds), so balancing files by their cost alone does not pay.
HEAVY_FIRST = ("test_fit_loops.py", "test_gradients.py", "test_amplitude.py",
               "test_calibration.py", "test_timemarch.py", "test_docs.py", "test_batch.py",
               "test_study.py", "test_cli_exported.py", "test_response.py", "test_uncertainty.py",
               "test_optimize_robust.py", "test_cli_response.py", "test_sequence.py",
               "test_band.py", "test_cli_study.py", "test_coupled_hbm.py", "test_notebooks.py")


# The slow tier in shards (README, "Two commands"): CI runs every test but those marked slow, and
# one shard of those, the commit count of the checkout modulo the number of shards
# (`--slow-shard auto`, scripts/test.sh); `--full` runs them all. tests/slow_shards.json holds
# the number of shards and assigns each slow test to one, balanced by measured worker-seconds
# (scripts/slow_shards.py writes it from runs' JUnit files or `--durations=0` lists); a slow test it
# does not name yet goes to the shard of a stable hash of its id. It also names, under
# "slow_by_measure", tests that carry no mark in their file but took over SLOW_SECONDS in a CI
# run (most often the first test of a file to compile a long program, or one case of a
# parametrized test): they are slow too, marked here before `-m` and the shards select.
SLOW_SECONDS = 5.0
SHARDS_FILE = Path(__file__).with_name("slow_shards.json")


def pytest_addoption(parser):
    parser.addoption("--slow-shard", default=None, metavar="K",
                     help="run the tests marked slow of shard K only (tests/slow_shards.json; "
                          "auto: the commit count modulo the number of shards), with every "
                          "test not marked slow")


@functools.cache  # read once per process (the header, the collection)
def slow_shards() -> tuple[int, dict, dict]:
    """(the number of shards, {test id: its shard}, {test id slow by measure: its seconds}) of
    tests/slow_shards.json."""
    table = json.loads(SHARDS_FILE.read_text())
    return int(table["n_shards"]), table["shards"], table.get("slow_by_measure", {})


def slow_shard_of(nodeid: str, assigned: dict, n_shards: int) -> int:
    """The shard of a slow test: its entry in tests/slow_shards.json, else a stable hash."""
    if nodeid in assigned:
        return int(assigned[nodeid])
    return zlib.crc32(nodeid.encode()) % n_shards


@functools.cache
def commit_count() -> int:
    """The checkout's commit count (0 outside a git checkout), which picks CI's shard."""
    try:
        out = subprocess.run(["git", "rev-list", "--count", "HEAD"], capture_output=True,
                             text=True, cwd=Path(__file__).parent, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return 0
    return int(out.strip() or 0)


def chosen_shard(config):
    """The shard of `--slow-shard` (None: every slow test), checked."""
    shard = config.getoption("--slow-shard")
    if shard is None:
        return None
    n_shards = slow_shards()[0]
    k = commit_count() % n_shards if shard == "auto" else shard
    try:
        k = int(k)
    except ValueError:
        k = -1
    if not 0 <= k < n_shards:
        raise pytest.UsageError(f"--slow-shard must be auto or an integer in [0, {n_shards}); "
                                f"got {shard}")
    return k


def pytest_configure(config):
    # A bad --slow-shard is one usage line before any work (raised later, in the report header
    # or the collection, xdist shows it as an INTERNALERROR traceback).
    chosen_shard(config)


def pytest_report_header(config):
    k = chosen_shard(config)
    n_shards = slow_shards()[0]
    return f"slow tier: {'every test' if k is None else f'shard {k} of {n_shards}'}"


@pytest.hookimpl(tryfirst=True)  # before `-m` deselects by the marks
def pytest_collection_modifyitems(config, items):
    n_shards, assigned, by_measure = slow_shards()
    for item in items:
        if item.nodeid in by_measure and not item.get_closest_marker("slow"):
            item.add_marker(pytest.mark.slow)
    k = chosen_shard(config)
    if k is not None:
        keep, drop = [], []
        for item in items:
            is_out = (item.get_closest_marker("slow")
                      and slow_shard_of(item.nodeid, assigned, n_shards) != k)
            (drop if is_out else keep).append(item)
        if drop:
            config.hook.pytest_deselected(items=drop)
            items[:] = keep
    rank = {name: i for i, name in enumerate(HEAVY_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))  # stable: files stay whole
