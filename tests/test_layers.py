"""The dependency rule of docs/design.md, walked over every import statement of the package:
numba core <- model building <- methods <- the top (cli, bench, ros/) <- railderail_monitor, whose rooms are
ordered too (ROOMS); nothing imports upward, package __init__ files import nothing, and importing a core module
does not load the model."""
import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "railderail_sim"
HELPERS = ("railderail_sim.ranges", "railderail_sim.jsonout", "railderail_sim.atomic", "railderail_sim.plotting",
           "railderail_sim.scalarmath")
CORE, MODEL, METHODS, TOP = range(4)
LAYERS = [  # module name prefix -> layer (the first prefix that matches)
    ("railderail_sim.record", CORE), ("railderail_sim.jit", CORE), ("railderail_sim.lookup", CORE), ("railderail_sim.contact", CORE),
    ("railderail_sim.track.irregularity", MODEL), ("railderail_sim.track.spectra", MODEL), ("railderail_sim.track", CORE),
    ("railderail_sim.loads.wind", MODEL), ("railderail_sim.loads", CORE), ("railderail_sim.vehicle.layout", CORE),
    ("railderail_sim.vehicle.dynamics", CORE), ("railderail_sim.vehicle.integrator", CORE),
    ("railderail_sim.vehicle.run_end", CORE),
    ("railderail_sim.parameters", MODEL), ("railderail_sim.profiles", MODEL), ("railderail_sim.vehicle", MODEL),
    ("railderail_sim.sensors", MODEL), ("railderail_sim.line", MODEL), ("railderail_sim.methods", METHODS),
    ("railderail_sim.assessment", METHODS), ("railderail_sim.supervision", METHODS),
    ("railderail_sim.cli", TOP), ("railderail_sim.bench", TOP), ("railderail_sim.ros", TOP),
]


def layer(module):
    if module in PACKAGES or module.startswith(HELPERS):
        return None                                  # the packages themselves and the small helpers
    for prefix, level in LAYERS:
        if module == prefix or module.startswith(prefix + "."):
            return level
    raise AssertionError(f"module {module} has no layer in tests/test_layers.py (add it to LAYERS)")


def module_name(path, root=ROOT):
    parts = path.relative_to(root).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


PACKAGES = {module_name(path) for path in PACKAGE.rglob("__init__.py")}


