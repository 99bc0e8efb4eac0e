"""The cyclic reduction against the whole ring with N explicit dampers (issue 35, item 5).

The small disk: `LumpedDisk(n_blades=6)` (the example disk's parameters, six blades). The damper:
60sym, mu = 0.5, default contacts and load (q* = 100 mm), rotation centres h_C = 20 mm below D,
damper size h_L = 10 mm. For every nodal diameter n = 0 ... 3 (engine order e = n):

- the reduction (one mode): `jaxdamp.nodal_scene` on the disk's first family (`modal_family`),
  the damper's k(psi) on the scene's path from assembly (`amplitude_kernel` straight,
  `elliptic_kernel` elliptic); peak where A (eta k_b + 1e-3 r^2 k_Im(r A)) = F_tip, at
  f0 sqrt(1 + 1e-3 r^2 k_Re / k_b). The force F is chosen so that this peak sits at
  psi = 0.7 psi_max, psi_max the path amplitude of the largest k_Im (microslip, short of gross
  slip; psi_max = psi_BC in-phase), or where the root turns by 2 mrad if that is less (off nodal
  diameter 0 the platforms turn relative to each other, a path the damper resists weakly:
  slipping there takes root rotations of tens of mrad);
- the same first harmonic with both families of the sector (the 2x2 sector problem of the lumped
  disk with the damper as the complex spring 1e-3 rho^2 k(psi) on the root rotation, rho = psi
  per rad of root rotation): what the one-mode reduction drops is the second family (the damper
  changes the mode shape), which this isolates;
- the ring (`jaxdamp.baselines.ring.ring_response`: time integration, no reduction, no harmonic
  balance) at frequencies around the two-family peak, a parabola through the amplitudes near its
  maximum (refined once) giving the ring's peak.

Each ring run starts on the two-family first-harmonic solution at its frequency (after the
dampers' assembly at rest and a quasi-static move there: `ring_response`'s history), to shorten
the transient; one run per nodal diameter from rest at the ring's peak frequency measures the
history (growth from rest). Step size: 128 steps per period, checked against 64 and 256 once.

Run: python benchmarks/ring_check.py -> benchmarks/results/ring_check.{json,png}.
"""

from __future__ import annotations

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

from bench_common import machine  # noqa: E402

RESULTS = Path(__file__).parent / "results"
N_SMALL, Q_STAR_MM, H_C_MM, H_L_MM, MU = 6, 100.0, 20.0, 10.0, 0.5
STEPS, PERIODS, THETA_MRAD = 128, 160, 2.0
SHAPE = jd.family_shape("60sym")


class Damper:
    """k(psi) of the damper on one scene's path from assembly (jitted kernels, cached)."""

    def __init__(self):
        # The inputs as float64 arrays, kn and kt per pad (what the checked entry points pass on;
        # the kernels take them unchecked).
        shape = jd.DamperShape(*(None if v is None else jnp.asarray(float(v)) for v in SHAPE))
        c = jd.Contacts()
        contacts = jd.Contacts(jnp.full(3, float(c.kn)), jnp.full(3, float(c.kt)))
        load = jd.LoadCase(*(jnp.asarray(float(v)) for v in jd.LoadCase()))
        self.args = (shape, jnp.asarray(MU), contacts, load)
        self.straight = jax.jit(jd.amplitude_kernel, static_argnames=("initial", "max_tracts",
                                                                        "loop", "max_pairs"))
        self.elliptic = jax.jit(jd.elliptic_kernel, static_argnames=("initial", "max_tracts",
                                                                       "loop", "max_periods"))
        self.calls, self.seconds = 0, 0.0

    def k(self, scene, psi):
        t = time.perf_counter()
        if scene.straight:
            c = self.straight(*self.args, jnp.asarray(float(psi)), initial="assembly",
                              motion=scene.motion)
        else:
            c = self.elliptic(*self.args, jnp.asarray(float(psi)), scene.motion)
        out = complex(float(c.k_re), float(c.k_im)), jd.RESULTS.name_of(int(c.status))
        self.calls += 1
        self.seconds += time.perf_counter() - t
        return out


def two_family(disk, phi, rho, kd, omega):
    """(Theta rad, X mm) per N of tip force: the sector's first harmonic with the damper's complex
    stiffness kd (N mm/mrad) on the root rotation (1e-3 rho^2 kd per rad of Theta... in N mm/rad:
    rho mrad of psi per rad, psi in mrad: 1e-3 rho^2 kd)."""
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


