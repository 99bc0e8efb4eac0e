"""Stability map (issue 6, part 3): hard cases x methods, with the outcome of each method.

Rows are the hard cases: vertical flanks, mu near the liftoff threshold, mu -> 0, very soft and very
stiff tangential springs, back-slide, cycle closure, coarse steps that miss a transition. Columns are
the direct method and the conventional ones at typical settings:

    direct            jd.base_cycle + five numbers
    time marching     jaxdamp.baselines.timemarch, N = 2000 steps per half-cycle, 10 pairs of halves
    HBM-AFT           jaxdamp.baselines.hbm at psi_BC, Nt = 256 samples per period, 3 periods
    tanh-regularised  jaxdamp.baselines.regularized at psi_BC, eps = 1e-3, Nt = 256, 8 periods (its creep
                      transient needs more than 3)
(the "coarse" rows use N = 20 or 50 and Nt = 16 instead).

Truth. Liftoff is established by the full-slip statics (a normal force <= 0 at a full-slip end) or
by the independent time marcher opening a contact. Otherwise the direct method's numbers are checked
against the independent time marcher at two fine steps with error bounds that do not depend on the
direct method (`check_direct`); where they agree, the direct numbers are the truth for the others.

Outcomes: exact (error <= 1e-6), slow (1e-6 < error <= 1e-2: right, but only as accurate as its
step/sample/eps knob, so accuracy costs time), wrong (error > 1e-2 with no flag, or liftoff not
flagged), flagged (the method reports liftoff, failure or non-convergence), fails (non-finite output
without a flag). Errors are relative; k_Im is measured relative to k_Re where |k_Im| < 1e-3 k_Re.

    python benchmarks/stability_map.py     # writes results/stability_map.json and docs/stability_map.png,
                                           # prints a table
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxdamp as jd  # noqa: E402
from jaxdamp import base_cycle_kernel  # noqa: E402
from jaxdamp.baselines.hbm import hbm_aft_kernel  # noqa: E402
from jaxdamp.baselines.regularized import regularized_aft_kernel  # noqa: E402
from jaxdamp.baselines.timemarch import time_march_kernel  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))  # also when tests/test_stability_map.py loads this file
from bench_common import machine, warm_times  # noqa: E402

OUT = Path(__file__).parent / "results"
DOCS = Path(__file__).resolve().parent.parent / "docs"  # the figure (docs/performance.md, notebook 04)
FIVE = ("psi_fs", "k_re_fs", "psi_bc", "k_re_bc", "k_im_bc")
LOAD = jd.LoadCase(*(jnp.asarray(v, float) for v in (1000.0, 100.0, 0.0)))
METHODS = ("direct", "time marching", "HBM-AFT", "tanh-regularised")
EXACT, SLOW = 1e-6, 1e-2


def liftoff_threshold(name="74L", lo=0.3, hi=0.9) -> float:
    """The mu above which the full-slip statics of a shape has a normal force <= 0 (bisection)."""
    shape = jd.family_shape(name)
    lifts = lambda mu: bool(jd.RESULTS.stopped(jd.full_slip_statics(shape, mu).status))  # noqa: E731
    assert not lifts(lo) and lifts(hi)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if lifts(mid) else (mid, hi)
    return lo


def hard_cases() -> list[dict]:
    mu_star = liftoff_threshold("74L")
    rows = [
        ("90L", 0.5, 0.2, None, "vertical left flank", "vertical flank"),
        ("90R", 0.5, 0.2, None, "vertical right flank: frozen mechanism", "vertical flank"),
        ("74L", mu_star - 1e-3, 0.2, None, "mu = mu* - 0.001, just below liftoff", "liftoff threshold"),
        ("74L", mu_star + 1e-3, 0.2, None, "mu = mu* + 0.001, just above liftoff", "liftoff threshold"),
        ("74L", 0.7, 0.2, None, "the paper's liftoff case", "liftoff threshold"),
        ("60sym", 0.01, 0.2, None, "mu = 0.01", "mu -> 0"),
        ("60sym", 0.001, 0.2, None, "mu = 0.001", "mu -> 0"),
        ("60sym", 0.5, 0.01, None, "kt/kn = 0.01 (very soft tangential)", "kt/kn"),
        ("60sym", 0.5, 10.0, None, "kt/kn = 10 (very stiff tangential)", "kt/kn"),
        ("90L", 0.5, 10.0, None, "kt/kn = 10 on a vertical flank", "kt/kn"),
        ("90R", 0.5, 10.0, None, "kt/kn = 10: cycle closes slowly (~100 pairs)", "kt/kn"),
        ("74R", 0.7, 0.2, None, "back-slide of L1 at the start of the forward half", "back-slide"),
        ("74L", 0.5, 0.2, None, "closure by a full-slip stretch F-0; short back-slide tract", "cycle closure"),
        ("74R", 0.5, 0.2, None, "closure by a full-slip stretch C-C2 at mid-cycle", "cycle closure"),
        ("60sym", 0.5, 0.2, (20, 16), "coarse: N = 20 steps/half, Nt = 16", "coarse steps"),
        ("74L", 0.5, 0.2, (50, 16), "coarse: N = 50 misses the 0.0004 mm tract", "coarse steps"),
    ]
    out = []
    for name, mu, ratio, coarse, what, cat in rows:
        out.append(dict(id=f"{name} mu={mu:.4g} kt/kn={ratio:g}" + (" coarse" if coarse else ""),
                        shape=name, mu=float(mu), kt_over_kn=ratio, coarse=coarse, what=what,
                        category=cat))
    return out


def contacts_of(case):
    kn = jd.REFERENCE_KN
    return jd.Contacts(jnp.asarray(kn), jnp.asarray(case["kt_over_kn"] * kn))


def _stack(cases):
    shapes = [jd.family_shape(c["shape"]) for c in cases]
    shape = jd.DamperShape(*(jnp.asarray([getattr(s, f) for s in shapes], float)
                             for f in ("theta_l", "theta_r", "br_over_hr", "bl2_over_hl")))
    kn = jnp.asarray([jd.REFERENCE_KN] * len(cases))
    kt = jnp.asarray([c["kt_over_kn"] * jd.REFERENCE_KN for c in cases])
    return shape, jnp.asarray([c["mu"] for c in cases]), jd.Contacts(kn, kt)


def direct_batch(cases) -> dict:
    shape, mu, contacts = _stack(cases)
    bc = jax.vmap(lambda s, m, c: base_cycle_kernel(s, m, c, LOAD))(shape, mu, contacts)
    five = np.array(jax.vmap(jd.five_numbers)(bc).numbers()).T
    span = np.maximum(np.asarray(bc.forward.span), np.asarray(bc.backward.span))
    return dict(five=five, span=span, **outcome_masks(bc.status))


def outcome_masks(status) -> dict:
    """liftoff / failed / converged masks of a batch, read from its statuses (the one truth)."""
    status = np.asarray(status)
    return dict(liftoff=status == jd.RESULTS.liftoff, failed=status == jd.RESULTS.singular,
                converged=status == jd.RESULTS.ok)


def statics_liftoff(case) -> bool:
    return bool(jd.RESULTS.stopped(jd.full_slip_statics(jd.family_shape(case["shape"]), case["mu"]).status))


def reference_batch(cases, direct, n1=4000, n2=8000, max_pairs=12) -> dict:
    """The independent time marcher at two steps h_i = S / (N_i + 1/2) (S: a step scale, here the
    direct span; S = 1 mm where the direct method reports liftoff). Returns both runs and h."""
    shape, mu, contacts = _stack(cases)
    span = np.where(direct["liftoff"] | ~(direct["span"] > 0), 1.0, direct["span"])
    run = jax.vmap(lambda s, m, c, h: time_march_kernel(s, m, c, LOAD, h, n_steps=int(n2 * 1.02) + 4,
                                                   max_pairs=max_pairs))
    out = {}
    for key, n in (("coarse", n1), ("fine", n2)):
        h = span / (n + 0.5)
        r = run(shape, mu, contacts, jnp.asarray(h))
        out[key] = dict(five=np.array(r[:5]).T, h=h, **outcome_masks(r.status), q_star=100.0)
    return out


def check_direct(i, direct, ref, statics_lift) -> tuple[bool, str, dict]:
    """Is the direct method right (within the independent reference's error bounds) or flagged?

    Bounds of the time marcher at step h (psi in mrad = dv / (2 q*) * 1e3 for half a span):
    psi_BC: it overestimates by less than one step; psi_fs: within half a step; k_Re,fs: the slope
    of the first step, exact when the first tract is longer than a step; k_Re,BC, k_Im,BC: within
    three times the change between steps 2h and h, plus 1e-5 of the scale. (First-order convergence
    would give a factor 1; a slip-to-stick transition inside a step adds an O(h) error that does not
    halve exactly with h, e.g. 74L's back-slide, whence the margin.)
    """
    flagged = bool(direct["liftoff"][i] | direct["failed"][i] | ~direct["converged"][i])
    fine, coarse = ref["fine"], ref["coarse"]
    truth_lift = statics_lift or bool(fine["liftoff"][i])
    if flagged:
        ok = bool(direct["liftoff"][i]) == truth_lift or not bool(direct["liftoff"][i])
        return ok, "flagged" + (" liftoff" if direct["liftoff"][i] else ""), {}
    if truth_lift:
        return False, "liftoff not flagged", {}
    if not bool(fine["converged"][i]):
        return False, "reference did not close its cycle", {}
    d, t, t1 = direct["five"][i], fine["five"][i], coarse["five"][i]
    psi_step = fine["h"][i] / (2 * fine["q_star"]) * 1e3
    k_scale = np.abs(d[3])
    im_scale = abs(d[4]) if abs(d[4]) > 1e-3 * k_scale else k_scale
    err = {
        "psi_bc": (t[2] - d[2], -1e-9 * d[2], psi_step * (1 + 1e-6)),
        "psi_fs": (t[0] - d[0], -0.5 * psi_step * (1 + 1e-6), 0.5 * psi_step * (1 + 1e-6)),
        "k_re_fs": (t[1] - d[1], -1e-8 * abs(d[1]), 1e-8 * abs(d[1])),
        "k_re_bc": (t[3] - d[3], -_k_bound(t[3], t1[3], k_scale), _k_bound(t[3], t1[3], k_scale)),
        "k_im_bc": (t[4] - d[4], -_k_bound(t[4], t1[4], im_scale), _k_bound(t[4], t1[4], im_scale)),
    }
    bad = [k for k, (e, lo, hi) in err.items() if not (lo <= e <= hi)]
    detail = {k: dict(diff=float(e), lo=float(lo), hi=float(hi)) for k, (e, lo, hi) in err.items()}
    return not bad, "agrees with the independent reference" if not bad else f"outside bounds: {bad}", detail


def _k_bound(fine, coarse, scale):
    return 3.0 * abs(fine - coarse) + 1e-5 * scale


def rel_errors(truth, got, names):
    k_scale = abs(truth["k_re_bc"])
    out = {}
    for n, v in zip(names, got):
        scale = abs(truth[n])
        if n == "k_im_bc" and abs(truth[n]) < 1e-3 * k_scale:
            scale = k_scale
        out[n] = float(abs(float(v) - truth[n]) / scale) if scale > 0 else float(abs(float(v)))
    return out


def classify(truth_lift, flagged, lifted, errs) -> str:
    if truth_lift:
        return "flagged" if (lifted or flagged) else "wrong"
    if flagged:
        return "flagged"
    vals = list(errs.values())
    if not np.all(np.isfinite(vals)):
        return "fails"
    e = max(vals) if vals else 0.0
    return "exact" if e <= EXACT else ("slow" if e <= SLOW else "wrong")


def _timed(fn, *args):
    """(time in s, output) of one warm call, by bench_common's timer."""
    times, out = warm_times(fn, *args, repeats=1)
    return times[0], out


@jax.jit
def _direct_one(shape, mu, contacts):
    return jnp.stack(jd.five_numbers(base_cycle_kernel(shape, mu, contacts, LOAD)).numbers())


def merge_reference(cases, direct):
    """Reference runs: most rows at N = 4000/8000 with 12 pairs; rows whose cycle closes slowly
    (90R with a stiff tangential spring, ~100 pairs) at N = 1000/2000 with 150 pairs."""
    n = len(cases)
    slow = [i for i, c in enumerate(cases) if c["shape"] == "90R" and c["kt_over_kn"] >= 10]
    fast = [i for i in range(n) if i not in slow]
    ref = {lvl: dict(five=np.zeros((n, 5)), h=np.zeros(n), liftoff=np.zeros(n, bool),
                     failed=np.zeros(n, bool), converged=np.zeros(n, bool), q_star=100.0)
           for lvl in ("fine", "coarse")}
    for rows, kw in ((fast, dict(n1=4000, n2=8000, max_pairs=12)),
                     (slow, dict(n1=1000, n2=2000, max_pairs=150))):
        if not rows:
            continue
        sub = {k: v[rows] for k, v in direct.items()}
        r = reference_batch([cases[i] for i in rows], sub, **kw)
        for lvl in ("fine", "coarse"):
            for key in ("five", "h", "liftoff", "failed", "converged"):
                ref[lvl][key][rows] = r[lvl][key]
    return ref


def evaluate(cases=None, progress=print) -> dict:
    cases = hard_cases() if cases is None else cases
    direct = direct_batch(cases)
    ref = merge_reference(cases, direct)
    progress("reference done")
    results = []
    for i, case in enumerate(cases):
        lift_s = statics_liftoff(case)
        ok, why, detail = check_direct(i, direct, ref, lift_s)
        truth_lift = lift_s or bool(ref["fine"]["liftoff"][i])
        truth = dict(zip(FIVE, map(float, direct["five"][i])))
        row = dict(case=case, truth_liftoff=truth_lift, direct_check=dict(ok=ok, why=why, detail=detail),
                   truth=None if truth_lift else truth, cells={})
        shape = jd.DamperShape(*(jnp.asarray(v, float) for v in jd.family_shape(case["shape"])[:4]))
        contacts = contacts_of(case)
        mu = jnp.asarray(case["mu"])
        # direct
        t, _ = _timed(_direct_one, shape, mu, contacts)
        d_flag = bool(direct["liftoff"][i] | direct["failed"][i] | ~direct["converged"][i])
        d_err = {} if truth_lift else {k: 0.0 for k in FIVE}
        outcome = classify(truth_lift, d_flag, bool(direct["liftoff"][i]), d_err) if ok else "wrong"
        row["cells"]["direct"] = dict(outcome=outcome, time_s=t, errors=d_err,
                                      note="closed form; checked against the time marcher")
        # time marching
        n_steps, nt = (case["coarse"] if case["coarse"] else (2000, 256))
        span = 1.0 if truth_lift else float(direct["span"][i])
        h = span / (n_steps + 0.5)
        t, r = _timed(_TM[n_steps], shape, mu, contacts, jnp.asarray(h))
        status = jd.RESULTS.name_of(r.status)
        errs = {} if truth_lift else rel_errors(truth, r[:5], FIVE)
        row["cells"]["time marching"] = dict(outcome=classify(truth_lift, status != "ok",
                                                              status == "liftoff", errs),
                                             time_s=t, errors=errs, setting=f"N={n_steps}",
                                             flags=dict(status=status))
        # HBM-AFT and the regularised law at psi_BC (3 mrad where the truth is liftoff)
        psi = jnp.asarray(3.0 if truth_lift else truth["psi_bc"])
        for label, fn, setting in (("HBM-AFT", _HBM[nt], f"Nt={nt}, 3 periods"),
                                   ("tanh-regularised", _REG[nt], f"eps=1e-3, Nt={nt}, 8 periods")):
            t, r = _timed(fn, shape, mu, contacts, psi)
            status = jd.RESULTS.name_of(r.status)
            errs = {} if truth_lift else rel_errors(truth, (r.k_re, r.k_im), ("k_re_bc", "k_im_bc"))
            row["cells"][label] = dict(outcome=classify(truth_lift, status != "ok", status == "liftoff",
                                                        errs), time_s=t,
                                       errors=errs, setting=setting,
                                       flags=dict(status=status, periodicity=float(r.periodicity)))
        results.append(row)
        progress(f"{case['id']}: " + ", ".join(f"{m} {row['cells'][m]['outcome']}" for m in METHODS))
    return dict(rows=results, methods=METHODS, thresholds=dict(exact=EXACT, slow=SLOW))


class _Compiled(dict):
    """Jitted method runners keyed by their static knob (compiled once per knob value)."""

    def __init__(self, make):
        super().__init__()
        self.make = make

    def __missing__(self, key):
        self[key] = fn = self.make(key)
        return fn


_TM = _Compiled(lambda n: jax.jit(lambda s, m, c, h: time_march_kernel(s, m, c, LOAD, h, n_steps=int(n * 1.02) + 4)))
_HBM = _Compiled(lambda nt: jax.jit(lambda s, m, c, a: hbm_aft_kernel(s, m, c, LOAD, a, n_time=nt)))
_REG = _Compiled(lambda nt: jax.jit(lambda s, m, c, a: regularized_aft_kernel(s, m, c, LOAD, a, 1e-3, n_time=nt,
                                                                         n_periods=8)))


def markdown(res) -> str:
    lines = ["| hard case | " + " | ".join(METHODS) + " |", "|---" * (len(METHODS) + 1) + "|"]
    for row in res["rows"]:
        c = row["case"]
        cells = []
        for m in METHODS:
            cell = row["cells"][m]
            e = max(cell["errors"].values()) if cell["errors"] else None
            cells.append(cell["outcome"] + ("" if e is None or cell["outcome"] in ("flagged",) or m == "direct"
                                            else f" ({e:.0e})"))
        lines.append(f"| {c['shape']}, mu={c['mu']:.4g}, {c['what']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


COLORS = {"exact": "#4caf50", "slow": "#ffd54f", "flagged": "#64b5f6", "wrong": "#e57373", "fails": "#424242"}


def plot(res, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = res["rows"]
    fig, ax = plt.subplots(figsize=(12, 0.42 * len(rows) + 1.6))
    for i, row in enumerate(rows):
        for j, m in enumerate(METHODS):
            cell = row["cells"][m]
            ax.add_patch(plt.Rectangle((j, i), 1, 1, color=COLORS[cell["outcome"]], ec="white"))
            e = max(cell["errors"].values()) if cell["errors"] else None
            txt = cell["outcome"] + ("" if e is None or m == "direct" or cell["outcome"] == "flagged"
                                     else f" {e:.0e}")
            ax.text(j + 0.5, i + 0.5, txt, ha="center", va="center", fontsize=7,
                    color="white" if cell["outcome"] == "fails" else "black")
    ax.set_xlim(0, len(METHODS))
    ax.set_ylim(len(rows), 0)
    ax.set_xticks(np.arange(len(METHODS)) + 0.5)
    ax.set_xticklabels(["direct", "time marching\nN=2000 (coarse rows: 20, 50)",
                        "HBM-AFT\nNt=256 (coarse: 16), 3 periods",
                        "tanh-regularised\neps=1e-3, Nt=256 (coarse: 16), 8 periods"], fontsize=8)
    ax.set_yticks(np.arange(len(rows)) + 0.5)
    ax.set_yticklabels([f"{r['case']['shape']} mu={r['case']['mu']:.4g}: {r['case']['what']}" for r in rows],
                       fontsize=7)
    ax.xaxis.tick_top()
    ax.set_title("Stability map: exact <= 1e-6 < slow <= 1e-2 < wrong (max relative error of the method's "
                 "outputs); flagged = liftoff / failure / not periodic reported", fontsize=8, pad=28)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description="hard cases x methods stability map")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    info = machine()
    t0 = time.perf_counter()
    res = evaluate()
    res["wall_time_s"] = time.perf_counter() - t0
    res["machine"] = dict(info, load_average_at_end=list(os.getloadavg()))
    args.out.mkdir(parents=True, exist_ok=True)

    def clean(x):
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [clean(v) for v in x]
        if isinstance(x, (np.floating, np.integer, np.bool_)):
            return x.item()
        return x

    (args.out / "stability_map.json").write_text(json.dumps(clean(res), indent=2))
    # the figure is the docs' copy; with --out it stays beside the JSON
    plot(res, (DOCS if args.out.resolve() == OUT.resolve() else args.out) / "stability_map.png")
    print(markdown(res))


if __name__ == "__main__":
    main()
