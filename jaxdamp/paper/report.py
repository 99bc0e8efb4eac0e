"""The study report as Markdown and HTML, built from the study summary (plain string building).

A report is a list of blocks (headings, paragraphs, tables, figures, lists); `Doc.markdown()` and
`Doc.html()` render the same blocks. Inline markup in text: **bold** and `code` only.
"""

from __future__ import annotations

import html
import re

from .claim import PLATFORM_CLAIM_SECTION, claim_section
from .scoring import MARK_SYMBOLS

FIVE = (("psi_fs_mrad", "ψ_fs (mrad)", 3), ("k_re_fs", "k_Re,fs (N mm/mrad)", 0),
        ("psi_bc_mrad", "ψ_BC (mrad)", 3), ("k_re_bc", "k_Re,BC (N mm/mrad)", 0),
        ("k_im_bc", "k_Im,BC (N mm/mrad)", 0))
WORK = (("w_R1", "w_R1"), ("w_L1", "w_L1"), ("w_L2", "w_L2"), ("w_M", "w_M"))


class Doc:
    """A report built block by block (headings, paragraphs, tables, figures), written out as
    Markdown or HTML."""

    def __init__(self, title: str):
        self.title = title
        self.blocks: list[tuple] = []

    def h(self, level: int, text: str):
        self.blocks.append(("h", level, text))

    def toc(self):
        """A table of contents (headings of level 1 and 2, linked) at this point of the document."""
        self.blocks.append(("toc",))

    def _anchors(self):
        """GitHub-style anchors of the headings, in order (duplicates get -1, -2, ...)."""
        seen, out = {}, []
        for b in self.blocks:
            if b[0] == "h":
                slug = _slug(b[2])
                n = seen.get(slug, 0)
                seen[slug] = n + 1
                out.append(slug if n == 0 else f"{slug}-{n}")
        return out

    def _toc_entries(self):
        heads = [b for b in self.blocks if b[0] == "h"]
        return [(b[1], b[2], a) for b, a in zip(heads, self._anchors()) if b[1] <= 2]

    def p(self, text: str):
        self.blocks.append(("p", text))

    def items(self, lines):
        self.blocks.append(("ul", list(lines)))

    def table(self, header, rows, caption: str | None = None):
        self.blocks.append(("table", [str(h) for h in header], [[str(c) for c in r] for r in rows], caption))

    def figure(self, path: str, caption: str):
        self.blocks.append(("img", path, caption))

    # ---------------------------------------------------------------- markdown
    def markdown(self) -> str:
        out = [f"# {self.title}", ""]
        for b in self.blocks:
            kind = b[0]
            if kind == "toc":
                out += ["**Contents**", ""]
                out += [f"{'  ' * (lvl - 1)}- [{text}](#{a})" for lvl, text, a in self._toc_entries()] + [""]
            elif kind == "h":
                out += ["#" * (b[1] + 1) + " " + b[2], ""]
            elif kind == "p":
                out += [b[1], ""]
            elif kind == "ul":
                out += [f"- {line}" for line in b[1]] + [""]
            elif kind == "table":
                _, header, rows, caption = b
                if caption:
                    out += [f"*{caption}*", ""]
                out.append("| " + " | ".join(_md_cell(h) for h in header) + " |")
                # Numbers right-aligned, text (transitions, notes) left-aligned.
                out.append("|" + "|".join("---:" if _numeric_column(rows, j) else "---"
                                          for j in range(len(header))) + "|")
                out += ["| " + " | ".join(_md_cell(c) for c in r) + " |" for r in rows]
                out.append("")
            elif kind == "img":
                out += [f"![{b[2]}]({b[1]})", "", f"*{b[2]}*", ""]
        return "\n".join(out)

    # ---------------------------------------------------------------- html
    def html(self) -> str:
        body = [f"<h1>{_inline(self.title)}</h1>"]
        anchors = iter(self._anchors())
        for b in self.blocks:
            kind = b[0]
            if kind == "toc":
                body.append("<nav><b>Contents</b><ul>" + "".join(
                    f'<li class="toc{lvl}"><a href="#{a}">{_inline(text)}</a></li>'
                    for lvl, text, a in self._toc_entries()) + "</ul></nav>")
            elif kind == "h":
                n = min(b[1] + 1, 6)
                body.append(f'<h{n} id="{next(anchors)}">{_inline(b[2])}</h{n}>')
            elif kind == "p":
                body.append(f"<p>{_inline(b[1])}</p>")
            elif kind == "ul":
                body.append("<ul>" + "".join(f"<li>{_inline(x)}</li>" for x in b[1]) + "</ul>")
            elif kind == "table":
                _, header, rows, caption = b
                cap = f"<caption>{_inline(caption)}</caption>" if caption else ""
                head = "".join(f"<th>{_inline(h)}</th>" for h in header)
                cls = ["num" if _numeric_column(rows, j) else "txt" for j in range(len(header))]
                trs = "".join("<tr>" + "".join(f'<td class="{k}">{_inline(c)}</td>' for k, c in zip(cls, r))
                              + "</tr>" for r in rows)
                body.append(f"<table>{cap}<thead><tr>{head}</tr></thead><tbody>{trs}</tbody></table>")
            elif kind == "img":
                src = html.escape(b[1], quote=True)
                body.append(f'<figure><img src="{src}" alt="{html.escape(b[2], quote=True)}">'
                            f"<figcaption>{_inline(b[2])}</figcaption></figure>")
        style = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;line-height:1.45;padding:0 1em}"
                 "table{border-collapse:collapse;margin:1em 0;font-size:0.92em}"
                 "td,th{border:1px solid #bbb;padding:3px 8px;text-align:left}td.num{text-align:right}"
                 "nav li.toc2{margin-left:1.5em;font-size:0.92em}"
                 "th{background:#eee}caption{font-style:italic;margin-bottom:4px;text-align:left}"
                 "img{max-width:100%;border:1px solid #ddd}figcaption{font-style:italic;color:#444}"
                 "code{background:#f4f4f4;padding:0 3px}")
        return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f"<title>{html.escape(self.title)}</title><style>{style}</style></head>\n<body>\n"
                + "\n".join(body) + "\n</body></html>\n")


