"""The contact-state chart of a cycle: one row per tract with each pad's state (stick, slip,
back-slide, open), the paper's Table 2 form. One function for every cycle the library computes."""

from __future__ import annotations

import string

import numpy as np

from .amplitude import AmplitudeCycle
from .cycle import BaseCycle
from .ellipse import EllipticCycle
from .geometry import CONTACT_NAMES, pad_names
from .status import RESULTS
from .tract import STATE_NAMES

__all__ = ["transitions_chart"]


def transitions_chart(cycle) -> list[dict]:
    """One row per tract of a cycle, with the state of every pad.

    - a `BaseCycle`: the paper's Table 2 form, rows (half, tract 0-A, A-B, ..., dv_mm, R1, L1, L2);
      a constant-force gross-slip stretch that completes the shorter half is a row with every
      contact in slip ('C-C′' at mid-cycle or 'F-0' at the end, as in the paper), stretch=True;
    - an `AmplitudeCycle`: the same rows for the steady cycle at its amplitude;
    - an `EllipticCycle`: rows of tau_start_deg, tau_end_deg (degrees of the period) and every
      pad's state (`pad_names`), so that the intervals a pad is open read off directly; empty for
      a result without valid numbers.
    """
    if isinstance(cycle, BaseCycle):
        return _base_cycle_chart(cycle)
    if isinstance(cycle, AmplitudeCycle):
        return _amplitude_chart(cycle)
    if isinstance(cycle, EllipticCycle):
        return _elliptic_chart(cycle)
    raise TypeError(f"cycle must be a BaseCycle, AmplitudeCycle or EllipticCycle; got "
                    f"{type(cycle).__name__}")


def _letters():
    """The points between tracts, named as in the paper: 0, A, B, ..."""
    return ["0"] + list(string.ascii_uppercase)


def _tract_row(half: str, names, k: int, dv_mm: float, states) -> dict:
    """One row of an in-phase chart: the tract from point k to k + 1 and each contact's state."""
    return dict(half=half, tract=f"{names[k]}-{names[k + 1]}", dv_mm=dv_mm,
                **{c: STATE_NAMES[int(s)] for c, s in zip(CONTACT_NAMES, states)})


def _base_cycle_chart(bc: BaseCycle) -> list[dict]:
    """The paper's Table 2 form: one row per tract with its contacts in stick / slip / back-slide.

    Rows carry the tract name (0-A, A-B, ...), dv_mm, and a state per contact. A constant-force
    gross-slip stretch that completes the shorter half is a row with every contact in slip
    ('C-C′' at mid-cycle or 'F-0' at the end, as in the paper).
    """
    names = _letters()
    rows, k = [], 0
    longest = max(float(bc.forward.span), float(bc.backward.span))
    for label, half in (("forward", bc.forward), ("backward", bc.backward)):
        active = np.asarray(half.active)
        states = np.asarray(half.state)
        dvs = np.asarray(half.dv)
        for i in np.nonzero(active)[0]:
            rows.append(_tract_row(label, names, k, float(dvs[i]), states[i]))
            k += 1
        stretch = longest - float(half.span)
        if stretch > 1e-12 * max(longest, 1e-300):
            end = names[k]
            tail = "0" if label == "backward" else f"{end}\u2032"  # the paper's C′
            rows.append(dict(half=label, tract=f"{end}-{tail}", dv_mm=stretch, stretch=True,
                             **{c: "slip" for c in CONTACT_NAMES}))
            if label == "forward":
                names[k] = f"{end}\u2032"
    return rows


def _amplitude_chart(ac: AmplitudeCycle) -> list[dict]:
    """One row per tract of the steady cycle: half, dv_mm, the state of R1, L1, L2, and
    stretch=True for a constant-force gross-slip stretch (as the Base-Cycle's chart)."""
    names = _letters()
    rows, k = [], 0
    for label, half in (("forward", ac.forward), ("backward", ac.backward)):
        active = np.asarray(half.active)
        for i in np.nonzero(active)[0]:
            row = _tract_row(label, names, k, float(half.dv[i]), np.asarray(half.state[i]))
            if bool(half.stretch[i]):
                row["stretch"] = True
            rows.append(row)
            k += 1
    return rows


def _elliptic_chart(ec: EllipticCycle) -> list[dict]:
    """The contact-state chart of a steady elliptic cycle: one row per tract of its period,
    tau_start_deg and tau_end_deg (degrees of the period) and the state of every pad
    (`geometry.pad_names`: stick, slip or open), so that the intervals in which a pad is open
    read off directly (as the in-phase charts' tracts). Empty for a result without valid
    numbers."""
    if not bool(RESULTS.valid(ec.status)):
        return []
    period = ec.period
    rows = []
    for k in np.flatnonzero(np.asarray(period.active)):
        t0 = float(period.p0[k])
        rows.append(dict(tau_start_deg=float(np.rad2deg(t0)),
                         tau_end_deg=float(np.rad2deg(t0 + float(period.dp[k]))),
                         **{name: STATE_NAMES[int(s)] for name, s in
                            zip(pad_names(ec.shape), np.asarray(period.state[k]))}))
    return rows
