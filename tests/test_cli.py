"""The CLI as a whole: parser, one-line usage errors, entry-point commands, runtime configuration,
output-path checks, and the JSON document helpers. Commands have their own tests/test_cli_*.py."""

import json
import os
import re
import tomllib
from pathlib import Path

import pytest

import jaxdamp.cli as cli
from jaxdamp.cli import common as C

from helpers import one_error_line, run_cli

ROOT = Path(__file__).resolve().parents[1]


def test_help_explains_units(capsys):
    with pytest.raises(SystemExit):
        cli.main(["--help"])
    out = capsys.readouterr().out
    assert "N/mm" in out and "mrad" in out and "degrees" in out


@pytest.mark.parametrize("argv, needle", [
    ([], "COMMAND"),
    (["no-such-command"], "invalid choice"),
    (["statics", "--shape", "60sym", "--mu", "abc"], "--mu"),
    (["statics", "--shape", "60sym"], "--mu"),
    (["cycle", "--shape", "60sym", "--mu", "0.5", "--bogus"], "--bogus"),
    (["grad", "--shape", "60sym", "--mu", "0.5", "--mode", "sideways"], "--mode"),
    (["cycle", "--shape", "60sym", "--mu", "0.5", "--damper", "wedge", "--br", "0.5"],
     "--br places the curved-flat damper's pad R1"),
    (["response", "--shape", "60sym", "--mu", "0.5", "--force-n", "5", "--damper", "wedge",
      "--diagram"], "--diagram is computed for the paper's in-phase motion and curved-flat"),
])
def test_usage_errors_are_one_line_exit_2(capsys, argv, needle):
    code, out, err = run_cli(capsys, *argv)
    assert code == 2 and out == ""
    assert needle in one_error_line(err)


def test_every_builtin_command_is_a_module_with_register_and_run():
    import importlib

    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name in cli.COMMANDS:
        mod = importlib.import_module(f"jaxdamp.cli.{name}")
        assert callable(mod.register) and callable(mod.run)
        assert name.replace("_", "-") in sub.choices


def test_pyproject_declares_the_console_script_and_the_optimize_entry_point():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert meta["scripts"]["jaxdamp"] == "jaxdamp.cli:console"
    group = meta["entry-points"][cli.ENTRY_POINT_GROUP]
    assert group == {"optimize": "jaxdamp_optimize.cli:register"}
    # the declared object loads and registers the command
    import importlib
    from importlib.metadata import EntryPoint

    ep = EntryPoint("optimize", group["optimize"], cli.ENTRY_POINT_GROUP)
    register = ep.load()
    assert register is importlib.import_module("jaxdamp_optimize.cli").register
    parser = cli.build_parser((register,))
    args = parser.parse_args(["optimize", "--mu-set", "0.5"])
    assert args.func.__module__ == "jaxdamp_optimize.cli" and args.mu_set == "0.5"


def test_jaxdamp_never_names_optimize():
    for path in (ROOT / "jaxdamp").rglob("*.py"):
        text = path.read_text()
        for name in ("optimize", "jaxdamp_optimize"):
            assert f"import {name}" not in text and f"from {name}" not in text, path


def test_no_library_module_parses_arguments_or_prints():
    import re

    for path in (ROOT / "jaxdamp").rglob("*.py"):
        if "cli" in path.relative_to(ROOT / "jaxdamp").parts:
            continue
        text = path.read_text()
        assert "argparse" not in text, path
        assert not re.search(r"(?<![\w.])print\(", text), path


def test_extra_commands_are_added_once(capsys):
    calls = []

    def register(sub):
        p = sub.add_parser("hello")
        p.set_defaults(func=lambda args: calls.append(args.command) or 0)

    assert cli.main(["hello"], extra_commands=[register]) == 0
    assert calls == ["hello"]


