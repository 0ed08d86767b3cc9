#!/usr/bin/env python3
"""Fails if a test that skips itself under AddressSanitizer is missing from the Release-only list.

`scripts/test.sh --full` (CI) runs each test once: under ASan+UBSan unless
`scripts/sanitize_exclusions.sh` leaves it to the Release build. A test that calls GTEST_SKIP
inside `#ifdef VDBLIGHT_SANITIZED` would then never run in CI unless it is on that list.

    scripts/check_sanitize_exclusions.py [ROOT]
"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
pattern = subprocess.run(["bash", "-c", f'source "{root}/scripts/sanitize_exclusions.sh"; printf %s "$SANITIZE_SKIP_TESTS"'],
                         check=True, capture_output=True, text=True).stdout
# ctest -R takes an extended regex; this one is also a valid Python regex (groups, |, \., ^, $).
release_only = re.compile(pattern)
test_re = re.compile(r"^TEST(?:_F|_P)?\(\s*(\w+)\s*,\s*(\w+)\s*\)", re.M)
missing, skipping = [], 0
for path in sorted((root / "tests").rglob("*.cpp")):
    text = path.read_text(errors="replace")
    heads = [(m.start(), f"{m.group(1)}.{m.group(2)}") for m in test_re.finditer(text)]
    for i, (start, name) in enumerate(heads):
        body = text[start:heads[i + 1][0] if i + 1 < len(heads) else len(text)]
        guarded = re.search(r"#ifdef VDBLIGHT_SANITIZED\s*(//[^\n]*\n\s*)*GTEST_SKIP", body)
        if not guarded:
            continue
        skipping += 1
        if not release_only.search(name):
            missing.append(f"{path.relative_to(root)}: {name}")
if missing:
    print("tests that skip under ASan but are not in scripts/sanitize_exclusions.sh's SANITIZE_SKIP_TESTS "
          "(CI would never run them):")
    print("\n".join("  " + m for m in missing))
    sys.exit(1)
print(f"{skipping} tests skip under ASan; every one runs in the Release build of scripts/test.sh --full")
