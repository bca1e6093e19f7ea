"""Every example of docs/python.md (and the README's) runs (CTest python.module): tools/guide_snippets.py writes the
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


def test_the_readme_example_prints_the_csv_value(tmp_path):
    subprocess.run([sys.executable, os.path.join(ROOT, "tools", "guide_snippets.py"),
                    os.path.join(ROOT, "README.md"), str(tmp_path)], check=True)
    os.symlink(os.path.join(ROOT, "inputs"), tmp_path / "inputs")
    r = subprocess.run([sys.executable, "readme_example.py"], cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "out" / "hypoelastic_python" / "curves" / "load_settlement.csv") as f:
        rows = [line.strip().split(",") for line in f if not line.startswith("#")][1:]
    (value,) = [s for load, s in rows if float(load) == 60.0]
    assert r.stdout == "settlement at 60 kN: %s mm\n" % value


@pytest.mark.parametrize("example", EXAMPLES)
def test_example_runs(written, example):
    r = subprocess.run([sys.executable, example], cwd=written, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    print(r.stdout)
