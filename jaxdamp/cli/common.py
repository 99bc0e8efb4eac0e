"""What every command shares: argument groups (shape, contacts, load, --json, --no-progress), input
and output-path checks, the JSON document (status, inputs, versions, no NaN) and progress bars.

The CLI adds no validation of its own for physical parameters: the library's ValueError messages
(jaxdamp._validate) are the CLI's messages, and `main` prints them as one line with exit code 2.
"""

from __future__ import annotations

import argparse
import json
import contextlib
import math
import os
import sys
from pathlib import Path

from ..paper.files import atomic_file, save_figure, write_text  # noqa: F401 - every CLI writer's

# 3: the inputs are echoed under "inputs" in every document (schema 2 had them at the top level in
# some); 2: every document carries status, schema_version, jaxdamp_version and echoes its inputs;
# numbers that do not exist are null (schema 1 had 0.0 and no status).
SCHEMA_VERSION = 3


# The library names a parameter as Python does (jaxdamp._validate); the CLI user typed a flag. Every
# ValueError message that starts with one of these names is shown with the flag instead (`main`).
FLAG_OF = {"theta_l": "--theta-l", "theta_r": "--theta-r", "br_over_hr": "--br", "bl2_over_hl": "--bl2",
           "x_d": "--x-d", "mu": "--mu", "mu_max": "--mu-max", "kn": "--kn", "kt": "--kt", "F_D": "--fd",
           "q_star": "--q", "r_sin_beta": "--r-sin-beta", "psi_a_mrad": "--psi-a", "psi_a": "--psi-a",
           "eta": "--loss-factor", "f0_hz": "--f0-hz", "k_b": "--modal-stiffness-n-per-mm",
           "r": "--psi-per-mm", "max_iter": "--max-iter", "shape": "--shape", "initial": "--initial",
           "force_n": "--force-n", "start_mu": "--start-mu", "start_kn": "--start-kn",
           "start_kt": "--start-kt", "h_l": "--h-l", "h_c": "--h-c", "ibpa": "--ibpa",
           "motion": "--motion", "modes": "--modes", "engine_order": "--engine-order"}


def flag_message(message: str) -> str:
    """A library ValueError message with its leading parameter name replaced by the CLI flag
    ("eta must be in ..." -> "--loss-factor must be in ...")."""
    name, sep, rest = message.partition(" ")
    flag = FLAG_OF.get(name)
    return f"{flag} {rest}" if flag and sep else message


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
    g.add_argument("--shape", help="a paper shape: 90L, 74L, 60sym, 74R, 90R, 45sym (any case)")
    g.add_argument("--theta-l", type=float, help="left base angle, deg, in (0, 90]")
    g.add_argument("--theta-r", type=float, help="right base angle, deg, in (0, 90]")
    if with_br:
        g.add_argument("--br", help="b_R/h_R: offset of pad R1 up the right flank, in [-0.5, 0.5], or "
                       "'centred' (the paper's rule: the b_R/h_R that centres the left resultant at --mu)")
    g.add_argument("--bl2", type=float, default=None,
                   help="2b_L/h_L: pad spacing on the left flank, in (0, 1] (default 0.8; custom shapes "
                        "only: a paper shape fixes it)")
    g.add_argument("--x-d", type=float, default=None,
                   help="horizontal position of the centre of mass, where F_D acts, in units of the "
                        "height H from the left base corner, in [-1e6, 1e6] (default: the triangle's "
                        "centroid)")


def shape_name(text: str, flag: str = "--shape") -> str:
    """A paper shape's name as the tables spell it, whatever the case the user typed ('60SYM')."""
    from ..geometry import paper_tables

    known = list(paper_tables()["shapes"])
    by_lower = {k.lower(): k for k in known}
    name = by_lower.get(text.strip().lower())
    if name is None:
        raise CliError(f"{flag} must name shapes among {', '.join(known)} (any case); got {text.strip()!r}")
    return name


def parse_br(text, flag: str = "--br"):
    """'centred' (or 'centered'), else a number (checked against [-0.5, 0.5] by the library)."""
    if text is None or isinstance(text, float):
        return text
    if text.strip().lower() in ("centred", "centered"):
        return "centred"
    try:
        return float(text)
    except ValueError:
        raise CliError(f"{flag} must be a number in [-0.5, 0.5] or 'centred', e.g. {flag} 0.1; "
                       f"got {text!r}") from None


