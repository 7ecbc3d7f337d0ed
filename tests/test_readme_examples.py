"""Every ```python block of README.md runs as written (issue 13): each saved as a script in a directory of
its own and run with this interpreter, as a user who copies it into a file would; the files it writes
(``save("….npz")``, ``save_plot("….png")``) must be there afterwards.

The blocks run side by side (each in its own process) to keep the test short; each is independent of
the others.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"^```python\n(.*?)^```$", README.read_text(), flags=re.M | re.S)
TIMEOUT = 600  # s, for all blocks together


def first_line(code: str) -> str:
    return next(line for line in code.splitlines() if line.strip() and not line.startswith("import"))[:60]


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """``{index: (directory, CompletedProcess-like (returncode, stdout, stderr))}`` of every block."""
    env = {**os.environ, "MPLBACKEND": "Agg"}
    running = {}
    for i, code in enumerate(BLOCKS):
        d = tmp_path_factory.mktemp(f"readme{i}")
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


def test_the_readme_has_a_quick_start_of_at_most_five_lines_and_an_example_per_use():
    assert len(BLOCKS) >= 5
    quick = [line for line in BLOCKS[0].splitlines() if line.strip()]
    assert len(quick) <= 5 and "ekm.load()" in BLOCKS[0] and "ekm.run(" in BLOCKS[0] and "plot" in BLOCKS[0]
    for use in ("ekm.train(", "ekm.evaluate(", "ekm.compare(", ".save(", "ekm.load("):
        assert any(use in b for b in BLOCKS[1:]), use


@pytest.mark.parametrize("i", range(len(BLOCKS)), ids=[first_line(b) for b in BLOCKS])
def test_readme_python_example_runs_as_written(finished, i):
    d, code, out, err = finished[i]
    assert code == 0, f"README block {i} failed:\n{BLOCKS[i]}\n--- stderr ---\n{err[-3000:]}"
    for name in re.findall(r"save(?:_plot)?\(\"([^\"]+)\"\)", BLOCKS[i]):
        assert (d / name).is_file() and (d / name).stat().st_size > 0, f"README block {i} did not write {name}"
    assert out.strip(), "every example prints something"
