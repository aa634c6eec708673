"""The shape of the package's code, read from its source: no import circle
among its modules (imports inside functions included), and no function
over 100 lines of code or 12 parameters."""

import ast
import pathlib

import pytest

SRC = pathlib.Path(__file__).resolve().parent.parent / "src"
MAX_LINES, MAX_PARAMETERS = 100, 12


def modules():
    """{dotted name: path} of every module of the package."""
    out = {}
    for path in sorted(SRC.rglob("*.py")):
        parts = path.relative_to(SRC).with_suffix("").parts
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def imports(name, path, known):
    """The package's modules that the module ``name`` imports anywhere in
    its source: ``from . import x`` names the submodule x if there is one,
    otherwise the package it reads x from."""
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            source = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:
                sub = f"{source}.{alias.name}"
                found.add(sub if sub in known else source)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
    return {m for m in found if m in known and m != name}


def find_circle(graph):
    """One import circle of ``graph`` as a list of modules, or None."""
    state = {}

    def visit(node, trail):
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                return trail[trail.index(nxt):] + [nxt]
            if nxt not in state:
                circle = visit(nxt, trail + [nxt])
                if circle:
                    return circle
        state[node] = "done"
        return None

    for node in sorted(graph):
        if node not in state:
            circle = visit(node, [node])
            if circle:
                return circle
    return None


def test_find_circle_finds_one():
    """The search itself: a circle of three is found, a chain is not one."""
    assert find_circle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert find_circle({"a": {"b"}, "b": {"c"}, "c": set()}) is None


def test_no_import_circle():
    known = modules()
    assert "splinestep.driver" in known and "splinestep.problems._problem" in known
    graph = {name: imports(name, path, known) for name, path in known.items()}
    assert "splinestep.spline" in graph["splinestep.problems._problem"]
    assert find_circle(graph) is None, " -> ".join(find_circle(graph))


def functions():
    for path in sorted(SRC.rglob("*.py")):
        lines = path.read_text().splitlines()
        for node in ast.walk(ast.parse("\n".join(lines))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield path.relative_to(SRC), node, lines


def code_lines(node, lines):
    """Lines of code in a function's body: its docstring, blank lines and
    comment lines aside."""
    body = node.body
    if (isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)
            and isinstance(body[0].value.value, str)):
        body = body[1:]
    numbers = {n for stmt in body for n in range(stmt.lineno, stmt.end_lineno + 1)}
    return sum(1 for n in numbers if lines[n - 1].strip() and
               not lines[n - 1].strip().startswith("#"))


# The front door whose options stand in its signature, keyword-only with
# their defaults, so that help(), IDEs and the API page show them (scipy's
# solve_ivp hides them in **options): its keyword-only options not counted.
FRONT_DOORS = {"splinestep/spline.py:solve"}


def parameters(node, name=""):
    a = node.args
    keyword_only = 0 if name in FRONT_DOORS else len(a.kwonlyargs)
    return (len(a.posonlyargs) + len(a.args) + keyword_only
            + (a.vararg is not None) + (a.kwarg is not None))


@pytest.mark.parametrize("measure, limit", [(code_lines, MAX_LINES), (parameters, MAX_PARAMETERS)])
def test_no_function_over_the_limits(measure, limit):
    sizes = {f"{path}:{node.name}": (measure(node, lines) if measure is code_lines
                                     else measure(node, f"{path}:{node.name}"))
             for path, node, lines in functions()}
    assert all(name in sizes for name in FRONT_DOORS)
    assert len(sizes) > 100
    assert max(sizes.values()) > limit // 2   # the measure sees real functions
    over = {name: size for name, size in sizes.items() if size > limit}
    assert not over, over


# A notebook's main line: a code cell a reader sees unfolded has at most
# 18 lines (blank lines not counted); figure code is folded (cell
# metadata jupyter.source_hidden, which JupyterLab and the website read).
MAX_CELL_LINES = 18


def test_no_unfolded_notebook_cell_over_the_limit():
    jupytext = pytest.importorskip("jupytext", reason="reads the notebooks (the repository's tooling)")
    long = []
    for path in sorted((SRC.parent / "notebooks").glob("[0-9][0-9]_*.py")):
        for index, cell in enumerate(jupytext.read(path).cells):
            folded = cell.metadata.get("jupyter", {}).get("source_hidden", False)
            lines = [line for line in cell.source.splitlines() if line.strip()]
            if cell.cell_type == "code" and not folded and len(lines) > MAX_CELL_LINES:
                long.append((path.name, index, len(lines)))
            if cell.cell_type == "code" and folded and "save_figure" not in cell.source:
                long.append((path.name, index, "folded without a figure"))
    assert not long, long
