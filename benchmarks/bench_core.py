"""Core solver benchmark: warm latency of one Base-Cycle + five numbers, and the measured design
choices behind the solver (the reduced tract solve vs building and solving each candidate state
set's 3x3 stiffness, by Cramer's rule or jnp.linalg.solve; plain vmap vs the two-stage batch). Every number is a median of repeats of warm (already compiled) calls, and choices are
reported as ratios against a baseline measured in the same run.

    python benchmarks/bench_core.py [--quick]

Writes benchmarks/results/core_solver.json (docs/model.md and docs/performance.md quote its ratios in a table;
no figure: none is shown).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import jax
import jax.numpy as jnp

jax.config.update("jax_enable_x64", True)

import jaxdamp as jd  # noqa: E402
from bench_common import random_shapes, interleaved_ms, machine, median_time  # noqa: E402
from jaxdamp.linalg import solve3  # noqa: E402
from jaxdamp import choice, cycle, tract  # noqa: E402

OUT = Path(__file__).parent / "results"


def designs(n, seed=0):
    return random_shapes(n, seed, angles=(35, 90), br=(-0.3, 0.4), mu=(0.1, 0.9))


def five(bc):
    return jnp.stack(jd.five_numbers(bc).numbers())


def linalg_solve3(m, b, rel_tol=1e-12):
    det = jnp.linalg.det(m)
    scale = jnp.prod(jnp.linalg.norm(m, axis=-1), axis=-1)
    ok = jnp.abs(det) > rel_tol * scale
    safe = jnp.where(ok[..., None, None], m, jnp.eye(3))
    x = jnp.linalg.solve(safe, b[..., None])[..., 0]
    return jnp.where(ok[..., None], x, 0.0), ok


def variant_flops(program, *args) -> float:
    """XLA's flop count of a compiled program (its cost analysis)."""
    cost = program.lower(*args).compile().cost_analysis()
    cost = cost[0] if isinstance(cost, (list, tuple)) else cost
    return float(cost.get("flops", 0.0))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    n = 2000 if args.quick else 20000
    contacts = jd.Contacts(jnp.asarray(jd.REFERENCE_KN), jnp.asarray(jd.REFERENCE_KT))
    load = jd.LoadCase(*(jnp.asarray(v, float) for v in jd.LoadCase()))
    res = {"machine": machine()}

    # 1. single design: compile time and warm latency
    shape = jd.DamperShape(*(jnp.asarray(v, float) for v in jd.family_shape("60sym")[:4]))
    single = jax.jit(lambda s, m: five(cycle.base_cycle_kernel(s, m, contacts, load)))
    t = time.perf_counter()
    jax.block_until_ready(single(shape, 0.5))
    res["single_compile_s"] = time.perf_counter() - t
    res["single_warm_latency_ms"] = 1e3 * median_time(single, shape, 0.5, repeats=50)

    # 2. the tract solve inside the solver, same batch, same run, timed round-robin:
    #    reduced (all-stick system reduced once per design, closed form per slipping set) vs
    #    building and solving K_S for each of the 8 candidate sets (Cramer or jnp.linalg.solve).
    shapes, mus = designs(n)

    def batched(max_pairs):
        return jax.jit(jax.vmap(lambda s, m: five(cycle.base_cycle_kernel.__wrapped__(
            s, m, contacts, load, max_tracts=cycle.MAX_TRACTS, max_pairs=max_pairs))))

    def plain(solve):
        return lambda mech, signs, direction: jax.vmap(
            lambda slipping: tract.plain_tract_rates(mech, slipping, signs, direction, solve))(
                tract.CANDIDATE_SETS)

    variants = {"reduced": choice.candidate_rates, "plain_cramer": plain(solve3),
                "plain_linalg": plain(linalg_solve3)}
    programs = {}
    for name, candidate_rates in variants.items():
        # The solver calls the name that jaxdamp.choice imported (`choose_closed`), so that is the
        # one swapped, while this program is traced; nothing in the chain is jitted on its own,
        # so every variant is traced afresh; their flop counts show that the programs differ.
        original = choice.candidate_rates
        choice.candidate_rates = candidate_rates
        try:
            programs[name] = batched(1)
            jax.block_until_ready(programs[name](shapes, mus))
            res.setdefault("variant_flops_per_design", {})[name] = variant_flops(
                programs[name], shapes, mus) / n
        finally:
            choice.candidate_rates = original
    flops = res["variant_flops_per_design"]
    assert len(set(flops.values())) == len(flops), f"the variants compiled alike: {flops}"
    ms = interleaved_ms(programs, shapes, mus, repeats=9)
    res["tract_solve"] = {f"{k}_designs_per_s": n / (1e-3 * v) for k, v in ms.items()}
    res["tract_solve"].update({f"{k}_time_over_reduced": v / ms["reduced"] for k, v in ms.items()
                               if k != "reduced"})

    # 3. plain vmap over the full iteration bound vs the two-stage batch
    t_plain = median_time(batched(cycle.MAX_PAIRS), shapes, mus)
    two_stage = lambda s, m: jax.vmap(five)(jd.base_cycles(s, m, contacts, load))  # noqa: E731
    t_two = median_time(two_stage, shapes, mus, repeats=5)
    res["batch"] = {"size": n, "plain_vmap_designs_per_s": n / t_plain, "two_stage_designs_per_s": n / t_two,
                    "plain_time_over_two_stage": t_plain / t_two}

    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "core_solver.json").write_text(json.dumps(res, indent=2))
    print(json.dumps(res, indent=2))


if __name__ == "__main__":
    main()
