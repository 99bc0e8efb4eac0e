"""Speed against accuracy on the new paths (issue 34, item 4): the engine against HBM-AFT.

For a few cases on the paper's Fig. 4 kinematics (h_C = 20 mm, q* = 100 mm, h_L = 10 mm, kn =
17900, kt = 3580 N/mm, F_D = 1000 N, from assembly), in one run on one machine:

* the engine, `jaxdamp.elliptic_kernel` (events in closed form: exact, the reference; checked
  against the fine stepper in results/pads_vs_marcher.json);
* HBM-AFT on the path, `jaxdamp.baselines.hbm_aft_path_kernel`, at Nt = 16 .. 4096 samples per
  period and 3 or 8 periods (the stepper `march_ellipse` from assembly is the same computation:
  tests/test_hbm_path.py holds them equal, and its time at one Nt is measured beside it).

Error = |k_Im - k_Im,engine| / max(|k_Re|, |k_Im|)_engine, at the targets 1e-3, 1e-4 (the
issue's) and 1e-6. A point whose status is not ok (singular: Newton found no equilibrium at a
sample; not_converged: not periodic to 1e-9) is plotted but never used: a method's time to a
target is the log-log interpolated warm time at which its error falls below the target and stays
below for every finer valid setting (`bench_common.time_below`), the better of 3 and 8 periods.
Two jobs: one cycle (single calls), and a batch of B cycles of the same damper at B amplitudes
(0.9-1.1 a), `jax.vmap` on both sides, the whole batch in one call (its error: the largest over
the lanes; a flag on any lane flags the point; the periods: those of one cycle's best time to
1e-4; the sweep stops once two successive settings are below 1e-6, or at Nt 1024 where one cycle
never reached 1e-4 validly). The ratio per job is HBM-AFT's time to the target over the engine's
time for the same job. Where HBM-AFT is
singular, the contact state at the first failing sample is recorded (`first_failure`).

Cases (where pads open, harmonic balance needs many more samples, or breaks):
  60sym, mu 0.5, phi 90 deg, 2 mrad: no pad opens;
  wedge 60/60 (2b/h 0.8 on both flanks), mu 0.5, phi 90, 2 mrad: no pad opens, the cycle settles
    over periods;
  wedge, mu 0.5, phi 90, 10 mrad: R1 and R2 open and close;
  wedge, mu 0.3, phi 90, 10 mrad: R1 and R2 open and close;
  wedge, mu 0.5, phi 180 (the straight out-of-phase path), 10 mrad: R1 and L1 open and close.

Timing: warm (one call first), median of interleaved rounds (every program of a case once per
round, so that the machine's load hits all alike; the engine's one cycle and, in the batch job,
both methods several times in a row per round: the samples right after the other method's call
are also kept, `*_after_other*`), JAX's CPU calls on the calling thread
(jax_cpu_enable_async_dispatch = False, both sides), the measured XLA flags (bench_common); the
load average is recorded per case.

    python benchmarks/path_speed_accuracy.py            # full: results/path_speed_accuracy.json and
                                                        # docs/path_speed_accuracy.png
    python benchmarks/path_speed_accuracy.py --quick    # reduced (< 3 min), writes results/*_quick.*
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_cpu_enable_async_dispatch", False)

import jaxdamp as jd  # noqa: E402
from jaxdamp.baselines import hbm_aft_path_kernel, march_ellipse  # noqa: E402
from jaxdamp.baselines.ellipse_march import path_model, path_step  # noqa: E402
from jaxdamp.baselines.timemarch import assemble, respond  # noqa: E402
from jaxdamp.baselines.timemarch import step as march_step  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from bench_common import (call_time, interleaved_times, loadavg, machine, time_below,  # noqa: E402
                          use_measured_xla_flags)

use_measured_xla_flags()  # before JAX starts its backend: both sides get it

OUT = Path(__file__).parent / "results"
DOCS = Path(__file__).resolve().parent.parent / "docs"  # the full run's figure (docs/motions.md)
TARGETS = (1e-3, 1e-4, 1e-6)
MAIN = 1e-4  # the accuracy: the periods of the batch, the ratios in the chart
H_C_MM, Q_STAR_MM, H_L_MM = 20.0, 100.0, 10.0
CONTACTS = jd.Contacts(17900.0, 3580.0)
CURVED_FLAT = jd.family_shape("60sym")
WEDGE = CURVED_FLAT._replace(br_over_hr=0.0, br2_over_hr=0.8)
CASES = (
    dict(key="60sym_phi90_2mrad", damper="60sym", mu=0.5, phi=90.0, amplitude=2.0),
    dict(key="wedge_phi90_2mrad", damper="wedge", mu=0.5, phi=90.0, amplitude=2.0),
    dict(key="wedge_phi90_10mrad", damper="wedge", mu=0.5, phi=90.0, amplitude=10.0),
    dict(key="wedge_phi90_10mrad_mu0.3", damper="wedge", mu=0.3, phi=90.0, amplitude=10.0),
    dict(key="wedge_phi180_10mrad", damper="wedge", mu=0.5, phi=180.0, amplitude=10.0),
)
FULL = dict(nt=(16, 32, 64, 128, 256, 512, 1024, 2048, 4096), periods=(3, 8), rounds=15,
            engine_calls_per_round=5, batch=16, batch_nt=(16, 64, 256, 1024, 4096),
            batch_rounds=3, batch_calls_per_round=5, stepper_nt=1024)
QUICK = dict(nt=(16, 64, 256, 1024), periods=(3, 8), rounds=3, engine_calls_per_round=3,
             batch=4, batch_nt=(16, 256, 1024), batch_rounds=2, batch_calls_per_round=3,
             stepper_nt=None)

ENGINE_STATICS = ("initial", "max_tracts", "max_periods", "loop")


def engine_numbers(shape, mu, contacts, load, amplitude, motion):
    ec = jd.elliptic_kernel(shape, mu, contacts, load, amplitude, motion, initial="assembly")
    return ec.k_re, ec.k_im, ec.status


def hbm_numbers(shape, mu, contacts, load, amplitude, motion, n_time, n_periods):
    r = hbm_aft_path_kernel(shape, mu, contacts, load, amplitude, motion, n_time, n_periods,
                            initial="assembly")
    return r.k_re, r.k_im, r.status


ENGINE_ONE = jax.jit(engine_numbers)
HBM_ONE = jax.jit(hbm_numbers)
ENGINE_BATCH = jax.jit(jax.vmap(engine_numbers, in_axes=(None, None, None, None, 0, None)))
HBM_BATCH = jax.jit(jax.vmap(hbm_numbers, in_axes=(None, None, None, None, 0, None, None, None)))


def prepared(case):
    """(shape, the kernels' inputs as float arrays, kn and kt per pad, the motion)."""
    shape = WEDGE if case["damper"] == "wedge" else CURVED_FLAT
    n_pads = len(jd.blocks.pad_names(shape))
    sh = jd.DamperShape(*(None if v is None else jnp.asarray(float(v)) for v in shape))
    c = jd.Contacts(*(jnp.full(n_pads, float(k)) for k in CONTACTS))
    load = jd.LoadCase(*(jnp.asarray(float(v)) for v in jd.LoadCase()))
    mu = jnp.asarray(float(case["mu"]))
    motion = jd.interblade_motion(case["phi"], H_C_MM, Q_STAR_MM, H_L_MM)
    if motion.quadrature is None:  # the straight path as an ellipse of zero width
        motion = motion._replace(quadrature=jnp.zeros(3))
    return shape, (sh, mu, c, load), motion


def interleaved(programs: dict, rounds: int, calls: dict | None = None, raw: bool = False):
    """Warm median (s) of each program, timed round-robin: every program once per round (or
    calls[k] times), so that the machine's load hits all alike. Returns {k: (median, min, max)};
    raw: also {k: every time, in call order}."""
    times, _ = interleaved_times(programs, repeats=rounds, calls=calls)
    stats = {k: (float(np.median(v)), float(min(v)), float(max(v))) for k, v in times.items()}
    return (stats, times) if raw else stats


def error(k_im, exact_re, exact_im):
    return np.abs(np.asarray(k_im) - exact_im) / np.maximum(np.abs(exact_re), np.abs(exact_im))


def order(points):
    """Convergence order: -slope of log(error) against log(Nt), least squares over every valid
    point above 1e-13 (None where fewer than three)."""
    pts = [(p["Nt"], p["err_k_im"]) for p in points if p["status"] == "ok" and p["err_k_im"] > 1e-13]
    if len(pts) < 3:
        return None
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(-np.polyfit(x, y, 1)[0])


def to_target(points, target):
    """(time s, how, Nt needed on the grid) from points ordered by Nt: valid points only."""
    ok = [p for p in points if p["status"] == "ok"]
    if not ok:
        return None, "no valid point", None
    t, how = time_below([p["time_s"] for p in ok], [p["err_k_im"] for p in ok], target,
                        "first valid point already below (upper bound)")
    errs = [p["err_k_im"] for p in ok]
    above = [i for i, e in enumerate(errs) if e > target]
    nt = None if t is None else ok[0 if not above else above[-1] + 1]["Nt"]
    return t, how, nt


def best_to_target(curves: dict, target):
    """The best (fastest) of the period counts: (time, how, Nt, periods)."""
    found = [(*to_target(pts, target), int(p)) for p, pts in curves.items()]
    reached = [f for f in found if f[0] is not None]
    if not reached:
        return dict(time_s=None, how="; ".join(f"{p} periods: {how}" for _, how, _, p in found),
                    nt=None, periods=None)
    t, how, nt, p = min(reached, key=lambda f: f[0])
    return dict(time_s=t, how=how, nt=nt, periods=p)


def first_failure(shape, shape_args, motion, amplitude, n_time):
    """Where HBM-AFT finds no equilibrium: the contact state at its first failing sample (in the
    approach from assembly to X(pi), or on the path), the closed and slipping pads and the
    singular values of the consistent tangent there, by stepping the same history and path with
    the same functions (`timemarch.assemble`, `timemarch.step`, `ellipse_march.path_step`) one
    sample at a time. From assembly only."""
    sh, mu, c, load = shape_args
    pm = path_model(sh, mu, c, load, motion)
    s_a = float(amplitude) * float(load.q_star) / 1e3  # mm of the path parameter (travel_mm)

    def state(r, where, i, tau=None):
        return dict(where=where, sample=i, tau_rad=tau, pads=list(jd.blocks.pad_names(shape)),
                    closed=[bool(x) for x in np.asarray(r.closed)],
                    slipping=[bool(x) for x in np.asarray(r.slip)],
                    N_over_F_D=[float(x) for x in np.asarray(r.N)],
                    residual=float(np.max(np.abs(np.asarray(r.R)))),
                    tangent_singular_values=[float(x) for x in
                                             np.linalg.svd(np.asarray(r.J), compute_uv=False)])

    m0, s, _ = jax.jit(lambda: assemble(pm.m, 16))()
    move = jax.jit(lambda s, dv: march_step(m0, s, dv))
    n_move = n_time // 2
    for k in range(1, n_move + 1):  # the approach: a straight move to X(pi) = -a X_r
        p_before = s.p
        s, smp = move(s, -s_a / n_move * k)
        if not bool(smp.newton_ok):  # the return mapping from the step's start, as Newton saw it
            return state(respond(m0, s.q, -s_a / n_move * k, p_before), "approach to X(pi)", k)
    path = jax.jit(lambda carry, tau: path_step(pm, m0, s_a, 0.0, carry, tau))
    h = 2 * np.pi / n_time
    taus = [np.pi + h * k for k in range(1, n_move + 1)] + [h * k for k in range(1, n_time + 1)] * 3
    carry = (s.q, s.p)
    for i, tau in enumerate(taus):
        p_before = carry[1]
        carry, smp = path(carry, tau)
        if not bool(smp[5]):
            u1, u2 = s_a * np.cos(tau), -s_a * np.sin(tau)
            here = m0._replace(nw=u1 * pm.nw_r + u2 * pm.nw_i, tw=u1 * pm.tw_r + u2 * pm.tw_i)
            return state(respond(here, carry[0], 1.0, p_before), "path", i, float(tau % (2 * np.pi)))
    return None


def run_case(case, cfg, log):
    shape, args, motion = prepared(case)
    a = jnp.asarray(case["amplitude"])
    res = dict(case, pads=list(jd.blocks.pad_names(shape)), load_average_start=loadavg())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jd.SmallRotationWarning)
        ec = jd.elliptic_cycle(shape, case["mu"], case["amplitude"],
                               jd.interblade_motion(case["phi"], H_C_MM, Q_STAR_MM, H_L_MM),
                               CONTACTS, initial="assembly")
    k_re, k_im = float(ec.k_re), float(ec.k_im)
    res["engine"] = dict(status=jd.RESULTS.name_of(ec.status), k_re=k_re, k_im=k_im,
                         periods=int(ec.periods),
                         open_fraction=[float(x) for x in np.asarray(ec.open_fraction)],
                         slip_fraction=[float(x) for x in np.asarray(ec.slip_fraction)])

    # One cycle: the engine and every HBM-AFT setting, interleaved.
    programs = {"engine": lambda: ENGINE_ONE(*args, a, motion)}
    for p in cfg["periods"]:
        for nt in cfg["nt"]:
            programs[f"hbm_{nt}_{p}"] = (lambda nt=nt, p=p: HBM_ONE(*args, a, motion, nt, p))
    times = interleaved(programs, cfg["rounds"], {"engine": cfg["engine_calls_per_round"]})
    res["engine"]["time_s"], *res["engine"]["time_min_max_s"] = times["engine"]
    curves = {}
    for p in cfg["periods"]:
        pts = []
        for nt in cfg["nt"]:
            r = hbm_aft_path_kernel(*args, a, motion, nt, p, initial="assembly")
            t, lo, hi = times[f"hbm_{nt}_{p}"]
            pts.append(dict(Nt=nt, periods=p, time_s=t, time_min_max_s=[lo, hi],
                            status=jd.RESULTS.name_of(r.status),
                            err_k_im=float(error(r.k_im, k_re, k_im)),
                            err_k_re=float(abs(float(r.k_re) - k_re) / max(abs(k_re), abs(k_im))),
                            periodicity=float(r.periodicity),
                            newton_failures=int(r.newton_failures),
                            open_fraction=[float(x) for x in np.asarray(r.open_fraction)]))
        curves[str(p)] = pts
    res["hbm_aft"] = curves
    res["one_cycle"] = {}
    for target in TARGETS:
        best = best_to_target(curves, target)
        best["hbm_time_over_engine_time"] = (None if best["time_s"] is None
                                             else best["time_s"] / res["engine"]["time_s"])
        res["one_cycle"][f"{target:g}"] = best
    res["convergence_order"] = {p: order(pts) for p, pts in curves.items()}
    res["valid_from_nt"] = {p: next((pts[i]["Nt"] for i in range(len(pts))
                                     if all(q["status"] == "ok" for q in pts[i:])), None)
                            for p, pts in curves.items()}
    log(f"[{case['key']}] engine {res['engine']['time_s'] * 1e3:.2f} ms ({res['engine']['status']}); "
        + "; ".join(f"P{p}: " + " ".join(f"{q['Nt']}:{q['err_k_im']:.1e}{'' if q['status'] == 'ok' else '*'}"
                                         for q in pts) for p, pts in curves.items()))

    # Where HBM-AFT finds no equilibrium: the contact state at the first failing sample of its
    # finest singular sampling.
    singular = [q for q in curves[str(cfg["periods"][0])] if q["status"] == "singular"]
    if singular:
        res["first_failure"] = dict(Nt=singular[-1]["Nt"], **(first_failure(
            shape, args, motion, case["amplitude"], singular[-1]["Nt"]) or {}))

    # A batch: B amplitudes 0.9-1.1 a, vmap on both sides, the whole batch in one call.
    amps = jnp.asarray(case["amplitude"] * np.linspace(0.9, 1.1, cfg["batch"]))
    t_eng, eng = call_time(ENGINE_BATCH, *args, amps, motion)
    e_re, e_im, e_status = (np.asarray(x) for x in eng)
    e_valid = np.array([jd.RESULTS.name_of(int(s)) in ("ok", "shakedown") for s in e_status])
    periods = res["one_cycle"][f"{MAIN:g}"]["periods"] or max(cfg["periods"])
    batch = dict(size=cfg["batch"], amplitudes_mrad=[float(x) for x in amps], periods=periods,
                 engine_status=[jd.RESULTS.name_of(int(s)) for s in e_status], hbm_aft=[])
    eng_times, eng_after, below = [], [], 0
    calls = cfg["batch_calls_per_round"]
    for nt in cfg["batch_nt"]:
        programs = {"engine": lambda: ENGINE_BATCH(*args, amps, motion),
                    "hbm": lambda nt=nt: HBM_BATCH(*args, amps, motion, nt, periods)}
        # Each method `calls` times in a row per round, both alike (until 2026-12-02 once each:
        # the engine's batch, under a millisecond, was then timed only right after HBM-AFT's
        # batch of 2 ms to 3 s, which leaves its caches cold; that sample is kept as
        # *_after_other_s).
        tt, raw = interleaved(programs, cfg["batch_rounds"], {"engine": calls, "hbm": calls},
                              raw=True)
        eng_times += raw["engine"]
        eng_after += raw["engine"][::calls]
        h_re, h_im, h_status = (np.asarray(x) for x in HBM_BATCH(*args, amps, motion, nt, periods))
        names = [jd.RESULTS.name_of(int(s)) for s in h_status]
        errs = error(h_im, e_re, e_im)[e_valid]
        ok = all(n == "ok" for n in names) and bool(e_valid.all())
        batch["hbm_aft"].append(dict(Nt=nt, time_s=tt["hbm"][0], time_min_max_s=list(tt["hbm"][1:]),
                                     time_after_other_s=float(np.median(raw["hbm"][::calls])),
                                     status="ok" if ok else "flagged",
                                     lanes_not_ok={n: names.count(n) for n in set(names) if n != "ok"},
                                     err_k_im=float(np.max(errs)), err_k_im_median=float(np.median(errs))))
        log(f"[{case['key']}] batch {cfg['batch']} Nt {nt} P{periods}: {tt['hbm'][0]:.3f} s, "
            f"max err {np.max(errs):.1e} ({batch['hbm_aft'][-1]['status']}); engine {tt['engine'][0] * 1e3:.1f} ms")
        below = below + 1 if ok and np.max(errs) <= TARGETS[-1] else 0
        if below >= 2:  # below the tightest target at two successive settings: enough
            break
        if nt >= 1024 and res["one_cycle"][f"{MAIN:g}"]["time_s"] is None:
            break  # one cycle never reached 1e-4 validly: the batch is not run further
    batch["engine_time_s"] = float(np.median(eng_times))
    batch["engine_time_after_other_s"] = float(np.median(eng_after))
    batch["engine_first_call_s"] = t_eng
    batch["targets"] = {}
    for target in TARGETS:
        t, how, nt = to_target(batch["hbm_aft"], target)
        # The same from the samples right after the other method's call (the protocol until
        # 2026-12-02): both methods alike.
        t_after, _, _ = to_target([dict(p, time_s=p["time_after_other_s"])
                                   for p in batch["hbm_aft"]], target)
        batch["targets"][f"{target:g}"] = dict(time_s=t, how=how, nt=nt, hbm_time_over_engine_time=(
            None if t is None else t / batch["engine_time_s"]),
            hbm_over_engine_after_other=(None if t_after is None
                                         else t_after / batch["engine_time_after_other_s"]))
    res["batch"] = batch
    res["load_average_end"] = loadavg()
    return res


