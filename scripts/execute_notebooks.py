"""Execute every notebook in notebooks/ in place, so that they are committed with their outputs.

Run from the repository root (after scripts/make_notebook*.py):
    python scripts/execute_notebooks.py [notebooks/NAME.ipynb ...]

The kernel is this interpreter (a temporary kernelspec named python3 runs `sys.executable -m
ipykernel_launcher`), each notebook runs with notebooks/ as its working directory, and the wall time
of each is printed. Exits 1 if a cell fails or an output shows a bare matplotlib repr such as
`Text(...)` (end such plotting statements with `;`).
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOK_DIR = ROOT / "notebooks"
CLUTTER = ("Text(", "[<matplotlib", "<matplotlib.", "<Figure size")
KERNEL_METADATA = {"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}}


def write_notebook(cells, name: str, execute_now: bool = False) -> int:
    """Write notebooks/NAME from `cells` without outputs (the scripts/make_notebook*.py generators
    call this); with execute_now, execute it in place as `main` does. Exit code."""
    import nbformat
    from nbformat.v4 import new_notebook

    path = NOTEBOOK_DIR / name
    nbformat.write(new_notebook(cells=cells, metadata=KERNEL_METADATA), path)
    print(f"wrote {path}")
    return main([str(path)]) if execute_now else 0


def kernel_root(tmp: Path) -> str:
    spec = tmp / "kernels" / "python3"
    spec.mkdir(parents=True)
    (spec / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "Python 3 (jaxdamp)", "language": "python"}))
    return str(tmp)


def clutter(nb) -> list[str]:
    """Text outputs that are only the repr of a matplotlib object."""
    found = []
    for k, cell in enumerate(nb.cells):
        for out in cell.get("outputs", []) if cell.cell_type == "code" else []:
            text = out.get("text", "") or out.get("data", {}).get("text/plain", "")
            text = "".join(text) if isinstance(text, list) else text
            if out.get("output_type") in ("execute_result", "display_data") and "image/png" not in out.get("data", {}):
                if any(text.lstrip().startswith(c) for c in CLUTTER):
                    found.append(f"cell {k}: {text.strip()[:60]}")
    return found


def execute(path: Path) -> float:
    import nbclient
    import nbformat

    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(nb, kernel_name="python3", timeout=600,
                                     resources={"metadata": {"path": str(NOTEBOOK_DIR)}})
    t0 = time.perf_counter()
    client.execute()
    elapsed = time.perf_counter() - t0
    nbformat.write(nb, path)
    bad = clutter(nb)
    if bad:
        raise RuntimeError(f"{path.name}: matplotlib repr in the outputs: {'; '.join(bad)}")
    return elapsed


def main(argv=None) -> int:
    import os

    paths = [Path(p) for p in (argv if argv is not None else sys.argv[1:])] or sorted(NOTEBOOK_DIR.glob("*.ipynb"))
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["JUPYTER_PATH"] = kernel_root(Path(tmp))
        for path in paths:
            try:
                elapsed = execute(path)
            except Exception as exc:  # a failing cell: report it and stop with status 1
                print(f"FAILED {path.name}: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}",
                      file=sys.stderr)
                return 1
            print(f"{path.name}: executed in {elapsed:.1f} s, {path.stat().st_size / 1024:.0f} KiB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
