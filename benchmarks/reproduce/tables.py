"""Write the result tables of the README and the reproduction pages from the commands they quote.

Each table sits in a page between ``<!-- table: NAME -->`` and ``<!-- end table -->``; this script runs the
table's command (through the Python API, which the command wraps), renders the table and puts it there.

    python benchmarks/reproduce/tables.py                   # every table: run, render, rewrite the pages
    python benchmarks/reproduce/tables.py compare ch62      # only these
    python benchmarks/reproduce/tables.py --check           # fail (exit 1) where a page differs; write nothing
    python benchmarks/reproduce/tables.py --cache /tmp/t    # keep each command's result, reuse it next time
    python benchmarks/reproduce/tables.py --check --long    # the check of the LONG tables too (hours)

Every table here is deterministic — a comparison is the same run for run on any number of workers, and
training is bit for bit the same for the same seed on the same machine — so ``--check`` is how CI knows
the pages say what the commands give (the slow test ``tests/docs/test_tables.py``).
"""

from __future__ import annotations

import argparse
import functools
import re
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parents[2]
PAGES = ("README.md", "docs/reproduce/ch61.md", "docs/reproduce/ch62.md", "docs/reproduce/comparison.md",
         "docs/reproduce/generalisation.md", "docs/reproduce/discrete.md", "docs/reproduce/adaptation.md")
NAMED = ("three-rooms-static", "three-rooms-moving", "three-rooms-changed", "extended-obstacle", "concave-obstacle",
         "three-rooms", "open-arena", "moving-target")
FIGURES = {"three-rooms-static": "6.3, 6.6", "three-rooms-moving": "6.4", "three-rooms-changed": "6.5",
           "extended-obstacle": "6.7", "concave-obstacle": "6.8"}
SUITE = "corridor:20,traps:20,clutter:20,maze:20,movers:20,blocked:20"
# Command fusion as ch. 4.4-4.5 wrote it: every reading avoided, Z facing the robot's front (docs/reproduce/ch62.md).
THESIS_FUSION = "fusion:avoid=all,facing=front,remember=false,lane=1,escape_s=0"
# ch. 6.2.2
THESIS_FUSION_LONG = "fusion:sensors=long,period=0.128,avoid=all,facing=front,remember=false,lane=1,escape_s=0"
THESIS_FIELDS = "fields,fields:form=thesis"
THESIS_ARCHITECTURES = f"{THESIS_FUSION},{THESIS_FUSION_LONG},{THESIS_FIELDS}"
CLAIM_ARCHITECTURES = "fusion,fields,schema,samba,subsumption,damn,deliberation"
CLAIM_SUITE = "corridor:10,traps:10,clutter:10,maze:10,movers:10,blocked:10"
LEVELS = "deliberation,deliberation:level=half,deliberation:level=none"
ROBOTS = ("khepera", "worn-wheel", "weak-motor", "wide-base", "slippery", "e-puck")
LEARNING = "fusion,fields"  # the architectures whose maps learn with --learn
STILL = "samba,schema,subsumption,damn,deliberation"  # ... and those that have nothing to learn
THESIS_HEADS = {THESIS_FUSION: "fusion, short-range (ch. 6.2.1)",
                THESIS_FUSION_LONG: "fusion, long-range, 0.128 s (ch. 6.2.2)",
                "fields": "fields (extended)", "fields:form=thesis": "fields, thesis form"}


# ------------------------------------------------------------------------------------------- commands

#: With ``--cache DIR``: each command's result is kept there as JSON and read back instead of run again (to
#: change how a table looks without running its command; never with ``--check``).
CACHE: Path | None = None


def cached(fn):
    """``fn``'s result (a comparison's rows, labels and families, or an evaluation's dict), from ``CACHE`` if it
    holds it."""
    import json
    from types import SimpleNamespace

    @functools.cache
    def run():
        file = CACHE / f"{fn.__name__}.json" if CACHE else None
        if file and file.exists():
            data = json.loads(file.read_text())
        else:
            result = fn()
            data = result.to_dict() if fn.__name__ in ("ch61", "adapt_arena") else \
                {"rows": list(result.rows), "labels": list(result.labels), "families": list(result.families),
                 "overall": list(result.overall)}
            if file:
                file.write_text(json.dumps(data))
        return data if fn.__name__ in ("ch61", "adapt_arena") else SimpleNamespace(**data)
    return run


@cached
def named_defaults():
    """``ekm compare --worlds NAMED --trials 10`` (the package's defaults)."""
    import ekm

    return ekm.compare(list(NAMED), "fusion,fields,samba,schema", trials=10)