def reductions(disk, family, damper, e, fd=None):
    """The one-mode reduction's peak (and the force that puts it at 0.7 psi_max) and the
    two-family peak at the same force."""
    scene = jd.nodal_scene(family, e, Q_STAR_MM, H_L_MM)
    mode = scene.mode
    t = time.perf_counter()
    phi = 2.0 * np.pi * scene.nodal_diameter / disk.n_blades
    _, modes = sector_modes(disk, phi)
    rho = mode.r * abs(modes[1, 0] / modes[0, 0])  # mrad of psi per rad of root rotation
    grid = np.geomspace(0.2, 400.0, 45)
    kims = np.array([damper.k(scene, p)[0].imag for p in grid])
    psi_max = float(grid[int(np.argmax(kims))])
    # Microslip at a root rotation of at most THETA_MRAD (psi is the path's parameter, which off
    # nodal diameter 0 counts the relative rotation too).
    psi = min(0.7 * psi_max, THETA_MRAD * rho / 1e3)
    k, status = damper.k(scene, psi)
    amp = psi / mode.r
    f_tip = amp * (mode.eta * mode.k_b + 1e-3 * mode.r ** 2 * k.imag)
    force = f_tip / scene.force_per_unit
    f_peak = mode.f0_hz * np.sqrt(1.0 + 1e-3 * mode.r ** 2 * k.real / mode.k_b)
    one = dict(peak_mm=amp, frequency_hz=float(f_peak), psi_mrad=psi, psi_max_mrad=psi_max,
               k_re=k.real, k_im=k.imag, status=status, seconds=time.perf_counter() - t,
               r_mrad_per_mm=mode.r, k_b=mode.k_b, f0_hz=mode.f0_hz,
               straight=bool(scene.straight), force_per_unit=scene.force_per_unit)
    # Two families: psi = rho |Theta|, with rho = r X_mode / Theta_mode (mrad per rad).
    t = time.perf_counter()

    def layer(p):
        kd, st = damper.k(scene, p)
        w, theta, x = two_family_peak(disk, phi, rho, kd, 2 * np.pi * f_peak)
        return p / (rho * abs(theta)), w, theta, x, kd, st  # the force whose peak is at p

    lo, hi = 0.25 * psi, 2.0 * psi  # the force needed grows with psi across microslip
    for _ in range(40):
        mid = np.sqrt(lo * hi)
        if layer(mid)[0] < force:
            lo = mid
        else:
            hi = mid
    p2 = np.sqrt(lo * hi)
    f2, w2, theta2, x2, kd2, st2 = layer(p2)
    two = dict(peak_mm=float(abs(x2) * force), frequency_hz=float(w2 / (2 * np.pi)), psi_mrad=p2,
               k_re=kd2.real, k_im=kd2.imag, status=st2, seconds=time.perf_counter() - t,
               rho_mrad_per_rad=rho, force_check=f2 / force - 1.0)
    return scene, force, one, two, dict(rho=rho, kd=kd2, phi=phi)


def start_state(disk, e, force, omega, sol):
    """(x0, v0) of the ring on the two-family first harmonic at omega (with the peak's kd)."""
    theta, x = force * two_family(disk, sol["phi"], sol["rho"], sol["kd"], omega)
    n = disk.n_blades
    shift = np.exp(1j * 2 * np.pi * e * np.arange(n) / n)
    y = np.zeros(2 * n, complex)
    y[0::2], y[1::2] = theta * shift, x * shift
    return np.real(y), np.real(1j * omega * y)


def ring_at(disk, e, force, freq, sol, *, steps=STEPS, periods=PERIODS, from_rest=False):
    x0 = v0 = None
    if not from_rest:
        x0, v0 = start_state(disk, e, force, 2 * np.pi * freq, sol)
    t = time.perf_counter()
    r = ring_response(SHAPE, MU, jd.Contacts(), jd.LoadCase(), disk, e, force, freq,
                      h_c_mm=H_C_MM, h_l_mm=H_L_MM, x0=x0, v0=v0, n_periods=periods,
                      steps_per_period=steps)
    jax.block_until_ready(r.amplitude_mm)
    hist = np.asarray(r.history_mm)
    # Aitken's extrapolation of blade 0's first harmonic from the last three periods (the slowest
    # transient decays geometrically): a measure of what the run has not reached yet.
    z0, z1, z2 = hist[-3:, 0]
    den = z2 - 2 * z1 + z0
    limit = z2 - (z2 - z1) ** 2 / den if abs(den) > 0 else z2
    return dict(frequency_hz=float(freq), amplitude_mm=float(np.mean(np.asarray(r.amplitude_mm))),
                spread=float(r.spread), change=float(r.change),
                extrapolated_mm=float(abs(limit)), status=jd.RESULTS.name_of(int(r.status)),
                newton_failures=int(r.newton_failures), seconds=time.perf_counter() - t,
                history_blade0_mm=[float(abs(h)) for h in hist[:, 0]])


def parabola_peak(rows):
    f = np.array([r["frequency_hz"] for r in rows])
    a = np.array([r["amplitude_mm"] for r in rows])
    i = np.argsort(a)[-3:]
    c = np.polyfit(f[i] - f[i].mean(), a[i], 2)
    if c[0] >= 0:
        return float(f[np.argmax(a)]), float(a.max())
    fv = -c[1] / (2 * c[0])
    return float(fv + f[i].mean()), float(np.polyval(c, fv))


