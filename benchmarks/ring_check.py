"""The cyclic reduction against the whole ring with N explicit dampers (issue 35, item 5).

The small disk: `LumpedDisk(n_blades=6)` (the example disk's parameters, six blades). The damper:
60sym, mu = 0.5, default contacts and load (q* = 100 mm), rotation centres h_C = 20 mm below D,
damper size h_L = 10 mm. For every nodal diameter n = 0 ... 3 (engine order e = n), at two tip
forces: one where the damper microslips at the peak (its steady cycle depends on how it was
reached) and one where the cycle at the peak is the same from assembly and from gross slip (the
pads' slip erases the history: `history_free` records the two cycles' difference):

- the reduction: `jaxdamp.row_response` on the disk's first family with the platforms' residual
  flexibility from the second family (`modal_family(..., residual=True)`: the damper in series
  with it, `response.stiffness.through_residual`), history "assembly": its peak amplitude and
  frequency. Cross-check: the one-mode peak equation with k from one independent cycle
  (`path_cycle_kernel`) at the row's damper amplitude. The same reduction without the residual
  (the free-platform modes alone) is the column "free platforms";
- the same first harmonic with both families of the sector (the 2x2 sector problem of the lumped
  disk with the damper as the complex spring 1e-3 rho^2 k(psi) on the root rotation, rho = psi
  per rad of root rotation): what the one-mode reduction with its residual still drops (the
  second family's own tip motion), which this isolates;
- the ring (`jaxdamp.baselines.ring.ring_response`: time integration, no reduction, no harmonic
  balance) started from rest (F_D applied with the platforms at rest, then the forcing: the
  physical history), at frequencies around the two-family peak, a parabola through the largest
  three amplitudes (refined twice) giving the ring's peak. At nodal diameter 0 in microslip one
  more run at the ring's peak frequency has the reduction's history (assembly, a straight
  quasi-static move to X(pi), then the vibration: `ring_response`'s start x0 with the force's
  phase set), so that the history and the higher harmonics can be told apart (off nodal
  diameter 0 the dampers of a travelling wave are at different points of their paths at any
  instant: no common start gives them all that history). Every run has the same length (one
  compiled program); its last per-period change and Aitken's extrapolation of blade 0's first
  harmonic say how steady it is. Step size: 128 steps per period, checked against 64 and 256 once.

Run: python benchmarks/ring_check.py -> benchmarks/results/ring_check.json (summary numbers) and its
figure, docs/ring_check_example.png. Another disk, design or set of cases (issue 61's check of the
row optimum on the 24-blade example disk):

    PYTHONPATH=$PWD python benchmarks/ring_check.py --blades 24 --design "row robust optimum" \
        --cases microslip:3=2,history-free:6=20 --no-step-check --out ring_check_optimum.json \
        --figure docs/ring_check_optimum.png

(--design: "60sym" or a design's name in results/row_optimisation.json; --cases: regime:ND=force
in N, comma-separated.)
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

import jaxdamp as jd  # noqa: E402
from jaxdamp.baselines.lumped_disk import LumpedDisk, modal_family, sector_matrices, sector_modes  # noqa: E402
from jaxdamp.baselines.ring import ring_response  # noqa: E402
from jaxdamp import BladeMode, path_cycle_kernel  # noqa: E402
from jaxdamp.blocks import prepare_scene
from jaxdamp_optimize.design import shape_of_vector  # noqa: E402

from bench_common import call_time, machine  # noqa: E402

RESULTS = Path(__file__).parent / "results"
N_SMALL, Q_STAR_MM, H_C_MM, H_L_MM, MU = 6, 100.0, 20.0, 10.0, 0.5
STEPS, PERIODS = 128, 1500
SHAPE = jd.family_shape("60sym")
# Tip forces per nodal diameter (N). Microslip: the reduction's damper microslips at its peak
# (status ok, not shakedown; the peak 0.43, 0.38, 0.55 and 0.76 of the free one), and its steady
# cycle depends on the history. History-free: the cycles from assembly and from gross slip agree
# at the peak (to 1e-11 or better; measured 2026-11-27); not higher: at nodal diameter 0 and 40 N
# a first try found the ring from rest 14 % below the first harmonic (likely the lower branch of
# the strongly softening peak; not pursued). Off
# nodal diameter 0 the neighbouring platforms move more and more together radially (at N/2 only
# their relative rotation and gap change reach the damper), so that slipping takes a larger tip
# motion.
FORCES = {"microslip": {0: 2.0, 1: 2.0, 2: 5.0, 3: 10.0},
          "history-free": {0: 20.0, 1: 20.0, 2: 20.0, 3: 20.0}}


class Damper:
    """k(psi) of the damper on one scene's path from assembly (one jitted cycle, cached)."""

    def __init__(self):
        shape, mu, contacts, load, _ = prepare_scene(SHAPE, MU, jd.Contacts(), jd.LoadCase(),
                                                     BladeMode())
        self.args = (shape, mu, contacts, load)
        self.cycle = jax.jit(path_cycle_kernel, static_argnames=("initial", "loop"))
        self.calls, self.seconds = 0, 0.0

    def k(self, scene, psi, initial="assembly"):
        seconds, (k_re, k_im, status) = call_time(lambda: self.cycle(
            *self.args, jnp.asarray(float(psi)), scene.motion, initial=initial, loop="while"))
        self.calls += 1
        self.seconds += seconds
        return complex(float(k_re), float(k_im)), jd.RESULTS.name_of(int(status))


