"""The peak search's roots (`jaxdamp.response.root_search`) against numpy's roots of a cubic:
every sign change on the grid found and refined, whatever the search's width."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxdamp.response.root_search import grid_apart_then_roots, grid_then_roots

from helpers import assert_tree_allclose

GRID = jnp.linspace(0.1, 4.0, 101)
# g0 - F for a cubic with three real roots at F = 1 (folds), one at F = 5 and at F = -1.4, none
# on the grid at F = 40; MAX_ROOTS 4 brackets per force, so most brackets are empty.
FORCES = jnp.array([[1.0], [5.0], [-1.4], [40.0], [1.2]])
MAX_ROOTS, STEPS = 4, 60


def _g0(x):
    """The residual at zero force and an aux that the search keeps at each root (x itself and an
    integer, so that aux of several dtypes is carried)."""
    return (x - 1.0) * (x - 2.0) * (x - 3.0) + 1.0, (2.0 * x, (x > 2.0).astype(jnp.int32))


def _numpy_roots(f):
    """The real roots of (x-1)(x-2)(x-3) + 1 - f in the grid's span, ascending."""
    r = np.roots([1.0, -6.0, 11.0, -6.0 + 1.0 - f])
    r = np.sort(r[np.abs(r.imag) < 1e-9].real)
    return r[(r > float(GRID[0])) & (r < float(GRID[-1]))]


def _search(width):
    if width is None:
        return jax.jit(lambda: grid_apart_then_roots(_g0, GRID, FORCES, MAX_ROOTS, STEPS))()
    return jax.jit(lambda: grid_then_roots(_g0, GRID, FORCES, MAX_ROOTS, STEPS, width))()


@pytest.mark.parametrize("width", [None, 1, 3, 4, 16, 64])
def test_every_root_of_a_cubic_whatever_the_width(width):
    """Widths below the count of brackets still searching (1, 3: the three roots at F = 1 and
    one per other force wait their turn), equal to the forces' count, and above the brackets'
    count (64 > 5 x 4, most slots free)."""
    roots, (twice, right), found, n_roots = _search(width)
    for i, f in enumerate(np.asarray(FORCES)[:, 0]):
        want = _numpy_roots(f)
        assert int(n_roots[i]) == want.size
        assert np.asarray(found[i]).tolist() == [j < want.size for j in range(MAX_ROOTS)]
        got = np.asarray(roots[i])[:want.size]
        assert_tree_allclose(got, want, rtol=1e-12, atol=0.0)
        # aux is g0's at each root's last evaluation
        assert_tree_allclose(np.asarray(twice[i])[:want.size], 2.0 * got, rtol=1e-15, atol=0.0)
        assert np.asarray(right[i])[:want.size].tolist() == (got > 2.0).tolist()


def test_the_width_changes_no_root():
    """A bracket's evaluations do not depend on when it steps: every width gives the roots of
    the search that evaluates the grid apart, the same counts and, to rounding (the same
    evaluations in other programs, which XLA may fuse otherwise: 1-2 ulp seen), the same values."""
    ref = _search(None)
    for width in (1, 3, 16):
        got = _search(width)
        assert np.array_equal(got[2], ref[2]) and np.array_equal(got[3], ref[3])
        assert np.array_equal(got[1][1], ref[1][1])
        assert_tree_allclose((got[0], got[1][0]), (ref[0], ref[1][0]), rtol=1e-15, atol=0.0)
