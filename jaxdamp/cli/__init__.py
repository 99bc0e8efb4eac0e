"""Command-line interface: `jaxdamp <command> ...`.

Units: angles in degrees, b_R/h_R and 2b_L/h_L dimensionless (fractions of the flank lengths),
forces normalised to the centrifugal force F_D (statics) or in N, stiffness in N/mm, q* in mm,
platform rotation psi in mrad, rotational stiffness k in N mm/mrad, energy in N mm per cycle.

Exit codes: 0 with a result (whose "status" says whether it is a working damper), 2 for bad input
(one line on stderr naming the parameter and its valid range, before any computing).
Compiled programs are cached in $JAXDAMP_CACHE_DIR (default $XDG_CACHE_HOME/jaxdamp/jax or
~/.cache/jaxdamp/jax; JAXDAMP_CACHE_DIR=off disables the cache, deleting the folder clears it).
Programs of the one-design commands compile fast rather than optimised (JAXDAMP_COMPILE=auto, the
default; fast or optimized for every command).
"""

from __future__ import annotations

import os
import sys

# The helpers a command module outside jaxdamp (an entry point) may use.
from .common import (CliError, UsageError, add_contact_args, add_json_arg, add_load_args,
                      add_progress_arg, add_shape_args, check_output_dir, check_output_file,
                      contacts_echo, contacts_from_args, document, emit, float_list, load_echo,
                      progress_bar, save_figure, write_text)

UNITS = __doc__.split("\n\n", 1)[1]

# Built-in commands, one module each, every one exposing register(sub) and run(args) -> int.
COMMANDS = ("statics", "design_br", "cycle", "amplitude", "response", "grad", "sweep", "calibrate",
            "fit_loops", "study", "section")
# Third-party commands: entry points of this group load a register(sub) function
# (pyproject.toml declares `optimize = "jaxdamp_optimize.cli:register"`).
ENTRY_POINT_GROUP = "jaxdamp.commands"
CACHE_ENV = "JAXDAMP_CACHE_DIR"
# Programs compiling faster than this are not cached (the solver's take seconds; tiny eager ops
# would only fill the cache folder).
CACHE_MIN_COMPILE_S = 0.1


def cache_dir() -> str | None:
    """The persistent compilation cache folder, or None where JAXDAMP_CACHE_DIR=off."""
    env = os.environ.get(CACHE_ENV)
    if env is not None and env.strip().lower() in ("off", "0", "none", "false", ""):
        return None
    if env:
        return os.path.expanduser(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "jaxdamp", "jax")


def configure_runtime() -> None:
    """What the CLI (not the library) decides for the process: float64, a headless matplotlib
    backend, and the persistent compilation cache (second runs skip XLA compilation)."""
    if "matplotlib" in sys.modules:
        import matplotlib

        matplotlib.use("Agg")
    else:
        os.environ["MPLBACKEND"] = "Agg"  # read by matplotlib when (if) it is imported
    import jax

    jax.config.update("jax_enable_x64", True)
    path = cache_dir()
    if path is not None and not jax.config.jax_compilation_cache_dir:
        try:
            os.makedirs(path, exist_ok=True)
        except OSError:
            return  # an unusable cache folder only costs compile time
        jax.config.update("jax_compilation_cache_dir", path)
        jax.config.update("jax_persistent_cache_min_compile_time_secs", CACHE_MIN_COMPILE_S)


# Commands made of a few single-design calls run them on the calling thread: JAX's CPU client hands
# each call to a worker thread by default, ~60 us of a ~210 us warm Base-Cycle call; batched
# commands keep the default (benchmarks/results/cpu_runtime_options.json, no_async_dispatch).
SYNC_DISPATCH_COMMANDS = frozenset({"statics", "design-br", "cycle", "grad", "section"})