_NUMBER = re.compile(r"^[+\-−]?[\d,]*\.?\d+( %)?( \(.*\))?$")


def _numeric_column(rows, j) -> bool:
    """A column of numbers (or '—', 'LIFTOFF' placeholders): right-aligned; anything else left."""
    cells = [r[j] for r in rows if j < len(r) and r[j] not in ("", "—", "LIFTOFF", "yes", "no")]
    return bool(cells) and all(_NUMBER.match(c) for c in cells)


def _slug(text: str) -> str:
    """The anchor GitHub gives a heading: lower case, punctuation dropped, spaces to hyphens."""
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


def _md_cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _inline(text: str) -> str:
    t = html.escape(text)
    t = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", t)
    t = re.sub(r"`(.+?)`", r"<code>\1</code>", t)
    return t


# ---------------------------------------------------------------- content
def fmt(v, digits=3):
    """A number for the report: `digits` decimals, "—" for None (no value), yes/no for booleans,
    never "-0"."""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if abs(v) < 0.5 * 10.0 ** -digits:
        v = 0.0  # no "-0"
    return f"{v:,.{digits}f}" if abs(v) >= 1000 and digits == 0 else f"{v:.{digits}f}"


def _pct(v):
    return "—" if v is None else f"{v:+.2f} %"


def _verdict(holds):
    return {True: "**holds**", False: "**does not hold**", None: "not checked"}[holds]


def build_report(summary: dict) -> Doc:
    """The study report from the summary dict that `jaxdamp.plotting.run_study` writes."""
    meta, res = summary["meta"], summary["results"]
    c, load = summary["contacts"], summary["load"]
    doc = Doc("jaxdamp study: the 60sym family of underplatform dampers")
    doc.p(f"Shapes {', '.join(meta['shapes'])}; friction coefficients μ = {', '.join(meta['mus'])}. "
          f"Contacts (shared by R1, L1, L2): kn = {c['kn']:g} N/mm, kt = {c['kt']:g} N/mm. "
          f"Reference case: F_D = {load['F_D']:g} N, q* = {load['q_star']:g} mm, "
          f"r sin β = {load['r_sin_beta']:g} mm. Units: ψ in mrad, k in N mm/mrad, energy in N mm per cycle.")
    doc.p(f"Computed by jaxdamp {meta['version']} (JAX {meta['jax']}, float64) in "
          f"{meta['runtime_s']:.1f} s on this machine, jit compilation included. Method: the direct "
          "piecewise-linear Base-Cycle of M. M. Gola, \"On comparing behavior and performance of "
          "Underplatform Dampers according to shape\" (doi:10.25518/2684-6500.239).")
    doc.toc()
    shapes = ", ".join(meta["shapes"])
    _flags(doc, summary, shapes)
    figures = summary.get("figures", [])
    _key_figure(doc, figures)
    _paper_tables(doc, summary)
    _five_numbers(doc, res, shapes)
    _scores(doc, summary, shapes)
    _findings(doc, summary, shapes)
    _interpolation_gaps(doc, summary, shapes)
    _peak_response(doc, summary, shapes)
    _work(doc, res, summary.get("energies", {}), shapes)
    _statics(doc, summary.get("statics", {}), shapes)
    _transitions(doc, summary.get("transitions", {}), summary.get("paper_transitions", {}), shapes)
    claim_section(doc, summary.get("platform_claim"), figures, fmt)
    _figures(doc, [f for f in figures if f.get("section") not in (KEY_FIGURE_SECTION,
                                                                   PLATFORM_CLAIM_SECTION)], shapes)
    return doc


