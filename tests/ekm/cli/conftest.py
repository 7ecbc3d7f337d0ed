"""Fixtures of the command-line tests."""

import pytest

from ekm.cli import main


@pytest.fixture(scope="session")
def trained(tmp_path_factory):
    """A small indirect map trained by ``ekm train`` once per test session: ``(dir, map file, plot, train JSON)``.
    Every test that uses it can run alone."""
    d = tmp_path_factory.mktemp("maps")
    out, plot = d / "ind.npz", d / "ind.png"
    code = main(["train", "--mapping", "indirect", "--neurons", "8", "--steps", "1500", "--trials", "2",
                 "--eval-every", "500", "--eval-targets", "10", "--out", str(out), "--plot", str(plot), "--json"])
    assert code == 0
    return d, out, plot


@pytest.fixture
def cli(capsys):
    """``cli(*argv)`` runs ``ekm ARGV`` in this process (arguments made strings) and returns ``(exit status,
    stdout, stderr)``."""
    def run(*argv):
        code = main([str(a) for a in argv])
        cap = capsys.readouterr()
        return code, cap.out, cap.err
    return run