def centred_br(shape, mu_max: float, flag: str = "--br") -> float:
    """The paper's rule (jaxdamp.statics.design_br) as `--br centred` means it in every command."""
    from ..params import validate_mu
    from ..statics import design_br

    if mu_max is None:
        raise CliError(f"{flag} centred needs --mu (the rule centres the left resultant at it)")
    validate_mu(mu_max)
    res = design_br(shape, mu_max)
    if not bool(res.found):
        raise CliError(f"{flag} centred: no b_R/h_R in [-0.45, 0.45] centres the left resultant at "
                       f"mu = {mu_max:g}; give a number, e.g. {flag} 0.1")
    return float(res.br_over_hr)


def shape_from_args(args, *, need_br: bool = True, check: bool = True):
    """The DamperShape of the arguments (validated by the library). need_br=False: b_R/h_R is not an
    input (design-br computes it); the returned shape has b_R/h_R = 0, a placeholder. check=False:
    not validated here (the command checks it once later, e.g. in `response.prepare_scene`; with
    --br centred the shape the rule needs is validated anyway)."""
    from ..geometry import DamperShape, family_shape, validate_shape

    keep = validate_shape if check else (lambda s: s)  # noqa: E731
    br = parse_br(getattr(args, "br", None))
    x_d = getattr(args, "x_d", None)
    angles = {"--theta-l": args.theta_l, "--theta-r": args.theta_r}
    if need_br:
        angles["--br"] = br
    given = [k for k, v in angles.items() if v is not None]
    if args.shape:
        if given:
            raise CliError(f"give either --shape or {'/'.join(angles)}, not both")
        name = shape_name(args.shape)
        if args.bl2 is not None:
            raise CliError("--bl2 applies to a custom shape (--theta-l/--theta-r); the paper shape "
                           f"{name} fixes 2b_L/h_L")
        return keep(family_shape(name)._replace(x_d=x_d))
    missing = [k for k, v in angles.items() if v is None]
    if missing:
        raise CliError(f"a shape needs --shape NAME or all of {', '.join(angles)} (missing "
                       f"{', '.join(missing)})")
    shape = DamperShape(args.theta_l, args.theta_r, 0.0, 0.8 if args.bl2 is None else args.bl2, x_d)
    if need_br and br == "centred":
        validate_shape(shape)
        return shape._replace(br_over_hr=centred_br(shape, resolve_mu(args)))
    return keep(shape._replace(br_over_hr=br if need_br else 0.0))


def add_contact_args(p, required: bool = False) -> None:
    """--kn, --kt (one value for all three contacts, or three for R1, L1, L2) and --contacts-from
    FILE (a fit-loops JSON); explicit flags override the file. The reference pair where neither is
    given (required=True: one of them must be)."""
    from ..params import REFERENCE_KN, REFERENCE_KT

    p.add_argument("--kn", default=None,
                   help="normal contact stiffness, N/mm, in (0, inf): one value for all three contacts "
                        f"or three for R1,L1,L2 (e.g. 2e4,2e4,1.8e4; default {REFERENCE_KN:g})")
    p.add_argument("--kt", default=None,
                   help="tangential contact stiffness, N/mm, in (0, inf): one value or three for "
                        f"R1,L1,L2 (default {REFERENCE_KT:g})")
    p.add_argument("--contacts-from", metavar="FILE", default=None,
                   help='JSON with "contacts": {"kn_n_per_mm": [R1, L1, L2], "kt_n_per_mm": [...], '
                        '"mu": [...]} (as fit-loops writes it); --kn, --kt, --mu override it')
    p.set_defaults(contacts_required=required)


def add_load_args(p) -> None:
    p.add_argument("--fd", type=float, default=1000.0, help="centrifugal force F_D, N (default 1000)")
    p.add_argument("--q", type=float, default=100.0, help="virtual blade pitch q*, mm (default 100)")
    p.add_argument("--r-sin-beta", type=float, default=0.0, help="r sin(beta), mm (default 0)")


def add_design_args(p, mu_default=None) -> None:
    """Shape, friction, contact and load arguments: one Design's worth (mu required unless a
    default is given)."""
    add_shape_args(p)
    # --mu may come from --contacts-from: its presence is checked by contacts_from_args.
    help_ = "friction coefficient, in (0, 5]" + ("" if mu_default is None else f" (default {mu_default:g})")
    p.add_argument("--mu", type=float, default=None, help=help_)
    p.set_defaults(mu_default=mu_default)
    add_contact_args(p)
    add_load_args(p)


