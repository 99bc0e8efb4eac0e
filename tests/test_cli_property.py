"""Property: whatever flags and values a user types, the cheap commands (statics, design-br, cycle,
grad) end with exit 0 and one strict JSON document (no NaN/Infinity) or a text whose first line
shows the status, or with exit 2 and exactly one line on stderr. Never a traceback.

main() runs in-process, so the solver compiles once per program and the examples reuse it."""

import contextlib
import io

from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

from jaxdamp.cli import main
from jaxdamp.status import RESULTS

from helpers import strict_json

GARBAGE = st.sampled_from(["nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "0", "-0", "-1", "abc",
                           "", "1,2", "0x10", "--json", "5e400"])


def in_range(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False).map(repr)


def value(lo, hi):
    """Mostly (15 in 16) values in the valid range, so that the solver runs on many command lines
    with several flags; otherwise garbage or any float at all."""
    anything = st.one_of(GARBAGE, st.floats(allow_nan=True, allow_infinity=True).map(repr))
    # hypothesis favours the simplest draw (0): make it the valid one
    return st.integers(0, 15).flatmap(lambda i: anything if i == 15 else in_range(lo, hi))


SHAPE_NAMES = st.sampled_from(["60sym", "74R", "90L", "74L", "90R", "45sym", "61sym", ""])
FLAGS = {
    "--shape": SHAPE_NAMES,
    "--theta-l": value(1.0, 90.0),
    "--theta-r": value(1.0, 90.0),
    "--br": value(-0.5, 0.5),
    "--bl2": value(0.05, 1.0),
    "--mu": value(0.01, 5.0),
    "--mu-max": value(0.01, 5.0),
    "--kn": value(1.0, 1e9),
    "--kt": value(1.0, 1e9),
    "--fd": value(1.0, 1e6),
    "--q": value(1.0, 1e4),
    "--r-sin-beta": value(-1e3, 1e3),
    "--psi-a": value(0.0, 50.0),
}
SHAPE = ["--shape", "--theta-l", "--theta-r", "--br", "--bl2"]
COMMANDS = {
    "statics": SHAPE + ["--mu"],
    "design-br": [f for f in SHAPE if f != "--br"] + ["--mu-max"],
    "cycle": SHAPE + ["--mu", "--kn", "--kt", "--fd", "--q", "--r-sin-beta"],
    "grad": SHAPE + ["--mu", "--kn", "--kt", "--fd", "--q", "--r-sin-beta", "--psi-a"],
}


@st.composite
def command_lines(draw):
    command = draw(st.sampled_from(sorted(COMMANDS)))
    own = COMMANDS[command]
    argv = [command]
    # a custom shape or a paper shape most of the time, so that many runs reach the solver
    style = draw(st.sampled_from(["paper", "custom", "random"]))
    chosen = {"paper": ["--shape"], "custom": [f for f in own if f in SHAPE and f not in ("--shape",)],
              "random": []}[style]
    for flag in own:
        # --mu is required: left out now and then; other options half of the time
        keep = draw(st.integers(0, 15)) < 15 if flag == "--mu" else not draw(st.booleans())
        if flag in chosen or (flag not in SHAPE and keep) or (style == "random" and draw(st.booleans())):
            argv += [flag, draw(FLAGS[flag])]
    if draw(st.integers(0, 9)) == 9:  # a flag of another command
        other = draw(st.sampled_from(sorted(FLAGS)))
        argv += [other, draw(FLAGS[other])]
    if not draw(st.booleans()):
        argv.append("--json")
    return argv


def run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


@example(["grad", "--shape", "60sym", "--mu", "0.5", "--psi-a", "3", "--json"])
@example(["grad", "--shape", "74L", "--mu", "0.7"])
@example(["cycle", "--shape", "74L", "--mu", "0.7", "--json"])
@example(["cycle", "--shape", "60sym", "--mu", "0.5", "--kn", "1e300", "--kt", "1e-300", "--json"])
@example(["cycle", "--theta-l", "1e-300", "--theta-r", "90", "--br", "0.5", "--mu", "5", "--json"])
@example(["statics", "--theta-l", "90", "--theta-r", "90", "--br", "-0.5", "--mu", "1e-300", "--json"])
@example(["design-br", "--theta-l", "1e-300", "--theta-r", "1e-300", "--mu-max", "5", "--json"])
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(command_lines())
def test_every_command_line_ends_in_a_result_or_one_error_line(argv):
    code, out, err = run(argv)
    event(f"{argv[0]} exit {code}")  # pytest --hypothesis-show-statistics shows the mix
    assert "Traceback" not in err and "Traceback" not in out
    assert code in (0, 2), (argv, code, err)
    if code == 2:
        lines = [ln for ln in err.splitlines() if ln.strip()]
        assert len(lines) == 1 and out == "", (argv, err)
        return
    if "--json" in argv:
        doc = strict_json(out)
        assert doc["status"] in RESULTS.__members__ and doc["schema_version"] == 3, argv
    else:
        assert "[status: " in out.splitlines()[0], (argv, out)