def two_family(disk, phi, rho, kd, omega):
    """(Theta rad, X mm) per N of tip force: the sector's first harmonic with the damper's complex
    stiffness kd (N mm/mrad of psi) on the root rotation (rho mrad of psi per rad of Theta:
    1e-3 rho^2 kd N mm/rad)."""
    M, K = sector_matrices(disk, phi)
    D = K * (1.0 + 1j * disk.eta) - omega ** 2 * M
    D[0, 0] += 1e-3 * rho ** 2 * kd
    return np.linalg.solve(D, np.array([0.0, 1.0]))


def two_family_peak(disk, phi, rho, kd, omega_guess):
    """(omega, Theta, X) at the maximum of |Theta| over omega for a fixed kd (golden section)."""
    a, b = 0.9 * omega_guess, 1.1 * omega_guess
    grid = np.linspace(a, b, 401)
    i = int(np.argmax([abs(two_family(disk, phi, rho, kd, w)[0]) for w in grid]))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    g = (np.sqrt(5.0) - 1.0) / 2.0
    for _ in range(60):
        c, d = b - g * (b - a), a + g * (b - a)
        if abs(two_family(disk, phi, rho, kd, c)[0]) > abs(two_family(disk, phi, rho, kd, d)[0]):
            b = d
        else:
            a = c
    w = 0.5 * (a + b)
    theta, x = two_family(disk, phi, rho, kd, w)
    return w, theta, x


def reduction(family, orders, forces):
    """`jaxdamp.row_response` at every engine order and force: {(e, F): peak dict}."""
    seconds, row = call_time(lambda: jd.row_response(SHAPE, MU, jd.Contacts(), jd.LoadCase(),
                                                     modes=family, engine_orders=orders,
                                                     force_n=forces, h_l_mm=H_L_MM))
    out = {}
    for i, e in enumerate(orders):
        for j, f in enumerate(forces):
            out[e, f] = dict(peak_mm=float(row.peaks.peak_amplitude_mm[i, j]),
                             frequency_hz=float(row.peaks.peak_frequency_hz[i, j]),
                             psi_mrad=float(row.peaks.psi_a_mrad[i, j]),
                             status=jd.RESULTS.name_of(int(row.status[i, j])),
                             free_peak_mm=float(row.free_peak_mm[i, j]),
                             f0_hz=float(row.frequency_hz[i]),
                             tip_force_n=float(row.tip_force_n[i, j]))
    return out, seconds