def add_damper_args(p) -> None:
    """--damper and --br2: the paper's curved-flat damper or a wedge (`DamperShape.br2_over_hr`)."""
    p.add_argument("--damper", choices=("curved-flat", "wedge"), default="curved-flat",
                   help="the paper's curved-flat damper R1 | L1, L2 (default) or a wedge R1, R2 | "
                   "L1, L2 (two flat pads on each flank; computed on the platform path, pads that "
                   "open and close included)")
    p.add_argument("--br2", type=float, default=None,
                   help="a wedge's right pad spacing 2b/h_R, in (0, 1] (default 0.8, like --bl2): R1 "
                   "and R2 at +-b from the right flank's midpoint")


def damper_from_args(args, shape):
    """The shape of --damper/--br2: unchanged for the curved-flat damper; a wedge otherwise
    (its right pads from --br2, --br refused: it places the curved pad R1). Checked."""
    from ..geometry import validate_shape

    if args.damper != "wedge":
        if args.br2 is not None:
            raise CliError("--br2 places a wedge's right pads: give --damper wedge, or drop --br2")
        return shape
    if getattr(args, "br", None) is not None:
        raise CliError("--br places the curved-flat damper's pad R1; a wedge's right pads are "
                       "placed by --br2 (2b/h_R, default 0.8)")
    return validate_shape(shape._replace(br_over_hr=0.0,
                                         br2_over_hr=0.8 if args.br2 is None else args.br2),
                          wedge_ok=True)


def add_json_arg(p) -> None:
    p.add_argument("--json", action="store_true", help="machine-readable output (one JSON document)")


def add_progress_arg(p) -> None:
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar (it is shown on stderr only when stderr is a terminal)")


def stiffness(text, flag: str):
    """--kn/--kt: one number (all three contacts) or three (R1, L1, L2), N/mm."""
    import numpy as np

    if text is None or isinstance(text, float):
        return text
    values = float_list(str(text), flag, example="2e4,2e4,1.8e4")
    if len(values) == 1:
        return values[0]
    if len(values) != 3:
        raise CliError(f"{flag} takes one value (all contacts) or three (R1,L1,L2), e.g. {flag} "
                       f"2e4,2e4,1.8e4; got {len(values)} values")
    return np.array(values)


def read_contacts_file(path, flag: str = "--contacts-from") -> dict:
    """{"kn": .., "kt": .., "mu": ..} from a fit-loops JSON (each a number or three numbers, R1, L1,
    L2; mu one number: the solver has one friction coefficient); CliError in one line otherwise."""
    import numpy as np

    try:
        data = json.loads(Path(path).expanduser().read_text())
        block = data["contacts"]
        out = {}
        for key, field in (("kn", "kn_n_per_mm"), ("kt", "kt_n_per_mm"), ("mu", "mu")):
            if field in block:
                a = np.asarray(block[field], dtype=float)
                if a.ndim > 1 or a.size not in (1, 3):
                    raise ValueError(f"{field} must be a number or three numbers (R1, L1, L2)")
                out[key] = float(a.reshape(-1)[0]) if a.size == 1 else a
    except OSError as exc:
        raise CliError(f"{flag} {str(path)!r} cannot be read: {exc.strerror or exc}") from None
    except (ValueError, KeyError, TypeError) as exc:
        why = "no \"contacts\" object" if isinstance(exc, (KeyError, TypeError)) else str(exc)
        raise CliError(f"{flag} {str(path)!r} is not a contacts file ({why}); expected "
                       '{"contacts": {"kn_n_per_mm": [R1, L1, L2], "kt_n_per_mm": [...], "mu": [...]}}') from None
    mu = out.get("mu")
    if mu is not None and np.ndim(mu) and not np.all(mu == mu[0]):
        raise CliError(f"{flag} {str(path)!r}: per-contact mu {list(map(float, mu))} is not supported "
                       "(the solver takes one friction coefficient); give --mu")
    if mu is not None and np.ndim(mu):
        out["mu"] = float(mu[0])
    return out