@cached
def named_thesis():
    """``ekm compare --worlds NAMED --architectures THESIS_ARCHITECTURES --checkpoints thesis --no-recover
    --trials 10``."""
    import ekm

    return ekm.compare(list(NAMED), THESIS_ARCHITECTURES, checkpoints="thesis", recover=False, trials=10)


@cached
def suite_defaults():
    """``ekm compare --suite SUITE --trials 1``."""
    import ekm

    return ekm.compare(suite=SUITE, trials=1)


@cached
def suite_thesis():
    """``ekm compare --suite SUITE --trials 1 --architectures THESIS_FUSION,THESIS_FIELDS --checkpoints thesis
    --no-recover``."""
    import ekm

    return ekm.compare(suite=SUITE, architectures=f"{THESIS_FUSION},{THESIS_FIELDS}", checkpoints="thesis",
                       recover=False, trials=1)


@cached
def claim_named():
    """``ekm compare --worlds NAMED --architectures CLAIM_ARCHITECTURES --trials 10 --motion``."""
    import ekm

    return ekm.compare(list(NAMED), CLAIM_ARCHITECTURES, trials=10)


@cached
def claim_suite():
    """``ekm compare --suite CLAIM_SUITE --architectures CLAIM_ARCHITECTURES --trials 1 --motion``."""
    import ekm

    return ekm.compare(suite=CLAIM_SUITE, architectures=CLAIM_ARCHITECTURES, trials=1)


@cached
def claim_levels():
    """``ekm compare --suite CLAIM_SUITE --architectures deliberation,deliberation:level=half,deliberation:level=none
    --trials 1 --motion``."""
    import ekm

    return ekm.compare(suite=CLAIM_SUITE, architectures=LEVELS, trials=1)


@cached
def adapt_arena():
    """``ekm adapt`` (every named robot; fine-tuned 10,000 steps, from scratch 20,000; seeds 1000)."""
    import ekm

    return ekm.adapt()


def _robot_runs(name: str, robot: str, **where):
    """``ekm compare … --architectures LEARNING,STILL --robot ROBOT`` and ``… --architectures LEARNING --robot ROBOT
    --learn`` as one table: the learning runs labelled ``A --learn``."""
    import ekm
    from types import SimpleNamespace

    frozen = ekm.compare(architectures=f"{LEARNING},{STILL}", robot=robot, **where)
    learned = ekm.compare(architectures=LEARNING, robot=robot, learn=True, **where)
    rows = list(frozen.rows) + [{**r, "architecture": f"{r['architecture']} --learn"} for r in learned.rows]
    families = list(frozen.families) + [{**r, "architecture": f"{r['architecture']} --learn"} for r in learned.families]
    return SimpleNamespace(rows=rows, families=families, labels=list(frozen.labels))


def _cached_robot(kind: str, robot: str):
    """The runs of ``robot`` in the named worlds (``kind`` "named": 10 trials) or the claim's suite ("suite"),
    through the cache like every other command."""
    import json
    from types import SimpleNamespace

    file = CACHE / f"adapt_{kind}_{robot}.json" if CACHE else None
    if file and file.exists():
        return SimpleNamespace(**json.loads(file.read_text()))
    where = {"worlds": list(NAMED), "trials": 10} if kind == "named" else {"suite": CLAIM_SUITE, "trials": 1}
    result = _robot_runs(kind, robot, **where)
    if file:
        file.write_text(json.dumps(result.__dict__))
    return result


@cached
def ch61():
    """``ekm train --mapping indirect --out indirect.npz && ekm train --mapping direct --out direct.npz``, then
    ``ekm evaluate indirect.npz direct.npz``."""
    import ekm

    with tempfile.TemporaryDirectory() as d:
        maps = [ekm.train(mapping=m, out=f"{d}/{m}.npz") for m in ("indirect", "direct")]
        return ekm.evaluate([m.path for m in maps])


# ------------------------------------------------------------------------------------------ rendering

def _count(r) -> str:
    if r["success_rate"] is None:
        return "failed"
    made = r["trials"] - r["failed"]
    return f"{round(r['success_rate'] * made)}/{made}"


