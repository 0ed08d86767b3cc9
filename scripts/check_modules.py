#!/usr/bin/env python3
"""Module edges of libvdblight, from its #includes, checked against docs/architecture.md.

docs/architecture.md is the single source of truth: its module table (the one whose header
row is `| module | headers | owns | depends on |`) names every module, the public headers of
each (column "headers") and the modules each may include (column "depends on": a token that
is a module name, in backticks or not, is an edge; anything else, e.g. "TBB", is an outside
library and ignored; a backticked token that is no module is an error).

Which file belongs to which module:
  - a .cpp under libvdblight/src/: the CMake target (`vdblight_module(name SOURCES ...)` or
    `target_sources(vdblight_name ...)` in libvdblight/CMakeLists.txt) that compiles it;
  - a private header under libvdblight/src/<folder>/: the module named <folder> if there is
    one, else the only module compiling sources in that folder;
  - a public header libvdblight/include/vdblight/x.h: the one table row listing `x.h`.
A module listed in the table with no CMake target is header-only (no sources allowed).

Test-support libraries (tests/support/, e.g. the test scenes): a row of the same table, whose
target is an `add_library(vdblight_<name> ...)` in tests/support/CMakeLists.txt (sources
relative to that folder, links from its `target_link_libraries`) and whose headers are
listed as included, `support/x.h` (relative to tests/). Their edges are checked like the
library's; in addition no library module may include one of their headers or list one as a
dependency (the library must not need its tests' scenes).

The check fails (exit 1, one line per problem) on:
  - a cycle among the module edges found in the includes;
  - an edge found in the includes that the table does not list (with the file and line);
  - an edge the table lists that no include uses (the table must draw the real graph);
  - a public header in no row or in two rows, a listed header that does not exist, a source
    file in no module, a quoted include that resolves to no file;
  - a library module that includes a test-support header or lists a test-support module;
  - a CMake target whose vdblight_* link dependencies differ from the table's edges to
    modules that have a target (each module links exactly what it may include; header-only
    modules need no link).

Usage: check_modules.py [--root DIR] [--list]   (--list: one line per edge with an example)
Only the standard library; `import check_modules` gives check(root) -> (edges, errors).
"""
import argparse
import os
import re
import sys

TABLE_HEADER = re.compile(r"^\|\s*module\s*\|\s*headers\s*\|\s*owns\s*\|\s*depends on\s*\|\s*$")
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^">]+)[">]')
SOURCE_EXT = (".cpp", ".cc", ".cxx")
HEADER_EXT = (".h", ".hpp")


def parse_table(doc_path, errors):
    """Returns {module: {"headers": set, "deps": set}} (deps still unfiltered tokens)."""
    rows = {}
    with open(doc_path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    start = next((i for i, l in enumerate(lines) if TABLE_HEADER.match(l.strip())), None)
    if start is None:
        errors.append(f"{doc_path}: no module table (header row '| module | headers | owns | depends on |')")
        return rows
    for number, line in enumerate(lines[start + 2:], start + 3):
        line = line.strip()
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) != 4:
            errors.append(f"{doc_path}:{number}: module table row has {len(cells)} cells, not 4")
            continue
        module = cells[0].strip("`").strip()
        if module in rows:
            errors.append(f"{doc_path}:{number}: module '{module}' has two rows")
            continue
        headers = set(re.findall(r"`([A-Za-z0-9_./]+\.h)`", cells[1]))
        deps = []
        for token in cells[3].split(","):
            token = token.strip()
            ticked = token.startswith("`") and token.endswith("`") and len(token) > 1
            deps.append((token.strip("`").strip(), ticked, number))
        rows[module] = {"headers": headers, "deps": deps, "line": number}
    return rows


def split_cmake_calls(text, name):
    """Argument lists (whitespace-split, comments removed) of every call `name(...)`."""
    text = re.sub(r"#[^\n]*", "", text)
    calls = []
    for m in re.finditer(r"\b" + re.escape(name) + r"\s*\(", text):
        depth, i = 1, m.end()
        while depth and i < len(text):
            depth += {"(": 1, ")": -1}.get(text[i], 0)
            i += 1
        calls.append(text[m.end():i - 1].split())
    return calls


