"""One design type: a damper shape with its friction coefficient, contacts and load.

`Design` is a pytree. Every leaf is data (a traced array under jit/vmap/grad); nothing in it is a
static argument, so changing any value never recompiles. What does select a compiled program is the
pytree's structure, fixed here in one place:

- `shape.x_d` is None (the triangle's centroid) or a number;
- kn and kt are always carried per contact, shape (3,) for (R1, L1, L2) (`prepared` broadcasts a
  shared scalar), so shared and per-contact stiffness run the same program;
- a batch of designs is a Design whose leaves have a leading batch axis (`jaxdamp.stack_designs`).

Derivatives of any output with respect to a Design are again a Design (d/d theta_L is
`d.shape.theta_l`, per degree; d/d kn is `d.contacts.kn`, per N/mm and per contact).
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from .geometry import DamperShape
from .params import Contacts, LoadCase, prepare_inputs


class Design(NamedTuple):
    """shape (DamperShape), mu (friction coefficient), contacts (kn, kt in N/mm), load (F_D in N,
    q* in mm, r sin beta in mm)."""

    shape: DamperShape
    mu: jnp.ndarray | float
    contacts: Contacts = Contacts()
    load: LoadCase = LoadCase()

    @property
    def size(self) -> int:
        """Number of designs: the leading axis of mu in a batch, 1 for a single design."""
        return int(np.shape(self.mu)[0]) if np.ndim(self.mu) else 1

    def prepared(self) -> "Design":
        """Validated (ValueError naming the parameter and range; float64 required) and converted
        to float arrays with kn, kt per contact: the form every compiled kernel takes."""
        return Design(*prepare_inputs(*self))


def as_design(shape_or_design, mu=None, contacts: Contacts = Contacts(),
              load: LoadCase = LoadCase()) -> Design:
    """A Design from either a Design or the (shape, mu, contacts, load) arguments."""
    if isinstance(shape_or_design, Design):
        if mu is not None:
            raise ValueError("give either a Design or (shape, mu, contacts, load), not both")
        return shape_or_design
    if mu is None:
        raise ValueError("mu is required: the friction coefficient, in (0, 5]")
    return Design(shape_or_design, mu, contacts, load)


__all__ = ["Design", "as_design"]
