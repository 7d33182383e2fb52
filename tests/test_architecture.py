"""Dependencies point one way: railderail_monitor builds on railderail_sim, never the reverse."""
import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def imported_modules(path):
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            yield node.module


def test_railderail_sim_never_imports_railderail_monitor():
    found = [f"{path.relative_to(ROOT)} imports {name}" for path in sorted((ROOT / "railderail_sim").rglob("*.py"))
             for name in imported_modules(path) if name.split(".")[0] == "railderail_monitor"]
    assert not found, found
    assert not (ROOT / "railderail_monitor" / "messages.py").exists()
