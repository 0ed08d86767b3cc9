#!/usr/bin/env python3
"""Fails if a test that skips itself under AddressSanitizer is missing from the Release-only list,
or if a Release-only test lives in a program that --full's Release build does not build.

`scripts/test.sh --full` (CI) runs each test once: under ASan+UBSan unless
`scripts/sanitize_exclusions.sh` leaves it to the Release build. A test that calls GTEST_SKIP
inside `#ifdef VDBLIGHT_SANITIZED` would then never run in CI unless it is on that list.
The Release build of --full builds only the test programs in SANITIZE_SKIP_TARGETS: a test on
the list in any other program would not be built there, and would never run either.

    scripts/check_sanitize_exclusions.py [ROOT]
"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
def exclusion(variable):
    return subprocess.run(["bash", "-c", f'source "{root}/scripts/sanitize_exclusions.sh"; printf %s "${variable}"'],
                          check=True, capture_output=True, text=True).stdout


pattern = exclusion("SANITIZE_SKIP_TESTS")
release_targets = set(exclusion("SANITIZE_SKIP_TARGETS").split())
# Which program each test source is compiled into: vdblight_test(NAME SOURCES a.cpp b.cpp DEPS ...)
# and target_sources(NAME PRIVATE c.cpp) in tests/CMakeLists.txt.
cmake = (root / "tests" / "CMakeLists.txt").read_text()
program_of = {}
for m in re.finditer(r"vdblight_test\(\s*(\w+)\s+SOURCES\s+(.*?)(?:\bDEPS\b|\))", cmake, re.S):
    for source in m.group(2).split():
        program_of[source] = m.group(1)
for m in re.finditer(r"target_sources\(\s*(\w+)\s+(?:PRIVATE|PUBLIC)\s+(.*?)\)", cmake, re.S):
    for source in m.group(2).split():
        program_of.setdefault(source, m.group(1))
# ctest -R takes an extended regex; this one is also a valid Python regex (groups, |, \., ^, $).
release_only = re.compile(pattern)
test_re = re.compile(r"^TEST(?:_F|_P)?\(\s*(\w+)\s*,\s*(\w+)\s*\)", re.M)
missing, skipping, unbuilt, release_tests = [], 0, [], 0
for path in sorted((root / "tests").rglob("*.cpp")):
    text = path.read_text(errors="replace")
    heads = [(m.start(), f"{m.group(1)}.{m.group(2)}") for m in test_re.finditer(text)]
    for i, (start, name) in enumerate(heads):
        if release_only.search(name):
            release_tests += 1
            program = program_of.get(str(path.relative_to(root / "tests")))
            if program not in release_targets:
                unbuilt.append(f"{path.relative_to(root)}: {name} (program {program})")
        body = text[start:heads[i + 1][0] if i + 1 < len(heads) else len(text)]
        guarded = re.search(r"#ifdef VDBLIGHT_SANITIZED\s*(//[^\n]*\n\s*)*GTEST_SKIP", body)
        if not guarded:
            continue
        skipping += 1
        if not release_only.search(name):
            missing.append(f"{path.relative_to(root)}: {name}")
if unbuilt:
    print("Release-only tests in programs missing from scripts/sanitize_exclusions.sh's SANITIZE_SKIP_TARGETS "
          "(--full's Release build would not build them):")
    print("\n".join("  " + m for m in unbuilt))
    sys.exit(1)
if missing:
    print("tests that skip under ASan but are not in scripts/sanitize_exclusions.sh's SANITIZE_SKIP_TESTS "
          "(CI would never run them):")
    print("\n".join("  " + m for m in missing))
    sys.exit(1)
print(f"{skipping} tests skip under ASan; every one runs in the Release build of scripts/test.sh --full")
print(f"{release_tests} Release-only tests, in {len(release_targets)} programs that --full's Release build builds")