def _cell(r, *, ci=False, time=False, path=False, trapped=False, collisions=False, best=False) -> str:
    text = f"**{_count(r)}**" if best else _count(r)
    parts = [text + (f" ({r['success_ci95'][0]:.2f}–{r['success_ci95'][1]:.2f})" if ci and r["success_ci95"] else "")]
    if time and r["mean_time_s"] is not None:
        parts.append(f"{r['mean_time_s']:.1f} s")
    if path and r["mean_path_m"] is not None:
        parts.append(f"{r['mean_path_m']:.2f} m")
    if trapped and r["trapped"]:
        parts.append(f"T {r['trapped']}")
    if collisions and r["collisions"]:
        parts.append(f"C {r['collisions']}")
    return ", ".join(parts)


def _grid(rows_of, keys, labels, key_name, name_of, heads=None, **cell) -> list[str]:
    """A table: one line per key (world or family), one column per architecture (headed by ``heads``, default
    the labels); the best success of each line in bold, unless every column has it."""
    heads = heads or {}
    lines = [f"| {key_name} | " + " | ".join(heads.get(a, a) for a in labels) + " |",
             "|---|" + "---|" * len(labels)]
    for key in keys:
        rs = [rows_of(key, a) for a in labels]
        rates = [r["success_rate"] or 0.0 for r in rs]
        top, shared = max(rates), len(set(rates)) == 1
        lines.append(f"| {name_of(key)} | " + " | ".join(
            _cell(r, best=r["success_rate"] == top and top > 0 and not shared, **cell) for r in rs) + " |")
    return lines


def _by_world(table):
    rows = {(r["world"], r["architecture"]): r for r in table.rows}
    return lambda w, a: rows[(w, a)]


def _by_family(table):
    rows = {(r["family"], r["architecture"]): r for r in table.families}
    return lambda f, a: rows[(f, a)]


def _families(table) -> list[str]:
    return list(dict.fromkeys(r["family"] for r in table.families))


def _world_name(w: str) -> str:
    return f"`{w}` ({FIGURES[w]})" if w in FIGURES else f"`{w}`"


def _family_name(f: str) -> str:
    return "all 120" if f == "all" else f"`{f}`"


def compare_long():
    t = named_defaults()
    return _grid(_by_world(t), NAMED, t.labels, "world", lambda w: f"`{w}`", ci=True, time=True, collisions=True)


def ch62():
    t = named_thesis()
    return _grid(_by_world(t), NAMED, t.labels, "world (thesis figure)", _world_name, THESIS_HEADS, path=True,
                 trapped=True, collisions=True)


def generalisation():
    t = suite_defaults()
    return _grid(_by_family(t), _families(t), t.labels, "family", _family_name, ci=True)


def generalisation_thesis():
    t = suite_thesis()
    return _grid(_by_family(t), _families(t), t.labels, "family", _family_name, THESIS_HEADS, trapped=True,
                 collisions=True)


def _motion_cell(m, scale, digits) -> str:
    if m["mean"] is None:
        return ""
    lo, hi = (x * scale for x in m["ci95"])
    return f"{m['mean'] * scale:.{digits}f} ({lo:.{digits}f}–{hi:.{digits}f})"


def _motion_table(overall, keys=None) -> list[str]:
    """One line per architecture (its encoding, success over all its runs, each motion measure — those of
    ``keys``, default all — as mean (95 % interval)); the lowest mean of each measure in bold."""
    from evaluation.motion import MEASURES
    from robots.controllers.spec import ARCHITECTURES

    columns = [m for m in MEASURES if keys is None or m.key in keys]
    best = {m.key: min(r["motion"][m.key]["mean"] for r in overall if r["motion"][m.key]["mean"] is not None)
            for m in columns}
    lines = ["| architecture | encoding | success | " + " | ".join(m.head for m in columns) + " |",
             "|---|---|---|" + "---|" * len(columns)]
    for r in overall:
        cells = []
        for m in columns:
            cell = _motion_cell(r["motion"][m.key], m.scale, m.digits)
            top = r["motion"][m.key]["mean"] is not None and round(r["motion"][m.key]["mean"] * m.scale, m.digits) \
                == round(best[m.key] * m.scale, m.digits)
            cells.append(f"**{cell}**" if top else cell)
        lines.append(f"| `{r['architecture']}` | {ARCHITECTURES[r['architecture']].encoding} | {_count(r)} | "
                     + " | ".join(cells) + " |")
    return lines


def claim():
    return _motion_table(claim_named().overall)


def claim_readme():
    return _motion_table(claim_named().overall, ("angular_accel_rms", "stopped_s", "turn_reversals_per_m",
                                                 "stop_distance_m"))


def claim_suite_table():
    return _motion_table(claim_suite().overall)


