"""Every notebook in notebooks/ runs top to bottom without error (not timed: tests never time); the
committed notebooks carry their outputs (scripts/execute_notebooks.py), with small figures, no bare
matplotlib reprs, and use jaxdamp's public API only.

The kernel is this interpreter: a temporary kernelspec named python3 (put first on JUPYTER_PATH)
runs `sys.executable -m ipykernel_launcher`, so a fresh virtualenv works without `jupyter
kernelspec install`. New notebooks are picked up automatically.
"""

import importlib.util
import json
from pathlib import Path

import pytest

NOTEBOOK_DIR = Path(__file__).resolve().parent.parent / "notebooks"
_spec = importlib.util.spec_from_file_location(
    "execute_notebooks", NOTEBOOK_DIR.parent / "scripts" / "execute_notebooks.py")
_execute_notebooks = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_execute_notebooks)
NOTEBOOKS = sorted(NOTEBOOK_DIR.glob("*.ipynb"))


@pytest.fixture(scope="module")
def kernel_path(tmp_path_factory):
    # The kernel spec scripts/execute_notebooks.py executes the committed notebooks with.
    return _execute_notebooks.kernel_root(tmp_path_factory.mktemp("jupyter"))


def test_notebooks_exist():
    assert NOTEBOOKS, f"no notebooks in {NOTEBOOK_DIR}"


# Executing a notebook compiles its programs in a fresh kernel: those that took over 10
# worker-seconds in the run of 2026-11-25 belong to the full tier (`bash scripts/test.sh --full`).
SLOW_NOTEBOOKS = {"02_family_comparison.ipynb": 26, "03_design_space_and_optimisation.ipynb": 120,
                  "04_speed_vs_accuracy.ipynb": 37, "05_forced_response.ipynb": 258,
                  "06_robust_design.ipynb": 319, "07_row_robust_design.ipynb": 218}


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow)
                                  if p.name in SLOW_NOTEBOOKS else p for p in NOTEBOOKS],
                         ids=[p.name for p in NOTEBOOKS])
def test_notebook_runs(path, kernel_path, monkeypatch):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    monkeypatch.setenv("JUPYTER_PATH", kernel_path)
    nb = nbformat.read(path, as_version=4)
    # Tests never time anything (benchmarks do): the cell timeout only stops a hang.
    client = nbclient.NotebookClient(nb, kernel_name="python3", timeout=600,
                                     resources={"metadata": {"path": str(NOTEBOOK_DIR)}})
    client.execute()  # raises CellExecutionError on the first failing cell
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
              if o.get("output_type") == "error"]
    assert not errors


def _code_cells(path):
    return [c for c in json.loads(path.read_text())["cells"] if c["cell_type"] == "code"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_committed_notebook_is_executed_with_small_figures(path):
    cells = _code_cells(path)
    assert all(c.get("execution_count") for c in cells), "commit the notebook executed"
    assert [c["execution_count"] for c in cells] == list(range(1, len(cells) + 1)), "run top to bottom"
    outputs = [o for c in cells for o in c.get("outputs", [])]
    assert outputs and not [o for o in outputs if o.get("output_type") == "error"]
    import base64
    import struct

    for o in outputs:
        png = o.get("data", {}).get("image/png")
        if png:
            raw = base64.b64decode(png)
            width, height = struct.unpack(">II", raw[16:24])
            assert width <= 1100 and height <= 800 and len(raw) < 160_000, (width, height, len(raw))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_no_matplotlib_repr_in_outputs(path):
    """End plotting statements with `;` (or assign them): no `Text(...)` or `[<matplotlib...>]` lines."""
    for c in _code_cells(path):
        for o in c.get("outputs", []):
            text = "".join(o.get("data", {}).get("text/plain", "")) if "image/png" not in o.get("data", {}) else ""
            assert not text.lstrip().startswith(_execute_notebooks.CLUTTER), text


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebooks_use_the_public_api_only(path):
    import re

    source = "\n".join("".join(c["source"]) for c in _code_cells(path))
    private = re.findall(r"(?:import|from)\s+[\w.]*\b_\w+|import\s+.*\b_\w+|\bjd\._\w+", source)
    assert not private, f"private names in {path.name}: {private}"