def stepper_parity(cfg, log):
    """The stepper (`march_ellipse`: a scan of stored samples, 4 periods) against HBM-AFT's loop at
    the same Nt and periods: the same numbers, and their times."""
    out = {}
    for case in (CASES[0], CASES[2]):
        shape, args, motion = prepared(case)
        nt = cfg["stepper_nt"]
        m = jd.interblade_motion(case["phi"], H_C_MM, Q_STAR_MM, H_L_MM)
        step = lambda: march_ellipse(shape, case["mu"], case["amplitude"], m, CONTACTS,  # noqa: E731
                                     n_steps=nt, periods=4).k_im
        hbm = lambda: HBM_ONE(*args, jnp.asarray(case["amplitude"]), motion, nt, 4)[1]  # noqa: E731
        tt = interleaved({"stepper": step, "hbm": hbm}, cfg["rounds"])
        out[case["key"]] = dict(Nt=nt, periods=4, stepper_s=tt["stepper"][0], hbm_s=tt["hbm"][0],
                                stepper_over_hbm=tt["stepper"][0] / tt["hbm"][0],
                                k_im_difference=abs(float(step()) - float(hbm())))
        log(f"[stepper {case['key']}] march_ellipse {tt['stepper'][0] * 1e3:.1f} ms, "
            f"hbm_aft_path {tt['hbm'][0] * 1e3:.1f} ms")
    return out


