"""`python -m jaxdamp.cli ...` (the same as the `jaxdamp` console script)."""

from . import console

console()