def parse_cmake(cmake_path, module_call="vdblight_module"):
    """Returns ({module: [source paths relative to the file's folder]}, {module: set(link deps)}).

    module_call: "vdblight_module" (libvdblight/CMakeLists.txt) or "add_library" (a
    test-support library: `add_library(vdblight_<name> STATIC sources...)`)."""
    with open(cmake_path, encoding="utf-8") as f:
        text = f.read()
    sources, links = {}, {}
    keywords = {"SOURCES", "DEPS", "PUBLIC", "PRIVATE", "INTERFACE"}
    for args in split_cmake_calls(text, module_call):
        if module_call == "add_library":
            if not args or not args[0].startswith("vdblight_"):
                continue
            args = [args[0][len("vdblight_"):], "SOURCES"] + [a for a in args[1:] if a not in ("STATIC", "OBJECT")]
        module, mode = args[0], None
        sources.setdefault(module, [])
        links.setdefault(module, set())
        for a in args[1:]:
            if a in keywords:
                mode = a
            elif mode == "SOURCES":
                sources[module].append(a)
            elif mode == "DEPS" and a.startswith("vdblight_"):
                links[module].add(a[len("vdblight_"):])
    for call, target in (("target_sources", sources), ("target_link_libraries", links)):
        for args in split_cmake_calls(text, call):
            if not args or not args[0].startswith("vdblight_"):
                continue
            module = args[0][len("vdblight_"):]
            if module not in sources:
                continue  # not a module target (the umbrella, flags)
            for a in args[1:]:
                if a in keywords:
                    continue
                if call == "target_sources":
                    target[module].append(a)
                elif a.startswith("vdblight_") and a != "vdblight_flags":
                    target[module].add(a[len("vdblight_"):])
    return sources, links


def find_cycle(edges):
    """One cycle (list of modules, first == last) in {a: set(b)}, or None."""
    colour, stack = {}, []

    def visit(a):
        colour[a] = 1
        stack.append(a)
        for b in sorted(edges.get(a, ())):
            if colour.get(b) == 1:
                return stack[stack.index(b):] + [b]
            if colour.get(b) is None:
                found = visit(b)
                if found:
                    return found
        stack.pop()
        colour[a] = 2
        return None

    for a in sorted(edges):
        if colour.get(a) is None:
            found = visit(a)
            if found:
                return found
    return None


