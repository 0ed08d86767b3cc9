#!/usr/bin/env python3
"""Self-test of check_modules.py: on a temporary copy of the tree it must pass, and each
injected problem (a cycle, an edge docs/architecture.md does not list, a listed edge no
include uses, a header in no row, a link CMake declares but the table does not, a source in
no target) must make it fail with the matching message. Also: a `core` module with sources,
listed in the table and linked, is accepted; the test scenes (tests/support) are checked like
a module, and a library module that includes or lists them fails. Only the standard library."""
import os
import re
import shutil
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import check_modules  # noqa: E402


class ModuleCheck(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="check_modules_")
        os.makedirs(os.path.join(self.tmp, "docs"))
        shutil.copy(os.path.join(ROOT, "docs", "architecture.md"), os.path.join(self.tmp, "docs"))
        os.makedirs(os.path.join(self.tmp, "libvdblight"))
        shutil.copy(os.path.join(ROOT, "libvdblight", "CMakeLists.txt"), os.path.join(self.tmp, "libvdblight"))
        for d in ("include", "src"):
            shutil.copytree(os.path.join(ROOT, "libvdblight", d), os.path.join(self.tmp, "libvdblight", d))
        shutil.copytree(os.path.join(ROOT, "tests", "support"), os.path.join(self.tmp, "tests", "support"))

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def path(self, rel):
        return os.path.join(self.tmp, rel)

    def append(self, rel, text):
        with open(self.path(rel), "a", encoding="utf-8") as f:
            f.write(text)

    def edit(self, rel, old, new):
        with open(self.path(rel), encoding="utf-8") as f:
            s = f.read()
        self.assertIn(old, s, f"{rel} no longer contains {old!r}: update the self-test")
        with open(self.path(rel), "w", encoding="utf-8") as f:
            f.write(s.replace(old, new, 1))

    def set_deps(self, module, deps):
        """Replaces the "depends on" cell of `module`'s row in the copied table."""
        rel = "docs/architecture.md"
        with open(self.path(rel), encoding="utf-8") as f:
            lines = f.read().split("\n")
        for i, line in enumerate(lines):
            if line.startswith(f"| `{module}` |"):
                cells = line.strip().strip("|").split("|")
                cells[3] = " " + deps + " "
                lines[i] = "|" + "|".join(cells) + "|"
                break
        else:
            self.fail(f"no row for {module}")
        with open(self.path(rel), "w", encoding="utf-8") as f:
            f.write("\n".join(lines))

    def deps_cell(self, module):
        with open(self.path("docs/architecture.md"), encoding="utf-8") as f:
            for line in f:
                if line.startswith(f"| `{module}` |"):
                    return line.strip().strip("|").split("|")[3].strip()
        self.fail(f"no row for {module}")

    def errors(self):
        return check_modules.check(self.tmp)[1]

    def assertFailsWith(self, pattern):
        errors = self.errors()
        self.assertTrue(any(re.search(pattern, e) for e in errors),
                        f"expected an error matching {pattern!r}, got {errors}")
        return errors

    def test_copy_passes(self):
        edges, errors = check_modules.check(self.tmp)
        self.assertEqual(errors, [])
        self.assertIn(("bake", "volume"), edges)

    def test_injected_cycle_fails(self):
        # layout is below query (query -> layout); layout including a query header closes a loop.
        self.append("libvdblight/src/layout/levels.cpp", '\n#include "vdblight/query/query.h"\n')
        errors = self.assertFailsWith(r"^cycle between modules: .*layout.*query|^cycle between modules: .*query.*layout")
        self.assertTrue(any(e.startswith("edge layout -> query is not listed") for e in errors), errors)

    def test_cycle_listed_in_doc_fails(self):
        # Even when the doc lists both directions (so no edge is "unlisted"), a cycle fails.
        self.append("libvdblight/src/layout/levels.cpp", '\n#include "vdblight/query/query.h"\n')
        self.set_deps("layout", self.deps_cell("layout").replace("—", "").strip(", ") + ", `query`")
        self.edit("libvdblight/CMakeLists.txt", "src/layout/seams.cpp", "src/layout/seams.cpp DEPS vdblight_query")
        errors = self.assertFailsWith(r"^cycle between modules")
        self.assertTrue(any("module table has a cycle" in e for e in errors), errors)

    def test_unlisted_edge_fails(self):
        self.append("libvdblight/src/trace/tracer.cpp", '\n#include "basis/sh.h"\n')
        errors = self.assertFailsWith(r"^edge trace -> basis is not listed in docs/architecture.md \(libvdblight/src/trace/tracer.cpp:\d+\)")
        self.assertFalse(any(e.startswith("cycle") for e in errors), errors)

    def test_private_header_edge_counts(self):
        # A private header of another module (through the src/ include directory) is an edge too.
        self.append("libvdblight/src/trace/tracer.cpp", '\n#include "bake/parallel_nodes.h"\n')
        self.assertFailsWith(r"^edge trace -> bake is not listed")

    def test_stale_listed_edge_fails(self):
        self.set_deps("trace", self.deps_cell("trace") + ", `basis`")
        self.assertFailsWith(r"lists trace -> basis, but no file of trace includes a header of basis")
        self.assertFailsWith(r"vdblight_trace does not link vdblight_basis")

    def test_backticked_unknown_module_fails(self):
        self.set_deps("trace", self.deps_cell("trace") + ", `tracer`")
        self.assertFailsWith(r"depends on `tracer`, which is no module")

    def test_header_in_no_row_fails(self):
        self.append("libvdblight/include/vdblight/new_thing.h", "#pragma once\n")
        self.assertFailsWith(r"include/vdblight/new_thing.h: public header in no row")

    def test_cmake_link_not_listed_fails(self):
        self.edit("libvdblight/CMakeLists.txt", "src/layout/seams.cpp", "src/layout/seams.cpp DEPS vdblight_query")
        self.assertFailsWith(r"vdblight_layout links vdblight_query, an edge docs/architecture.md does not list")

    def test_source_in_no_target_fails(self):
        os.makedirs(self.path("libvdblight/src/core"), exist_ok=True)
        self.append("libvdblight/src/core/parallel_for.cpp", "int x;\n")
        self.assertFailsWith(r"src/core/parallel_for.cpp: compiled by no module target")

    def test_module_that_does_not_link_a_listed_dependency_fails(self):
        # core has a target (issue 16): every module the table says depends on core must link it.
        self.edit("libvdblight/CMakeLists.txt", "DEPS vdblight_core vdblight_layout vdblight_basis vdblight_light_exact OpenVDB",
                  "DEPS vdblight_layout vdblight_basis vdblight_light_exact OpenVDB")
        self.assertFailsWith(r"vdblight_volume does not link vdblight_core")
        # ... and core must not reach back up.
        self.append("libvdblight/src/core/atomic_file.cpp", '#include "vdblight/volume/volume.h"\n')
        self.assertFailsWith(r"^cycle between modules: .*core.*volume|^cycle between modules: .*volume.*core")

    def test_library_including_a_test_scene_fails(self):
        # The test scenes (tests/support) are for tests and benchmarks: no library module may use them.
        edges, errors = check_modules.check(self.tmp)
        self.assertEqual(errors, [])
        self.assertIn(("test_scenes", "scene"), edges)
        self.append("libvdblight/src/scene/scene.cpp", '\n#include "support/office_scene.h"\n')
        errors = self.assertFailsWith(r"src/scene/scene.cpp:\d+: library module 'scene' includes the test-support header")
        self.assertTrue(any(e.startswith("cycle between modules") for e in errors), errors)  # scene <-> test_scenes

    def test_library_listing_a_test_support_module_fails(self):
        self.set_deps("bake", self.deps_cell("bake") + ", `test_scenes`")
        self.assertFailsWith(r"library module 'bake' lists the test-support module 'test_scenes'")

    def test_test_scenes_edges_are_checked(self):
        # An include the row does not list fails, as in the library; so does a header in no row
        # and a link that differs from the table.
        self.append("tests/support/office_scene.cpp", '\n#include "vdblight/trace/trace.h"\n')
        self.assertFailsWith(r"^edge test_scenes -> trace is not listed .*tests/support/office_scene.cpp")
        self.append("tests/support/new_scene.h", "#pragma once\n")
        self.assertFailsWith(r"tests/support/new_scene.h: test-support header in no row")
        self.edit("tests/support/CMakeLists.txt", "PUBLIC vdblight_core", "PUBLIC vdblight_core vdblight_bake")
        self.assertFailsWith(r"tests/support/CMakeLists.txt: vdblight_test_scenes links vdblight_bake")

    def test_find_cycle_on_fake_edges(self):
        self.assertIsNone(check_modules.find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}))
        self.assertEqual(check_modules.find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}), ["a", "b", "c", "a"])


if __name__ == "__main__":
    unittest.main()