def contacts_from_args(args, shared: bool = False, check: bool = True):
    """The Contacts of --kn/--kt over --contacts-from over the reference pair (validated; the
    error names the flag). Sets args.kn, args.kt (and args.mu where the file gives it and --mu
    does not) to what is used, so that every later line of the command shows them. shared: the
    command runs one pair for all three contacts (sweep, optimize): three values are an error.
    check=False: neither the stiffnesses nor mu are validated here (the command checks them once
    later, e.g. in `response.prepare_scene`)."""
    from ..params import REFERENCE_KN, REFERENCE_KT, Contacts, validate_contacts

    given = _contacts_file(args)
    resolve_mu(args, check=check)
    kn, kt = stiffness(args.kn, "--kn"), stiffness(args.kt, "--kt")
    kn = given.get("kn") if kn is None else kn
    kt = given.get("kt") if kt is None else kt
    if getattr(args, "contacts_required", False) and (kn is None or kt is None):
        raise CliError("give --kn and --kt (or --contacts-from FILE)")
    args.kn = REFERENCE_KN if kn is None else kn
    args.kt = REFERENCE_KT if kt is None else kt
    if shared:
        for flag, k in (("--kn", args.kn), ("--kt", args.kt)):
            if not isinstance(k, float):
                raise CliError(f"{flag} takes one value here (one pair for all three contacts), e.g. "
                               f"{flag} 2e4; got {k_text(k)}")
    contacts = Contacts(args.kn, args.kt)
    return validate_contacts(contacts) if check else contacts


def _contacts_file(args) -> dict:
    """The --contacts-from file's values, read once per command."""
    if getattr(args, "contacts_from", None) is None:
        return {}
    if getattr(args, "_contacts_given", None) is None:
        args._contacts_given = read_contacts_file(args.contacts_from)
    return args._contacts_given


def resolve_mu(args, check: bool = True):
    """args.mu: --mu, else the --contacts-from file's mu, else the command's default; CliError when
    none is given and the command has no default. Validated (the error names --mu) unless
    check=False."""
    from ..params import validate_mu

    if hasattr(args, "mu_default") and args.mu is None:
        args.mu = _contacts_file(args).get("mu", args.mu_default)
        if args.mu is None:
            raise CliError("--mu is required (the friction coefficient, in (0, 5], e.g. --mu 0.5), "
                           "or a --contacts-from FILE that gives mu")
    if check and hasattr(args, "mu_default"):  # a command of one design (sweep's --mu is a list)
        validate_mu(args.mu)
    return getattr(args, "mu", None)


def k_text(k) -> str:
    """A stiffness for a text line: '20000' or '(20000, 20000, 18000)'."""
    import numpy as np

    a = np.asarray(k, float)
    return f"{float(a):g}" if a.ndim == 0 else "(" + ", ".join(f"{v:g}" for v in a) + ")"


def load_from_args(args, check: bool = True):
    """The LoadCase of --fd, --q, --r-sin-beta; validated unless check=False (checked later)."""
    from ..params import LoadCase, validate_load

    load = LoadCase(args.fd, args.q, args.r_sin_beta)
    return validate_load(load) if check else load


def float_list(text: str, flag: str, example: str = "0.7,0.5,0.3") -> tuple:
    """'a,b,c' -> floats (validated later by the library); example: a valid value of this flag."""
    try:
        values = tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise CliError(f"{flag} must be comma-separated numbers, e.g. {flag} {example}; got {text!r}") from None
    if not values:
        raise CliError(f"{flag} must list at least one number, e.g. {flag} {example}; got {text!r}")
    return values


# ---------------------------------------------------------------- output paths (checked before work)
def _not_a_directory(path: Path) -> Path | None:
    """The first ancestor of path (path included) that exists and is not a directory, if any."""
    for q in reversed((path, *path.parents)):
        if q.exists() and not q.is_dir():
            return q
        if not q.exists():
            return None
    return None


def _make_dir(flag: str, given, p: Path) -> None:
    """Create directory p (and its parents): the only sure check that it can be written."""
    blocker = _not_a_directory(p.absolute())
    if blocker is not None:
        raise CliError(f"{flag} {str(given)!r} cannot be created: {str(blocker)!r} is a file, not a directory")
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CliError(f"{flag} {str(given)!r} cannot be created: {exc.strerror or exc}") from None
    if not os.access(p, os.W_OK | os.X_OK):
        raise CliError(f"{flag} {str(given)!r} is not writable")


def check_output_dir(flag: str, path) -> Path:
    """A writable directory: created now (with its parents), before any work."""
    p = Path(path).expanduser()
    if p.exists() and not p.is_dir():
        raise CliError(f"{flag} {str(path)!r} exists and is not a directory")
    _make_dir(flag, path, p)
    return p