def plot(res, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    cases = res["cases"]
    fig, axes = plt.subplots(2, len(cases), figsize=(4.3 * len(cases), 8.0), squeeze=False)
    floor = 1e-12
    for col, c in enumerate(cases):
        ax = axes[0, col]
        for p, fmt in zip(c["hbm_aft"], ("o-", "s--")):
            pts = c["hbm_aft"][p]
            t = [q["time_s"] for q in pts]
            e = [max(q["err_k_im"], floor) for q in pts]
            ax.loglog(t, e, fmt, ms=4, label=f"HBM-AFT, {p} periods (Nt)")
            for q, ti, ei in zip(pts, t, e):
                if q["status"] != "ok":
                    ax.plot(ti, ei, "x", color="k", ms=8)
                if p == next(iter(c["hbm_aft"])):
                    ax.annotate(str(q["Nt"]), (ti, ei), fontsize=6, xytext=(3, 3),
                                textcoords="offset points")
        ax.axvline(c["engine"]["time_s"], color="C3", ls="--", label="engine (exact)")
        one = c["one_cycle"][f"{MAIN:g}"]
        ratio = "not reached" if one["time_s"] is None else f"{one['hbm_time_over_engine_time']:.2g}x engine"
        opened = ", ".join(f"{n} {f:.0%}" for n, f in zip(c["pads"], c["engine"]["open_fraction"])
                           if f > 0) or "no pad opens"
        ax.set_title(f"{c['damper']}, mu {c['mu']:g}, phi {c['phi']:g} deg, {c['amplitude']:g} mrad\n"
                     f"({opened}); one cycle: HBM at 1e-4 {ratio}", fontsize=8)
        ax.set_xlabel("warm wall time per cycle, s")
        b = c["batch"]
        ax = axes[1, col]
        t = [q["time_s"] for q in b["hbm_aft"]]
        e = [max(q["err_k_im"], floor) for q in b["hbm_aft"]]
        ax.loglog(t, e, "o-", ms=4, label=f"HBM-AFT, {b['periods']} periods, max over lanes")
        for q, ti, ei in zip(b["hbm_aft"], t, e):
            if q["status"] != "ok":
                ax.plot(ti, ei, "x", color="k", ms=8)
            ax.annotate(str(q["Nt"]), (ti, ei), fontsize=6, xytext=(3, 3), textcoords="offset points")
        ax.axvline(b["engine_time_s"], color="C3", ls="--", label="engine (exact)")
        bt = b["targets"][f"{MAIN:g}"]
        ratio = "not reached" if bt["time_s"] is None else f"{bt['hbm_time_over_engine_time']:.2g}x engine"
        ax.set_title(f"batch of {b['size']} amplitudes (0.9-1.1 a), vmap both sides\n"
                     f"HBM at 1e-4: {ratio}", fontsize=8)
        ax.set_xlabel("warm wall time per batch, s")
        for ax in axes[:, col]:
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            for target in TARGETS:
                ax.axhline(target, color="grey", lw=0.8, ls=":")
            ax.grid(True, which="both", alpha=0.2)
    for ax in axes[:, 0]:
        ax.set_ylabel("error of k_Im / max(|k_Re|, |k_Im|)")
        ax.legend(fontsize=6, loc="lower left")
    m = res["machine"]
    fig.suptitle(f"HBM-AFT against the engine on the new paths ({m['cpu']}, {m['cores']} cores, "
                 f"jax {m['jax']}, load {m['load_average_1min_at_start']:.1f}-"
                 f"{res['load_average_end'][0]:.1f}); x = flagged (singular / not periodic), never "
                 "used for a time", fontsize=9)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    fig.savefig(path, dpi=100)
    plt.close(fig)


def summary(res):
    rows = {}
    for c in res["cases"]:
        row = {"engine_ms": 1e3 * c["engine"]["time_s"],
               "engine_batch_ms": 1e3 * c["batch"]["engine_time_s"],
               "engine_batch_after_other_ms": 1e3 * c["batch"]["engine_time_after_other_s"],
               "valid_from_nt": c["valid_from_nt"], "convergence_order": c["convergence_order"]}
        for target in TARGETS:
            one, b = c["one_cycle"][f"{target:g}"], c["batch"]["targets"][f"{target:g}"]
            row[f"{target:g}"] = {
                "hbm_ms": None if one["time_s"] is None else 1e3 * one["time_s"], "hbm_how": one["how"],
                "hbm_nt": one["nt"], "hbm_periods": one["periods"],
                "hbm_over_engine": one["hbm_time_over_engine_time"],
                "batch_hbm_ms": None if b["time_s"] is None else 1e3 * b["time_s"], "batch_how": b["how"],
                "batch_hbm_nt": b["nt"], "batch_hbm_over_engine": b["hbm_time_over_engine_time"],
                "batch_hbm_over_engine_after_other": b["hbm_over_engine_after_other"]}
        rows[c["key"]] = row
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="reduced sweep (< 3 min)")
    args = ap.parse_args(argv)
    cfg = QUICK if args.quick else FULL
    t0 = time.perf_counter()
    res = {"machine": machine(), "async_dispatch": False,
           "config": {k: list(v) if isinstance(v, tuple) else v for k, v in cfg.items()},
           "targets": list(TARGETS), "initial": "assembly",
           "kinematics": dict(h_c_mm=H_C_MM, q_star_mm=Q_STAR_MM, h_l_mm=H_L_MM,
                              kn_n_per_mm=17900.0, kt_n_per_mm=3580.0, F_D_N=1000.0),
           "cases": []}
    for case in CASES:
        res["cases"].append(run_case(case, cfg, print))
    if cfg["stepper_nt"]:
        res["stepper_parity"] = stepper_parity(cfg, print)
    res["summary"] = summary(res)
    res["load_average_end"] = loadavg()
    res["wall_time_s"] = time.perf_counter() - t0
    stem = "path_speed_accuracy_quick" if args.quick else "path_speed_accuracy"
    OUT.mkdir(exist_ok=True)
    (OUT / f"{stem}.json").write_text(json.dumps(res, indent=1) + "\n")
    png = (OUT if args.quick else DOCS) / f"{stem}.png"  # a quick run's figure stays beside its JSON
    plot(res, png)
    print(json.dumps(res["summary"], indent=1))
    print(f"wrote {OUT / stem}.json and {png} in {res['wall_time_s']:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
