"""The example disk's modal file and its figure (issue 35, item 4).

Writes jaxdamp/data/example_disk_modes.npz (`jaxdamp.baselines.lumped_disk.write_example_family`, through `modal_file.save_modal_family`:
the first family of `LumpedDisk()` with 24 blades, q* = 100 mm, h_C = 20 mm) and
docs/example_disk_frequencies.png (natural frequency against nodal diameter, both families).

Run from the repository root: python scripts/make_example_disk.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from jaxdamp.baselines.lumped_disk import LumpedDisk, sector_modes, write_example_family

DOCS = Path(__file__).resolve().parent.parent / "docs"


def main() -> Path:
    path = write_example_family()
    plot(DOCS / "example_disk_frequencies.png")
    return path


def plot(out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    disk = LumpedDisk()
    n = disk.n_blades
    nds = np.arange(n // 2 + 1)
    freqs = np.array([np.sqrt(sector_modes(disk, 2 * np.pi * nd / n)[0]) / (2 * np.pi) for nd in nds])
    r = np.array([1e3 * (lambda m: m[0, 0] / m[1, 0])(sector_modes(disk, 2 * np.pi * nd / n)[1])
                  for nd in nds])
    fig, (ax, ax1, ax2) = plt.subplots(1, 3, figsize=(11, 3.4), constrained_layout=True)
    ax.plot(nds, freqs[:, 0], "ko-", ms=4)
    ax.set_xlabel("nodal diameter")
    ax.set_ylabel("natural frequency (Hz), platforms free")
    ax.set_title(f"1st family (blade bending): the example file\n{n} blades "
                 "(jaxdamp.baselines.lumped_disk)", fontsize=9)
    ax.grid(alpha=0.3)
    ax1.plot(nds, freqs[:, 1], "s--", color="0.5", ms=3)
    ax1.set_xlabel("nodal diameter")
    ax1.set_ylabel("natural frequency (Hz), platforms free")
    ax1.set_title("2nd family (root rocking)", fontsize=9)
    ax1.grid(alpha=0.3)
    ax2.plot(nds, r, "ko-", ms=4)
    ax2.set_xlabel("nodal diameter")
    ax2.set_ylabel("root rotation per tip motion (mrad/mm)")
    ax2.set_title("1st family: platform rotation r", fontsize=9)
    ax2.set_ylim(0.0, None)
    ax2.grid(alpha=0.3)
    fig.savefig(out, dpi=130)


if __name__ == "__main__":
    main()