def check_output_file(flag: str, path, suffixes=None) -> Path:
    """A file path in an existing writable directory (a typo in a file's folder is an error, not a
    new folder; nothing is created)."""
    p = Path(path).expanduser()
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise CliError(f"{flag} must end in {', '.join(suffixes[:-1])} or {suffixes[-1]}; got {str(path)!r}")
    if p.is_dir():
        raise CliError(f"{flag} {str(path)!r} is a directory, not a file")
    parent = p.parent if str(p.parent) else Path(".")
    blocker = _not_a_directory(parent.absolute())
    if blocker is not None:
        raise CliError(f"{flag} {str(path)!r} cannot be written: {str(blocker)!r} is a file, not a directory")
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


@contextlib.contextmanager
def model_warnings():
    """Collect the library's warnings (small rotation, ...) for the output instead of stderr:
    yields a list that holds their messages once the block ends."""
    import warnings

    messages: list[str] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield messages
    messages.extend(dict.fromkeys(str(w.message) for w in caught))


def status_name(result) -> str:
    """The RESULTS name of a result (its `status` field): see jaxdamp.status.status_of."""
    from ..status import status_of

    return status_of(result).name


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
    echo = {"theta_l_deg": number(shape.theta_l), "theta_r_deg": number(shape.theta_r),
            "br_over_hr": number(shape.br_over_hr), "bl2_over_hl": number(shape.bl2_over_hl)}
    if getattr(shape, "x_d", None) is not None:  # given: the centre of mass, in units of H
        echo["x_d_over_h"] = number(shape.x_d)
    return echo


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


def status_reason(status: str, contacts=None, load=None) -> str | None:
    """Why a status is not ok, in one line (None for ok). For ill_conditioned with the command's
    contacts and load: the validated-range limits they leave, each with its value and the range
    (jaxdamp.params.validated_range_violations), or, where they are inside the range, that the
    solves lost their digits; for any other status (or without contacts), its RESULTS message."""
    if status == "ok":
        return None
    from ..status import RESULTS

    code = RESULTS.__members__.get(status)
    if code == RESULTS.ill_conditioned and contacts is not None and load is not None:
        from ..params import validated_range_violations

        limits = validated_range_violations(contacts, load)
        if limits:
            return "; ".join(limits) + " (docs/model.md): the linear solves lose their digits there"
        return ("the linear solves lost their digits (an equilibrium residual above tolerance) with "
                "the contact stiffness inside the validated range: the numbers are not trustworthy")
    return RESULTS.message(code) if code is not None else f"status {status}"


def document(status: str, payload: dict, *, reason: str | None = None, **inputs) -> dict:
    """The JSON document of a command: status, versions and the status's cause first, the inputs
    echoed under "inputs" (every command's document has it: given here as keywords, or as
    payload["inputs"]), then the payload. reason: why the status is not ok (`status_reason`; by
    default the status's own message); null for ok. A non-ok status's reason is also the last
    entry of "warnings" (the payload's list, or a new one)."""
    reason = None if status == "ok" else (reason or status_reason(status))
    doc = {"status": status, "schema_version": SCHEMA_VERSION, "jaxdamp_version": version(),
           "status_reason": reason}
    if inputs:
        doc["inputs"] = inputs
    doc.update(payload)
    if reason is not None:
        warnings = doc.get("warnings")
        if warnings is None:
            doc["warnings"] = [reason]
        elif isinstance(warnings, list) and reason not in warnings:
            doc["warnings"] = [*warnings, reason]
    return clean(doc)


def dumps(doc: dict, indent=2) -> str:
    return json.dumps(clean(doc), indent=indent, allow_nan=False, ensure_ascii=False)


def emit(args, doc: dict, text: str) -> None:
    """Print the document (--json) or the text, whose first line then shows the status and, where
    it is not ok, its cause."""
    if getattr(args, "json", False):
        print(dumps(doc))
        return
    first, _, rest = text.partition("\n")
    why = f" {doc['status_reason']}" if doc.get("status_reason") else ""
    print(f"{first}   [status: {doc['status']}]{why}" + (f"\n{rest}" if rest else ""))


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


__all__ = ["SCHEMA_VERSION", "FLAG_OF", "flag_message", "CliError", "UsageError", "Parser",
           "add_shape_args", "shape_name", "parse_br", "centred_br", "shape_from_args",
           "add_contact_args", "add_load_args", "add_design_args", "add_json_arg",
           "add_progress_arg", "stiffness", "read_contacts_file", "contacts_from_args",
           "resolve_mu", "k_text", "load_from_args", "float_list", "check_output_dir",
           "check_output_file", "version", "model_warnings", "status_name", "number", "named",
           "shape_echo", "contacts_echo", "load_echo", "clean", "status_reason", "document", "dumps", "emit",
           "show_progress", "progress_bar"]
