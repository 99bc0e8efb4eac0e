"""What an elliptic-path cycle costs against an in-phase one (60sym, mu 0.5, from assembly).

One compiled call of each kernel at 2 and 10 mrad (inputs prepared, no checks): 15 rounds, each
timing both kernels best of 20 back to back, so that the machine's load changes hit both; the
median of the rounds' ratios. A batch of 256 designs (mu 0.3-0.7) at each amplitude as one vmapped
program (best of 5): the same per-cycle comparison with the call overhead spread over the batch.
And a whole curve of 256 amplitudes (0.5-20 mrad) as one vmapped program (best of 5), with the
number of periods (ellipse) or pairs of halves (in-phase) each lane ran: under vmap every lane pays
for the slowest one. The elliptic path is the interblade phase angle 90 deg (h_C = 20 mm, h_L = 10 mm),
the out-of-phase (straight) path is timed beside them. And batches of 256 random shapes, curved-
flat and wedge, at three phase angles against the in-phase batch of the same curved-flat designs
and against the same designs' in-phase path cycles on the path engine (`random_shapes`); and the
in-phase engine against the path engine on one in-phase path, on designs that stay seated in phase
(`seated_split`).

Run: python benchmarks/ellipse_cost.py -> benchmarks/results/ellipse_cost.json
On an accelerator: python benchmarks/ellipse_cost.py --out FILE --designs 256,8192,65536 (the
batch of designs at each size; the machine is noted in the JSON).
"""

from __future__ import annotations

import json
from pathlib import Path

import jax
import numpy as np

from bench_common import best_time, machine

RESULTS = Path(__file__).parent / "results"


def best(f, n):
    """Shortest of n warm calls (s), by bench_common's timer."""
    return best_time(f, repeats=n)


def main(out: Path = RESULTS / "ellipse_cost.json", designs=(256,)) -> dict:
    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    import jaxdamp as jd

    statics = ("initial", "max_tracts", "loop")
    straight_kernel = jax.jit(jd.amplitude_kernel, static_argnames=statics + ("max_pairs",))
    elliptic_kernel = jax.jit(jd.elliptic_kernel, static_argnames=statics + ("max_periods",))
    sh, mu, load = jd.family_shape("60sym"), jnp.asarray(0.5), jd.LoadCase(1000.0, 100.0, 0.0)
    c = jd.Contacts(jnp.asarray(17900.0), jnp.asarray(3580.0))
    sh = jd.DamperShape(*(None if v is None else jnp.asarray(float(v)) for v in sh))
    load = jd.LoadCase(*(jnp.asarray(float(v)) for v in load))
    ellipse = jd.interblade_motion(90, 20.0, 100.0, 10.0)
    out_of_phase = jd.interblade_motion(180, 20.0, 100.0, 10.0)
    one, batch = [], []
    for psi in (2.0, 10.0):
        p = jnp.asarray(psi)
        kinds = dict(
            in_phase=lambda: straight_kernel(sh, mu, c, load, p, initial="assembly").k_im,
            out_of_phase=lambda: straight_kernel(sh, mu, c, load, p, initial="assembly",
                                                 motion=out_of_phase).k_im,
            ellipse=lambda: elliptic_kernel(sh, mu, c, load, p, ellipse, initial="assembly").k_im)
        rounds = [{k: best(f, 20) for k, f in kinds.items()} for _ in range(15)]
        med = {k: float(np.median([r[k] for r in rounds])) for k in kinds}
        ratio = [r["ellipse"] / r["in_phase"] for r in rounds]
        one.append(dict(psi_a_mrad=psi, in_phase_ms=1e3 * med["in_phase"],
                        out_of_phase_ms=1e3 * med["out_of_phase"], ellipse_ms=1e3 * med["ellipse"],
                        ratio_ellipse_in_phase=float(np.median(ratio)),
                        ratio_range=[float(min(ratio)), float(max(ratio))]))
        many_in = jax.jit(jax.vmap(lambda m: jd.amplitude_kernel(sh, m, c, load, p,
                                                                 initial="assembly").k_im))
        many_el = jax.jit(jax.vmap(lambda m: jd.elliptic_kernel(sh, m, c, load, p, ellipse,
                                                                initial="assembly").k_im))
        for n in designs:
            mus = jnp.linspace(0.3, 0.7, n)
            t_in, t_el = best(lambda: many_in(mus), 5), best(lambda: many_el(mus), 5)
            batch.append(dict(psi_a_mrad=psi, designs=n, in_phase_ms=1e3 * t_in,
                              ellipse_ms=1e3 * t_el, ratio_ellipse_in_phase=t_el / t_in))
    ps = jnp.linspace(0.5, 20.0, 256)
    curve_in = jax.jit(jax.vmap(lambda p: jd.amplitude_kernel(sh, mu, c, load, p, initial="assembly")))
    curve_el = jax.jit(jax.vmap(lambda p: jd.elliptic_kernel(sh, mu, c, load, p, ellipse,
                                                             initial="assembly")))
    t_in = best(lambda: curve_in(ps).k_im, 5)
    t_el = best(lambda: curve_el(ps).k_im, 5)
    r_in, r_el = curve_in(ps), curve_el(ps)
    curve = dict(amplitudes=256, in_phase_ms=1e3 * t_in, ellipse_ms=1e3 * t_el,
                 ratio_ellipse_in_phase=t_el / t_in,
                 in_phase_pairs=np.bincount(np.asarray(r_in.cycles)).tolist(),
                 ellipse_periods=np.bincount(np.asarray(r_el.periods)).tolist(),
                 ellipse_max_tracts_per_period=int(np.max(np.sum(np.asarray(r_el.period.active), 1))))
    doc = dict(machine=machine(), one_cycle=one, batch_of_designs=batch, curve=curve,
               random_shapes=random_shapes(jd, c, load), seated_split=seated_split(jd, c, load))
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(doc, indent=1))
    return doc


