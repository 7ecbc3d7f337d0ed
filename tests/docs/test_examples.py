"""Every ```python block of README.md and of the guide's Python pages runs as written: each saved as a script
in a directory of its own and run with this interpreter, as a user who copies it into a file would; the
files it writes (``save("….npz")``, ``save_plot("….png")``) must be there afterwards. A block that shows a
file of the repository is that file.

The blocks run side by side (each in its own process) to keep the test short; each is independent of the
others.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = ("README.md", "docs/guide/python.md", "docs/guide/architectures.md", "docs/guide/gym.md")
#: A ```python block, or one titled with the file it shows (```python title="examples/…"): that one must be
#: the file, word for word (the file itself is run by tests/ekm/cli/test_architectures.py).
BLOCK = re.compile(r'^```python(?: title="([^"]+)")?\n(.*?)^```$', flags=re.M | re.S)
FOUND = [(page, title, code) for page in PAGES for title, code in BLOCK.findall((ROOT / page).read_text())]
BLOCKS = [(page, code) for page, title, code in FOUND if not title]
FILES = [(page, title, code) for page, title, code in FOUND if title]
TIMEOUT = 600  # s, for all blocks together


def block_id(page: str, code: str) -> str:
    line = next(line for line in code.splitlines() if line.strip() and not line.startswith(("import", "if __")))
    return f"{Path(page).stem}: {line.strip()[:50]}"


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """``{index: (directory, returncode, stdout, stderr)}`` of every block."""
    env = {**os.environ, "MPLBACKEND": "Agg"}
    running = {}
    for i, (_, code) in enumerate(BLOCKS):
        d = tmp_path_factory.mktemp(f"example{i}")
        (d / "example.py").write_text(code)
        running[i] = (d, subprocess.Popen([sys.executable, "example.py"], cwd=d, env=env, text=True,
                                          stdout=subprocess.PIPE, stderr=subprocess.PIPE))
    done = {}
    for i, (d, proc) in running.items():
        try:
            out, err = proc.communicate(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
            err += f"\n(timed out after {TIMEOUT} s)"
        done[i] = (d, proc.returncode, out, err)
    return done


@pytest.mark.parametrize("page, title, code", FILES, ids=[f"{Path(p).stem}: {t}" for p, t, _ in FILES])
def test_a_block_titled_with_a_file_is_that_file(page, title, code):
    if code.strip() == f'--8<-- "{title}"':  # the site includes the file itself (pymdownx.snippets)
        assert (ROOT / title).is_file()
        return
    assert code == (ROOT / title).read_text(), f"{page} shows {title} other than it is"


def test_the_readme_shows_the_example_package_in_about_30_lines():
    (shown,) = [code for page, title, code in FILES if page == "README.md"]
    assert len(shown.splitlines()) <= 32 and "ekm.Architecture(" in shown


def test_the_readme_example_is_five_lines_and_the_guide_shows_every_use():
    readme = [code for page, code in BLOCKS if page == "README.md"]
    assert len(readme) == 1, "the README has one Python example"
    lines = [line for line in readme[0].splitlines() if line.strip()]
    assert len(lines) <= 5 and "ekm.run(" in readme[0] and "save_plot(" in readme[0]
    guide = "\n".join(code for page, code in BLOCKS if page != "README.md")
    for use in ("ekm.train(", "ekm.evaluate(", "ekm.compare(", ".save(", "ekm.load("):
        assert use in guide, f"docs/guide/python.md shows no {use}"


@pytest.mark.parametrize("i", range(len(BLOCKS)), ids=[block_id(*b) for b in BLOCKS])
def test_python_example_runs_as_written(finished, i):
    page, code = BLOCKS[i]
    d, rc, out, err = finished[i]
    assert rc == 0, f"{page} example failed:\n{code}\n--- stderr ---\n{err[-3000:]}"
    for name in re.findall(r"save(?:_plot)?\(\"([^\"]+)\"\)", code):
        assert (d / name).is_file() and (d / name).stat().st_size > 0, f"{page} example did not write {name}"
    assert out.strip(), "every example prints something"
