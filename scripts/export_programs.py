"""Save the programs of the commonest CLI commands into the package (jaxdamp/data/exported/), so that
a first call in a new compilation cache folder skips tracing and lowering them.

Run from the repository root after any change to jaxdamp's sources (tests/test_cli_exported.py
fails until the saved programs match the sources):
    python scripts/export_programs.py

Each command below runs once in a new process with an empty cache folder; `jaxdamp.cli.exported`
saves every program it runs there (StableHLO, keyed by the sources, the JAX version, the platform
and the inputs' shapes), and this script moves them into the package with a manifest of what they
were saved for. The commands compile fast (JAXDAMP_COMPILE=fast): only the saved StableHLO is
kept, and it does not depend on how XLA compiles it.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# The README's and issue 32's commands; every flag that changes a program's inputs' shapes or its
# static options selects another program (a response with over four forces, another --initial).
COMMANDS = [
    "cycle --shape 74R --mu 0.5",
    "cycle --shape 60sym --mu 0.5 --damper wedge",
    "amplitude --shape 60sym --mu 0.5 --psi-a 0.5,1.2,3",
    "grad --shape 74R --mu 0.5",
    "response --shape 60sym --mu 0.5 --force-n 2,5,20 --band",
    # docs/blade.md's row (issue 60): a row of 13 engine orders (2 straight, 11 elliptic paths,
    # padded to 4 and 12) at up to 4 forces, from assembly, with the example's residual
    "response --shape 60sym --mu 0.5 --modes example --engine-order all --h-l 10 --force-n 2,5",
    "study --no-figures --no-progress --out {tmp}/study",  # the README's main job
    # issue 32's fit: three moment loops of 720 samples (`write_sample_loops`); another count of
    # loops, or over 1024 samples in a loop, is another program
    "fit-loops {tmp}/a.csv {tmp}/b.csv {tmp}/c.csv --shape 60sym --no-progress --out {tmp}/fit.json",
]


def write_sample_loops(folder) -> None:
    """Three exact moment loops of 720 samples (60sym, mu = 0.4, psi_a 0.8, 1.5, 3 mrad) as the
    CSV files a.csv, b.csv, c.csv that `jaxdamp fit-loops` reads."""
    import numpy as np

    import jaxdamp as jd

    for name, a in zip("abc", (0.8, 1.5, 3.0)):
        psi, m = jd.sample_loop(jd.family_shape("60sym"), 0.4, a, t=np.linspace(0.0, 2.0, 720))
        np.savetxt(Path(folder, f"{name}.csv"), np.c_[psi, m], delimiter=",",
                   header="psi_mrad,moment_nmm", comments="")


def main() -> int:
    sys.path.insert(0, str(ROOT))
    import jax

    from jaxdamp.cli.exported import SHIPPED_DIR, sources_digest

    out = SHIPPED_DIR
    jax.config.update("jax_enable_x64", True)  # for write_sample_loops
    with tempfile.TemporaryDirectory() as tmp:
        write_sample_loops(tmp)
        env = dict(os.environ, JAXDAMP_CACHE_DIR=tmp, JAXDAMP_COMPILE="fast",
                   PYTHONPATH=f"{ROOT}{os.pathsep}{os.environ.get('PYTHONPATH', '')}")
        programs = {}
        for command in COMMANDS:
            t0 = time.perf_counter()
            before = set(Path(tmp, "exported").glob("*.bin"))
            subprocess.run([sys.executable, "-m", "jaxdamp.cli", *command.format(tmp=tmp).split()], env=env,
                           check=True, stdout=subprocess.DEVNULL)
            new = sorted(set(Path(tmp, "exported").glob("*.bin")) - before)
            programs.update({p.name: command for p in new})
            print(f"{time.perf_counter() - t0:6.1f} s  {command}: "
                  f"{', '.join(p.name.split('-')[0] for p in new) or 'nothing new'}")
        if out.exists():
            shutil.rmtree(out)
        out.mkdir(parents=True)
        for name in programs:
            shutil.copyfile(Path(tmp, "exported", name), out / name)
    manifest = {"sources": sources_digest(), "jax": jax.__version__,
                "platform": jax.default_backend(), "programs": programs}
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")
    size = sum(p.stat().st_size for p in out.glob("*.bin"))
    print(f"{len(programs)} programs, {size / 1e6:.1f} MB, in {out.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