def cross_checks(disk, family, damper, e, red):
    """The one-mode peak equation at the row's damper amplitude psi_d (independent cycle): the tip
    amplitude A = psi_d |1 + c k| / r and A (eta k_b + 1e-3 r^2 Im(k / (1 + c k))) = F; the
    effective loss factor there; whether the cycle there is history-free (from gross slip against
    from assembly); and the two-family peak at the same force."""
    scene = jd.nodal_scene(family, e, Q_STAR_MM, H_L_MM)
    mode, c = scene.mode, scene.residual_mrad_per_nmm
    k, status = damper.k(scene, red["psi_mrad"])
    k_gs, _ = damper.k(scene, red["psi_mrad"], initial="gross_slip")
    k_eff = k / (1.0 + c * k)
    amp = red["psi_mrad"] * abs(1.0 + c * k) / mode.r
    f_tip = red["tip_force_n"]
    residual = amp * abs(mode.eta * mode.k_b + 1e-3 * mode.r ** 2 * k_eff.imag) / f_tip - 1.0
    f_check = mode.f0_hz * np.sqrt(1.0 + 1e-3 * mode.r ** 2 * k_eff.real / mode.k_b)
    eta_eff = (mode.eta * mode.k_b + 1e-3 * mode.r ** 2 * k_eff.imag) / (
        mode.k_b + 1e-3 * mode.r ** 2 * k_eff.real)
    one = dict(peak_equation_residual=float(residual), amplitude_check=float(amp / red["peak_mm"] - 1),
               frequency_check_hz=float(f_check), k_re=k.real, k_im=k.imag, cycle_status=status,
               r_mrad_per_mm=mode.r, k_b=mode.k_b, residual_mrad_per_nmm=c,
               straight=bool(scene.straight), eta_eff=float(eta_eff),
               history_free=float(abs(k_gs - k) / abs(k)))
    # Two families: psi = rho |Theta|, with rho = r X_mode / Theta_mode (mrad per rad).
    t = time.perf_counter()
    phi = 2.0 * np.pi * scene.nodal_diameter / disk.n_blades
    _, modes = sector_modes(disk, phi)
    rho = mode.r * abs(modes[1, 0] / modes[0, 0])
    force = f_tip / scene.force_per_unit

    def layer(p):
        kd, st = damper.k(scene, p)
        w, theta, x = two_family_peak(disk, phi, rho, kd, 2 * np.pi * red["frequency_hz"])
        return p / (rho * abs(theta)), w, theta, x, kd, st  # the force whose peak is at p

    lo, hi = 0.25 * red["psi_mrad"], 2.0 * red["psi_mrad"]  # the force grows with psi here
    for _ in range(30):
        mid = np.sqrt(lo * hi)
        if layer(mid)[0] < force:
            lo = mid
        else:
            hi = mid
    p2 = np.sqrt(lo * hi)
    f2, w2, theta2, x2, kd2, st2 = layer(p2)
    two = dict(peak_mm=float(abs(x2) * force), frequency_hz=float(w2 / (2 * np.pi)), psi_mrad=p2,
               k_re=kd2.real, k_im=kd2.imag, status=st2, seconds=time.perf_counter() - t,
               rho_mrad_per_rad=rho, force_check=f2 / force - 1.0,
               # the damper's stiffness on the root rotation against the root's own
               damper_over_root=float(1e-3 * rho ** 2 * kd2.real / sector_matrices(disk, phi)[1][0, 0]))
    return one, two


def ring_damper_stiffness(disk, e, r, rho):
    """(psi mrad, kd N mm/mrad): the ring's dampers as the first harmonic sees them over the last
    period: each blade's root moment from its two dampers over its root rotation, as 1e-3 rho^2 kd
    on Theta (the two-family model's term), averaged over the blades."""
    steps = np.asarray(r.root_mrad).shape[0]
    e_k = np.exp(-1j * 2 * np.pi * np.arange(1, steps + 1) / steps)
    theta = 2.0 / steps * (e_k @ np.asarray(r.root_mrad)) / 1e3  # (N,) rad
    m = 2.0 / steps * np.tensordot(e_k, np.asarray(r.damper_moment), 1)  # (N, 2) N mm
    k_theta = (np.roll(m[:, 0], 1) + m[:, 1]) / theta  # N mm per rad, blade j
    return float(rho * np.mean(np.abs(theta))), complex(np.mean(k_theta) / (1e-3 * rho ** 2))