def _random_designs(n: int, seed: int):
    """(theta_l, theta_r, b_R/h_R, 2b_L/h_L, a wedge's 2b/h, mu), n each (numpy, seeded):
    pads_vs_marcher.py's ranges."""
    rng = np.random.default_rng(seed)
    tl, tr, bl2 = rng.uniform([45.0, 45.0, 0.5], [80.0, 80.0, 0.9], (n, 3)).T
    br, br2, mu = rng.uniform([-0.2, 0.5, 0.3], [0.3, 0.9, 0.7], (n, 3)).T
    return tl, tr, br, bl2, br2, mu


def _in_phase_path(jd):
    """The in-phase path as an ellipse of zero width: the path engine's in-phase cycle, the one a
    wedge has (the in-phase engine is the paper's three-pad model, whose pads may not open)."""
    import jax.numpy as jnp

    return jd.interblade_motion(0.0, 20.0, 100.0, 10.0)._replace(quadrature=jnp.zeros(3))


def random_shapes(jd, contacts, load, n: int = 256, seed: int = 3434) -> list:
    """Batches of n random designs (seeded; pads_vs_marcher.py's ranges: base angles 45-80 deg,
    2b_L/h_L 0.5-0.9, b_R/h_R -0.2-0.3 for the curved pad, 2b/h 0.5-0.9 on a wedge's right flank,
    mu 0.3-0.7) from assembly, at phi = 45, 90 and 135 deg and 2 and 10 mrad: the elliptic batch
    (curved-flat, and the wedge of the same base angles, spacings and mu) against the in-phase
    batch of the curved-flat designs, one vmapped program each (best of 5), with the statuses."""
    import jax.numpy as jnp

    tl, tr, br, bl2, br2, mu = _random_designs(n, seed)
    curved = jd.DamperShape(*(jnp.asarray(v) for v in (tl, tr, br, bl2)))
    wedge = curved._replace(br_over_hr=jnp.zeros(n), br2_over_hr=jnp.asarray(br2))
    mu = jnp.asarray(mu)
    rows = []
    in_phase_path = _in_phase_path(jd)
    for psi in (2.0, 10.0):
        p = jnp.asarray(psi)
        in_phase = jax.jit(jax.vmap(lambda s, m: jd.amplitude_kernel(s, m, contacts, load, p,
                                                                     initial="assembly")))
        t_in = best(lambda: in_phase(curved, mu).k_im, 5)
        st_in = np.bincount(np.asarray(in_phase(curved, mu).status), minlength=10).tolist()
        on_path = jax.jit(jax.vmap(lambda s, m: jd.elliptic_kernel(s, m, contacts, load, p,
                                                                   in_phase_path,
                                                                   initial="assembly")))
        t_path, st_path = {}, {}
        for name, shapes in (("curved_flat", curved), ("wedge", wedge)):
            t_path[name] = best(lambda: on_path(shapes, mu).k_im, 5)
            st_path[name] = np.bincount(np.asarray(on_path(shapes, mu).status),
                                        minlength=10).tolist()
        for phi in (45.0, 90.0, 135.0):
            motion = jd.interblade_motion(phi, 20.0, 100.0, 10.0)
            el = jax.jit(jax.vmap(lambda s, m: jd.elliptic_kernel(s, m, contacts, load, p, motion,
                                                                  initial="assembly")))
            row = dict(psi_a_mrad=psi, ibpa_deg=phi, designs=n, in_phase_ms=1e3 * t_in,
                       in_phase_statuses=st_in)
            for name, shapes in (("curved_flat", curved), ("wedge", wedge)):
                t_el = best(lambda: el(shapes, mu).k_im, 5)
                row[f"{name}_ellipse_ms"] = 1e3 * t_el
                row[f"{name}_ratio_in_phase"] = t_el / t_in
                row[f"{name}_in_phase_path_ms"] = 1e3 * t_path[name]
                row[f"{name}_ratio_in_phase_path"] = t_el / t_path[name]
                row[f"{name}_in_phase_path_statuses"] = st_path[name]
                row[f"{name}_statuses"] = np.bincount(np.asarray(el(shapes, mu).status),
                                                      minlength=10).tolist()
            rows.append(row)
            print(row, flush=True)
    return rows


