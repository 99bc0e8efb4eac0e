"""benchmarks/README.md is the index of what backs the docs' figures: every script and every result
file is named there, and every result file a current document cites exists. The dated history
(docs/performance-history.md) may cite snapshots that live in git history only."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"
RESULTS = BENCH / "results"
INDEX = (BENCH / "README.md").read_text()
CITED = re.compile(r"results/([A-Za-z0-9_-]+\.(?:json|png))")


def test_every_benchmark_script_is_in_the_index():
    missing = [p.name for p in sorted(BENCH.glob("*.py")) if f"`{p.name}`" not in INDEX]
    assert missing == []


def test_every_result_file_is_in_the_index():
    missing = [p.name for p in sorted(RESULTS.iterdir()) if p.name not in INDEX]
    assert missing == []


def test_current_documents_cite_only_result_files_that_exist():
    current = [ROOT / "README.md", ROOT / "CHANGELOG.md", BENCH / "README.md"]
    current += [p for p in sorted((ROOT / "docs").glob("*.md")) if p.name != "performance-history.md"]
    absent = sorted({(doc.name, name) for doc in current for name in CITED.findall(doc.read_text())
                     if not (RESULTS / name).exists()})
    assert absent == []
