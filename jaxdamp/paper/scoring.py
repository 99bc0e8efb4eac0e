"""The paper's Table 11 scores (§10.1) and the checks of its qualitative findings.

Scoring rules (for mu = 0.5 and 0.3 only, the operating range at temperature):
- k_Re,init (= k_Re,fs): best if highest;
- psi_BC: best if lowest;
- k_Re,BC: best if highest;
- w_M: best if highest;
- psi_fs and k_Im,BC are not evaluated.
Per indicator and mu the best, second best and worst shapes are marked; then the best and worst
marks are counted per shape. Values equal within a relative tolerance share a mark. A shape that
lifts off (or has no value) at a mu is not ranked there, and is listed as excluded.
"""

from __future__ import annotations

INDICATORS = (  # (key in study.json, label, better)
    ("k_re_fs", "k_Re,init (N mm/mrad)", "max"),
    ("psi_bc_mrad", "ψ_BC (mrad)", "min"),
    ("k_re_bc", "k_Re,BC (N mm/mrad)", "max"),
    ("w_M", "w_M (–)", "max"),
)
SCORED_MU = ("0.5", "0.3")
MARK_SYMBOLS = {"best": "●", "second": "◐", "worst": "○", "": ""}


def _levels(values: dict, better: str, rel_tol: float) -> list[list[str]]:
    """Shapes grouped into levels of equal value (within rel_tol), best level first."""
    order = sorted(values, key=lambda s: values[s], reverse=(better == "max"))
    scale = max((abs(v) for v in values.values()), default=0.0)
    levels: list[list[str]] = []
    for s in order:
        if levels and abs(values[s] - values[levels[-1][0]]) <= rel_tol * scale:
            levels[-1].append(s)
        else:
            levels.append([s])
    return levels


def rank_indicator(values: dict, better: str, rel_tol: float = 1e-6) -> dict:
    """Marks {shape: 'best' | 'second' | 'worst' | ''} for one indicator at one mu.

    With two distinct levels there is a best and a worst but no second best; with one, only best.
    """
    if better not in ("max", "min"):
        raise ValueError(f"better must be 'max' or 'min'; got {better!r}")
    levels = _levels(values, better, rel_tol)
    marks = {s: "" for s in values}
    for k, level in enumerate(levels):
        mark = "best" if k == 0 else "worst" if k == len(levels) - 1 else "second" if k == 1 else ""
        for s in level:
            marks[s] = mark
    return marks


def score_table(results: dict, mus=SCORED_MU, indicators=INDICATORS, rel_tol: float = 1e-6) -> dict:
    """Table 11 scores from study results {shape: {mu_key: entry}}.

    Returns {"mus", "indicators", "marks": {mu: {key: {shape: mark}}}, "values": {mu: {key: {shape: v}}},
    "best_count": {shape: n}, "worst_count": {shape: n}, "excluded": [[shape, mu, reason], ...]}.
    """
    shapes = list(results)
    marks, values, excluded = {}, {}, []
    for mu in mus:
        marks[mu], values[mu] = {}, {}
        for key, _, better in indicators:
            vals = {}
            for s in shapes:
                e = results[s].get(mu)
                if e is None:
                    continue
                if e.get("liftoff") or e.get(key) is None:
                    if key == indicators[0][0]:
                        excluded.append([s, mu, "liftoff" if e.get("liftoff") else "no value"])
                    continue
                vals[s] = float(e[key])
            values[mu][key] = vals
            marks[mu][key] = rank_indicator(vals, better, rel_tol) if vals else {}
    best = {s: sum(m.get(s) == "best" for per in marks.values() for m in per.values()) for s in shapes}
    worst = {s: sum(m.get(s) == "worst" for per in marks.values() for m in per.values()) for s in shapes}
    return {"mus": list(mus), "indicators": [list(i) for i in indicators], "marks": marks,
            "values": values, "best_count": best, "worst_count": worst, "excluded": excluded}


def _valid(entry, keys) -> bool:
    """A case with a cycle (no liftoff) and every key present."""
    return bool(entry) and not entry.get("liftoff") and all(entry.get(k) is not None for k in keys)


def _leaders(counts: dict) -> list[str]:
    top = max(counts.values(), default=0)
    return [s for s, n in counts.items() if n == top and top > 0]