KEY_FIGURE_SECTION = "Key figure: 60sym at μ = 0.7"


def _key_figure(doc, figures):
    key = [f for f in figures if f.get("section") == KEY_FIGURE_SECTION]
    if key:
        doc.h(1, KEY_FIGURE_SECTION)
        for f in key:
            doc.figure(f["file"], f["caption"])


def _flags(doc, summary, shapes):
    res = summary["results"]
    lift = [f"{s} at μ = {m}" for s, per in res.items() for m, e in per.items() if e["liftoff"]]
    nconv = [f"{s} at μ = {m}" for s, per in res.items() for m, e in per.items()
             if not e["liftoff"] and not e["converged"]]
    doc.h(1, f"Flags (liftoff, convergence): {shapes}")
    lines = []
    if lift:
        lines.append("**LIFTOFF** (a normal force reaches zero; not a valid damper design, no cycle, "
                     "numbers left empty, cycle figures skipped): " + "; ".join(lift) + ".")
    else:
        lines.append("No liftoff.")
    lines.append("Not converged: " + ("; ".join(nconv) if nconv else "none") + ".")
    if any(s == "74L" and m == "0.7" for s, per in res.items() for m, e in per.items() if e["liftoff"]):
        lines.append("74L at μ = 0.7: with the paper's geometry (b_R/h_R = 0.16, centroid as centre of "
                     "mass) the left resultant falls just outside L1–L2 in full slip, so a left pad lifts "
                     "off. The paper draws a cycle here; its real 74L may differ slightly (e.g. in the "
                     "centre of mass). We report the liftoff instead of hiding it.")
    doc.items(lines)


def _paper_tables(doc, summary):
    comp = summary["paper_comparison"]
    doc.h(1, "Our numbers next to the paper's (Appendix B tables): "
          + ", ".join(t["shape"] for t in comp["tables"]))
    crit = comp["criterion"]
    doc.p(f"Deviation = (ours − paper) / paper. Criterion: Tables {' and '.join(crit['tables'])} within "
          f"{crit['tol_pct']:g} % → largest |deviation| {crit['max_abs_dev_pct']:.2f} %: "
          f"{'**met**' if crit['holds'] else '**not met**'}.")
    for t in comp["tables"]:
        rows = []
        for r in t["rows"]:
            for key, label, digits in FIVE:
                rows.append([r["mu"], label, fmt(r["paper"][key], digits), fmt(r["ours"][key], digits),
                             _pct(r["dev_pct"][key])])
        doc.table(["μ", "quantity", "paper", "ours", "deviation"], rows,
                  caption=f"Table {t['table']}: {t['shape']}")
        if t.get("note"):
            doc.p(t["note"])


def _five_numbers(doc, res, shapes):
    doc.h(1, f"The five numbers: {shapes}")
    rows = []
    for s, per in res.items():
        for m, e in per.items():
            if e["liftoff"]:
                rows.append([s, m] + ["LIFTOFF"] * len(FIVE) + ["no"])
            else:
                rows.append([s, m] + [fmt(e[k], d) for k, _, d in FIVE] + [fmt(e["converged"])])
    doc.table(["shape", "μ"] + [label for _, label, _ in FIVE] + ["converged"], rows)


