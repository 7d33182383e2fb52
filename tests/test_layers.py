"""The layering rule: numba core <- model building <- methods <- CLI; nothing imports upward, and the
package __init__ files import nothing (importing one module does not load the whole stack)."""
import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "railderail_sim"
# a layer's folder: the packages it must not import (relative or absolute)
FORBIDDEN = {
    "contact": ("vehicle", "methods", "cli", "bench", "parameters", "profiles", "plotting"),
    "track": ("vehicle", "methods", "cli", "bench", "plotting"),
    "vehicle": ("methods", "cli", "bench", "plotting"),
    "methods": ("cli", "bench"),
}


def imported_modules(path):
    """Absolute names of the railderail_sim modules that the file at `path` imports."""
    package = path.relative_to(PACKAGE.parent).with_suffix("").parts[:-1]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else ()
            module = ".".join(base + tuple(filter(None, [node.module])))
            yield from (f"{module}.{a.name}" for a in node.names)


@pytest.mark.parametrize("layer", sorted(FORBIDDEN))
def test_no_layer_imports_upward(layer):
    bad = [(path.name, name) for path in sorted((PACKAGE / layer).glob("*.py")) for name in imported_modules(path)
           if any(name == f"railderail_sim.{up}" or name.startswith(f"railderail_sim.{up}.") for up in FORBIDDEN[layer])]
    assert bad == []


@pytest.mark.parametrize("package", ["contact", "track", "vehicle", "methods", "bench"])
def test_package_init_imports_nothing(package):
    tree = ast.parse((PACKAGE / package / "__init__.py").read_text())
    assert not [node for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))]


def test_layout_loads_without_the_model():
    code = ("import sys\nimport railderail_sim.vehicle.layout\n"
            "print(sorted(m for m in sys.modules if m.startswith('railderail_sim')))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    loaded = result.stdout.split()
    assert not any(name in text for text in loaded for name in ("assemble", "simulate", "parameters", "profiles"))