def main() -> dict:
    started = time.perf_counter()
    disk = LumpedDisk(n_blades=N_SMALL)
    family = jd.validate_family(modal_family(disk, Q_STAR_MM, H_C_MM))
    damper = Damper()
    rows = []
    for e in range(N_SMALL // 2 + 1):
        scene, force, one, two, sol = reductions(disk, family, damper, e)
        eta_eff = (disk.eta * one["k_b"] + 1e-3 * one["r_mrad_per_mm"] ** 2 * one["k_im"]) / (
            one["k_b"] + 1e-3 * one["r_mrad_per_mm"] ** 2 * one["k_re"])
        f2 = two["frequency_hz"]
        width = 0.25 * eta_eff * f2  # a quarter of the half-power band around the peak
        # Enough periods for the transient left by the start to decay by e^-3 (the slowest mode
        # decays as exp(-pi eta_eff per period)).
        periods = int(min(900, max(PERIODS, 3.0 / (np.pi * eta_eff))))
        runs = [ring_at(disk, e, force, f2 + d * width, sol, periods=periods)
                for d in (-1.0, 0.0, 1.0)]
        fv, _ = parabola_peak(runs)
        runs.append(ring_at(disk, e, force, fv, sol, periods=periods))
        f_ring, a_ring = parabola_peak(runs)
        from_rest = ring_at(disk, e, force, f_ring, sol, from_rest=True,
                            periods=int(min(1200, max(PERIODS, 8.0 / (np.pi * eta_eff)))))
        rows.append(dict(engine_order=e, nodal_diameter=scene.nodal_diameter,
                         ibpa_deg=scene.ibpa_deg, force_n=force, eta_eff=eta_eff,
                         reduction=one, two_family=two,
                         ring=dict(peak_mm=a_ring, frequency_hz=f_ring, runs=runs,
                                   seconds=sum(r["seconds"] for r in runs),
                                   from_rest=from_rest),
                         rel_diff_one_mode=one["peak_mm"] / a_ring - 1.0,
                         rel_diff_two_family=two["peak_mm"] / a_ring - 1.0,
                         rel_diff_freq_one_mode=one["frequency_hz"] / f_ring - 1.0,
                         rel_diff_freq_two_family=two["frequency_hz"] / f_ring - 1.0,
                         rel_diff_from_rest=from_rest["amplitude_mm"] / a_ring - 1.0))
        print(f"ND {e}: F {force:.4g} N, one-mode {one['peak_mm']:.5g} mm at "
              f"{one['frequency_hz']:.2f} Hz, two-family {two['peak_mm']:.5g} at "
              f"{two['frequency_hz']:.2f}, ring {a_ring:.5g} at {f_ring:.2f} "
              f"(from rest {from_rest['amplitude_mm']:.5g}); ring {rows[-1]['ring']['seconds']:.0f} s",
              flush=True)
    # Step-size convergence, once: ND 0 at its ring peak, 64 and 256 steps per period.
    e0 = rows[0]
    _, _, _, _, sol0 = reductions(disk, family, damper, 0)
    steps = {s: ring_at(disk, 0, e0["force_n"], e0["ring"]["frequency_hz"], sol0, steps=s)
             for s in (64, STEPS, 256)}
    doc = dict(machine=machine(), seconds=time.perf_counter() - started,
               disk=dict(disk._asdict()), damper=dict(shape="60sym", mu=MU, contacts="default",
                                                       load="default", q_star_mm=Q_STAR_MM,
                                                       h_c_mm=H_C_MM, h_l_mm=H_L_MM),
               steps_per_period=STEPS, periods=PERIODS, kernel_calls=damper.calls,
               kernel_seconds=damper.seconds, rows=rows,
               step_convergence={str(s): dict(amplitude_mm=r["amplitude_mm"], seconds=r["seconds"])
                                 for s, r in steps.items()})
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "ring_check.json").write_text(json.dumps(doc, indent=1))
    plot(doc)
    return doc


def plot(doc: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = doc["rows"]
    fig, axes = plt.subplots(1, len(rows), figsize=(3.2 * len(rows), 3.4), constrained_layout=True)
    for ax, row in zip(np.atleast_1d(axes), rows):
        runs = sorted(row["ring"]["runs"], key=lambda r: r["frequency_hz"])
        ax.plot([r["frequency_hz"] for r in runs], [r["amplitude_mm"] for r in runs], "ko-",
                ms=4, label="ring (time integration)")
        ax.plot(row["ring"]["frequency_hz"], row["ring"]["peak_mm"], "k*", ms=9, label="ring peak")
        ax.plot(row["two_family"]["frequency_hz"], row["two_family"]["peak_mm"], "bs", ms=6,
                label="two families, 1st harmonic")
        ax.plot(row["reduction"]["frequency_hz"], row["reduction"]["peak_mm"], "r^", ms=7,
                label="one-mode reduction")
        ax.set_title(f"ND {row['nodal_diameter']} (EO {row['engine_order']}), "
                     f"F = {row['force_n']:.3g} N", fontsize=9)
        ax.set_xlabel("frequency (Hz)")
    np.atleast_1d(axes)[0].set_ylabel("peak tip amplitude (mm)")
    np.atleast_1d(axes)[0].legend(fontsize=7)
    fig.savefig(RESULTS / "ring_check.png", dpi=130)


if __name__ == "__main__":
    main()