# Commands whose first call is mostly XLA compilation: XLA compiles them fast rather than
# optimises (runtime.compile_for_latency; first calls on the 2-core VM: `cycle` 7.2 -> 4.7 s,
# `response` 23.9 -> 15.1 s, `study` 157 -> 128 s, whose repeat took 87 -> 97 s). The commands
# that run their programs long keep optimised code (sweep, calibrate, optimize). fit-loops compiles
# fast since its step's Jacobian is one forward-mode matrix (2026-11-27: the step compiles in 5.5 s
# instead of 12.1 s, and a repeat ran 4.1-5.3 s fast against 5.1-5.8 s optimised; before, with
# the kernel's linearised scan in the step, fast compiling cost its repeat 7.9 s).
FAST_COMPILE_COMMANDS = frozenset({"statics", "design_br", "cycle", "amplitude", "grad", "response",
                                   "section", "study", "fit_loops"})
COMPILE_ENV = "JAXDAMP_COMPILE"
COMPILE_MODES = ("auto", "fast", "optimized")


def choose_compilation(argv) -> str | None:
    """Apply JAXDAMP_COMPILE (auto: per command, fast for FAST_COMPILE_COMMANDS, a blade row's
    `response --modes` between fast and optimised and its band optimised; fast; optimized) before
    anything compiles; returns an error line for a value it does not know, else None."""
    mode = os.environ.get(COMPILE_ENV, "auto").strip().lower() or "auto"
    if mode not in COMPILE_MODES:
        return (f"jaxdamp: error: {COMPILE_ENV}={os.environ[COMPILE_ENV]!r}: expected one of "
                f"{', '.join(COMPILE_MODES)}")
    if mode == "fast" or (mode == "auto" and _only_command(argv) in FAST_COMPILE_COMMANDS):
        from ..runtime import LATENCY_OPTIONS, ROW_LATENCY_OPTIONS, compile_for_latency

        if mode == "fast" or not _blade_row(argv):
            compile_for_latency(LATENCY_OPTIONS)
        elif not _asks(argv, "--band"):
            compile_for_latency(ROW_LATENCY_OPTIONS)
    return None


def _sync_dispatch() -> None:
    """Read when the CPU client is created: effective only before the first computation (parsing
    the arguments computes nothing)."""
    import jax

    jax.config.update("jax_cpu_enable_async_dispatch", False)


def _builtin_registers(names=COMMANDS):
    import importlib

    return [importlib.import_module(f"{__name__}.{name}").register for name in names]


def _asks(argv, flag: str) -> bool:
    """Whether argv has the option `flag` (as `--flag` or `--flag=value`)."""
    return any(isinstance(a, str) and (a == flag or a.startswith(flag + "="))
               for a in argv or ())


def _blade_row(argv) -> bool:
    """Whether argv asks `response` for a blade row (--modes). Its programs are long and, but for
    the band's, run a few times: they compile between fast and optimised
    (`runtime.ROW_LATENCY_OPTIONS`; on the 2-core VM, 2026-12-01, first call with an empty cache
    and repeat: the example row 14 -> 7 s and 2.0 s alike, with --diagram 44 -> 32 s and 3.5 ->
    3.8 s). The band's (--band) stay optimised: they run long, and so compiled the whole row's
    band took 52 s first and 18 s repeated against 64 s and 13 s. Compiled fast (level 0) the
    row's programs ran 5.8 s a call where optimised ones ran 0.5 s (2026-11-29, before they held
    one copy of the cycle)."""
    return _asks(argv, "--modes")


def _only_command(argv) -> str | None:
    """The built-in command module that argv names first (`design-br` -> design_br), if any: then
    the parser needs that command alone, and a call imports neither the other commands nor the
    entry points' packages (optax, for optimize), a tenth of a second of a second call."""
    if argv and isinstance(argv[0], str):
        name = argv[0].replace("-", "_")
        if name in COMMANDS:
            return name
    return None


def _entry_point_registers():
    from importlib.metadata import entry_points

    return [_loader(ep) for ep in entry_points(group=ENTRY_POINT_GROUP)]


