"""The API pages render every docstring as written: griffe — what mkdocstrings reads the docstrings with
(numpy style, mkdocs.yml) — parses every docstring of the five packages without a warning. A warning is a
docstring it misreads: a continuation line taken for a parameter named ``The``, a parameter the signature does
not have, a line it cannot parse. ``mkdocs build --strict`` (CI) fails on the same warnings; this test finds them
in a second, without building the site."""

import logging
from pathlib import Path

import pytest

griffe = pytest.importorskip("griffe")  # the docs extra: pip install '.[docs]'

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("ekm", "planner", "robots", "training", "evaluation")


def objects(obj):
    """``obj`` and everything defined in it (not what it imports)."""
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from objects(member)


def misreadings(package: str, path: Path = ROOT) -> tuple[int, list[str]]:
    """How many docstrings of ``package`` (found in ``path``) griffe parsed, and the warning of each it misread."""
    caught = []

    class Catch(logging.Handler):
        def emit(self, record):
            caught.append(record.getMessage())

    logger = logging.getLogger("griffe")
    handler, level = Catch(level=logging.WARNING), logger.level
    logger.addHandler(handler)
    logger.setLevel(logging.WARNING)
    try:
        docstrings = [o.docstring for o in objects(griffe.load(package, search_paths=[str(path)],
                                                               docstring_parser="numpy")) if o.docstring]
        for docstring in docstrings:
            docstring.parsed  # noqa: B018  (parsing is what warns)
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)
    return len(docstrings), caught


def test_the_check_finds_a_continuation_read_as_parameters(tmp_path):
    (tmp_path / "pitchlike.py").write_text('''
def f(field):
    """A pitch.

    Parameters
    ----------
    field : Field
        The walls.

    The ball starts still. Robots are added later (static or
    kinematic bodies).
    """
''')
    parsed, caught = misreadings("pitchlike", tmp_path)
    assert parsed == 1
    assert any("'The'" in line for line in caught) and any("'kinematic'" in line for line in caught)


@pytest.mark.parametrize("package", PACKAGES)
def test_griffe_reads_every_docstring_as_written(package):
    parsed, warnings = misreadings(package)
    assert parsed > 20 and warnings == []
