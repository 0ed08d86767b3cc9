#!/usr/bin/python3
"""Re-runs every artifact libFuzzer saved for one harness and classifies it: a leak that the
exact-frame suppressions in lsan.supp cover (the run then passes), a known library finding
listed in known_crashes.txt, or a new finding. Exit status 1 if any is new (scripts/fuzz.sh).

    triage.py HARNESS_BINARY ARTIFACT_DIR_PREFIX   # every file whose path starts with the prefix
    triage.py HARNESS_BINARY --inputs DIR          # every file in DIR (the seed/regression replay)
"""
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SKIP = re.compile(r"^(fuzzer::|__sanitizer|__asan|__lsan|__interceptor_|operator new|operator delete|malloc|calloc|"
                  r"__pthread_kill|pthread_kill|raise|abort|__assert|"
                  r"realloc|posix_memalign|aligned_alloc|std::__new_allocator|__gnu_cxx::new_allocator)")
FRAME = re.compile(r"^\s*#\d+ 0x[0-9a-f]+ in (.+?)(?: /| \(|$)")


def known(harness):
    out = []
    with open(os.path.join(HERE, "known_crashes.txt")) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                h, report, frame = line.rstrip("\n").split("\t")
                if h == harness:
                    out.append((re.compile(report), re.compile(frame)))
    return out


def first_frame(report):
    for line in report.splitlines():
        m = FRAME.match(line)
        in_libc = any(k in line for k in ("libc.so", "sysdeps/", "libio/", "nptl/", "stdlib/"))
        if m and not SKIP.match(m.group(1)) and not in_libc:
            return m.group(1)
    return ""


def main():
    binary = sys.argv[1]
    harness = os.path.basename(binary)
    replay = sys.argv[2] == "--inputs"
    if replay:
        directory, stem = sys.argv[3], ""
    else:
        directory, stem = os.path.split(sys.argv[2])
    artifacts = sorted(f for f in os.listdir(directory) if f.startswith(stem)) if os.path.isdir(directory) else []
    env = dict(os.environ)
    # Full stacks, so that the suppressions and signatures see the library frames.
    env["ASAN_OPTIONS"] = env.get("ASAN_OPTIONS", "") + ":fast_unwind_on_malloc=0:malloc_context_size=40"
    env["LSAN_OPTIONS"] = "suppressions=" + os.path.join(HERE, "lsan.supp")
    signatures = known(harness)
    new = counts = 0
    counts = {}
    for name in artifacts:
        path = os.path.join(directory, name)
        # A timeout's stack is printed from the alarm handler; with slow unwinding it is lost.
        run_env = dict(env, ASAN_OPTIONS=os.environ.get("ASAN_OPTIONS", "")) if "timeout-" in name else env
        run = subprocess.run([binary, "-rss_limit_mb=2048", "-malloc_limit_mb=" + os.environ.get("MALLOC_LIMIT_MB", "2048"),
                              "-timeout=25", path], env=run_env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True, errors="replace")
        if run.returncode == 0:
            kind = "ran clean" if replay else "suppressed library leak (lsan.supp)"
        else:
            frame = first_frame(run.stdout)
            kind = next(("known: %s in %s" % (r.pattern, frame) for r, fr in signatures
                         if r.search(run.stdout) and fr.search(frame)), None)
            if kind is None:
                new += 1
                kind = "NEW"
                print("fuzz: %s: NEW finding %s (first frame: %s):" % (harness, path, frame or "?"))
                lines = [l for l in run.stdout.splitlines() if "ERROR" in l or "runtime error" in l or FRAME.match(l)]
                print("\n".join(lines[:14]))
        counts[kind] = counts.get(kind, 0) + 1
    for kind, n in sorted(counts.items()):
        if kind != "NEW":
            print("fuzz: %s: %d artifact(s): %s" % (harness, n, kind))
    return 1 if new else 0


if __name__ == "__main__":
    sys.exit(main())
