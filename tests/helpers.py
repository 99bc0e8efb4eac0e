"""Shared test helpers: finite-difference JVPs for gradient checks."""

import numpy as np


def fd_jvp(f, x, v, h=1e-6):
    """Central finite-difference directional derivative of f at x along v (float64)."""
    x = np.asarray(x, float)
    v = np.asarray(v, float)
    return (np.asarray(f(x + h * v)) - np.asarray(f(x - h * v))) / (2 * h)


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