def ring_at(disk, e, force, freq, *, steps=STEPS, periods=PERIODS, rho=None):
    t = time.perf_counter()
    r = ring_response(SHAPE, MU, jd.Contacts(), jd.LoadCase(), disk, e, force, freq,
                      h_c_mm=H_C_MM, h_l_mm=H_L_MM, n_periods=periods, steps_per_period=steps)
    jax.block_until_ready(r.amplitude_mm)
    hist = np.asarray(r.history_mm)
    # Aitken's extrapolation of blade 0's first harmonic from the last three periods (the slowest
    # transient decays geometrically): a measure of what the run has not reached yet.
    z0, z1, z2 = hist[-3:, 0]
    den = z2 - 2 * z1 + z0
    limit = z2 - (z2 - z1) ** 2 / den if abs(den) > 0 else z2
    amp = float(np.mean(np.asarray(r.amplitude_mm)))
    extra = {}
    if rho is not None:
        psi, kd = ring_damper_stiffness(disk, e, r, rho)
        extra = dict(psi_mrad=psi, k_re=kd.real, k_im=kd.imag)
    return dict(frequency_hz=float(freq), amplitude_mm=amp, spread=float(r.spread), **extra,
                change_per_period=float(r.change),
                extrapolated_gap=float(abs(limit) / abs(z2) - 1.0),
                status=jd.RESULTS.name_of(int(r.status)), newton_failures=int(r.newton_failures),
                periods=periods, steps_per_period=steps, seconds=time.perf_counter() - t)


def ring_from_assembly(disk, e, force, freq, two, amplitude_mm):
    """Nodal diameter 0 with the reduction's history: every damper assembled at rest, moved
    quasi-statically straight to X(pi) (the root rotation at its most negative: dv = q* theta),
    then the vibration. The start is the two-family first harmonic at freq, scaled to the ring's
    own amplitude, taken at the point of its period where theta = -|Theta| (the force's phase set
    to match)."""
    kd = complex(two["k_re"], two["k_im"])
    theta, x = force * two_family(disk, 0.0, two["rho_mrad_per_rad"], kd, 2 * np.pi * freq)
    theta, x = np.array([theta, x]) * amplitude_mm / abs(x)
    alpha = np.pi - np.angle(theta)
    n = disk.n_blades
    shift = np.exp(1j * 2 * np.pi * e * np.arange(n) / n) * np.exp(1j * alpha)
    y = np.zeros(2 * n, complex)
    y[0::2], y[1::2] = theta * shift, x * shift
    t = time.perf_counter()
    r = ring_response(SHAPE, MU, jd.Contacts(), jd.LoadCase(), disk, e, force, freq,
                      h_c_mm=H_C_MM, h_l_mm=H_L_MM, x0=np.real(y),
                      v0=np.real(1j * 2 * np.pi * freq * y), force_phase_rad=alpha,
                      n_periods=PERIODS, steps_per_period=STEPS)
    jax.block_until_ready(r.amplitude_mm)
    return dict(frequency_hz=float(freq), amplitude_mm=float(np.mean(np.asarray(r.amplitude_mm))),
                spread=float(r.spread), change_per_period=float(r.change),
                status=jd.RESULTS.name_of(int(r.status)), seconds=time.perf_counter() - t)


def parabola_peak(rows):
    f = np.array([r["frequency_hz"] for r in rows])
    a = np.array([r["amplitude_mm"] for r in rows])
    i = np.argsort(a)[-3:]
    c = np.polyfit(f[i] - f[i].mean(), a[i], 2)
    if c[0] >= 0:
        return float(f[np.argmax(a)]), float(a.max())
    fv = -c[1] / (2 * c[0])
    return float(fv + f[i].mean()), float(np.polyval(c, fv))


def configure() -> argparse.Namespace:
    """The disk, the design and the cases from the command line (defaults: the committed check of
    60sym on the six-blade disk); the module's N_SMALL, SHAPE and FORCES are set from them."""
    global N_SMALL, SHAPE, FORCES
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--blades", type=int, default=N_SMALL)
    ap.add_argument("--design", default="60sym")
    ap.add_argument("--cases", default=None, help="regime:ND=force_N,... (default: the 8 cases)")
    ap.add_argument("--no-step-check", action="store_true",
                    help="skip the step-size check (64/128/256 steps per period)")
    ap.add_argument("--out", default="ring_check.json", help="file name in benchmarks/results")
    ap.add_argument("--figure", default="docs/ring_check_example.png")
    a = ap.parse_args()
    N_SMALL = a.blades
    if a.design != "60sym":
        designs = json.loads((RESULTS / "row_optimisation.json").read_text())["designs"]
        vec = next(d["shape"] for d in designs if d["name"] == a.design)
        SHAPE = shape_of_vector(np.asarray(vec, float))
    if a.cases:
        FORCES = {}
        for item in a.cases.split(","):
            regime, rest = item.split(":")
            nd, force = rest.split("=")
            FORCES.setdefault(regime, {})[int(nd)] = float(force)
    return a


