"""A fuzzer of our own over every file and spelling a user hands the package (issue 34, slow suite).

Seeded mutations of valid inputs — world files, map files' metadata, soccer field files, robot files, results
files, and the spellings of architectures and players — each one change: a value at a random place replaced by
one of another JSON type (or by NaN, a negative number, a huge one), a key dropped, an unknown key added; the
spellings are random strings of names, misspellings, ``:``, ``,``, ``=``, spaces, keys and values. Every input
either loads or is refused with one :class:`ekm.InputError` line (:func:`tests.fuzzing.assert_loads_or_refuses`:
no other exception, no warning), and a value replaced by one of another type is never accepted silently — except
where the format takes both (:data:`EITHER`). The counts are fixed (:data:`COUNT` per kind) and the mutations
seeded, so every run tries the same inputs; docs/guide/refused.md gives the total.
"""

import copy
import json
import math
import random
from pathlib import Path

import numpy as np
import pytest

from tests.fuzzing import assert_loads_or_refuses

pytestmark = pytest.mark.slow

#: Inputs tried per kind (seven kinds: docs/guide/refused.md gives the total).
COUNT = 500
ROOT = Path(__file__).resolve().parents[1]

#: Values a mutation puts in place of another.
VALUES = ["x", "", None, True, False, -1, 0, 1e9, 0.5, [], [1, 2], [0.1, 0.2, 0.3], {}, {"a": 1}, math.nan]

#: Places (a path's keys and indices joined by ".", indices as "#") where the format takes a value of either type.
EITHER = ("goal",)  # a world's goal: a point [x, y] or a moving target {"path": …}

#: What the package reads of a map file's metadata (ekm.mapfile): the rest is a record of how the map was made.
MAP_READ = ("format", "version", "ekm", "train.arena", "robot.name", "seed", "steps", "seconds", "world",
            "package_version", "jax_version")


def kind_of(value) -> str:
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, (int, float)):
        return "number"
    if value is None:
        return "null"
    return type(value).__name__


