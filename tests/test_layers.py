"""The package's layers (docs/architecture.md) hold: the import-linter contracts of pyproject.toml pass, and no
module imports back up into its own package's ``__init__``."""

import shutil
import subprocess
import sys
from pathlib import Path

import grimp

ROOT = Path(__file__).resolve().parents[1]


def test_import_linter_contracts_are_kept():
    lint_imports = shutil.which("lint-imports") or str(Path(sys.executable).with_name("lint-imports"))
    assert Path(lint_imports).exists(), "lint-imports (PyPI import-linter, in the [test] extra) is not installed"
    result = subprocess.run([lint_imports, "--config", str(ROOT / "pyproject.toml")], cwd=ROOT, capture_output=True,
                            text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "BROKEN" not in result.stdout


def test_no_module_imports_the_package_it_sits_in():
    # e.g. tuning importing fusion_altitude/__init__, or cli/fleet.py importing cli/__init__: an arrow back up
    graph = grimp.build_graph("fusion_altitude", exclude_type_checking_imports=True)
    back_up = []
    for package in sorted(m for m in graph.modules if graph.find_children(m)):
        for importer in sorted(graph.find_modules_that_directly_import(package)):
            if importer.startswith(package + "."):
                back_up.append(f"{importer} -> {package}")
    assert back_up == []


def test_the_layers_contract_names_every_top_level_module():
    # a new module or folder must be placed in a layer, or the contract would say nothing about it
    import re

    text = (ROOT / "pyproject.toml").read_text()
    block = re.search(r'id = "layers".*?layers = \[(.*?)\]', text, re.S).group(1)
    placed = set(re.findall(r"[\w]+", " ".join(re.findall(r'"([^"]+)"', block))))
    package = ROOT / "fusion_altitude"
    modules = {p.stem for p in package.glob("*.py") if p.stem not in ("__init__", "__main__", "_version", "_aliases")}
    modules |= {p.name for p in package.iterdir() if (p / "__init__.py").is_file()}
    assert sorted(modules - placed) == []
