"""Every example of docs/python.md runs (CTest python.module): tools/guide_snippets.py writes the
blocks marked `# file: NAME.py` out of the page, and each runs with Debian's python3 in a scratch
folder that sees the repository's inputs/ and tests/ (so that out/ is written there)."""
import os
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
PAGE = os.path.join(ROOT, "docs", "python.md")
EXAMPLES = ["parameter_loop.py", "point_calibration.py", "read_folder.py"]


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    d = tmp_path_factory.mktemp("docs_python")
    subprocess.run([sys.executable, os.path.join(ROOT, "tools", "guide_snippets.py"), PAGE, str(d)], check=True)
    for name in ("inputs", "tests"):
        os.symlink(os.path.join(ROOT, name), d / name)
    return d


def test_the_page_has_the_examples(written):
    assert sorted(p for p in os.listdir(written) if p.endswith(".py")) == sorted(EXAMPLES)


@pytest.mark.parametrize("example", EXAMPLES)
def test_example_runs(written, example):
    r = subprocess.run([sys.executable, example], cwd=written, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    print(r.stdout)
