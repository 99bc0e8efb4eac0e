import os

import jax
import pytest

# Figures are drawn headless, as the CLI draws them (the library itself chooses no backend).
os.environ.setdefault("MPLBACKEND", "Agg")

# Float64 is enabled here explicitly; importing jaxdamp never changes JAX's configuration.
jax.config.update("jax_enable_x64", True)
# Implicit rank promotion hides shape bugs (a (3,) meeting a (n, 3) by accident): make it an error.
jax.config.update("jax_numpy_rank_promotion", "raise")


@pytest.fixture(scope="session")
def paper():
    from jaxdamp import paper_tables

    return paper_tables()