def main() -> dict:
    a = configure()
    started = time.perf_counter()
    disk = LumpedDisk(n_blades=N_SMALL)
    family = jd.blocks.validate_family(modal_family(disk, Q_STAR_MM, H_C_MM, residual=True))
    damper = Damper()
    orders = sorted({nd for per_nd in FORCES.values() for nd in per_nd})
    forces = sorted({f for per_nd in FORCES.values() for f in per_nd.values()})
    reds, row_seconds = reduction(family, orders, forces)
    print(f"row_response: {row_seconds:.0f} s", flush=True)
    bare, bare_seconds = reduction(family._replace(platform_residual=None), orders, forces)
    print(f"row_response, free platforms: {bare_seconds:.0f} s", flush=True)
    rows = []
    for regime, per_nd in FORCES.items():
        for e in sorted(per_nd):
            force = per_nd[e]
            red = reds[e, force]
            one, two = cross_checks(disk, family, damper, e, red)
            f2 = two["frequency_hz"]
            width = 0.25 * one["eta_eff"] * f2  # a quarter of the half-power band around the peak
            runs = [ring_at(disk, e, force, f2 + d * width) for d in (-1.0, 0.0, 1.0)]
            fv, _ = parabola_peak(runs)
            runs.append(ring_at(disk, e, force, fv))
            fv, _ = parabola_peak(runs)  # refined once more: the vertex of the largest three
            runs.append(ring_at(disk, e, force, fv, rho=two["rho_mrad_per_rad"]))
            f_ring, a_ring = parabola_peak(runs)
            # The damper in the ring against the reduction's cycle (history assembly) at the same
            # amplitude of its path: what the ring's dampers dissipate, from their moments.
            near = runs[-1]
            k_cycle, st = damper.k(jd.nodal_scene(family, e, Q_STAR_MM, H_L_MM), near["psi_mrad"])
            damper_check = dict(frequency_hz=near["frequency_hz"], psi_mrad=near["psi_mrad"],
                                k_re_ring=near["k_re"], k_im_ring=near["k_im"],
                                k_re_cycle=k_cycle.real, k_im_cycle=k_cycle.imag, cycle_status=st,
                                rel_diff_k_im=near["k_im"] / k_cycle.imag - 1.0,
                                rel_diff_k_re=near["k_re"] / k_cycle.real - 1.0)
            free = bare[e, force]
            rows.append(dict(regime=regime, engine_order=e, nodal_diameter=e, force_n=force,
                             reduction=red, free_platforms=free, one_mode_check=one,
                             two_family=two, damper_in_ring=damper_check,
                             ring=dict(peak_mm=a_ring, frequency_hz=f_ring,
                                       runs=sorted(runs, key=lambda r: r["frequency_hz"]),
                                       seconds=sum(r["seconds"] for r in runs)),
                             rel_diff_reduction=red["peak_mm"] / a_ring - 1.0,
                             rel_diff_free_platforms=free["peak_mm"] / a_ring - 1.0,
                             rel_diff_two_family=two["peak_mm"] / a_ring - 1.0,
                             rel_diff_freq_reduction=red["frequency_hz"] / f_ring - 1.0,
                             rel_diff_freq_two_family=two["frequency_hz"] / f_ring - 1.0))
            if e == 0 and regime == "microslip":
                # The history: the same frequency started the reduction's way (assembly, a
                # straight move to X(pi), then the path) against from rest.
                nearest = min(runs, key=lambda r: abs(r["frequency_hz"] - f_ring))
                assembled = ring_from_assembly(disk, e, force, nearest["frequency_hz"], two,
                                               nearest["amplitude_mm"])
                assembled["rel_diff_from_rest"] = (assembled["amplitude_mm"]
                                                   / nearest["amplitude_mm"] - 1)
                assembled["rel_diff_reduction"] = red["peak_mm"] / assembled["amplitude_mm"] - 1
                rows[-1]["ring"]["from_assembly"] = assembled
                print(f"  ND 0 from assembly at {assembled['frequency_hz']:.2f} Hz: "
                      f"{assembled['amplitude_mm']:.5g} mm ({assembled['rel_diff_from_rest']:+.2%} "
                      f"against from rest)", flush=True)
            worst = max(runs, key=lambda r: r["change_per_period"])
            print(f"{regime} ND {e}: F {force:.4g} N, reduction {red['peak_mm']:.5g} mm at "
                  f"{red['frequency_hz']:.2f} Hz ({red['status']}; free platforms "
                  f"{free['peak_mm']:.5g}), two-family {two['peak_mm']:.5g} at "
                  f"{two['frequency_hz']:.2f}, ring {a_ring:.5g} at {f_ring:.2f} "
                  f"({rows[-1]['rel_diff_reduction']:+.2%}); history-free to "
                  f"{one['history_free']:.1e}; worst change/period "
                  f"{worst['change_per_period']:.1e}; ring {rows[-1]['ring']['seconds']:.0f} s; "
                  f"damper in the ring at psi {near['psi_mrad']:.4g}: k_Im "
                  f"{damper_check['rel_diff_k_im']:+.2%}, k_Re {damper_check['rel_diff_k_re']:+.2%} "
                  f"against the cycle", flush=True)
    # Step-size convergence, once: the first case at its ring peak, 64, 128 and 256.
    e0 = rows[0]
    steps = {} if a.no_step_check else {
        s: ring_at(disk, e0["nodal_diameter"], e0["force_n"], e0["ring"]["frequency_hz"], steps=s)
        for s in (64, STEPS, 256)}
    doc = dict(machine=machine(), seconds=time.perf_counter() - started,
               disk=dict(disk._asdict()), damper=dict(shape=a.design,
                                                       shape_vector=[float(v) for v in (
                                                           SHAPE.theta_l, SHAPE.theta_r,
                                                           SHAPE.br_over_hr, SHAPE.bl2_over_hl)],
                                                       mu=MU, contacts="default",
                                                       load="default", q_star_mm=Q_STAR_MM,
                                                       h_c_mm=H_C_MM, h_l_mm=H_L_MM),
               history=dict(reduction="assembly", ring="from rest"), forces=FORCES,
               steps_per_period=STEPS, periods=PERIODS, row_response_seconds=row_seconds,
               row_response_free_platforms_seconds=bare_seconds,
               kernel_calls=damper.calls, kernel_seconds=damper.seconds, rows=rows,
               step_convergence={str(s): dict(amplitude_mm=r["amplitude_mm"], seconds=r["seconds"])
                                 for s, r in steps.items()})
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / a.out).write_text(json.dumps(doc, indent=1))
    plot(doc, RESULTS.parent.parent / a.figure)
    print(f"total {doc['seconds']:.0f} s")
    return doc


