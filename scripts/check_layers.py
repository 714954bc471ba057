#!/usr/bin/env python3
"""Checks the folders of src/ against the layering drawn in docs/architecture.md.

That file's table between the markers `<!-- layers:begin -->` and `<!-- layers:end -->` lists,
for every folder of src/, the folders it may include. This script fails (exit status 1, one
line per problem) when
  - a folder of src/ is missing from the table, or the table names a folder that does not exist;
  - a file includes a header of a folder its own folder may not include;
  - the table itself, or the includes actually found, contain a cycle between folders;
  - a folder's CMakeLists.txt links a carve_<folder> library its folder may not include.

Usage: scripts/check_layers.py [REPOSITORY_ROOT]   (run from scripts/test.sh and by ctest)
"""

import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"/]+)/[^"]+"', re.MULTILINE)
ROW = re.compile(r"^\|\s*`([a-z_]+)`\s*\|[^|]*\|([^|]*)\|\s*$")
LINKED = re.compile(r"\bcarve_([a-z_]+)\b")
TABLE = "docs/architecture.md"  # where the layers table lives (README.md until issue 37)


def read_table(readme):
    text = readme.read_text(encoding="utf-8")
    try:
        block = text.split("<!-- layers:begin -->", 1)[1].split("<!-- layers:end -->", 1)[0]
    except IndexError:
        sys.exit(f"{readme}: no <!-- layers:begin --> ... <!-- layers:end --> table")
    allowed = {}
    for line in block.splitlines():
        m = ROW.match(line.strip())
        if m:
            allowed[m.group(1)] = set(re.findall(r"`([a-z_]+)`", m.group(2)))
    if not allowed:
        sys.exit(f"{readme}: the layers table has no rows")
    return allowed


def find_cycle(graph):
    """One cycle of `graph` (folder -> set of folders) as a list, or None."""
    state = {}  # 1 = on the current path, 2 = done
    path = []

    def visit(node):
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent)
    src = root / "src"
    allowed = read_table(root / TABLE)
    folders = {p.name for p in src.iterdir() if p.is_dir()}
    problems = []
    for name in sorted(folders - allowed.keys()):
        problems.append(f"src/{name}/: not in the layers table of {TABLE}")
    for name in sorted(allowed.keys() - folders):
        problems.append(f"{TABLE}: the layers table names {name}, which is not a folder of src/")
    for name, deps in sorted(allowed.items()):
        for dep in sorted(deps - allowed.keys()):
            problems.append(f"{TABLE}: {name} may include {dep}, which is not in the table")

    cycle = find_cycle(allowed)
    if cycle:
        problems.append(f"{TABLE}: the layers table has a cycle: " + " -> ".join(cycle))

    found = {name: set() for name in folders}
    for path in sorted(src.rglob("*")):
        if path.suffix not in (".hpp", ".cpp", ".h", ".inc") or not path.is_file():
            continue
        folder = path.relative_to(src).parts[0]
        for dep in INCLUDE.findall(path.read_text(encoding="utf-8", errors="replace")):
            if dep == folder or dep not in folders:
                continue  # own folder, or not one of carve's (a system header with a slash)
            found[folder].add(dep)
            if dep not in allowed.get(folder, set()):
                problems.append(f"{path.relative_to(root)}: includes {dep}/, "
                                f"which {folder}/ may not include ({TABLE} layers)")

    cycle = find_cycle(found)
    if cycle:
        problems.append("include cycle between folders: " + " -> ".join(cycle))

    for cmake in sorted(src.glob("*/CMakeLists.txt")):
        folder = cmake.parent.name
        text = re.sub(r"#.*", "", cmake.read_text(encoding="utf-8"))
        for dep in sorted(set(LINKED.findall(text))):
            if dep != folder and dep in folders and dep not in allowed.get(folder, set()):
                problems.append(f"{cmake.relative_to(root)}: links carve_{dep}, "
                                f"which {folder}/ may not include ({TABLE} layers)")

    for p in problems:
        print(p)
    if problems:
        return 1
    print(f"layers: {len(folders)} folders of src/, includes and links as {TABLE} draws them")
    return 0


if __name__ == "__main__":
    sys.exit(main())
