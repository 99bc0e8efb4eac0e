import os

import jax
import pytest

# Figures are drawn headless, as the CLI draws them (the library itself chooses no backend).
os.environ.setdefault("MPLBACKEND", "Agg")

# Float64 is enabled here explicitly; importing jaxdamp never changes JAX's configuration.
jax.config.update("jax_enable_x64", True)
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


@pytest.fixture(scope="session")
def paper():
    from jaxdamp import paper_tables

    return paper_tables()