def _scores(doc, summary, names):
    sc = summary["scores"]
    shapes = list(summary["results"])
    doc.h(1, f"Table 11 scores: {names}")
    doc.p("Scored from our numbers with the paper's rules (§10.1), for μ = "
          f"{' and '.join(sc['mus'])}: k_Re,init best if highest, ψ_BC best if lowest, k_Re,BC best if "
          "highest, w_M best if highest; ψ_fs and k_Im,BC not evaluated. "
          f"{MARK_SYMBOLS['best']} best, {MARK_SYMBOLS['second']} second best, {MARK_SYMBOLS['worst']} worst.")
    rows = []
    for mu in sc["mus"]:
        for key, label, _ in sc["indicators"]:
            vals, marks = sc["values"][mu][key], sc["marks"][mu][key]
            cells = []
            for s in shapes:
                if s not in vals:
                    cells.append("LIFTOFF" if summary["results"][s].get(mu, {}).get("liftoff") else "—")
                    continue
                d = 3 if "psi" in key or key == "w_M" else 0
                cells.append(f"{fmt(vals[s], d)} {MARK_SYMBOLS[marks.get(s, '')]}".strip())
            rows.append([mu, label] + cells)
    rows.append(["", f"best {MARK_SYMBOLS['best']} count"] + [str(sc["best_count"][s]) for s in shapes])
    rows.append(["", f"worst {MARK_SYMBOLS['worst']} count"] + [str(sc["worst_count"][s]) for s in shapes])
    doc.table(["μ", "indicator"] + shapes, rows)
    if sc["excluded"]:
        doc.p("Not ranked: " + "; ".join(f"{s} at μ = {m} ({why})" for s, m, why in sc["excluded"]) + ".")


def _gap_cell(g):
    if g.get("gap") is None:
        return "—"
    if g["gap"] == 0.0:
        return "0 (inside)"
    bound = "maximum" if g["side"] == "above" else "minimum"
    return (f"{fmt(g['gap'], 0)} {g['side']} the band's {bound} ({fmt(g['pct'], 1)} % of that {bound}) "
            f"at ψ_a = {fmt(g['psi_a_mrad'], 3)} mrad")


def _interpolation_gaps(doc, summary, shapes):
    bands = summary.get("stiffness_band")
    if not bands:
        return
    doc.h(1, f"The paper's interpolation against the band of exact cycles: {shapes}")
    some = next((e["band"] for per in bands.values() for e in per.values() if "band" in e), None)
    grid = ("" if some is None else
            f"{len(some['psi_a_mrad'])} amplitudes from 0.2 ψ_fs to 1.5 ψ_BC, {some['n_samples']} "
            "sampled admissible initial states each plus the polytope's vertices, not refined, "
            "the band widened to hold the two named states (gross slip, assembly)")
    doc.p("The band at an amplitude ψ_a is the range of k_Re and k_Im (N mm/mrad) of the exact "
          "steady cycles over every statically admissible initial state (" + grid + "). The gap is "
          "how far the paper's linear microslip interpolation lies outside the band (0 inside), "
          "largest over the amplitudes, in N mm/mrad and in % of the band bound it passes (above "
          "the maximum or below the minimum). The band is sampled, so it is an inner estimate: "
          "a gap can only be overstated by the sampling. Figures: the k(ψ_a) figures below.")
    rows = []
    for s, per in bands.items():
        for m, e in per.items():
            if "gap" not in e:
                rows.append([s, m, e["status"].upper(), "—", "—"])
                continue
            rows.append([s, m, e["status"], _gap_cell(e["gap"]["k_re"]), _gap_cell(e["gap"]["k_im"])])
    doc.table(["shape", "μ", "status", "k_Re gap (N mm/mrad)", "k_Im gap (N mm/mrad)"], rows)
    drawn = [e["band"] for per in bands.values() for e in per.values() if "band" in e]
    missed = sum(b["named_outside_samples"] for b in drawn)
    bounds = sum(4 * len(b["psi_a_mrad"]) for b in drawn)  # min and max of k_Re and k_Im per amplitude
    head = (f"Of the {bounds} band bounds (the minimum and maximum of k_Re and of k_Im at each "
            "amplitude), ")
    if missed:
        doc.p(head + f"{missed} lay outside every sampled initial state and were set by a named "
              "state (gross slip or assembly): the band was widened to hold them.")
    else:
        doc.p(head + "none lay outside the sampled initial states: the samples held both named "
              "states (gross slip and assembly) at every amplitude, to the band's rounding.")


