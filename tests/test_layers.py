"""The house's layers, read from the imports (every import statement counts: top level,
function level and under TYPE_CHECKING):

- no import cycle anywhere in `app/` or `physics/`;
- `physics` never imports `app` (nor viser);
- the app stacks ask ← cluster ← kit ← scenes ← the lecture (app.lecture: gate, caption, room
  plot ← the follower's panel ← lectern ← bus) ← the session's panels (app.hall) ← the browser's
  roles (app.roles) ← session ← main: a layer imports only layers below it, and a scene never
  imports another scene (the modules of one scene's package, `app.scenes.<scene>.*`, import
  each other);
- folders match the layers: each folder of `app/` (FOLDERS) holds one band of layers, and an
  import between two folders runs down only (no arrow back up to a folder above);
- the kit's rooms stack core ← panel, draw (neither imports the other) ← view ← rigid;
- a scene's simulation and readouts (`app.scenes.<scene>.simulation`, `.readouts`), the rigid
  body's simulation and texts, and the kit's core but its draw target import no viser, neither
  directly nor through a project module that does.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# Layer of each app module (a module may import only modules of a lower layer, or its own
# layer where the pair is listed in SAME_LAYER_OK).
LAYERS = {
    "app.viser_internals": -1,  # the one seam to viser's private names (below everything that uses them)
    "app.data": 0, "app.userdata": 0, "app.sweep": 0, "app.i18n": 0,  # i18n: the translation layer (Babel)
    "app.refusals": 0,  # NotAllowed: a refusal (physics.refusal) that is a PermissionError
    "app.cli_words": 0.5,  # the command line's words (app.i18n)
    "app.backpressure": 0, "app.wire": 0,
    "app.sharestore": 0.5, "app.lesson_errors": 0.5,  # their refusals in the reader's words (app.i18n)
    "app.ask": 0.5,  # questions to the class: the model (no viser)
    "app.cluster": 0.6,  # Redis, its typed messages, questions across processes, child processes
    # the kit's rooms: core <- panel, draw (neither imports the other) <- view <- rigid
    "app.kit": 1.0, "app.kit.core": 1.0, "app.kit.panel": 1.2, "app.kit.draw": 1.2, "app.kit.view": 1.4,
    "app.kit.rigid": 1.6,
    "app.scenes": 2, "app.theme": 2,
    "app.codec": 2.5,  # a room as bytes: imports the scenes registry
    "app.lessons": 3, "app.own": 3.5, "app.export": 3,
    # the lecture: gate, caption, room plot <- the follower's panel <- lectern <- bus
    "app.lecture": 4, "app.lecture.gate": 3.7, "app.lecture.caption": 3.8, "app.lecture.room_plot": 3.8,
    "app.lecture.follower": 3.9, "app.lecture.lectern": 4, "app.lecture.bus": 4.5,
    "app.launch": 4.8,  # the workers behind nginx: Redis, the gate's code
    "app.hall": 5, "app.tasks": 5.2,  # tasks between lectures: model and stores, their panels
    "app.roles": 5.5,  # the browser's roles (own room, following, presenting, student)
    "app.session": 6, "app.main": 7, "app.notebook": 7.5,
    "app.__main__": 8, "app": 8,
}
FOLDERS = ("app.ask", "app.cluster", "app.kit", "app.scenes", "app.lecture", "app.hall", "app.tasks", "app.roles")
"""The app's folders: each one a band of layers of its own, imported only from folders above it."""


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


def _viser_imported(path: Path) -> bool:
    """Whether the file imports viser itself (anywhere in the file)."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and not node.level and (node.module or "").split(".")[0] == "viser":
            return True
        if isinstance(node, ast.Import) and any(alias.name.split(".")[0] == "viser" for alias in node.names):
            return True
    return False


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
VISER_IMPORTED = {name for name, path in MODULES.items() if _viser_imported(path)}


def _viser_chain(module: str) -> list[str] | None:
    """A chain of project imports from `module` to one that imports viser (ending "viser"), or
    None.  Only the module's own imports count: the `__init__` of the packages above it, which
    Python runs first, is not followed."""
    seen: set[str] = set()

    def visit(name: str) -> list[str] | None:
        if name in VISER_IMPORTED:
            return [name, "viser"]
        seen.add(name)
        for dep in sorted(GRAPH[name]):
            if dep not in seen:
                chain = visit(dep)
                if chain is not None:
                    return [name, *chain]
        return None

    return visit(module)


def _scene(module: str) -> str | None:
    """The scene a module belongs to (`app.scenes.<scene>`, for a module or a package's), or None."""
    parts = module.split(".")
    return ".".join(parts[:3]) if len(parts) >= 3 and parts[:2] == ["app", "scenes"] else None


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
            if _scene(name) is not None and _scene(dep) is not None and _scene(name) != _scene(dep):
                wrong.append(f"{name} imports the scene {dep}")
            elif there[1] > here[1] or (there[1] == here[1] and there[0] != here[0]):
                wrong.append(f"{name} (layer {here[0]}) imports {dep} (layer {there[0]})")
    assert not wrong, "\n".join(sorted(wrong))


def test_folders_match_the_layers() -> None:
    """Each folder's layers form a band of their own: with every import running down
    (`test_app_layers_stack...`), no import runs from a folder back up to one above it."""
    bands = {f: sorted(LAYERS[p] for p in LAYERS if p == f or p.startswith(f + ".")) for f in FOLDERS}
    ordered = sorted(FOLDERS, key=lambda f: bands[f][0])
    for low, high in zip(ordered, ordered[1:]):
        assert bands[low][-1] < bands[high][0], f"the layers of {low} {bands[low]} and {high} {bands[high]} overlap"
    outside = {p: layer for p, layer in LAYERS.items() if not any(p == f or p.startswith(f + ".") for f in FOLDERS)}
    for f in FOLDERS:
        inside = [p for p, layer in outside.items() if bands[f][0] < layer < bands[f][-1]]
        assert not inside, f"{inside} lie within the band of {f} {bands[f]}"


def test_the_layer_table_covers_every_app_module() -> None:
    missing = [name for name in MODULES if name.startswith("app") and _layer(name) is None]
    assert not missing, missing


def test_scene_simulations_and_readouts_import_no_viser() -> None:
    checked = sorted(name for name in MODULES
                     if _scene(name) is not None and name.rpartition(".")[2] in ("simulation", "readouts"))
    packages = ("euler_angles", "inertia", "moving_frame", "constrained", "poinsot")
    assert {f"app.scenes.{p}.{m}" for p in packages for m in ("simulation", "readouts")} <= set(checked), checked
    assert _viser_chain("app.scenes.euler_angles.view") is not None  # the check finds viser where it is
    checked += ["app.kit.rigid.simulation", "app.kit.rigid.text", *KIT_CORE_WITHOUT_VISER,
                *(name for name in MODULES if name.startswith("app.ask"))]
    wrong = [" -> ".join(chain) for chain in map(_viser_chain, checked) if chain is not None]
    assert not wrong, "\n".join(wrong)


KIT_CORE_WITHOUT_VISER = [name for name in MODULES
                          if name.startswith("app.kit.core.") and name != "app.kit.core.target"]
"""The kit's core but the draw target (which wraps a viser client) holds no viser."""
