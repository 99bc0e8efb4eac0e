import jax
import pytest

# Float64 is enabled here explicitly; importing jaxdamp never changes JAX's configuration.
jax.config.update("jax_enable_x64", True)


@pytest.fixture(scope="session")
def paper():
    from jaxdamp import paper_tables

    return paper_tables()