def imports(path, root=ROOT):
    """(line, imported module) of every import statement of a file (absolute names)."""
    name = module_name(path, root)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            yield from ((node.lineno, a.name) for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            for a in node.names:            # `from .. import vehicle`, `from ..vehicle import simulate` name
                sub = f"{module}.{a.name}"  # modules; `from .geometry import Patch` a name in one
                path = root.joinpath(*sub.split("."))
                yield node.lineno, (sub if path.with_suffix(".py").exists() or path.is_dir() else module)


def violations(root):
    """Every import of the railderail_sim tree under `root` that breaks the rule, as 'file:line ...'."""
    bad = []
    for path in sorted((root / "railderail_sim").rglob("*.py")):
        name = module_name(path, root)
        own = layer(name)
        for line, target in imports(path, root):
            where = f"{path.relative_to(root)}:{line} imports {target}"
            if target.startswith("railderail_monitor"):
                bad.append(where)
            elif not target.startswith("railderail_sim") or target == "railderail_sim":
                continue
            elif own is None and name not in PACKAGES and layer(target) is not None:
                bad.append(where + " (a helper imports a layer)")
            elif own is not None and layer(target) is not None and layer(target) > own:
                bad.append(where + " (from a higher layer)")
    return sorted(set(bad))


def test_nothing_imports_upward_and_the_simulator_never_imports_the_monitor():
    assert violations(ROOT) == []


def test_the_walk_catches_an_upward_import(tmp_path):
    core = tmp_path / "railderail_sim" / "contact"
    core.mkdir(parents=True)
    (tmp_path / "railderail_sim" / "vehicle").mkdir()
    (tmp_path / "railderail_sim" / "vehicle" / "simulate.py").write_text("")
    (core / "bad.py").write_text("import math\nfrom ..vehicle import simulate\nfrom . import geometry\n"
                                 "import railderail_monitor.criteria\n")
    assert violations(tmp_path) == [
        "railderail_sim/contact/bad.py:2 imports railderail_sim.vehicle.simulate (from a higher layer)",
        "railderail_sim/contact/bad.py:4 imports railderail_monitor.criteria"]


@pytest.mark.parametrize("path", sorted(PACKAGE.rglob("__init__.py")), ids=lambda p: str(p.relative_to(ROOT)))
def test_package_init_imports_only_within_its_package(path):
    name = module_name(path)
    outside = [target for _, target in imports(path) if not target.startswith(name + ".")]
    assert outside == [] or name == "railderail_sim.cli", outside


def test_a_core_module_loads_without_the_model():
    code = ("import sys\nimport railderail_sim.vehicle.integrator\n"
            "print(sorted(m for m in sys.modules if m.startswith('railderail')))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    loaded = eval(result.stdout.strip().splitlines()[-1])
    assert [m for m in loaded if layer(m) not in (None, CORE)] == []
    assert "railderail_sim.contact.wheelset" in loaded


def import_graph(root=ROOT):
    """{module: modules of the two packages it imports, at any depth of its code} over both packages."""
    graph = {}
    for package in ("railderail_sim", "railderail_monitor"):
        for path in sorted((root / package).rglob("*.py")):
            targets = {t for _, t in imports(path, root) if t.split(".")[0] in ("railderail_sim", "railderail_monitor")}
            graph[module_name(path, root)] = targets - {module_name(path, root)}
    return graph


def cycles(graph):
    """The strongly connected groups of more than one module (Tarjan), each sorted."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                out.append(sorted(group))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(out)


# railderail_monitor's rooms (docs/design.md) by level: a room imports only rooms of lower levels
ROOMS = {"warning": 0, "onboard": 1, "supervision": 1, "evaluation": 2, "views": 2, "node": 2, "recording": 3,
         "demo": 4, "bench": 4, "commands": 4}


def room(module):
    """The room of a railderail_monitor module (its first name under the package), None for the package."""
    parts = module.split(".")
    return parts[1] if parts[0] == "railderail_monitor" and len(parts) > 1 else None


def room_violations(graph):
    bad = []
    for module, targets in sorted(graph.items()):
        own = room(module)
        if own is None:
            continue
        if own not in ROOMS:
            bad.append(f"{module} is in no room of tests/test_layers.py ROOMS (add it, and to docs/design.md)")
            continue
        for target in sorted(targets):
            other = room(target)
            if other not in (None, own) and ROOMS.get(other, 99) >= ROOMS[own]:
                bad.append(f"{module} imports {target} (room {other} is not below room {own})")
    return bad


def test_the_monitor_s_rooms_import_only_rooms_below_them():
    assert room_violations(import_graph()) == []


def test_the_rooms_walk_catches_an_import_sideways_and_upward():
    graph = {"railderail_monitor.warning.alarms": {"railderail_monitor.evaluation.scoring"},
             "railderail_monitor.views.rerun_views": {"railderail_monitor.node", "railderail_monitor.warning.limits"},
             "railderail_monitor.attic.old": set()}
    assert room_violations(graph) == [
        "railderail_monitor.attic.old is in no room of tests/test_layers.py ROOMS (add it, and to docs/design.md)",
        "railderail_monitor.views.rerun_views imports railderail_monitor.node (room node is not below room views)",
        "railderail_monitor.warning.alarms imports railderail_monitor.evaluation.scoring "
        "(room evaluation is not below room warning)"]


def test_no_module_imports_one_that_imports_it_back():
    """Every import statement, at module level or inside a function: no circle of modules."""
    assert cycles(import_graph()) == []


def test_the_walk_finds_a_circle_through_a_function_level_import():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
