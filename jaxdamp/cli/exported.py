"""Compiled programs that a second CLI process reuses without tracing them again.

JAX's persistent compilation cache skips XLA compilation only: every process still traces and
lowers each program before it can look the compiled code up. For `jaxdamp response` the tracing
was the cost (measured with jax_log_compiles: 8.3 s for the peaks, 13.9 s for the designer's
diagram, while loading the compiled code took 0.4 s): the exact damper curve is a vmapped
while-loop cycle with a custom JVP rule, traced inside the root search's custom_root. `call`
saves a program once as a serialized `jax.export.Exported` (StableHLO) in the cache folder and
later processes deserialize it: no tracing, and the XLA compile of the same module is a
persistent-cache hit. The key holds the jaxdamp sources, the JAX version, the program's name, its
function and static options (`program_identity`) and the inputs' structure, shapes and dtypes, so
that any change of code, options or input shapes exports anew.

The package ships the saved programs of the commonest commands (`SHIPPED_DIR`, written by
`scripts/export_programs.py` with the same key): a first call in a new cache folder then skips
tracing too, wherever the sources, the JAX version, the platform and the shapes are those they
were saved for; otherwise it traces and saves as before. They are StableHLO, not machine code:
XLA still compiles them on the user's machine.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import pickle
import threading
import types
from pathlib import Path

import jax
from jax import export as jexport

from ..paper.files import write_bytes
from ..runtime import options_jit
from . import cache_dir

__all__ = ["call", "compile_only", "Runner", "SHIPPED_DIR", "sources_digest", "program_identity"]

# Saved programs that come with the package (read-only; scripts/export_programs.py writes them).
SHIPPED_DIR = Path(__file__).resolve().parents[1] / "data" / "exported"


@functools.cache
def sources_digest() -> str:
    """The jaxdamp package's Python sources and the JAX version: a program saved by other code is
    never reused."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(jax.__version__.encode())
    for path in sorted(root.rglob("*.py")):
        h.update(path.relative_to(root).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


# Closure constants that name a program's static options (bands_program's sample count, a peak
# program's method): part of its identity. Anything else in a closure (an array, an object) could
# be baked into the program unseen by the key, and such a program is not saved.
_OPTION_TYPES = (str, int, float, bool, type(None))


def program_identity(program) -> str | None:
    """The traced function's module, qualified name, default arguments and closure constants (its
    static options), or None where it is not a plain function (a functools.partial, a callable
    object) or its closure or defaults hold something else: two programs with the same name and
    inputs but other code or options never share a saved export."""
    fun = getattr(program, "__wrapped__", program)

    def constant(v):
        if isinstance(v, _OPTION_TYPES):
            return True
        return isinstance(v, tuple) and all(constant(x) for x in v)

    if isinstance(fun, type):
        return f"{fun.__module__}.{fun.__qualname__}"
    if not isinstance(fun, types.FunctionType):
        return None
    defaults = (fun.__defaults__ or ()) + tuple((fun.__kwdefaults__ or {}).items())
    if not constant(defaults):
        return None
    parts = [f"{fun.__module__}.{fun.__qualname__}", repr(defaults)]
    for cell in fun.__closure__ or ():
        v = cell.cell_contents
        if constant(v):
            parts.append(repr(v))
        elif type(v) is object:  # a sentinel (jax.vmap keeps one): no state, no options
            parts.append("<sentinel>")
        elif callable(v):
            sub = program_identity(v)
            if sub is None:
                return None
            parts.append(sub)
        else:
            return None
    return "|".join(parts)


# Custom calls that JAX does not promise to keep stable across versions (jax.export refuses them
# unless told): the key holds the JAX version and the platform, so a saved program is only ever
# read back by the jaxlib that wrote it. The loop fit's QR solve (lineax) applies Q^T by ormqr.
ALLOWED_CUSTOM_CALLS = ("lapack_dormqr_ffi",)


def _key(name: str, variant: str, leaves, in_tree, identity: str = "") -> str:
    h = hashlib.sha256(sources_digest().encode())
    h.update(identity.encode())
    # The platform the program was lowered for: a CPU export does not run on a GPU.
    h.update(f"{name}|{variant}|{jax.default_backend()}".encode())
    h.update(str(in_tree).encode())
    h.update(str(bool(jax.config.jax_enable_x64)).encode())
    for x in leaves:
        h.update(f"{jax.numpy.shape(x)}{jax.numpy.result_type(x)}".encode())
    return h.hexdigest()[:32]


@functools.cache
def _loaded(exported_bytes: bytes, cpu_options: tuple):
    exp, out_tree = pickle.loads(exported_bytes)
    return options_jit(exp.call, cpu_options), out_tree


_LOADING = threading.Lock()


def _runner(exported_bytes: bytes, cpu_options: tuple = ()):
    """(the deserialized program jitted once per process with the batch compiler options and the
    program's own (`runtime.batch_jit`'s cpu_options), its output structure). One jitted function
    per program also where threads call it together (the library runs programs side by side): a
    jitted function compiles once for both."""
    with _LOADING:
        return _loaded(exported_bytes, cpu_options)


def forget_loaded() -> None:
    """Forget the programs this process has loaded from saved exports, so that the next call
    reads its file again, as a new process would."""
    _loaded.cache_clear()


def _serialized(exp, out_tree) -> bytes:
    """The Exported and the program's output structure (a PyTreeDef) as bytes. jax.export's own
    serialize() needs the flatbuffers package, which the project does not depend on, and keeps no
    output structure; a pickle of the dataclass holds the same StableHLO module, less its VJP
    builder (a closure, not needed to call it). The file is read back only by the JAX version and
    jaxdamp sources that wrote it (the key holds both), from the user's own cache folder."""
    return pickle.dumps((dataclasses.replace(exp, _get_vjp=None), out_tree))


_PATH_LOCKS_LOCK = threading.Lock()
_PATH_LOCKS: dict = {}


def _path_lock(path: Path) -> threading.Lock:
    """One lock per saved program's file: threads running parts of one batch through the same
    program (`band.amplitude_bands`' chunks) export it once, the others read it."""
    with _PATH_LOCKS_LOCK:
        return _PATH_LOCKS.setdefault(str(path), threading.Lock())


def _read(path: Path) -> bytes | None:
    try:
        return path.read_bytes()
    except OSError:
        return None


def _through_saved(name: str, program, args: tuple, variant: str):
    """(the saved program jitted, its output structure, args' leaves), or None where the cache
    folder is off or the program cannot be saved (`program_identity`)."""
    folder = cache_dir()
    identity = program_identity(program)
    if folder is None or identity is None:
        return None
    leaves, in_tree = jax.tree_util.tree_flatten(args)
    path = Path(folder) / "exported" / f"{name}-{_key(name, variant, leaves, in_tree, identity)}.bin"
    with _path_lock(path):
        data = _saved_or_export(path, program, leaves, in_tree)
    run, out_tree = _runner(data, getattr(program, "cpu_options", ()))
    # Committed to one device, every input: a saved program's outputs come back committed (they
    # carry the export's shardings), and JAX compiles a jitted function anew for a committed input
    # it first saw uncommitted (the fit's solver step, fed its own theta back, compiled twice,
    # 4.7 s each). device_put keeps dtypes and weak types.
    return run, out_tree, jax.device_put(leaves, jax.devices()[0])


def call(name: str, program, args: tuple, variant: str = ""):
    """program(*args), through a saved export where the cache folder allows (JAXDAMP_CACHE_DIR;
    off: a plain call). program: a jitted function of array pytrees; its outputs come back in
    their own structure, saved with the program, so that a later process neither traces nor
    lowers it. variant: what else selects the program (its static options), part of the key."""
    saved = _through_saved(name, program, args, variant)
    if saved is None:
        return program(*args)
    run, out_tree, leaves = saved
    return jax.tree_util.tree_unflatten(out_tree, run(*leaves))


def compile_only(name: str, program, args: tuple, variant: str = "") -> None:
    """What `call` does before it runs the program (load or export it, compile it for args' shapes
    and dtypes), without running it: a later call with inputs of those shapes runs at once."""
    saved = _through_saved(name, program, args, variant)
    if saved is None:
        program.lower(*args).compile()
    else:
        run, _, leaves = saved
        run.lower(*leaves).compile()


class Runner:
    """The library's runner= (`runtime.run_program`) through saved programs under one name: called
    as runner(program, args); `runtime.compile_ahead` compiles through its compile_ahead."""

    def __init__(self, name: str, variant: str = ""):
        self.name, self.variant = name, variant

    def __call__(self, program, args: tuple):
        return call(self.name, program, args, self.variant)

    def compile_ahead(self, program, args: tuple) -> None:
        compile_only(self.name, program, args, self.variant)


def _saved_or_export(path: Path, program, leaves, in_tree) -> bytes:
    """The saved program's bytes: from the cache folder, else from the package, else exported now
    and saved in the cache folder."""
    data = _read(path)
    if data is None:
        data = _read(SHIPPED_DIR / path.name)  # saved with the package for these sources
    if data is None:
        # The traced function itself: a batch_jit's compiler options belong to the top-level
        # jit (_runner's), not to a nested one.
        fun = getattr(program, "__wrapped__", program)
        out_trees = []

        def flat(*xs):
            out_leaves, out_tree = jax.tree_util.tree_flatten(
                fun(*jax.tree_util.tree_unflatten(in_tree, xs)))
            out_trees.append(out_tree)
            return out_leaves

        exp = jexport.export(jax.jit(flat), disabled_checks=[
            jexport.DisabledSafetyCheck.custom_call(t) for t in ALLOWED_CUSTOM_CALLS])(*leaves)
        data = _serialized(exp, out_trees[-1])
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            write_bytes(path, data)
        except OSError:
            pass  # an unusable cache folder only costs time
    return data