def _peak_response(doc, summary, shapes):
    pr = summary.get("peak_response")
    if not pr:
        return
    md, forces = pr["mode"], pr["forces_n"]
    doc.h(1, f"The shapes compared on peak blade response: {shapes}")
    free = [f / (md["eta"] * md["k_b"]) if md["eta"] * md["k_b"] > 0 else None for f in forces]
    doc.p(f"One blade mode (jaxdamp.response.BladeMode defaults, illustrative: f0 = {md['f0_hz']:g} Hz, "
          f"k_b = {md['k_b']:g} N/mm, η = {md['eta']:g}, r = {md['r']:g} mrad/mm) with the damper as "
          "a complex spring; A* is the peak tip amplitude (mm) at modal force F (N), f* its "
          "frequency (Hz), from the exact k(ψ_a) (steady cycles from a gross-slip history, the "
          "default) and, for comparison, the paper's interpolation. Without the damper A* = "
          + ", ".join(f"{fmt(a, 1)} mm at {f:g} N" for a, f in zip(free, forces))
          + f" at f0 = {md['f0_hz']:g} Hz. Smaller A* is better. LIFTOFF: no cycle, no damper curve.")
    rows = []
    for s, per in pr["results"].items():
        for m, e in per.items():
            if e.get("liftoff"):
                rows.append([s, m] + ["LIFTOFF"] * (3 * len(forces)))
                continue
            cells = []
            for i in range(len(forces)):
                a, f = e["exact"]["amplitude_mm"][i], e["exact"]["frequency_hz"][i]
                ai = e["interpolated"]["amplitude_mm"][i]
                cells += [fmt(a, 3) if a is not None else e["exact"]["status"][i], fmt(f, 1),
                          "—" if a is None or ai is None else f"{fmt(ai, 3)} ({_pct(100 * (ai - a) / a)})"]
            rows.append([s, m] + cells)
    head = []
    for f in forces:
        head += [f"A* at {f:g} N (mm)", f"f* at {f:g} N (Hz)", f"A* interpolated at {f:g} N (mm)"]
    doc.table(["shape", "μ"] + head, rows)
    best = []
    for m in summary["meta"]["mus"]:
        for i, f in enumerate(forces):
            vals = {s: per[m]["exact"]["amplitude_mm"][i] for s, per in pr["results"].items()
                    if m in per and not per[m].get("liftoff")
                    and per[m]["exact"]["amplitude_mm"][i] is not None}
            if vals:
                s_best = min(vals, key=vals.get)
                s_worst = max(vals, key=vals.get)
                best.append(f"μ = {m}, F = {f:g} N: lowest A* {s_best} ({fmt(vals[s_best], 3)} mm), "
                            f"highest {s_worst} ({fmt(vals[s_worst], 3)} mm)")
    if best:
        doc.items(best)


def _findings(doc, summary, shapes):
    doc.h(1, f"The paper's qualitative findings, checked with our numbers: {shapes}")
    doc.items([f"{f['claim']}: {_verdict(f['holds'])}. {f['evidence']}." for f in summary["findings"]])
    # A note already printed under its paper table (the 90R caveat) is referred to, not repeated.
    shown = {t["note"]: t["table"] for t in summary["paper_comparison"]["tables"] if t.get("note")}
    notes = [f"{n.split(':')[0]}: see the note under Table {shown[n]}." if n in shown else n
             for n in summary.get("notes", [])]
    if notes:
        doc.items(notes)


def _work(doc, res, energies, shapes):
    doc.h(1, f"Work shape factors and dissipated energy: {shapes}")
    doc.p("Work shape factors (Appendix C): W_i = F_D · Δψ · q*/2 · w_i for a full-slip stretch Δψ "
          "traversed forward and back; w_M = w_R1 + w_L1 + w_L2. Shares in % of w_M. Energies: "
          "dissipated per Base-Cycle (N mm), ∮M dψ for the platform moment.")
    rows = []
    for s, per in res.items():
        for m, e in per.items():
            if e["liftoff"]:
                rows.append([s, m] + ["LIFTOFF"] * 8)
                continue
            wm = e["w_M"] if e["w_M"] else float("nan")
            en = energies.get(s, {}).get(m, {})
            rows.append([s, m] + [f"{fmt(e[k], 4)} ({fmt(100 * e[k] / wm, 1)} %)" for k in ("w_R1", "w_L1", "w_L2")]
                        + [fmt(e["w_M"], 4)] + [fmt(en.get(k), 1) for k in ("R1", "L1", "L2", "M")])
    doc.table(["shape", "μ", "w_R1", "w_L1", "w_L2", "w_M", "W_R1 (N mm)", "W_L1", "W_L2", "∮M dψ"], rows)
    doc.p(W_VERSUS_w + _stuck_with_share(res, energies))


