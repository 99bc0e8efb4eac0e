import getpass
import os
import tempfile

import jax
import pytest

# Figures are drawn headless, as the CLI draws them (the library itself chooses no backend).
os.environ.setdefault("MPLBACKEND", "Agg")

# Float64 is enabled here explicitly; importing jaxdamp never changes JAX's configuration.
jax.config.update("jax_enable_x64", True)
# A persistent compilation cache per pytest-xdist worker: a program compiled once in a worker is
# loaded, not recompiled, by its later tests (the suite is compile-bound on 2 cores). Not one cache
# shared by the workers: JAX writes an entry with a plain write_bytes (no lock unless eviction is
# on), so a worker could read another's half-written entry, and deserialising it segfaulted
# (faulthandler: compiler._cache_read -> get_executable_and_time, three times on 2026-11-24).
# Cache keys include the program's fingerprint, so a changed program never reuses a stale entry.
jax.config.update("jax_compilation_cache_dir", os.path.join(
    tempfile.gettempdir(), f"jaxdamp-tests-{getpass.getuser()}",
    os.environ.get("PYTEST_XDIST_WORKER", "main")))
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.5)
# Implicit rank promotion hides shape bugs (a (3,) meeting a (n, 3) by accident): make it an error.
jax.config.update("jax_numpy_rank_promotion", "raise")


@pytest.fixture(scope="session")
def paper():
    from jaxdamp import paper_tables

    return paper_tables()
