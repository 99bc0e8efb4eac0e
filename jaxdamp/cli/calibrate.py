"""`jaxdamp calibrate`: fit kn, kt to the paper's Tables B3.1/B4.1 by least squares."""

from __future__ import annotations

import numpy as np

from . import common as C


def register(sub) -> None:
    p = sub.add_parser("calibrate", help="fit kn, kt to the paper's Tables B3.1/B4.1 (least squares)")
    p.add_argument("--start-kn", type=float, default=None,
                   help="start kn, N/mm (default 1e4: a generic guess, not the answer)")
    p.add_argument("--start-kt", type=float, default=None,
                   help="start kt, N/mm (default 5e3: a generic guess, not the answer)")
    p.add_argument("--split", action="store_true", help="separate (kn, kt) for R1 and the L pads")
    p.add_argument("--method", choices=("lbfgs", "adam"), default="lbfgs", help="optimiser (default lbfgs)")
    p.add_argument("--max-iter", type=int, default=None, help="iteration limit, >= 1")
    p.add_argument("--markdown", default=None, help="also write the paper comparison table to this file")
    C.add_json_arg(p)
    C.add_progress_arg(p)
    p.set_defaults(func=run)


def _k(v):
    return C.number(v) if np.ndim(v) == 0 else C.named(v)


def _fmt_k(v) -> str:
    a = np.asarray(v, float)
    return f"{float(a):.1f}" if a.ndim == 0 else "(" + ", ".join(f"{float(x):.1f}" for x in a) + ")"


def result_payload(res) -> dict:
    from ..paper.calibration import history_rows

    return {"kn": _k(res.kn), "kt": _k(res.kt), "residuals_pct": res.residuals,
            "residuals_90R_pct": res.reported, "iterations": res.iterations,
            "max_abs_residual_pct": res.max_abs_residual_pct,
            "loss": res.loss_history[-1], "grad_norm": res.grad_norm, "method": res.method,
            "split": res.split, "history": history_rows(res)}


def run(args) -> int:
    from ..paper.calibration import (DEFAULT_START_KN, DEFAULT_START_KT, calibrate,
                                     comparison_document, history_rows, validate_start)

    # The default start is a generic guess (calibration.DEFAULT_START_*), not the answer.
    start = (DEFAULT_START_KN if args.start_kn is None else args.start_kn,
             DEFAULT_START_KT if args.start_kt is None else args.start_kt)
    validate_start(start)  # the library's check, before the output path and any work
    if args.max_iter is not None and args.max_iter < 1:
        raise ValueError(f"max_iter must be an integer >= 1; got {args.max_iter!r}")
    markdown = None if args.markdown is None else C.check_output_file("--markdown", args.markdown)
    bar = C.progress_bar(args, total=args.max_iter, desc="calibrate", unit="iter")

    def tick(iteration, loss):
        bar.update(1)
        bar.set_postfix(loss=f"{loss:.3e}")

    try:
        res = calibrate(None, start, split=args.split, method=args.method, max_iter=args.max_iter,
                        callback=tick)
    finally:
        bar.close()
    status = res.status.name
    start_kn, start_kt = start
    doc = C.document(status, result_payload(res),
                     start={"kn_n_per_mm": start_kn, "kt_n_per_mm": start_kt},
                     targets=["B3.1 (60sym)", "B4.1 (74R)"], split=bool(args.split), method=args.method,
                     max_iter=args.max_iter)
    lines = [f"Calibration ({res.method}, {'R1 / L pads' if res.split else 'shared pair'}): "
             f"kn = {_fmt_k(res.kn)} N/mm, kt = {_fmt_k(res.kt)} N/mm after {res.iterations} iterations",
             f"  max |residual| over Tables B3.1/B4.1: {res.max_abs_residual_pct:.2f} %",
             "  convergence (iterate 0 = start; loss = 0.5 mean of squared relative residuals):"]
    for row in history_rows(res):
        ks = "  ".join(f"{k} = {v:9.1f}" for k, v in row.items() if k not in ("iterate", "loss"))
        lines.append(f"    {row['iterate']:3d}  loss = {row['loss']:.3e}  {ks}")
    lines.append("  residuals (%):")
    for key, v in res.residuals.items():
        lines.append(f"    {key:24} {v:+7.2f} %")
    lines.append("  Table B5.1 (90R, reported, not fitted; k_Im not comparable):")
    for key, v in res.reported.items():
        lines.append(f"    {key:24} {v:+7.2f} %")
    if markdown is not None:
        C.write_text(markdown, comparison_document(res))
        lines.append(f"wrote {markdown}")
    C.emit(args, doc, "\n".join(lines))
    return 0


__all__ = ["register", "result_payload", "run"]