def claim_smoothness():
    """Angular acceleration (rad/s², RMS; mean over the world's runs) by world and architecture."""
    t = claim_named()
    rows = _by_world(t)
    lines = ["| world | " + " | ".join(f"`{a}`" for a in t.labels) + " |", "|---|" + "---|" * len(t.labels)]
    for w in NAMED:
        values = [rows(w, a)["motion"]["angular_accel_rms"]["mean"] for a in t.labels]
        low = min(values)
        lines.append(f"| `{w}` | " + " | ".join(f"**{v:.2f}**" if v == low else f"{v:.2f}" for v in values) + " |")
    return lines


def claim_worlds():
    t = claim_named()
    return _grid(_by_world(t), NAMED, t.labels, "world", lambda w: f"`{w}`", time=True, collisions=True)


def levels():
    """Sahota's three levels by family: success, then angular acceleration and time stopped over all 60."""
    t = claim_levels()
    heads = {"deliberation": "full (reactive deliberation)", "deliberation:level=half": "half-wit",
             "deliberation:level=none": "no-wit"}
    lines = _grid(_by_family(t), _families(t), t.labels, "family", lambda f: "all 60" if f == "all" else f"`{f}`",
                  heads, time=True, collisions=True)
    overall = {r["architecture"]: r["motion"] for r in t.overall}
    for key, name, digits in (("angular_accel_rms", "angular acc. (rad/s², RMS)", 2),
                              ("stopped_s", "stopped away from the goal (s)", 1)):
        lines.append(f"| {name} | " + " | ".join(_motion_cell(overall[a][key], 1.0, digits) for a in t.labels) + " |")
    return lines


def claim_families():
    t = claim_suite()
    return _grid(_by_family(t), _families(t), t.labels, "family", lambda f: "all 60" if f == "all" else f"`{f}`",
                 ci=True)


def ch61_table():
    ev = ch61()
    lines = ["| after 100,000 steps | E (mm) | P(5) | P(10) | P(25) | T(5) | T(10) | T(25) steps/m | D(5) | D(10) | "
             "D(25) | capped |", "|---|" + "---:|" * 11]
    for m in ev["maps"]:
        name = f"**{m['mapping']}**" if m["mapping"] == "indirect" else m["mapping"]
        cells = [f"{m['E_mm']:.2f}"] + [f"{m['P'][e]:.3f}" for e in ("5", "10", "25")] + \
                [f"{m['T'][e]:.1f}" if e != "25" else f"{m['T'][e]:.2f}" for e in ("5", "10", "25")] + \
                [f"{m['D'][e]:.3f}" for e in ("5", "10", "25")] + [f"{m['capped']} / {m['trials'] * m['targets']}"]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return lines + ["| thesis, indirect (Webots) | ≈ 3 | | | > 0.9 | | | ≈ 9 | | | < 0.09 | |",
                    "| thesis, direct (Webots) | ≈ 8 | | | < 0.9 | | | ≈ 17.5 | | | ≈ 0.18 | |"]


def adaptation_table():
    """Each robot: the frozen, fine-tuned and from-scratch maps' E (95 % interval), T(5), D(25), and the steps to E ≤ 3
    mm and to the from-scratch map's T(5)."""
    t = adapt_arena()

    def cell(p):
        return f"{p['E_mm']:.2f} ({p['E_ci95'][0]:.2f}–{p['E_ci95'][1]:.2f}), {p['T5']:.1f}, {p['D25']:.3f}"

    def steps(pair):
        return " / ".join("never" if x is None else f"{x:,}" for x in (pair["fine_tuned"], pair["scratch"]))

    lines = ["| robot | frozen: E mm (95 %), T(5), D(25) | fine-tuned, 10,000 steps | from scratch, 20,000 steps | "
             "steps to E ≤ 3 mm: fine-tuned / scratch | steps to scratch's T(5): fine-tuned / scratch |",
             "|---|---|---|---|---|---|"]
    for r in t["robots"]:
        m = r["summary"]
        lines.append(f"| `{r['robot']}` | {cell(m['frozen'])} | {cell(m['fine_tuned'])} | {cell(m['scratch'])} | "
                     f"{steps(m['steps_to_thesis_E'])} | {steps(m['steps_to_scratch_T5'])} |")
    return lines