def places(doc, path=()):
    """Every (path, value) in a JSON document, the document itself first."""
    yield path, doc
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from places(v, path + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from places(v, path + (i,))


def mutate(doc, rng: random.Random):
    """One change to a copy of ``doc``: ``(new document, path, old value, new value or a word for the change)``."""
    doc = copy.deepcopy(doc)
    spots = list(places(doc))[1:]
    path, old = rng.choice(spots)
    parent = doc
    for k in path[:-1]:
        parent = parent[k]
    op = rng.random()
    if op < 0.15 and isinstance(parent, dict):
        del parent[path[-1]]
        return doc, path, old, "dropped"
    if op < 0.25 and isinstance(parent, dict):
        parent["zz_unknown"] = 1
        return doc, path[:-1] + ("zz_unknown",), None, "added"
    new = rng.choice(VALUES)
    if rng.random() < 0.3 and kind_of(old) == "number":
        new = rng.choice([-abs(old) - 1.0, old * 1e6, math.inf, 0])
    parent[path[-1]] = new
    return doc, path, old, new


def spelt(path) -> str:
    return ".".join("#" if isinstance(k, int) else str(k) for k in path)


def fuzz(kind: str, doc: dict, load, seed: int, read=lambda place: True) -> int:
    """:data:`COUNT` mutations of ``doc`` through ``load(document)``; returns how many were refused. A value
    retyped at a place the loader reads (``read(place)``) must be refused, unless the format takes both
    (:data:`EITHER`)."""
    rng = random.Random(seed)
    refused = 0
    for n in range(COUNT):
        new_doc, path, old, new = mutate(doc, rng)
        result = assert_loads_or_refuses(lambda: load(new_doc))
        if result is None:
            refused += 1
            continue
        retyped = new not in ("dropped", "added") and kind_of(old) != kind_of(new)
        place = spelt(path)
        either = any(place.startswith(p) for p in EITHER) or not read(place)
        assert not retyped or either, f"{kind} #{n}: {place}: {old!r} -> {new!r} was accepted"
    return refused


def world_document():
    return json.loads((ROOT / "robots/worlds/three-rooms-moving.json").read_text())


def test_world_files():
    from robots.worldfile import parse_world

    assert fuzz("world", world_document(), lambda d: parse_world(d, "fuzz.json"), 1) > COUNT // 2


def test_robot_files():
    from robots.robotfile import parse_robot

    doc = json.loads((ROOT / "robots/models/khepera.json").read_text())
    assert fuzz("robot", doc, lambda d: parse_robot(d, "fuzz.json"), 2) > COUNT // 2


def test_field_files():
    from robots.soccer.fieldfile import parse_field

    doc = json.loads((ROOT / "robots/worlds/soccer/lci-cup.json").read_text())
    assert fuzz("field", doc, lambda d: parse_field(d, "fuzz.json"), 3) > COUNT // 2


def test_map_files_metadata(tmp_path):
    from ekm.mapfile import load_maps

    with np.load(ROOT / "ekm/data/indirect-signed.npz", allow_pickle=False) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(str(arrays.pop("metadata")))
    path = tmp_path / "fuzz.npz"

    def load(doc):
        np.savez(path, metadata=np.array(json.dumps(doc)), **arrays)
        return load_maps(path)

    read = (lambda place: any(place == p or place.startswith(p + ".") for p in MAP_READ)
            or place.startswith("curve.#.step") or place.startswith("curve.#.E_mm"))
    assert fuzz("map", meta, load, 4, read) > 0  # most mutations land in the training curve, a record


def test_results_files(tmp_path):
    """A comparison's results file whose records are mutated: read back by ``ekm compare --from``."""
    from ekm.api.comparing import load_comparison

    settings = {"worlds": ["open-arena"], "labels": ["fusion"], "trials": 2, "seed": 0,
                "config": {"time_limit": 20.0}, "architectures": ["fusion"]}
    runs = [{"given": "open-arena", "world": "open-arena", "label": "fusion", "trial": i, "seed": i, "reached": i == 0,
             "trapped": False, "arrived": i == 0, "ended": "stopped at the goal" if i == 0 else "time limit",
             "collisions": 0, "contact_s": 0.0, "time_s": 12.5 if i == 0 else None, "path_m": 1.1 if i == 0 else None,
             "family": None, "path_ratio": 1.2, "command_change_mps": 0.01}
            for i in range(2)]
    path = tmp_path / "fuzz.jsonl"

    def load(records):
        lines = [{"ekm_results": 1, "settings": settings}] + [{"job": {}, "outcome": r} for r in records]
        path.write_text("".join(json.dumps(line) + "\n" for line in lines))
        return load_comparison(path)

    from evaluation.results import RECORD_KEYS

    keys = set(RECORD_KEYS["comparison"]) | {"family", "path_ratio", "command_change_mps"}
    rng = random.Random(5)
    for n in range(COUNT):
        records, where, old, new = mutate(runs, rng)
        table = assert_loads_or_refuses(lambda: load(records))
        if table is not None and len(where) == 2 and where[1] in keys and new not in ("dropped", "added"):
            nullable = ("time_s", "path_m", "family", "path_ratio", "command_change_mps")
            assert kind_of(old) == kind_of(new) or (old is None or new is None) and where[1] in nullable, \
                f"results #{n}: {spelt(where)}: {old!r} -> {new!r} was accepted"


@pytest.mark.parametrize("kind", ["architecture", "player"])
def test_spellings(kind):
    from robots.controllers.spec import ArchitectureSpec
    from robots.soccer.roster import PlayerSpec

    spec = ArchitectureSpec if kind == "architecture" else PlayerSpec
    names = list(spec.registry.all())
    keys = sorted({f.name for n in names for f in __import__("dataclasses").fields(spec.registry[n].params)})
    words = names + [n[:-1] for n in names] + keys + ["1", "0.5", "-3", "nan", "true", "x", "short", "long", " "]
    marks = [":", ",", "=", ", ", ":", "="]
    rng = random.Random(6 if kind == "architecture" else 7)
    for _ in range(COUNT // 2):
        text = "".join(rng.choice(words + marks) for _ in range(rng.randint(0, 8)))
        assert_loads_or_refuses(lambda: spec.parse(text))
