"""The folders are layers (docs/architecture.md, "The layers"): imports point
down, never up, and no file imports itself round a circle. Read from the
source (every import statement, those inside functions too)."""
import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# lower number = lower layer; a folder may import its own layer and those below
LAYER = {"meshes": 0, "loading": 0, "tribology": 0, "mechanics": 1, "machines": 2, "thermal": 2, "schema": 3, "coupling": 4, "outputs": 5,
         "studies": 6, "frontends": 7}
ALLOWED_UP = {("fpd", "frontends")}     # fpd/__init__ and __main__ hand over to the front ends
# fpd/__init__.py (the version, the API's names imported on first use) is the root
# every layer may read; it is not a node of the graph


def _modules():
    mods = {}
    for folder in (*LAYER, "fpd"):
        for f in sorted((ROOT / folder).glob("*.py")):
            name = "fpd" if folder == "fpd" and f.stem == "__init__" else \
                f"fpd.{folder}" if f.stem == "__init__" else \
                f"fpd.{f.stem}" if folder == "fpd" else f"fpd.{folder}.{f.stem}"
            mods[name] = (folder, f)
    return mods


def _imports(name, folder, path, mods):
    pkg = name if path.stem == "__init__" else name.rsplit(".", 1)[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = pkg
            for _ in range(max(node.level - 1, 0)):
                base = base.rsplit(".", 1)[0]
            mod = (base + ("." + node.module if node.module else "")) if node.level else (node.module or "")
            subs = [f"{mod}.{a.name}" for a in node.names if f"{mod}.{a.name}" in mods]
            # "from pkg import module": the module; "from module import name": the module
            for cand in subs or [mod]:
                if cand in mods and cand != name and cand != "fpd":
                    out.add(cand)
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name in mods and a.name not in (name, "fpd")}
    return out


def _graph():
    mods = _modules()
    return mods, {m: _imports(m, folder, f, mods) for m, (folder, f) in mods.items()}


def test_imports_point_down_the_layers():
    mods, graph = _graph()
    up = []
    for m, targets in graph.items():
        fm = mods[m][0]
        for t in targets:
            ft = mods[t][0]
            if fm == ft or (fm, ft) in ALLOWED_UP or ft == "fpd":
                continue
            if fm == "fpd" or LAYER[ft] > LAYER[fm]:
                up.append(f"{m} imports {t}")
    assert not up, "imports against the layers:\n" + "\n".join(sorted(up))


def test_no_import_circles():
    mods, graph = _graph()
    index, low, stack, on, circles = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    assert not circles, f"import circles: {circles}"


def test_no_folder_holds_more_than_a_third_of_the_code():
    lines = {f: sum(len(p.read_text().splitlines()) for p in (ROOT / f).glob("*.py")) for f in (*LAYER, "fpd")}
    total = sum(lines.values())
    big = {f: round(n / total, 3) for f, n in lines.items() if n > total / 3}
    assert not big, (big, lines)
