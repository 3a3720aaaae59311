"""The house's layers, read from the imports (every import statement counts: top level,
function level and under TYPE_CHECKING):

- no import cycle anywhere in `app/` or `physics/`;
- `physics` never imports `app` (nor viser);
- the app stacks kit ← scenes ← lectern, export ← session ← main: a layer imports only
  layers below it, and a scene never imports another scene.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# Layer of each app module (a module may import only modules of a lower layer, or its own
# layer where the pair is listed in SAME_LAYER_OK).
LAYERS = {
    "app.viser_internals": -1,  # the one seam to viser's private names (below everything that uses them)
    "app.data": 0, "app.backpressure": 0, "app.wire": 0, "app.kit": 1, "app.scenes": 2, "app.theme": 2,
    "app.lessons": 3,
    "app.lectern": 3, "app.export": 3, "app.session": 4, "app.main": 5, "app.__main__": 6, "app": 6,
}


def _modules() -> dict[str, Path]:
    found = {}
    for package in ("app", "physics"):
        for path in (ROOT / package).rglob("*.py"):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            found[".".join(parts)] = path
    return found


MODULES = _modules()


def _imports(name: str, path: Path) -> set[str]:
    """The project modules `name` imports, wherever in the file the import stands."""
    out: set[str] = set()
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, *([base] if base else [])])
            for alias in node.names:
                full = f"{base}.{alias.name}"
                out.add(full if full in MODULES else base)
        elif isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
    return {m for m in out if m in MODULES and m != name}


GRAPH = {name: _imports(name, path) for name, path in MODULES.items()}


def _layer(module: str) -> tuple[str, int] | None:
    for prefix in sorted(LAYERS, key=len, reverse=True):
        if module == prefix or module.startswith(prefix + "."):
            return prefix, LAYERS[prefix]
    return None


def test_no_import_cycle_in_app_or_physics() -> None:
    state: dict[str, int] = {}  # 1 on the path, 2 done
    path: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        path.append(node)
        for dep in sorted(GRAPH[node]):
            if state.get(dep) == 1:
                cycle = path[path.index(dep):] + [dep]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if dep not in state:
                visit(dep)
        path.pop()
        state[node] = 2

    for module in sorted(GRAPH):
        if module not in state:
            visit(module)


def test_physics_imports_no_app_and_no_viser() -> None:
    for name, path in MODULES.items():
        if name.startswith("physics"):
            assert not any(dep.startswith("app") for dep in GRAPH[name]), name
            source = path.read_text(encoding="utf-8")
            assert "import viser" not in source and "from viser" not in source, name


def test_app_layers_stack_and_no_scene_imports_another() -> None:
    wrong = []
    for name, deps in GRAPH.items():
        here = _layer(name)
        if here is None or name == "app":
            continue
        for dep in deps:
            there = _layer(dep)
            if there is None:
                continue  # physics
            if name.startswith("app.scenes.") and dep.startswith("app.scenes.") :
                wrong.append(f"{name} imports the scene {dep}")
            elif there[1] > here[1] or (there[1] == here[1] and there[0] != here[0]):
                wrong.append(f"{name} (layer {here[0]}) imports {dep} (layer {there[0]})")
    assert not wrong, "\n".join(sorted(wrong))


def test_the_layer_table_covers_every_app_module() -> None:
    missing = [name for name in MODULES if name.startswith("app") and _layer(name) is None]
    assert not missing, missing
