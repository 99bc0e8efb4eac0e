"""What every command shares: argument groups (shape, contacts, load, --json, --no-progress), input
and output-path checks, the JSON document (status, inputs, versions, no NaN) and progress bars.

The CLI adds no validation of its own for physical parameters: the library's ValueError messages
(jaxdamp._validate) are the CLI's messages, and `main` prints them as one line with exit code 2.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path

# 2: every document carries status, schema_version, jaxdamp_version and echoes its inputs;
# numbers that do not exist are null (schema 1 had 0.0 and no status).
SCHEMA_VERSION = 2


class CliError(Exception):
    """A user error found by the CLI itself (argument combinations, paths): one line, exit 2."""


class UsageError(CliError):
    """argparse's own usage errors, raised instead of exiting so that `main` prints one line."""


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors: `error` raises UsageError (main prints it, exit 2).

    Subparsers inherit the class (argparse builds them with type(parent))."""

    def error(self, message):
        raise UsageError(f"{self.prog}: error: {' '.join(str(message).split())}")


# ---------------------------------------------------------------- argument groups
def add_shape_args(p: argparse.ArgumentParser, *, with_br: bool = True) -> None:
    """--shape NAME, or --theta-l/--theta-r[/--br] with optional --bl2 (custom shapes only).

    with_br=False for commands that compute b_R/h_R themselves (design-br)."""
    g = p.add_argument_group("damper shape (either --shape or the angles" + (" and offsets)" if with_br else ")"))
    g.add_argument("--shape", help="a paper shape: 90L, 74L, 60sym, 74R, 90R, 45sym")
    g.add_argument("--theta-l", type=float, help="left base angle, deg, in (0, 90]")
    g.add_argument("--theta-r", type=float, help="right base angle, deg, in (0, 90]")
    if with_br:
        g.add_argument("--br", type=float, help="b_R/h_R: offset of pad R1 up the right flank, in [-0.5, 0.5]")
    g.add_argument("--bl2", type=float, default=None,
                   help="2b_L/h_L: pad spacing on the left flank, in (0, 1] (default 0.8; custom shapes "
                        "only: a paper shape fixes it)")


def shape_from_args(args, *, need_br: bool = True):
    """The DamperShape of the arguments (validated by the library). need_br=False: b_R/h_R is not an
    input (design-br computes it); the returned shape has b_R/h_R = 0, a placeholder."""
    from ..geometry import DamperShape, family_shape, validate_shape

    br = getattr(args, "br", None)
    angles = {"--theta-l": args.theta_l, "--theta-r": args.theta_r}
    if need_br:
        angles["--br"] = br
    given = [k for k, v in angles.items() if v is not None]
    if args.shape:
        if given:
            raise CliError(f"give either --shape or {'/'.join(angles)}, not both")
        if args.bl2 is not None:
            raise CliError("--bl2 applies to a custom shape (--theta-l/--theta-r); the paper shape "
                           f"{args.shape} fixes 2b_L/h_L")
        return family_shape(args.shape)
    missing = [k for k, v in angles.items() if v is None]
    if missing:
        raise CliError(f"a shape needs --shape NAME or all of {', '.join(angles)} (missing "
                       f"{', '.join(missing)})")
    shape = DamperShape(args.theta_l, args.theta_r, br if need_br else 0.0,
                        0.8 if args.bl2 is None else args.bl2)
    return validate_shape(shape)


def add_contact_args(p, required: bool = False) -> None:
    from ..params import REFERENCE_KN, REFERENCE_KT

    p.add_argument("--kn", type=float, default=None if required else REFERENCE_KN, required=required,
                   help=f"normal contact stiffness, N/mm, in (0, inf) (default {REFERENCE_KN:g})")
    p.add_argument("--kt", type=float, default=None if required else REFERENCE_KT, required=required,
                   help=f"tangential contact stiffness, N/mm, in (0, inf) (default {REFERENCE_KT:g})")


def add_load_args(p) -> None:
    p.add_argument("--fd", type=float, default=1000.0, help="centrifugal force F_D, N (default 1000)")
    p.add_argument("--q", type=float, default=100.0, help="virtual blade pitch q*, mm (default 100)")
    p.add_argument("--r-sin-beta", type=float, default=0.0, help="r sin(beta), mm (default 0)")


def add_design_args(p, mu_default=None) -> None:
    """Shape, friction, contact and load arguments: one Design's worth (mu required unless a
    default is given)."""
    add_shape_args(p)
    if mu_default is None:
        p.add_argument("--mu", type=float, required=True, help="friction coefficient, in (0, 5]")
    else:
        p.add_argument("--mu", type=float, default=mu_default,
                       help=f"friction coefficient, in (0, 5] (default {mu_default:g})")
    add_contact_args(p)
    add_load_args(p)


def add_json_arg(p) -> None:
    p.add_argument("--json", action="store_true", help="machine-readable output (one JSON document)")


def add_progress_arg(p) -> None:
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar (it is shown on stderr only when stderr is a terminal)")


def contacts_from_args(args):
    from ..params import Contacts, validate_contacts

    return validate_contacts(Contacts(args.kn, args.kt))


def load_from_args(args):
    from ..params import LoadCase, validate_load

    return validate_load(LoadCase(args.fd, args.q, args.r_sin_beta))


def float_list(text: str, flag: str) -> tuple:
    """'a,b,c' -> floats (validated later by the library)."""
    try:
        values = tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise CliError(f"{flag} must be comma-separated numbers, e.g. 0.7,0.5,0.3; got {text!r}") from None
    if not values:
        raise CliError(f"{flag} must list at least one number; got {text!r}")
    return values


# ---------------------------------------------------------------- output paths (checked before work)
def _first_existing(path: Path) -> Path:
    p = path
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


def check_output_dir(flag: str, path) -> Path:
    """A directory that exists and is writable, or can be created (nothing is created here)."""
    p = Path(path).expanduser()
    if p.exists():
        if not p.is_dir():
            raise CliError(f"{flag} {str(path)!r} exists and is not a directory")
        base = p
    else:
        base = _first_existing(p.absolute())
        if not base.is_dir():
            raise CliError(f"{flag} {str(path)!r} cannot be created: {str(base)!r} is not a directory")
    if not os.access(base, os.W_OK | os.X_OK):
        raise CliError(f"{flag} {str(path)!r}: {str(base)!r} is not writable")
    return p


def check_output_file(flag: str, path, suffixes=None) -> Path:
    """A file path whose directory exists and is writable (the file is not created here)."""
    p = Path(path).expanduser()
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise CliError(f"{flag} must end in {', '.join(suffixes[:-1])} or {suffixes[-1]}; got {str(path)!r}")
    parent = p.parent if str(p.parent) else Path(".")
    if p.is_dir():
        raise CliError(f"{flag} {str(path)!r} is a directory, not a file")
    if not parent.is_dir():
        raise CliError(f"{flag} {str(path)!r}: directory {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK) or (p.exists() and not os.access(p, os.W_OK)):
        raise CliError(f"{flag} {str(path)!r} is not writable")
    return p


# ---------------------------------------------------------------- JSON documents
def version() -> str:
    import jaxdamp

    v = getattr(jaxdamp, "__version__", None)
    if v:
        return str(v)
    import importlib.metadata as md

    try:
        return md.version("jaxdamp")
    except md.PackageNotFoundError:
        return "unknown"


def status_name(result) -> str:
    """The RESULTS name of a result (its `status` field, else its flags): see jaxdamp.status.status_of."""
    from ..status import status_of

    return status_of(result).name


def status_from_flags(*, converged=True, liftoff=False, failed=False) -> str:
    from types import SimpleNamespace

    return status_name(SimpleNamespace(converged=converged, liftoff=liftoff, failed=failed))


def number(value):
    """A JSON number: None where it does not exist (NaN, inf); -0.0 becomes 0.0."""
    if value is None:
        return None
    v = float(value)
    if not math.isfinite(v):
        return None
    return v + 0.0  # -0.0 + 0.0 == 0.0


def named(values) -> dict:
    from ..geometry import CONTACT_NAMES

    return {c: number(v) for c, v in zip(CONTACT_NAMES, values)}


def shape_echo(shape) -> dict:
    return {"theta_l_deg": number(shape.theta_l), "theta_r_deg": number(shape.theta_r),
            "br_over_hr": number(shape.br_over_hr), "bl2_over_hl": number(shape.bl2_over_hl)}


def contacts_echo(contacts) -> dict:
    import numpy as np

    def k(v):
        a = np.asarray(v, float)
        return number(a) if a.ndim == 0 else named(a)

    return {"kn_n_per_mm": k(contacts.kn), "kt_n_per_mm": k(contacts.kt)}


def load_echo(load) -> dict:
    return {"F_D_n": number(load.F_D), "q_star_mm": number(load.q_star),
            "r_sin_beta_mm": number(load.r_sin_beta)}


def clean(obj):
    """A JSON-safe copy: numpy scalars/arrays to Python, NaN/inf to None, -0.0 to 0.0."""
    import numpy as np

    if isinstance(obj, dict):
        return {str(k): clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return clean(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return number(obj)
    if obj is None or isinstance(obj, str):
        return obj
    if hasattr(obj, "shape") and hasattr(obj, "dtype"):  # a JAX array
        return clean(np.asarray(obj))
    return str(obj)


def document(status: str, payload: dict, **inputs) -> dict:
    """The JSON document of a command: status and versions first, the inputs echoed, then payload."""
    doc = {"status": status, "schema_version": SCHEMA_VERSION, "jaxdamp_version": version()}
    doc.update(inputs)
    doc.update(payload)
    return clean(doc)


def dumps(doc: dict, indent=2) -> str:
    return json.dumps(clean(doc), indent=indent, allow_nan=False, ensure_ascii=False)


def emit(args, doc: dict, text: str) -> None:
    """Print the document (--json) or the text, whose first line then shows the status."""
    if getattr(args, "json", False):
        print(dumps(doc))
        return
    first, _, rest = text.partition("\n")
    print(f"{first}   [status: {doc['status']}]" + (f"\n{rest}" if rest else ""))


# ---------------------------------------------------------------- progress
def show_progress(args) -> bool:
    """Progress bars on stderr: only on a terminal, and not with --no-progress."""
    if getattr(args, "no_progress", False):
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def progress_bar(args, total=None, desc="", unit="it"):
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, disable=not show_progress(args),
                leave=False, dynamic_ncols=True)
