"""Every code block of README.md and docs/**/*.md runs as written.

- ```python blocks: each file's blocks run in order in one fresh Python process (they share one
  namespace, as a reader running them one after the other would), with PYTHONPATH set to this
  checkout and the test suite's compilation cache.
- ```bash / ```console blocks: every line that starts with `jaxdamp ` (after an optional `$ `) is
  one command, run in-process through the CLI in a temporary directory; it must exit 0.
- A block preceded by the comment `<!-- not run: REASON -->` (the scripts and benchmarks that take
  minutes, pseudo-code) is skipped; the test counts them, so that skipping stays the exception.
"""

import json
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from helpers import run_cli

ROOT = Path(__file__).resolve().parent.parent
DOC_FILES = [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))
FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```[ \t]*$", re.S | re.M)
NOT_RUN = re.compile(r"<!--\s*not run:\s*(.+?)\s*-->\s*$")
RUN_LANGS = ("python", "bash", "console", "sh")
# Blocks that the Markdown says are not run, across all files: a bound that makes skipping visible.
MAX_NOT_RUN = 12


def code_blocks(path: Path):
    """(language, first line number, code, not-run reason or None) for each fenced block."""
    text = path.read_text()
    blocks = []
    for m in FENCE.finditer(text):
        before = text[: m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        reason = NOT_RUN.search(before)
        line = text.count("\n", 0, m.start()) + 2
        blocks.append((m.group(1).lower(), line, m.group(2), reason.group(1) if reason else None))
    return blocks


def _rel(path: Path) -> str:
    return str(path.relative_to(ROOT))


def _cli_commands(not_run=False):
    """The `jaxdamp ...` lines of the shell blocks that are run (or, not_run=True, of those that
    are not)."""
    cases = []
    for path in DOC_FILES:
        for lang, line, code, reason in code_blocks(path):
            if lang not in ("bash", "console", "sh") or bool(reason) != not_run:
                continue
            for k, raw in enumerate(code.splitlines()):
                cmd = raw.strip().removeprefix("$ ")
                cmd = cmd.split(" #", 1)[0].strip()
                if cmd.startswith("jaxdamp "):
                    marks = [pytest.mark.slow] if cmd in SLOW_COMMANDS else []
                    cases.append(pytest.param(cmd, id=f"{_rel(path)}:{line + k}", marks=marks))
    return cases


PYTHON_FILES = [p for p in DOC_FILES if any(b[0] == "python" and not b[3] for b in code_blocks(p))]

# Pages whose blocks took over 10 worker-seconds in the run of 2026-11-25 (XLA compiling the
# response, fit and optimiser programs in a fresh process): the full tier runs them
# (`bash scripts/test.sh --full`, README); the CLI commands by their command and options.
SLOW_PAGES = {"README.md": 62, "docs/response.md": 204, "docs/fit-loops.md": 126,
              "docs/exact-cycles.md": 88, "docs/optimize.md": 76, "docs/batching.md": 66,
              "docs/blade.md": 150}
SLOW_COMMANDS = {"jaxdamp grad --shape 74R --mu 0.5 --psi-a 3 --mode rev": 64,
                 "jaxdamp optimize --fix theta_l=45,theta_r=45 --mu-set 0.7": 37,
                 "jaxdamp response --shape 60sym --mu 0.5 --modes example --engine-order all "
                 "--h-l 10 --force-n 2,5 --plot figs": 150,
                 # the band over every history at the straight engine orders, in series with
                 # the example's residual flexibility (36 s as a process, empty cache,
                 # 2026-11-29; the whole row's band took 415 s on the free-platform file)
                 "jaxdamp response --shape 60sym --mu 0.5 --modes example --engine-order 0,12 "
                 "--h-l 10 --force-n 2,5 --band --plot figs": 36}

# Runs the blocks handed over as JSON in one namespace; a failure names the file and line.
_DRIVER = """
import json, sys, traceback
blocks = json.loads(sys.stdin.read())
ns = {"__name__": "__main__"}
for where, code in blocks:
    try:
        exec(compile(code, where, "exec"), ns)
    except BaseException:
        traceback.print_exc()
        print("FAILED BLOCK " + where, file=sys.stderr)
        sys.exit(1)
"""


def test_blocks_are_found_and_few_are_skipped():
    langs = [b[0] for p in DOC_FILES for b in code_blocks(p)]
    assert langs.count("python") >= 5 and len(_cli_commands()) >= 5
    not_run = [(_rel(p), b[1], b[3]) for p in DOC_FILES for b in code_blocks(p) if b[3]]
    assert len(not_run) <= MAX_NOT_RUN, not_run
    # Every fenced block is either run (python, shell) or declared not run: nothing slips through
    # as an unrecognised language.
    unknown = [(_rel(p), b[1], b[0]) for p in DOC_FILES for b in code_blocks(p)
               if b[0] not in RUN_LANGS and not b[3] and b[0] not in ("text", "json", "toml", "")]
    assert unknown == []
    # A shell block that is run holds only `jaxdamp ...` commands (and comments): anything else
    # (scripts, benchmarks) would pass unrun, so it must be marked not run.
    other = [(_rel(p), b[1], ln) for p in DOC_FILES for b in code_blocks(p)
             if b[0] in ("bash", "console", "sh") and not b[3]
             for ln in b[2].splitlines()
             if ln.strip() and not ln.strip().startswith("#")
             and not ln.strip().removeprefix("$ ").startswith("jaxdamp ")]
    assert other == []


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow)
                                  if _rel(p) in SLOW_PAGES else p for p in PYTHON_FILES], ids=_rel)
def test_python_blocks_run(path, tmp_path):
    blocks = [[f"{_rel(path)}:{line}", code] for lang, line, code, reason in code_blocks(path)
              if lang == "python" and not reason]
    import jax

    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg",
               JAX_COMPILATION_CACHE_DIR=jax.config.jax_compilation_cache_dir or "",
               JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS="0.5")
    proc = subprocess.run([sys.executable, "-c", _DRIVER], input=json.dumps(blocks), text=True,
                          capture_output=True, cwd=tmp_path, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]


def test_not_run_marker(tmp_path):
    doc = tmp_path / "x.md"
    doc.write_text("text\n\n<!-- not run: takes minutes -->\n```bash\nbash scripts/main.sh\n```\n\n"
                   "```python\nprint(1)\n```\n")
    assert [(b[0], b[1], b[3]) for b in code_blocks(doc)] == [("bash", 5, "takes minutes"),
                                                             ("python", 9, None)]


@pytest.mark.parametrize("cmd", _cli_commands(not_run=True))
def test_not_run_commands_parse(cmd):
    # The commands the docs show but the test does not run still name real commands and options.
    from jaxdamp.cli import build_parser

    args = build_parser().parse_args(shlex.split(cmd)[1:])
    assert args.command == shlex.split(cmd)[1]


@pytest.mark.parametrize("cmd", _cli_commands())
def test_cli_commands_run(cmd, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = shlex.split(cmd)[1:]
    try:
        code, out, err = run_cli(capsys, *argv)
    except SystemExit as e:  # --help exits through argparse
        code, err = e.code, capsys.readouterr().err
    assert code == 0, err
