"""Shape optimisation of underplatform dampers with optax (see issue: shape optimisation)."""