W_VERSUS_w = (
    "Why W and w can disagree (e.g. W_R1 = 0 beside w_R1 = 50 %): W_i is the energy dissipated at "
    "contact i in the converged Base-Cycle itself, integral of T d(slip) over its tracts; a contact "
    "that sticks in every tract and only reaches the onset of slip at the cycle's two ends (R1 of "
    "60sym) slides by zero and dissipates nothing. w_i is the work shape factor of the gross-slip "
    "state at those ends, where all contacts slide: it is the energy per unit of rotation added "
    "beyond ψ_BC. A stretched cycle of amplitude ψ_a dissipates W_i(ψ_a) = W_i(ψ_BC) + F_D · "
    "2(ψ_a − ψ_BC) · q*/2 · w_i, so R1's 50 % share is its share of every extra mrad, not of the "
    "Base-Cycle.")


def _stuck_with_share(res, energies) -> str:
    """The cases in the table where a contact has W_i = 0 yet w_i > 0 (named, for the reader)."""
    cases = [f"{c} of {s} at μ = {m}" for s, per in res.items() for m, e in per.items() if not e["liftoff"]
             for c in ("R1", "L1", "L2")
             if abs(energies.get(s, {}).get(m, {}).get(c, 1.0)) < 0.05 and (e[f"w_{c}"] or 0.0) > 1e-6]
    return f" Here: {'; '.join(cases)}." if cases else ""


def _statics(doc, statics, shapes):
    if not statics:
        return
    doc.h(1, f"Full-slip statics, left resultant distances (Tables 1, 4, 6, 8, 9): {shapes}")
    doc.p("Distance of the left resultant from the nearest left pad, % of L1–L2: from L1 at cycle start, "
          "from L2 at mid-cycle; negative means outside L1–L2 (liftoff). Paper's Table 1 (60sym) in brackets.")
    rows = []
    for s, per in statics.items():
        for m, d in per.items():
            ref = d.get("paper")
            p1 = f" ({ref['dist_L1']:.1f})" if ref else ""
            p2 = f" ({ref['dist_L2']:.1f})" if ref else ""
            rows.append([s, m, f"{d['dist_L1']:.1f}{p1}", f"{d['dist_L2']:.1f}{p2}",
                         "LIFTOFF" if d["liftoff"] else "no"])
    doc.table(["shape", "μ", "from L1, cycle start (%)", "from L2, mid-cycle (%)", "liftoff"], rows)


def _transitions(doc, trans, paper, shapes):
    if not trans:
        return
    doc.h(1, f"Transitions charts (Tables 2, 5, 7, 8, 10): {shapes}")
    doc.p("Contacts in slip per tract ('bs' = back-slide, Appendix A; '—' = all stick); 'full slip' marks the "
          "constant-force stretch that completes the shorter half (C–C′ at mid-cycle, F–0 at the end). "
          "Tract lengths in µm of relative platform displacement. The paper's chart, where its text "
          "gives one, is in the last column.")
    for s, per in trans.items():
        rows = []
        for m, tracts in per.items():
            ours = "LIFTOFF" if tracts is None else "; ".join(
                f"{t['tract']}: {t['slip']} ({t['dv_um']:.1f})" for t in tracts)
            rows.append([m, ours, paper.get(s, {}).get(m, "—")])
        doc.h(2, f"Transitions: {s}")
        doc.table(["μ", "ours: tract: slipping (µm)", "paper"], rows)


def _figures(doc, figures, shapes):
    if not figures:
        return
    doc.h(1, f"Figures: {shapes}")
    order = list(dict.fromkeys(f.get("section") for f in figures))
    for section in order:
        group = [f for f in figures if f.get("section") == section]
        named = [f.get("shape") for f in group if f.get("shape")]
        if section:
            doc.h(2, f"{section}: {', '.join(named) if named else shapes}")
        for f in group:
            doc.figure(f["file"], f["caption"])


__all__ = ["FIVE", "WORK", "Doc", "fmt", "build_report", "KEY_FIGURE_SECTION"]
