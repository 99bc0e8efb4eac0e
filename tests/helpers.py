"""Shared test helpers: pytree comparison (structure, shape, dtype, values), finite-difference JVPs
for gradient checks, compile counting and CLI runs."""

import contextlib

import jax
import numpy as np

# JAX records this event around every lowering-to-executable step (a persistent-cache load too);
# a call served from jit's in-memory cache records nothing.
_BACKEND_COMPILE_EVENT = "/jax/core/compile/backend_compile_duration"


def tree_difference(a, b, rtol=1e-12, atol=0.0, equal_nan=False):
    """None when two pytrees have the same structure and every pair of leaves has the same shape,
    the same dtype and close values (|a - b| <= atol + rtol |b| elementwise, b the reference, as in
    np.allclose); else a line saying where and how they first differ. No broadcasting: a (3,) never
    equals a (1,) or a scalar, and a float32 never equals a float64. None leaves must match None."""
    la, ta = jax.tree_util.tree_flatten_with_path(a)
    lb, tb = jax.tree_util.tree_flatten(b)
    if ta != tb:
        return f"structure differs: {ta} vs {tb}"
    for (path, x), y in zip(la, lb):
        where = jax.tree_util.keystr(path) or "the leaf"
        x, y = np.asarray(x), np.asarray(y)
        if x.shape != y.shape:
            return f"{where}: shape {x.shape} vs {y.shape}"
        if x.dtype != y.dtype:
            return f"{where}: dtype {x.dtype} vs {y.dtype}"
        close = np.isclose(x, y, rtol=rtol, atol=atol, equal_nan=equal_nan)
        if not close.all():
            bad = ~close
            first = tuple(int(i) for i in np.argwhere(bad)[0])
            wide = np.result_type(x, float)  # bool and int as float64, complex kept
            with np.errstate(all="ignore"):
                err = np.abs(x.astype(wide) - y.astype(wide))
                rel = err / np.abs(y.astype(wide))
            return (f"{where}: {int(bad.sum())} of {x.size} elements differ (first at {first}: "
                    f"{x[first]} vs {y[first]}); max abs error {np.max(err[bad]):.3g}, "
                    f"max rel error {np.max(rel[bad]):.3g} (rtol={rtol}, atol={atol})")
    return None


def tree_allclose(a, b, rtol=1e-12, atol=0.0, equal_nan=False) -> bool:
    """True when tree_difference finds none: same structure, and per leaf the same shape, the same
    dtype and close values."""
    return tree_difference(a, b, rtol, atol, equal_nan) is None


def assert_tree_allclose(actual, expected, *, rtol, atol, equal_nan=False, err_msg=""):
    """tree_allclose as an assertion whose message names the first leaf that differs and its
    largest errors. The tolerances are required (np.allclose's defaults are rtol=1e-5,
    atol=1e-8, np.testing.assert_allclose's rtol=1e-7, atol=0): a test says what it accepts."""
    diff = tree_difference(actual, expected, rtol, atol, equal_nan)
    if diff is not None:
        raise AssertionError(f"{err_msg}: {diff}" if err_msg else diff)


def fd_jvp(f, x, v, h=1e-6):
    """Central finite-difference directional derivative of f at x along v (float64)."""
    x = np.asarray(x, float)
    v = np.asarray(v, float)
    return (np.asarray(f(x + h * v)) - np.asarray(f(x - h * v))) / (2 * h)


def tree_fd_jvp(f, x, v, h=1e-6):
    """fd_jvp for pytree arguments: f(x + h v) - f(x - h v) over 2h, leaf by leaf (v has x's
    structure; the output may be any pytree)."""
    plus = jax.tree_util.tree_map(lambda a, d: np.asarray(a, float) + h * np.asarray(d, float), x, v)
    minus = jax.tree_util.tree_map(lambda a, d: np.asarray(a, float) - h * np.asarray(d, float), x, v)
    return jax.tree_util.tree_map(lambda p, m: (np.asarray(p) - np.asarray(m)) / (2 * h), f(plus),
                                  f(minus))
def run_cli(capsys, *argv, extra=()):
    """Run `jaxdamp argv...` in-process (compiled programs are reused): (exit code, stdout, stderr)."""
    from jaxdamp.cli import main

    code = main([str(a) for a in argv], extra_commands=extra)
    out = capsys.readouterr()
    return code, out.out, out.err


def _no_constant(name):
    raise ValueError(f"JSON holds {name}, which is not JSON")


def strict_json(text: str):
    """json.loads that rejects NaN, Infinity and -Infinity."""
    import json

    return json.loads(text, parse_constant=_no_constant)


def one_error_line(err: str) -> str:
    """The single line a CLI error writes on stderr (asserts there is exactly one, no traceback)."""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


def assert_leaf_close(name, a, b, rtol=1e-12):
    """Arrays equal (integers, booleans) or within rtol of each element and of the array's scale."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, name
    if a.dtype.kind in "bi":
        assert np.array_equal(a, b), name
        return
    scale = np.max(np.abs(b)) if b.size else 0.0
    bad = np.abs(a - b) > rtol * np.abs(b) + rtol * scale
    assert not bad.any(), (name, int(bad.sum()), np.max(np.abs(a - b) / (np.abs(b) + 1e-300)))


@contextlib.contextmanager
def count_compiles():
    """Collects the names of the XLA programs compiled (or loaded from the persistent cache) inside
    the block: `with count_compiles() as compiled: f(x)` then `assert compiled == []` checks that a
    second call with new values of the same shapes compiles nothing."""
    compiled = []

    def listener(event, duration, **kwargs):
        if event == _BACKEND_COMPILE_EVENT:
            compiled.append(kwargs.get("fun_name", "?"))

    jax.monitoring.register_event_duration_secs_listener(listener)
    try:
        yield compiled
    finally:
        jax.monitoring.unregister_event_duration_listener(listener)