def seated_split(jd, contacts, load, n: int = 256, seed: int = 3434) -> list:
    """Where the random batches' ratio comes from: n designs drawn (with repeats) from
    `random_shapes`' curved-flat designs that stay seated in phase (no liftoff), at 2 and 10 mrad:
    the in-phase engine (`amplitude_kernel`: three pads that may not open, eight sets in closed
    form), the path engine on the same in-phase path (`elliptic_kernel` on an ellipse of zero
    width: pads that may open, the proposal and the choice among every set) and on the phi = 90
    deg ellipse, one vmapped program each (best of 5); the two in-phase cycles' largest k_Im
    difference (the same cycles by two engines)."""
    import jax.numpy as jnp

    tl, tr, br, bl2, _, mu = _random_designs(n, seed)
    in_phase_path = _in_phase_path(jd)
    ellipse = jd.interblade_motion(90.0, 20.0, 100.0, 10.0)
    rows = []
    for psi in (2.0, 10.0):
        p = jnp.asarray(psi)
        in_phase = jax.jit(jax.vmap(lambda s, m: jd.amplitude_kernel(s, m, contacts, load, p,
                                                                     initial="assembly")))
        seated = np.asarray(in_phase(jd.DamperShape(*(jnp.asarray(v) for v in (tl, tr, br, bl2))),
                                     jnp.asarray(mu)).status) == 0
        idx = np.resize(np.flatnonzero(seated), n)
        shapes = jd.DamperShape(*(jnp.asarray(v[idx]) for v in (tl, tr, br, bl2)))
        mus = jnp.asarray(mu[idx])
        programs = {name: jax.jit(jax.vmap(lambda s, m, motion=motion: jd.elliptic_kernel(
            s, m, contacts, load, p, motion, initial="assembly"))) for name, motion in
            (("path_in_phase", in_phase_path), ("path_ellipse_90", ellipse))}
        programs["in_phase_engine"] = in_phase
        ms = {k: 1e3 * best(lambda f=f: f(shapes, mus).k_im, 5) for k, f in programs.items()}
        k_a = np.asarray(programs["in_phase_engine"](shapes, mus).k_im)
        k_b = np.asarray(programs["path_in_phase"](shapes, mus).k_im)
        row = dict(psi_a_mrad=psi, designs=n, distinct_designs=int(seated.sum()),
                   **{f"{k}_ms": v for k, v in ms.items()},
                   ratio_path_in_phase_over_engine=ms["path_in_phase"] / ms["in_phase_engine"],
                   ratio_ellipse_over_path_in_phase=ms["path_ellipse_90"] / ms["path_in_phase"],
                   k_im_largest_relative_difference=float(np.max(np.abs(k_a - k_b) / np.abs(k_a))))
        rows.append(row)
        print(row, flush=True)
    return rows


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=RESULTS / "ellipse_cost.json")
    parser.add_argument("--designs", default="256", help="batch sizes, comma-separated")
    args = parser.parse_args()
    doc = main(args.out, tuple(int(v) for v in args.designs.split(",")))
    print(json.dumps({k: v for k, v in doc.items() if k != "machine"}, indent=1))