def test_cache_dir_env(monkeypatch, tmp_path):
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", "off")
    assert cli.cache_dir() is None
    monkeypatch.setenv("JAXDAMP_CACHE_DIR", str(tmp_path / "c"))
    assert cli.cache_dir() == str(tmp_path / "c")
    monkeypatch.delenv("JAXDAMP_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "x"))
    assert cli.cache_dir() == str(tmp_path / "x" / "jaxdamp" / "jax")


def test_main_enables_float64_and_agg(capsys):
    import jax

    assert run_cli(capsys, "statics", "--shape", "60sym", "--mu", "0.5")[0] == 0
    assert jax.config.jax_enable_x64
    assert os.environ.get("MPLBACKEND") == "Agg" or __import__("matplotlib").get_backend().lower() == "agg"


# ---------------------------------------------------------------- output paths
def test_output_dir_checks(tmp_path):
    # The check creates the directory: the only sure test that the run can write there.
    assert C.check_output_dir("--out", tmp_path / "new" / "deeper") == tmp_path / "new" / "deeper"
    assert (tmp_path / "new" / "deeper").is_dir()
    f = tmp_path / "file.txt"
    f.write_text("x")
    with pytest.raises(C.CliError, match="not a directory"):
        C.check_output_dir("--out", f)
    with pytest.raises(C.CliError, match="--out .*is a file, not a directory"):
        C.check_output_dir("--out", f / "sub")
    with pytest.raises(C.CliError, match="--out '/proc/nonexistent/study' cannot be created"):
        C.check_output_dir("--out", "/proc/nonexistent/study")


def test_output_file_checks(tmp_path):
    assert C.check_output_file("--plot", tmp_path / "a.png", (".png",)) == tmp_path / "a.png"
    with pytest.raises(C.CliError, match="does not exist"):
        C.check_output_file("--plot", tmp_path / "missing" / "a.png")
    (tmp_path / "FILE").write_text("x")
    with pytest.raises(C.CliError, match="'.*FILE' is a file, not a directory"):
        C.check_output_file("--out", tmp_path / "FILE" / "x.png")
    with pytest.raises(C.CliError, match="is a directory"):
        C.check_output_file("--markdown", tmp_path)
    with pytest.raises(C.CliError, match="must end in"):
        C.check_output_file("--out", tmp_path / "a.txt", (".png", ".svg"))


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write anywhere")
def test_unwritable_dir(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        with pytest.raises(C.CliError, match="--out .*(cannot be created: Permission denied|not writable)"):
            C.check_output_dir("--out", ro / "x")
    finally:
        ro.chmod(0o700)


# ---------------------------------------------------------------- JSON helpers
def test_numbers_that_do_not_exist_are_null():
    import numpy as np

    assert C.number(float("nan")) is None and C.number(np.inf) is None
    assert str(C.number(-0.0)) == "0.0"
    doc = C.document("ok", {"a": np.array([1.0, np.nan]), "b": np.float32(-0.0)}, mu=0.5)
    text = C.dumps(doc)
    assert json.loads(text)["a"] == [1.0, None] and "-0.0" not in text
    assert list(doc)[:3] == ["status", "schema_version", "jaxdamp_version"]
    assert doc["schema_version"] == 3 and doc["inputs"]["mu"] == 0.5


def test_every_non_ok_status_says_its_cause():
    """document() gives every status its cause under "status_reason" (null for ok) and as the last
    of "warnings"; emit() puts it on the status line. For ill_conditioned with contacts and load,
    the cause names the limit, the value and the validated range (docs/model.md: kn/F_D, kt/F_D
    at most 1e6 per mm, kt/kn in [1e-4, 1e4]); inside the range it says the solves lost digits."""
    import numpy as np

    from jaxdamp import Contacts, LoadCase
    from jaxdamp.status import RESULTS

    ok = C.document("ok", {"warnings": []})
    assert ok["status_reason"] is None and ok["warnings"] == []
    assert list(ok)[:4] == ["status", "schema_version", "jaxdamp_version", "status_reason"]
    for name in ("liftoff", "singular", "not_converged", "no_root"):
        doc = C.document(name, {})
        assert doc["status_reason"] == RESULTS.message(RESULTS[name])
        assert doc["warnings"] == [doc["status_reason"]]
    # kt = 1 N/mm with the reference kn: kt/kn = 1/20246.3 = 4.94e-5, below 1e-4
    why = C.status_reason("ill_conditioned", Contacts(20246.3, 1.0), LoadCase())
    assert why.startswith("kt/kn = 4.94e-05 below the validated range [1e-4, 1e4]") and "kn/F_D" not in why
    # kn = 1e12 N/mm at F_D = 1000 N: kn/F_D = 1e9 per mm, above 1e6 (and kt/kn = 3.5e-9 too)
    why = C.status_reason("ill_conditioned", Contacts(1e12, 3500.0), LoadCase())
    assert "kn/F_D = 1e+09 per mm above the validated range (at most 1e6 per mm)" in why
    assert "kt/kn = 3.5e-09 below" in why
    # per contact: only the contacts outside are named; kt/F_D above at L2 only (2e9 / 1000 N)
    why = C.status_reason("ill_conditioned", Contacts(np.array([2e4, 2e4, 4e9]),
                                                      np.array([5e3, 5e3, 2e9])), LoadCase())
    assert why.startswith("kn/F_D = 4e+06 per mm at L2 above") and "kt/F_D = 2e+06 per mm at L2 above" in why
    assert "kt/kn" not in why
    # the same contacts under a heavier load are inside: the cause is then the solves' digits
    why = C.status_reason("ill_conditioned", Contacts(np.array([2e4, 2e4, 4e9]),
                                                      np.array([5e3, 5e3, 2e9])), LoadCase(F_D=1e4))
    assert "lost their digits" in why and "inside the validated range" in why
    doc = C.document("ill_conditioned", {"warnings": ["psi_BC above the small-rotation limit"]},
                     reason="kt/kn = 4.94e-05 below the validated range [1e-4, 1e4]")
    assert doc["warnings"] == ["psi_BC above the small-rotation limit", doc["status_reason"]]


def test_status_from_solver_flags_and_from_result_fields():
    from types import SimpleNamespace

    from jaxdamp.status import RESULTS

    name = lambda **flags: RESULTS.name_of(RESULTS.first(  # noqa: E731
        {getattr(RESULTS, k): v for k, v in flags.items()}))
    assert name(liftoff=False) == "ok"
    assert name(liftoff=True, singular=True) == "liftoff"
    assert name(liftoff=False, singular=True) == "singular"
    assert name(liftoff=False, not_converged=True) == "not_converged"
    assert name(liftoff=True, ill_conditioned=True) == "ill_conditioned"
    assert C.status_name(SimpleNamespace(status=RESULTS.ill_conditioned)) == "ill_conditioned"
    # a result without a status has none to report: no status is rebuilt from flags
    with pytest.raises(TypeError, match="no status"):
        C.status_name(SimpleNamespace(liftoff=True))


def test_a_broken_plugin_does_not_break_the_others(monkeypatch, capsys):
    import importlib.metadata as md

    broken = md.EntryPoint("broken", "no_such_module_xyz:register", cli.ENTRY_POINT_GROUP)
    installed = md.entry_points
    # The plugin as if installed: the command line finds its commands through entry_points.
    monkeypatch.setattr(md, "entry_points", lambda **kw: [broken] if kw.get("group") ==
                        cli.ENTRY_POINT_GROUP else installed(**kw))
    assert run_cli(capsys, "statics", "--shape", "60sym", "--mu", "0.5")[0] == 0
    code, _, err = run_cli(capsys, "broken")
    assert code == 2 and "failed to load" in one_error_line(err)


@pytest.mark.slow  # 10 worker-s (run of 2026-11-25)
def test_console_exits_with_the_commands_code_and_delivers_its_output(tmp_path):
    """The console entry ends the process with os._exit after main(): the exit code and the whole
    output must still arrive (here through pipes, as in scripts)."""
    import json
    import subprocess
    import sys

    env = {**__import__("os").environ, "JAXDAMP_CACHE_DIR": str(tmp_path / "cache")}
    run = lambda *a: subprocess.run([sys.executable, "-m", "jaxdamp.cli", *a],  # noqa: E731
                                    capture_output=True, text=True, env=env, timeout=300)
    bad = run("cycle", "--shape", "60sym", "--mu", "9")
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.count("\n") == 1 and "mu" in bad.stderr
    ok = run("cycle", "--shape", "60sym", "--mu", "0.5", "--json")
    assert ok.returncode == 0, ok.stderr
    doc = json.loads(ok.stdout)
    assert doc["status"] == "ok"
    # The paper's Table B value for 60sym at mu 0.5 (k_Im,BC = 4921), within the 0.7 % of the
    # reference contact pair's fit (jaxdamp.params.REFERENCE_KN)
    assert abs(doc["k_im_bc"] / 4921.0 - 1.0) < 0.007


def test_compilation_mode_per_command_and_from_the_environment(monkeypatch):
    """JAXDAMP_COMPILE: auto compiles the one-design commands fast (runtime.compile_for_latency),
    a blade row's response between fast and optimised (runtime.ROW_LATENCY_OPTIONS: LLVM level 1)
    and leaves the long-running ones (a row's band too) optimised; fast and optimized apply to
    every command; any other value is refused in one line naming the variable and its values."""
    from jaxdamp import cli

    monkeypatch.delenv("JAX_PLATFORMS", raising=False)
    fast, row, optimised = "0", "1", None  # the LLVM level each asks for (None: XLA's own)
    cases = [("auto", ["cycle", "--shape", "74R"], fast), ("auto", ["design-br", "--mu", "0.5"], fast),
             ("auto", ["study", "--out", "x"], fast), ("", ["sweep"], optimised),
             ("auto", ["fit-loops", "a.csv"], fast), ("auto", ["calibrate"], optimised),
             ("fast", ["sweep"], fast),
             ("optimized", ["cycle"], optimised),
             # a blade row's response runs long programs a few times: level 1, unless asked
             ("auto", ["response", "--shape", "60sym"], fast),
             ("auto", ["response", "--modes", "example", "--h-l", "10"], row),
             ("auto", ["response", "--modes=example"], row),
             ("auto", ["response", "--modes", "example", "--band"], optimised),
             ("fast", ["response", "--modes", "example"], fast),
             ("optimized", ["response", "--modes", "example"], optimised)]
    for mode, argv, level in cases:
        monkeypatch.setenv(cli.COMPILE_ENV, mode)
        monkeypatch.delenv("XLA_FLAGS", raising=False)
        assert cli.choose_compilation(argv) is None
        flags = os.environ.get("XLA_FLAGS", "")
        got = re.search(r"--xla_backend_optimization_level=(\d)", flags)
        assert (got.group(1) if got else None) == level, (mode, argv)
        assert ("--xla_cpu_use_fusion_emitters=false" in flags) == (level is not None), (mode, argv)
    monkeypatch.setenv(cli.COMPILE_ENV, "quick")
    error = cli.choose_compilation(["cycle"])
    assert "JAXDAMP_COMPILE='quick'" in error and "auto, fast, optimized" in error
    assert "\n" not in error


def test_unknown_compilation_mode_exits_2_before_any_work(tmp_path):
    import subprocess
    import sys

    env = {**os.environ, "JAXDAMP_COMPILE": "quick", "JAXDAMP_CACHE_DIR": str(tmp_path / "cache")}
    out = subprocess.run([sys.executable, "-m", "jaxdamp.cli", "cycle", "--shape", "60sym"],
                         capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr.count("\n") == 1 and "JAXDAMP_COMPILE" in out.stderr
    assert not (tmp_path / "cache").exists()


def test_an_interrupt_ends_the_console_at_once_with_130():
    """Ctrl-C during a command: one line, exit code 130, and no wait for work in other threads
    (the study's parts and the response's band run in threads)."""
    import subprocess
    import sys

    code = ("import threading, time, jaxdamp.cli as cli\n"
            "def main():\n"
            "    threading.Thread(target=time.sleep, args=(60,)).start()\n"
            "    raise KeyboardInterrupt\n"
            "cli.main = main\n"
            "cli.console()\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=30)
    assert out.returncode == 130 and out.stderr == "jaxdamp: interrupted\n"