def qualitative_findings(results: dict, scores: dict, share_tol: float = 0.02) -> list[dict]:
    """The paper's qualitative findings, checked against our numbers.

    Each finding: {"claim", "holds": True | False | None (cannot be checked), "evidence"}.
    """
    out = []

    def add(claim, holds, evidence):
        out.append({"claim": claim, "holds": holds, "evidence": evidence})

    best, worst = scores["best_count"], scores["worst_count"]
    counts = ", ".join(f"{s} {best[s]}/{worst[s]}" for s in best)
    for claim, shape, table in (("90L collects the most best scores (Table 11)", "90L", best),
                                ("74L collects the most worst scores (Table 11)", "74L", worst)):
        if shape not in table:
            add(claim, None, f"{shape} not in the study")
            continue
        lead = _leaders(table)
        holds = shape in lead
        tie = f" (tied with {', '.join(s for s in lead if s != shape)})" if holds and len(lead) > 1 else ""
        add(claim, holds, f"best/worst counts: {counts}; leader(s): {', '.join(lead) or 'none'}{tie}")

    # 90R: lowest w_M at every mu where the family is compared.
    mus = sorted({m for per in results.values() for m in per}, key=float, reverse=True)
    if "90R" in results:
        ok, ev = True, []
        for mu in mus:
            w = {s: results[s][mu]["w_M"] for s in results
                 if mu in results[s] and not results[s][mu].get("liftoff") and results[s][mu].get("w_M") is not None}
            if len(w) < 2 or "90R" not in w:
                continue
            low = min(w, key=w.get)
            ok &= low == "90R"
            ev.append(f"μ = {mu}: lowest w_M is {low} ({w[low]:.3f})")
        add("90R has the lowest w_M of the family", ok if ev else None, "; ".join(ev) or "not enough shapes")
    else:
        add("90R has the lowest w_M of the family", None, "90R not in the study")

    # 60sym: R1 takes 50 % of the full-slip work; L1 ~2/3 and L2 ~1/3 of the rest, at every mu.
    if "60sym" in results:
        ok, ev = True, []
        for mu in mus:
            e = results["60sym"].get(mu)
            if not _valid(e, ("w_M", "w_R1", "w_L1", "w_L2")):
                continue
            r1 = e["w_R1"] / e["w_M"]
            rest = e["w_L1"] + e["w_L2"]
            l1 = e["w_L1"] / rest if rest > 0 else float("nan")
            ok &= abs(r1 - 0.5) <= share_tol
            ev.append(f"μ = {mu}: R1 {100 * r1:.1f} %, L1 {100 * l1:.1f} % / L2 {100 * (1 - l1):.1f} % of the rest")
        add("60sym: R1 dissipates 50 % of the full-slip work at every μ (L1 ≈ 2/3, L2 ≈ 1/3 of the rest)",
            ok if ev else None, "; ".join(ev) or "no valid 60sym cycle")

    # Which contacts dissipate: 90L never slides on R1, 90R slides only on R1.
    for shape, claim, silent in (("90L", "90L: R1 never slips and dissipates nothing", ("w_R1",)),
                                 ("90R", "90R: in full slip only R1 slides (dissipates)", ("w_L1", "w_L2"))):
        if shape not in results:
            add(claim, None, f"{shape} not in the study")
            continue
        ok, ev = True, []
        for mu in mus:
            e = results[shape].get(mu)
            if not _valid(e, ("w_M",) + silent):
                continue
            share = sum(abs(e[k]) for k in silent) / max(abs(e["w_M"]), 1e-300)
            ok &= share < 1e-6
            ev.append(f"μ = {mu}: {' + '.join(silent)} = {100 * share:.2g} % of w_M")
        add(claim, ok if ev else None, "; ".join(ev) or f"no valid {shape} cycle")

    # Energy identity w_M = w_R1 + w_L1 + w_L2 for every case.
    worst_err, n = 0.0, 0
    for per in results.values():
        for e in per.values():
            if not _valid(e, ("w_M", "w_R1", "w_L1", "w_L2")):
                continue
            err = abs(e["w_R1"] + e["w_L1"] + e["w_L2"] - e["w_M"]) / max(abs(e["w_M"]), 1e-300)
            worst_err, n = max(worst_err, err), n + 1
    add("w_M = w_R1 + w_L1 + w_L2 for every shape", worst_err < 1e-6 if n else None,
        f"largest relative mismatch {worst_err:.1e} over {n} cycles")
    return out


__all__ = ["INDICATORS", "SCORED_MU", "MARK_SYMBOLS", "rank_indicator", "score_table",
           "qualitative_findings"]
