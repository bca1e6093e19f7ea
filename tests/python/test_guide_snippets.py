"""Tests of tools/guide_snippets.py, which writes out the code of docs/plugin-guide.md for the
SDK test (run by CTest with the system python3)."""
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
TOOL = os.path.join(ROOT, "tools", "guide_snippets.py")


def run(*args):
    return subprocess.run([sys.executable, TOOL, *args], capture_output=True, text=True)


GUIDE = """# A guide

```cpp
// file: src/a.hpp
#pragma once
int a();
```

Prose between the pieces.

1. A list item with an indented block:

   ```cpp
   // file: src/a.cpp
   #include "a.hpp"
   ```

```cpp
// file: src/a.cpp (continued)
int a() { return 1; }
```

```cpp
// no marker: an illustration, not written
int unused;
```

~~~cmake
# file: CMakeLists.txt
project(x)
~~~

```cpp
// excerpt of: lib/source.cpp
int b = 2;
int c = 3;
```
"""


class GuideSnippets(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)
        (self.dir / "lib").mkdir()
        (self.dir / "lib" / "source.cpp").write_text("// head\n  int b = 2;\n\n  int c = 3;\nint d;\n")

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, text):
        p = self.dir / "guide.md"
        p.write_text(text)
        return str(p)

    def test_files_pieces_and_indentation(self):
        r = run(self.write(GUIDE), str(self.dir / "out"), "--source", str(self.dir))
        self.assertEqual(r.returncode, 0, r.stderr)
        out = self.dir / "out"
        self.assertEqual((out / "src" / "a.hpp").read_text(), "// file: src/a.hpp\n#pragma once\nint a();\n")
        # Two pieces joined in order; the list item's three-space indentation removed.
        self.assertEqual(
            (out / "src" / "a.cpp").read_text(),
            '// file: src/a.cpp\n#include "a.hpp"\n\n// file: src/a.cpp (continued)\nint a() { return 1; }\n',
        )
        self.assertTrue((out / "CMakeLists.txt").exists())
        self.assertEqual(sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file()),
                         ["CMakeLists.txt", "src/a.cpp", "src/a.hpp"])
        self.assertIn("1 excerpts match", r.stdout)

    def test_excerpt_that_no_longer_matches_fails(self):
        text = GUIDE.replace("int c = 3;\n```", "int c = 4;\n```")
        r = run(self.write(text), str(self.dir / "out"), "--source", str(self.dir))
        self.assertEqual(r.returncode, 1)
        self.assertRegex(r.stderr, r"guide\.md:\d+: excerpt of lib/source\.cpp no longer matches it: "
                         r"'int c = 4;' is not in the file")
        # Lines present but not consecutive fail too.
        text = GUIDE.replace("int b = 2;\nint c = 3;", "int b = 2;\nint d;")
        r = run(self.write(text), str(self.dir / "out"), "--source", str(self.dir))
        self.assertEqual(r.returncode, 1)
        self.assertIn("not consecutive", r.stderr)

    def test_bad_input_is_located(self):
        r = run(self.write("text\n\n```cpp\n// file: ../escape.cpp\nint x;\n```\n"), str(self.dir / "out"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("guide.md:3: file: ../escape.cpp must be a relative path", r.stderr)
        r = run(self.write("text\n```cpp\n// file: a.cpp\nint x;\n"), str(self.dir / "out"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("guide.md:2: the code block opened here is never closed", r.stderr)
        r = run(self.write("no code\n"), str(self.dir / "out"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("no code block starts with", r.stderr)
        self.assertFalse((self.dir / "out").exists())  # nothing half-written

    def test_the_plugin_guide_itself(self):
        # The real guide: its project files are there and its excerpts match the source tree.
        out = self.dir / "guide"
        r = run(os.path.join(ROOT, "docs", "plugin-guide.md"), str(out), "--source", ROOT)
        self.assertEqual(r.returncode, 0, r.stderr)
        for f in ["CMakeLists.txt", "kg_elastic.hpp", "kg_elastic.cpp", "lame_kg.toml", "test_kg_elastic.cpp"]:
            self.assertTrue((out / f).exists(), f)
        hpp = (out / "kg_elastic.hpp").read_text()
        for needed in ["#pragma once", "#include <stratum/material.hpp>", "namespace example_kg {"]:
            self.assertIn(needed, hpp)
        self.assertIn("[[checks]]", (out / "lame_kg.toml").read_text())


if __name__ == "__main__":
    unittest.main()
