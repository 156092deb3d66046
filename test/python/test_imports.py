"""The Python package's modules import each other in one direction: no circle, counting the
imports written inside functions too (a lazy import still ties the two modules together). Read
from the sources with ast, so the test needs no build."""
import ast
import os

PACKAGE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "src", "kane_sim")


def imports_of(path):
    """The kane_sim modules a source file imports, anywhere in it (package __init__ aside)."""
    with open(path) as f:
        tree = ast.parse(f.read(), path)
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            if node.module == "kane_sim":  # from kane_sim import core, _core
                found.update(alias.name for alias in node.names)
            elif node.module.startswith("kane_sim."):  # from kane_sim.core import Config
                found.add(node.module.split(".")[1])
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("kane_sim."):
                    found.add(alias.name.split(".")[1])
    return found


def module_graph():
    graph = {}
    for name in os.listdir(PACKAGE):
        if name.endswith(".py") and name != "__init__.py":
            graph[name[:-3]] = imports_of(os.path.join(PACKAGE, name))
    return graph


def find_circle(graph):
    """A list of modules that import each other round, or None."""
    state = {}

    def visit(node, path):
        state[node] = "open"
        for nxt in sorted(graph.get(node, ())):
            if nxt not in graph:
                continue  # _core (compiled), msg (generated), or not a module of ours
            if state.get(nxt) == "open":
                return path[path.index(nxt):] + [nxt]
            if nxt not in state:
                circle = visit(nxt, path + [nxt])
                if circle:
                    return circle
        state[node] = "done"
        return None

    for start in sorted(graph):
        if start not in state:
            circle = visit(start, [start])
            if circle:
                return circle
    return None


def test_the_package_has_no_import_circle():
    graph = module_graph()
    assert "core" in graph and "cluster" in graph
    assert find_circle(graph) is None, " -> ".join(find_circle(graph))


def test_the_check_finds_a_circle():
    assert find_circle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert find_circle({"a": {"b", "_core"}, "b": set()}) is None


def test_cluster_needs_only_the_compiled_core():
    assert module_graph()["cluster"] <= {"_core"}
