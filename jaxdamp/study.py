"""The paper's study of the 60sym family as one command: `jaxdamp study`."""

from __future__ import annotations

import json
from pathlib import Path

DEFAULT_SHAPES = ("90L", "74L", "60sym", "74R", "90R")
DEFAULT_MU = (0.7, 0.5, 0.3)


def run_study(out: Path, shapes=DEFAULT_SHAPES, mus=DEFAULT_MU, kn=None, kt=None, progress=True):
    """Compute every shape x mu Base-Cycle and write study.json into out. Returns the summary dict."""
    from tqdm import tqdm

    from .cycle import base_cycle
    from .energy import work_shape_factors
    from .geometry import family_shape
    from .harmonics import five_numbers
    from .params import REFERENCE_KN, REFERENCE_KT, Contacts

    kn = REFERENCE_KN if kn is None else kn
    kt = REFERENCE_KT if kt is None else kt
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    jobs = [(s, m) for s in shapes for m in mus]
    for name, mu in tqdm(jobs, desc="Base-Cycles", disable=not progress):
        bc = base_cycle(family_shape(name), mu, Contacts(kn, kt))
        nums = five_numbers(bc)
        w = work_shape_factors(bc)
        entry = {"psi_fs_mrad": nums.psi_fs, "k_re_fs": nums.k_re_fs, "psi_bc_mrad": nums.psi_bc,
                 "k_re_bc": nums.k_re_bc, "k_im_bc": nums.k_im_bc, **w._asdict()}
        entry = {k: float(v) for k, v in entry.items()}
        entry["liftoff"] = bool(bc.liftoff)
        entry["converged"] = bool(bc.converged)
        results.setdefault(name, {})[f"{mu:g}"] = entry
    summary = {"results": results, "contacts": {"kn": float(kn), "kt": float(kt)}}
    (out / "study.json").write_text(json.dumps(summary, indent=2))
    return summary


def _floats(text):
    return tuple(float(x) for x in text.split(",") if x)


def cmd_study(args):
    out = Path(args.out)
    summary = run_study(out, tuple(args.shapes.split(",")), _floats(args.mu), args.kn, args.kt,
                        progress=not args.no_progress)
    print(f"wrote {out / 'study.json'} ({len(summary['results'])} shapes)")


def register_cli(sub):
    p = sub.add_parser("study", help="the paper's 60sym-family study: figures, tables, report")
    p.add_argument("--out", default="study_out", help="output directory (default study_out)")
    p.add_argument("--shapes", default=",".join(DEFAULT_SHAPES), help="comma-separated shape names")
    p.add_argument("--mu", default="0.7,0.5,0.3", help="comma-separated friction coefficients")
    p.add_argument("--kn", type=float, default=None, help="normal stiffness, N/mm (default: reference)")
    p.add_argument("--kt", type=float, default=None, help="tangential stiffness, N/mm (default: reference)")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(func=cmd_study)