def plot(doc: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = doc["rows"]
    regimes = list(dict.fromkeys(r["regime"] for r in rows))
    per = max(sum(r["regime"] == g for r in rows) for g in regimes)
    fig, axes = plt.subplots(len(regimes), per, figsize=(3.2 * per, 3.3 * len(regimes)),
                             constrained_layout=True, squeeze=False)
    for gi, regime in enumerate(regimes):
        for ax, row in zip(axes[gi], [r for r in rows if r["regime"] == regime]):
            runs = row["ring"]["runs"]
            ax.plot([r["frequency_hz"] for r in runs], [r["amplitude_mm"] for r in runs], "ko-",
                    ms=4, label="ring from rest (time integration)")
            ax.plot(row["ring"]["frequency_hz"], row["ring"]["peak_mm"], "k*", ms=9,
                    label="ring peak")
            ax.plot(row["two_family"]["frequency_hz"], row["two_family"]["peak_mm"], "bs", ms=6,
                    label="two families, 1st harmonic")
            ax.plot(row["reduction"]["frequency_hz"], row["reduction"]["peak_mm"], "r^", ms=7,
                    label="row_response (one mode + residual)")
            ax.plot(row["free_platforms"]["frequency_hz"], row["free_platforms"]["peak_mm"], "mv",
                    ms=6, label="row_response (free platforms)")
            ax.set_title(f"{regime}: ND {row['nodal_diameter']}, F = {row['force_n']:.3g} N "
                         f"({row['rel_diff_reduction']:+.2%})", fontsize=8)
            ax.set_xlabel("frequency (Hz)")
        axes[gi][0].set_ylabel("peak tip amplitude (mm)")
    axes[0][0].legend(fontsize=6)
    fig.savefig(path, dpi=130)


if __name__ == "__main__":
    main()
