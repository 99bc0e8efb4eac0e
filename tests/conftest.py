import getpass
import os
import tempfile

# XLA's C++ warnings stay off stderr, as the `jaxdamp` command keeps them (jaxdamp/__init__.py):
# set before JAX is imported, and inherited by the CLI subprocesses that tests start.
os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "2")

import jax  # noqa: E402
import pytest

# Figures are drawn headless, as the CLI draws them (the library itself chooses no backend).
os.environ.setdefault("MPLBACKEND", "Agg")

# Float64 is enabled here explicitly; importing jaxdamp never changes JAX's configuration.
jax.config.update("jax_enable_x64", True)
# The test processes (pytest-xdist workers, subprocesses) share one persistent compilation cache,
# so a program compiled by one worker is loaded by the next: the suite is compile-bound on 2 cores.
# Cache keys include the program's fingerprint, so a changed program never reuses a stale entry.
jax.config.update("jax_compilation_cache_dir",
                  os.path.join(tempfile.gettempdir(), f"jaxdamp-tests-{getpass.getuser()}"))
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.5)
# In-process CLI calls run their programs as plain calls (JAXDAMP_CACHE_DIR=off): a saved export
# (jaxdamp.cli.exported) is a second compiled form of a program the Python API tests compile
# anyway, and its folder (~/.cache/jaxdamp) would carry state from one run to the next.
# tests/test_cli_exported.py and tests/test_cli.py test the cache with folders of their own.
os.environ["JAXDAMP_CACHE_DIR"] = "off"
# Implicit rank promotion hides shape bugs (a (3,) meeting a (n, 3) by accident): make it an error.
jax.config.update("jax_numpy_rank_promotion", "raise")


@pytest.fixture(scope="session")
def paper():
    from jaxdamp import paper_tables

    return paper_tables()
