#!/usr/bin/env python3
"""Docs a user can read (issue 30 item 6): every doc under docs/ and every README.md of the
repository is at most 800 lines, and every relative Markdown link in them reaches a file that
exists and, for `file.md#anchor`, a heading of that file (GitHub's anchor rule), so that moving
a section cannot leave a dead link behind. Prints each problem on one line; exit 1 if any.

    scripts/check_docs.py [--root DIR] [--max-lines N]

Only the standard library."""
import argparse
import os
import re
import sys

MAX_LINES = 800
LINE_LIMIT_EXCEPTIONS = set()  # none: docs/engines.md was split into engines.md, engine_layouts.md, engine_visibility.md
SKIP_DIRS = {"node_modules", ".git", "build", "build-sanitize", "build-fuzz"}

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
FENCE = re.compile(r"^\s*(```|~~~)")


def docs_to_check(root):
    """docs/**/*.md and every README.md outside build and dependency folders, as paths relative to root."""
    found = []
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith("build"))
        rel = os.path.relpath(folder, root)
        for f in sorted(files):
            path = os.path.normpath(os.path.join(rel, f))
            if f == "README.md" or (path.startswith("docs" + os.sep) and f.endswith(".md")):
                found.append(path)
    return found


def github_anchor(heading):
    """The id GitHub gives a heading: lower case, markup and punctuation dropped, spaces to '-'."""
    text = re.sub(r"`([^`]*)`", r"\1", heading.strip())
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = text.lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors_of(path):
    seen, anchors, fenced = {}, set(), False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if FENCE.match(line):
                fenced = not fenced
                continue
            m = None if fenced else re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                base = github_anchor(m.group(1))
                n = seen.get(base, 0)
                seen[base] = n + 1
                anchors.add(base if n == 0 else f"{base}-{n}")
    return anchors


def links_of(path):
    """(line number, target) of every inline link outside code blocks and code spans."""
    out, fenced = [], False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if FENCE.match(line):
                fenced = not fenced
                continue
            if fenced:
                continue
            for m in LINK.finditer(re.sub(r"`[^`]*`", "", line)):
                out.append((number, m.group(1)))
    return out


def check(root, max_lines=MAX_LINES):
    problems, anchor_cache = [], {}
    for rel in docs_to_check(root):
        path = os.path.join(root, rel)
        with open(path, encoding="utf-8") as f:
            lines = sum(1 for _ in f)
        if lines > max_lines and rel not in LINE_LIMIT_EXCEPTIONS:
            problems.append(f"{rel}: {lines} lines, over {max_lines}")
        for number, target in links_of(path):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):
                continue  # http:, https:, mailto:, data:
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
            if not os.path.exists(dest):
                problems.append(f"{rel}:{number}: link to {target}: no such file")
                continue
            if anchor and dest.endswith(".md"):
                if dest not in anchor_cache:
                    anchor_cache[dest] = anchors_of(dest)
                if anchor not in anchor_cache[dest]:
                    problems.append(f"{rel}:{number}: link to {target}: no heading #{anchor} in {os.path.relpath(dest, root)}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument("--max-lines", type=int, default=MAX_LINES)
    args = parser.parse_args()
    problems = check(args.root, args.max_lines)
    for p in problems:
        print(p)
    print(f"check_docs: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
