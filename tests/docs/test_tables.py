"""The result tables of the README and the reproduction pages say what their commands give:
``benchmarks/reproduce/tables.py`` renders each from its command, and ``--check`` (the slow test) fails where
a page differs."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "reproduce" / "tables.py"
_spec = importlib.util.spec_from_file_location("reproduce_tables", SCRIPT)
tables = sys.modules["reproduce_tables"] = importlib.util.module_from_spec(_spec)  # dataclasses look it up
_spec.loader.exec_module(tables)


def test_update_replaces_only_the_named_tables_and_keeps_the_markers():
    text = ("intro\n<!-- table: a -->\n| old a |\n<!-- end table -->\nmiddle\n"
            "<!-- table: b -->\n| old b |\n<!-- end table -->\nend\n")
    assert tables.update(text, {"a": "| new a |\n"}) == (
        "intro\n<!-- table: a -->\n| new a |\n<!-- end table -->\nmiddle\n"
        "<!-- table: b -->\n| old b |\n<!-- end table -->\nend\n")
    assert tables.update(text, {}) == text


def test_every_marked_table_has_a_command_and_every_command_a_page():
    used = {m.group("name") for page in tables.PAGES for m in tables.BLOCK.finditer((ROOT / page).read_text())}
    assert used == set(tables.TABLES)
    assert "<!-- table: ch61 -->" in (ROOT / "README.md").read_text()


def test_an_unknown_table_is_refused_in_one_line():
    proc = subprocess.run([sys.executable, str(SCRIPT), "--check", "ch99"], capture_output=True, text=True)
    assert proc.returncode == 2 and "unknown table 'ch99'" in proc.stderr and "Traceback" not in proc.stderr


@pytest.mark.slow
def test_the_pages_say_what_the_commands_give():
    """Every command of every table but the LONG ones (hours: ``tables.py --check --long``), run afresh (about
    15 min on 2 cores)."""
    proc = subprocess.run([sys.executable, str(SCRIPT), "--check"], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stdout + proc.stderr[-3000:]