def check(root):
    """Returns (edges, errors): edges {(a, b): [(file, line), ...]} found in the includes."""
    errors = []
    root = os.path.abspath(root)
    lib = os.path.join(root, "libvdblight")
    src = os.path.join(lib, "src")
    public = os.path.join(lib, "include", "vdblight")
    support = os.path.join(root, "tests", "support")  # test-support libraries, included as "support/x.h"
    doc = os.path.join(root, "docs", "architecture.md")
    rows = parse_table(doc, errors)
    modules = set(rows)
    sources, links = parse_cmake(os.path.join(lib, "CMakeLists.txt"))
    source_dir = {m: lib for m in sources}
    test_support = set()
    if os.path.isfile(os.path.join(support, "CMakeLists.txt")):
        support_sources, support_links = parse_cmake(os.path.join(support, "CMakeLists.txt"), "add_library")
        for m in support_sources:
            if m in sources:
                errors.append(f"tests/support/CMakeLists.txt: vdblight_{m} is also a target of libvdblight/CMakeLists.txt")
                continue
            test_support.add(m)
            sources[m], links[m], source_dir[m] = support_sources[m], support_links[m], support

    # Allowed edges from the table.
    allowed = {m: set() for m in modules}
    for m, row in rows.items():
        for token, ticked, number in row["deps"]:
            if token in modules:
                if token == m:
                    errors.append(f"{doc}:{number}: module '{m}' lists itself as a dependency")
                allowed[m].add(token)
            elif ticked:
                errors.append(f"{doc}:{number}: '{m}' depends on `{token}`, which is no module of the table")
            if token in test_support and m not in test_support:
                errors.append(f"{doc}:{number}: library module '{m}' lists the test-support module '{token}'")

    owner = {}  # absolute path -> module
    for m, files in sources.items():
        if m not in modules:
            errors.append(f"libvdblight/CMakeLists.txt: target vdblight_{m} is not a module of docs/architecture.md's table")
        for rel in files:
            owner[os.path.normpath(os.path.join(source_dir[m], rel))] = m
    for m, row in rows.items():
        for h in row["headers"]:
            if m in test_support:
                path = os.path.normpath(os.path.join(root, "tests", h))
                where = "tests/ (a test-support header is listed as included: support/x.h)"
            else:
                path = os.path.normpath(os.path.join(public, h))
                where = "libvdblight/include/vdblight/"
            if not os.path.isfile(path):
                errors.append(f"{doc}:{row['line']}: module '{m}' lists `{h}`, which is not in {where}")
            elif path in owner:
                errors.append(f"{doc}: public header {h} is listed by both '{owner[path]}' and '{m}'")
            else:
                owner[path] = m

    files = []
    for d, _, names in os.walk(src):
        for n in sorted(names):
            if n.endswith(SOURCE_EXT) or n.endswith(HEADER_EXT):
                files.append(os.path.normpath(os.path.join(d, n)))
    for d, _, names in os.walk(public):
        for n in sorted(names):
            if n.endswith(HEADER_EXT):
                files.append(os.path.normpath(os.path.join(d, n)))
    for d, _, names in os.walk(support):
        for n in sorted(names):
            if n.endswith(SOURCE_EXT) or n.endswith(HEADER_EXT):
                files.append(os.path.normpath(os.path.join(d, n)))
    files.sort()
    for path in files:
        rel = os.path.relpath(path, root)
        if path in owner:
            continue
        if path.startswith(public + os.sep):
            errors.append(f"{rel}: public header in no row of docs/architecture.md's module table")
            continue
        if path.startswith(support + os.sep):
            errors.append(f"{rel}: " + ("compiled by no add_library(vdblight_<name> ...) in tests/support/CMakeLists.txt"
                                        if path.endswith(SOURCE_EXT) else
                                        "test-support header in no row of docs/architecture.md's module table"))
            continue
        folder = os.path.relpath(path, src).split(os.sep)[0]
        if path.endswith(SOURCE_EXT):
            errors.append(f"{rel}: compiled by no module target in libvdblight/CMakeLists.txt")
            continue
        in_folder = {owner[p] for p in owner if p.startswith(os.path.join(src, folder) + os.sep)}
        if folder in modules:
            owner[path] = folder
        elif len(in_folder) == 1:
            owner[path] = in_folder.pop()
        else:
            errors.append(f"{rel}: private header of folder '{folder}', which is no module of the table")
    for m in modules:
        if m not in sources and any(owner.get(p) == m for p in files if p.endswith(SOURCE_EXT)):
            errors.append(f"module '{m}' has sources but no vdblight_{m} target")

    # Edges from the includes.
    edges = {}
    for path in files:
        a = owner.get(path)
        if a is None:
            continue
        with open(path, encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                quote, name = m.groups()
                candidates = [os.path.join(lib, "include", name)]
                if quote == '"':
                    candidates += [os.path.join(os.path.dirname(path), name), os.path.join(src, name)]
                    if name.startswith("support/"):
                        candidates.append(os.path.join(root, "tests", name))
                target = next((os.path.normpath(c) for c in candidates if os.path.isfile(c)), None)
                if target is None:
                    if quote == '"' or name.startswith("vdblight/"):
                        errors.append(f"{os.path.relpath(path, root)}:{number}: #include \"{name}\" resolves to no file")
                    continue  # a system or third-party header
                b = owner.get(target)
                if b is None or b == a:
                    continue
                if b in test_support and a not in test_support:
                    errors.append(f"{os.path.relpath(path, root)}:{number}: library module '{a}' includes the "
                                  f"test-support header \"{name}\" (test scenes are for tests and benchmarks only)")
                edges.setdefault((a, b), []).append((os.path.relpath(path, root), number))

    found = {}
    for (a, b) in edges:
        found.setdefault(a, set()).add(b)
    cycle = find_cycle(found)
    if cycle:
        errors.append("cycle between modules: " + " -> ".join(cycle) + "  (e.g. " +
                      "; ".join("%s:%d" % edges[(x, y)][0] for x, y in zip(cycle, cycle[1:])) + ")")
    cycle = find_cycle(allowed)
    if cycle:
        errors.append("docs/architecture.md's module table has a cycle: " + " -> ".join(cycle))
    for (a, b), where in sorted(edges.items()):
        if a in allowed and b not in allowed[a]:
            errors.append(f"edge {a} -> {b} is not listed in docs/architecture.md ({where[0][0]}:{where[0][1]}"
                          + (f" and {len(where) - 1} more" if len(where) > 1 else "") + ")")
    for a in sorted(allowed):
        for b in sorted(allowed[a]):
            if (a, b) not in edges:
                errors.append(f"docs/architecture.md lists {a} -> {b}, but no file of {a} includes a header of {b}")
    def cmake_name(m):
        return "tests/support/CMakeLists.txt" if m in test_support else "libvdblight/CMakeLists.txt"

    for a in sorted(sources):
        if a not in allowed:
            continue
        want = {b for b in allowed[a] if b in sources}
        have = links.get(a, set())
        for b in sorted(have - want):
            errors.append(f"{cmake_name(a)}: vdblight_{a} links vdblight_{b}, an edge docs/architecture.md does not list")
        for b in sorted(want - have):
            errors.append(f"{cmake_name(a)}: vdblight_{a} does not link vdblight_{b} (docs/architecture.md: {a} depends on {b})")
    return edges, errors


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument("--list", action="store_true", help="one line per edge with an example include")
    args = parser.parse_args(argv)
    edges, errors = check(args.root)
    by_module = {}
    for (a, b) in edges:
        by_module.setdefault(a, set()).add(b)
    for a in sorted(by_module):
        print(f"{a} -> {', '.join(sorted(by_module[a]))}")
    if args.list:
        for (a, b), where in sorted(edges.items()):
            print(f"  {a} -> {b}: {len(where)} includes, e.g. {where[0][0]}:{where[0][1]}")
    for e in errors:
        print("error: " + e, file=sys.stderr)
    print(f"{len(edges)} module edges, {len(errors)} problems", file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
