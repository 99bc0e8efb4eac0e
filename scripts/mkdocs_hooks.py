"""mkdocs hook: the benchmark charts that docs/performance.md shows live in benchmarks/results/,
outside docs/; copy them into the built site at the same relative place (../benchmarks/results/
from a page), so the page shows them both on the site and in the repository."""

import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def on_post_build(config, **kwargs):
    target = Path(config["site_dir"]) / "benchmarks" / "results"
    target.mkdir(parents=True, exist_ok=True)
    for png in (ROOT / "benchmarks" / "results").glob("*.png"):
        shutil.copy2(png, target / png.name)