def _loader(ep):
    """ep.load, except that a plugin that fails to import does not break the other commands: its
    command is still listed and, when run, says in one line why it cannot load (exit 2)."""

    def load():
        try:
            return ep.load()
        except Exception as exc:  # noqa: BLE001 - any import-time error of third-party code
            reason = f"command {ep.name!r} ({ep.value}) failed to load: {type(exc).__name__}: {exc}"

            def unavailable(args):
                raise CliError(reason)

            def register(sub):
                p = sub.add_parser(ep.name, help=f"(unavailable: {reason})", add_help=False)
                p.add_argument("rest", nargs="*")
                p.set_defaults(func=unavailable)

            return register

    return load


def build_parser(extra_commands=(), only: str | None = None):
    """The parser: built-in commands, then entry points of `jaxdamp.commands`, then extra_commands
    (register functions, for tests and embedding). only: one built-in command module's name, to
    build the parser of that command alone."""
    import argparse

    from .common import Parser

    parser = Parser(prog="jaxdamp",
                    description="Underplatform damper Base-Cycles by the direct method.\n\n" + UNITS,
                    formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    if only is not None:
        _builtin_registers((only,))[0](sub)
        return parser
    registers = _builtin_registers()
    for load in _entry_point_registers():
        registers.append(load())
    # An extra register function that is also an entry point (the same object) is added once.
    registers += [r for r in extra_commands if r not in registers]
    for register in registers:
        register(sub)
    return parser


def main(argv=None, extra_commands=()) -> int:
    """Run one command; returns the exit code (0 result, 2 bad input). extra_commands: register
    functions added after the built-in and entry-point commands. The process's XLA options are
    chosen first (`choose_compilation`): XLA reads them at the process's first compilation."""
    argv = sys.argv[1:] if argv is None else list(argv)
    error = choose_compilation(argv)
    if error is not None:
        print(error, file=sys.stderr)
        return 2
    configure_runtime()
    command = "jaxdamp"
    try:
        only = None if extra_commands else _only_command(argv)
        parser = build_parser(tuple(extra_commands), only=only)
        args = parser.parse_args(argv)
        command = f"jaxdamp {args.command}"
        if args.command in SYNC_DISPATCH_COMMANDS:
            _sync_dispatch()
        return int(args.func(args) or 0)
    except UsageError as exc:
        print(str(exc), file=sys.stderr)
        return 2
    except (ValueError, CliError) as exc:
        from .common import flag_message

        message = ' '.join(str(exc).split())
        print(f"{command}: error: {flag_message(message)}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # `jaxdamp ... | head`: the reader left; not an error of ours
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        return 0


def console() -> None:
    """The `jaxdamp` console script and `python -m jaxdamp.cli`: main(), then exit at once.

    Interpreter teardown with JAX loaded (its client, thread pools and caches) took about a third
    of a second here, a quarter of a second CLI call; nothing of the command's is left to do by then (output is
    flushed, files are closed and the compilation cache is written when a program compiles), so the
    process ends with os._exit, which also ends at once any work still running in other threads
    after an interrupt (Ctrl-C: exit code 130)."""
    try:
        code = main()
    except KeyboardInterrupt:
        print("jaxdamp: interrupted", file=sys.stderr)
        code = 130
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe (`| head`): nothing more to deliver
            pass
    os._exit(code)


__all__ = ["COMMANDS", "COMPILE_ENV", "FAST_COMPILE_COMMANDS", "choose_compilation", "console", "ENTRY_POINT_GROUP", "CliError", "add_contact_args", "add_json_arg",
           "add_load_args", "add_progress_arg", "add_shape_args", "build_parser", "cache_dir",
           "check_output_dir", "check_output_file", "contacts_echo", "contacts_from_args", "document", "save_figure", "write_text", "emit", "float_list",
           "load_echo",
           "main", "progress_bar"]
