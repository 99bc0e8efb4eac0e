"""What the distribution declares (pyproject.toml) against what the repository holds: every
package folder is listed, the optimiser's folder optimize/ installs as `jaxdamp_optimize` (never
as a top-level `optimize`), the licence and the citation metadata agree with the package."""

import re
import tomllib
from pathlib import Path

import jaxdamp

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_every_package_folder_is_listed_and_the_optimiser_is_renamed():
    tool = PYPROJECT["tool"]["setuptools"]
    package_dir = tool["package-dir"]
    assert package_dir == {"jaxdamp_optimize": "optimize"}
    data = {name for name in tool["packages"] if name.startswith("jaxdamp.data")}
    assert data == set(tool["package-data"]) == {"jaxdamp.data", "jaxdamp.data.exported"}
    assert all(not list((ROOT / n.replace(".", "/")).glob("*.py")) for n in data)  # data only
    folder_of = {name: package_dir.get(name, name.replace(".", "/")) for name in tool["packages"]
                 if name not in data}
    # each listed package of code is a folder with an __init__.py
    assert all((ROOT / folder / "__init__.py").is_file() for folder in folder_of.values()), folder_of
    # and each such folder under jaxdamp/ and optimize/ is listed (a new subpackage must be added)
    on_disk = {str(p.parent.relative_to(ROOT)) for top in ("jaxdamp", "optimize")
               for p in (ROOT / top).rglob("__init__.py")}
    assert set(folder_of.values()) == on_disk
    assert "optimize" not in tool["packages"] and "jaxdamp_optimize" in tool["packages"]


def test_the_optimize_command_points_at_the_installed_name():
    group = PYPROJECT["project"]["entry-points"]["jaxdamp.commands"]
    assert group == {"optimize": "jaxdamp_optimize.cli:register"}


def test_licence_is_mit_and_declared():
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License") and "Copyright (c) 2026 the jaxdamp developers" in text
    assert PYPROJECT["project"]["license"] == "MIT"  # an SPDX expression
    assert PYPROJECT["project"]["license-files"] == ["LICENSE"]


def test_citation_names_this_version_and_the_paper():
    cff = (ROOT / "CITATION.cff").read_text()
    top = {m.group(1): m.group(2).strip().strip('"') for m in
           re.finditer(r"^([a-z-]+):[ \t]*(.*)$", cff, re.M)}
    assert top["cff-version"] == "1.2.0"
    assert top["title"] == "jaxdamp" and top["version"] == jaxdamp.__version__
    assert top["license"] == "MIT"
    assert "10.25518/2684-6500.239" in cff and "Gola" in cff


def test_changelog_has_this_version_and_an_unreleased_section():
    log = (ROOT / "CHANGELOG.md").read_text()
    heads = re.findall(r"^## \[([^\]]+)\]", log, re.M)
    assert heads[0] == "Unreleased"
    assert jaxdamp.__version__ in heads and "0.1.0" == heads[-1]
