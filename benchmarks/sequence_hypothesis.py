"""Issue 24, step 1: is the steady cycle piecewise affine in psi_a with few pieces?

For a design and a history, the steady cycle is computed by the per-amplitude method
(`amplitude_kernel`) on a uniform grid of amplitudes. Its signature (per half: the active tracts'
contact states and stretch flags; the pairs run; the status) is recorded, and within runs of equal
signature the second differences of the loop's corner data (tract lengths dv, moments M0 at the
tract starts, rates dM) are measured relative to their scale: an affine dependence on psi_a gives
rounding only.

    python benchmarks/sequence_hypothesis.py   # writes results/sequence_hypothesis.json
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxdamp as jd  # noqa: E402
from jaxdamp import amplitude_kernel, platform_moment  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from bench_common import machine  # noqa: E402

OUT = Path(__file__).parent / "results"


def corners(ac):
    out = []
    for h in (ac.forward, ac.backward):
        m0 = platform_moment(ac.shape, ac.load, h.N0, h.T0)
        dm = platform_moment(ac.shape, ac.load, h.dN, h.dT)
        out += [jnp.where(h.active, h.dv, 0.0), jnp.where(h.active, m0, 0.0), jnp.where(h.active, dm, 0.0)]
    return out


def make(initial):
    @jax.jit
    def f(shape, mu, psi):
        def one(p):
            ac = amplitude_kernel(shape, mu, jd.Contacts(), jd.LoadCase(), p, initial=initial, loop="while")
            sig = jnp.concatenate([jnp.where(ac.forward.active[:, None], ac.forward.state, -1).ravel(),
                                   jnp.where(ac.backward.active[:, None], ac.backward.state, -1).ravel(),
                                   ac.forward.stretch.astype(int), ac.backward.stretch.astype(int),
                                   ac.cycles[None], ac.status[None]])
            return sig, corners(ac), ac.k_re, ac.k_im
        return jax.vmap(one)(psi)
    return f


def analyse(sig, cor, psi):
    n = len(psi)
    # runs of equal signature
    change = np.any(sig[1:] != sig[:-1], axis=1)
    runs, start = [], 0
    for i in range(1, n):
        if change[i - 1]:
            runs.append((start, i))
            start = i
    runs.append((start, n))
    worst = 0.0
    scales = [max(np.max(np.abs(c)), 1e-300) for c in cor]
    for a, b in runs:
        if b - a < 3:
            continue
        for c, s in zip(cor, scales):
            d2 = c[a + 2:b] - 2 * c[a + 1:b - 1] + c[a:b - 2]
            worst = max(worst, float(np.max(np.abs(d2)) / s))
    # signature changes that are "pairs only" (same tracts)
    pairs_only = int(np.sum(np.all(sig[1:, :-2] == sig[:-1, :-2], axis=1) & change))
    return runs, worst, pairs_only


def main():
    res = {"machine": machine(), "grid": "400 amplitudes, uniform in 0.02..1.0 psi_BC", "cases": []}
    cases = [("60sym", 0.5), ("74R", 0.3), ("74L", 0.3), ("90L", 0.3), ("90R", 0.5), ("60sym", 0.3),
             ("74R", 0.7)]
    fs = {i: make(i) for i in ("gross_slip", "assembly")}
    for name, mu in cases:
        shape = jd.family_shape(name)
        bc = jd.base_cycle(shape, mu)
        pbc = float(jd.five_numbers(bc).psi_bc)
        psi = np.linspace(0.02, 1.0, 400) * pbc
        for initial, f in fs.items():
            sig, cor, kre, kim = f(shape, jnp.asarray(mu), jnp.asarray(psi))
            sig = np.asarray(sig)
            cor = [np.asarray(c) for c in cor]
            runs, worst, pairs_only = analyse(sig, cor, psi)
            st = sig[:, -1]
            row = dict(shape=name, mu=mu, initial=initial, psi_bc=pbc, signature_runs=len(runs),
                       run_lengths=[b - a for a, b in runs],
                       run_pairs=[int(sig[a, -2]) for a, b in runs],
                       run_status=[jd.RESULTS.name_of(int(st[a])) for a, b in runs],
                       changes_in_pairs_only=pairs_only,
                       max_rel_second_difference=worst)
            print(row, flush=True)
            res["cases"].append(row)
    OUT.mkdir(exist_ok=True)
    (OUT / "sequence_hypothesis.json").write_text(json.dumps(res, indent=1) + "\n")


if __name__ == "__main__":
    main()