def _robots_grid(kind: str, key: str, motion: bool = False) -> list[str]:
    """Success of every architecture on every robot (``kind``: the named worlds or the claim's suite), the learning
    architectures frozen and with --learn; with ``motion``, the mean time and path of the runs that reached the goal
    (the suite's "all" row; ``kind`` "suite" only)."""
    order = [*LEARNING.split(","), *(f"{a} --learn" for a in LEARNING.split(",")), *STILL.split(",")]
    heads = [f"`{a}`" for a in order]
    lines = ["| robot | " + " | ".join(heads) + " |", "|---|" + "---|" * len(order)]
    for robot in ROBOTS:
        t = _cached_robot(kind, robot)
        totals = {}
        for r in (t.rows if kind == "named" else [f for f in t.families if f["family"] == "all"]):
            k, n = totals.get(r["architecture"], (0, 0))
            made = r["trials"] - r["failed"]
            totals[r["architecture"]] = (k + round((r["success_rate"] or 0.0) * made), n + made)
        from evaluation.compare import wilson

        every = {r["architecture"]: r for r in t.families if r["family"] == "all"} if motion else {}
        cells = []
        for a in order:
            k, n = totals[a]
            lo, hi = wilson(k, n)
            cell = f"{k}/{n} ({lo:.2f}–{hi:.2f})"
            if motion and every[a]["mean_time_s"] is not None:
                cell += f", {every[a]['mean_time_s']:.0f} s, {every[a]['mean_path_m']:.2f} m"
            cells.append(cell)
        lines.append(f"| `{robot}` | " + " | ".join(cells) + " |")
    return lines


def adaptation_named():
    return _robots_grid("named", "worlds")


def adaptation_suite():
    return _robots_grid("suite", "families", motion=True)


@dataclass(frozen=True)
class Table:
    name: str
    render: Callable[[], list[str]]


TABLES = {t.name: t for t in (
    Table("ch61", ch61_table), Table("ch62", ch62), Table("compare-intervals", compare_long),
    Table("generalisation", generalisation), Table("generalisation-thesis", generalisation_thesis),
    Table("claim", claim), Table("claim-readme", claim_readme), Table("claim-worlds", claim_worlds),
    Table("claim-smoothness", claim_smoothness),
    Table("claim-suite", claim_suite_table), Table("claim-families", claim_families), Table("levels", levels),
    Table("adaptation", adaptation_table), Table("adaptation-named", adaptation_named),
    Table("adaptation-suite", adaptation_suite))}

#: Tables whose commands take hours on 2 cores (six robots, each trained from scratch and run through every named
#: world and the suite): made like the others, left out of a plain ``--check`` (CI's, about 15 min) unless named or
#: ``--long`` is given.
LONG = ("adaptation", "adaptation-named", "adaptation-suite")

BLOCK = re.compile(r"(<!-- table: (?P<name>[a-z0-9-]+) -->\n)(?P<body>.*?)(<!-- end table -->)", re.S)


def update(text: str, rendered: dict[str, str]) -> str:
    """``text`` with every marked table whose name is in ``rendered`` replaced by its rendering."""
    def put(m):
        name = m.group("name")
        if name not in rendered:
            return m.group(0)
        return m.group(1) + rendered[name] + m.group(4)
    return BLOCK.sub(put, text)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("names", nargs="*", help=f"tables to make (default all: {', '.join(TABLES)})")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 if a page differs")
    parser.add_argument("--long", action="store_true", help=f"with --check and no names: the long tables too "
                                                             f"({', '.join(LONG)})")
    parser.add_argument("--cache", metavar="DIR", help="keep each command's result in DIR and reuse it (not with --check)")
    args = parser.parse_args(argv)
    if args.cache and args.check:
        parser.error("--cache: the check runs every command afresh")
    global CACHE
    CACHE = Path(args.cache) if args.cache else None
    if CACHE:
        CACHE.mkdir(parents=True, exist_ok=True)
    unknown = [n for n in args.names if n not in TABLES]
    if unknown:
        parser.error(f"unknown table {unknown[0]!r} (tables: {', '.join(TABLES)})")
    names = args.names or [n for n in TABLES if args.long or not args.check or n not in LONG]
    used = {m.group("name") for p in PAGES for m in BLOCK.finditer((ROOT / p).read_text())}
    rendered = {n: "\n".join(TABLES[n].render()) + "\n" for n in names if n in used}
    differ = []
    for page in PAGES:
        path = ROOT / page
        old = path.read_text()
        new = update(old, rendered)
        if new != old:
            differ.append(page)
            if not args.check:
                path.write_text(new)
    for page in differ:
        print(f"{'differs' if args.check else 'rewrote'}: {page}")
    return 1 if (args.check and differ) else 0


if __name__ == "__main__":
    sys.exit(main())
