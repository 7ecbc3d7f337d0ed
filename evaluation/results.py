"""A comparison's (or a tournament's) results file: JSON Lines, one finished run a line, written as the runs finish.

The first line is the header, the comparison's settings::

    {"ekm_results": 1, "settings": {"worlds": [...], "architectures": [...], "labels": [...], "trials": 10,
     "seed": 0, "config": {...}, "map": null, "engine": "pymunk", "ekm_version": "0.1.0"}}

(``engine``: the world the runs drove in, ``pymunk`` or ``jax``; a file that does not say is pymunk's), then one line per finished run, in the order the runs finished::

    {"job": {"world": "maze:1003", "architecture": "fields:...", "label": "fields", "trial": 4, "seed": 4,
             "map": null, "engine": "pymunk", "ekm_version": "0.1.0"},
     "outcome": {... the run's record, as evaluation.compare.run_job returns it ...}}

Each line is written whole and flushed as its run arrives, so a crash loses at most the runs in flight;
a line cut short by a crash (the last one) is dropped when the file is read again. A run is the same
whatever process ran it (a pure function of its job), so the runs of a file and the runs still missing
make the same table as an uninterrupted comparison. A tournament's file (``ekm tournament --out``) is the same
format: its settings name the players, and each line is one game (:func:`evaluation.match.game_key`).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from ekm.errors import InputError
from ekm.files import atomic_write

FORMAT = 1


def key(world: str, label: str, trial: int) -> tuple[str, str, int]:
    """A run's place in its comparison: the world as given, the architecture's label, the trial."""
    return (world, label, int(trial))


def _read(path: Path) -> tuple[dict, list[dict], int]:
    """``(settings, records, length)`` of a results file: its header's settings, the outcome of every whole
    run line, and the length in bytes of its whole lines (a last line cut short is not counted)."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise InputError(f"{path}: no such results file") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    whole = data[:data.rfind(b"\n") + 1]
    lines = whole.decode("utf-8", errors="replace").splitlines()
    try:
        head = json.loads(lines[0]) if lines else None
    except json.JSONDecodeError:
        head = None
    if not isinstance(head, dict) or head.get("ekm_results") != FORMAT or not isinstance(head.get("settings"), dict):
        raise InputError(f"{path}: not an ekm results file (ekm compare or tournament --out; its first line is "
                         f"not the header of format {FORMAT})")
    records = []
    what = kind(head["settings"])
    for n, line in enumerate(lines[1:], 2):
        try:
            entry = json.loads(line)
            records.append(entry["outcome"])
        except (json.JSONDecodeError, KeyError, TypeError):
            raise InputError(f"{path}: line {n}: not a finished run or game") from None
        check_record(records[-1], what, f"{path}: line {n}")
    return head["settings"], records, len(whole)


#: What the tables read of each record, by the kind of file (:func:`kind`), as ``{key: type}``: "string",
#: "integer", "number", "boolean", a type ending in "?" may be null; ``failed`` (the reason), a generated world's
#: ``family`` and the motion measures (:data:`evaluation.motion.KEYS`) may be absent.
RECORD_KEYS = {
    "comparison": {"given": "string", "world": "string", "label": "string", "trial": "integer", "reached": "boolean",
                   "trapped": "boolean", "arrived": "boolean", "ended": "string", "collisions": "integer",
                   "contact_s": "number", "time_s": "number?", "path_m": "number?"},
    "tournament": {"pair": "pair", "seed": "integer", "players": "list", "goals": "pair?", "winner": "integer?"},
}


def check_record(record, what: str, where: str) -> None:
    """Refuse, in one line naming ``where`` (the file and line) and the key, a record read back from a results
    file that lacks a key the tables read (:data:`RECORD_KEYS`) or has one of the wrong type — checked as a world
    file is (:class:`robots.worldfile.Checker`), so that a hand-edited or damaged line is never counted as a run."""
    from robots.worldfile import _Checker as Checker

    ck = Checker(where)
    if not isinstance(record, dict):
        ck.fail("outcome", f"must be an object, got {type(record).__name__}")
    optional = {"failed": "string?"}
    if what == "comparison":
        from evaluation.motion import KEYS

        optional.update({"family": "string?"}, **{k: "number?" for k in KEYS})
    for name, type_ in {**RECORD_KEYS.get(what, {}), **optional}.items():
        key = f"outcome.{name}"
        if name not in record:
            if name not in optional:
                ck.fail(key, "missing")
            continue
        value = record[name]
        if type_.endswith("?"):
            if value is None:
                continue
            type_ = type_[:-1]
        if type_ == "pair":
            ck.vector(value, key, 2, "a pair of whole numbers")
            for i, v in enumerate(value):
                ck.integer(v, f"{key}[{i}]")
        elif type_ == "number":
            ck.number(value, key, nonneg=True)
        else:
            getattr(ck, type_)(value, key)
    if what == "comparison" and record["reached"]:
        for name in ("time_s", "path_m"):  # the means of the runs that reached the goal
            if record[name] is None:
                ck.fail(f"outcome.{name}", "must be a number for a run that reached the goal, got null")


def kind(settings: dict) -> str:
    """Which command's results file ``settings`` (its header's) are: "tournament", "comparison", or "another
    command" (settings of neither)."""
    if "tournament" in settings:
        return "tournament"
    return "comparison" if all(k in settings for k in ("worlds", "labels", "trials", "seed", "config")) \
        else "another command"


#: The command that writes each kind of results file.
COMMAND = {"comparison": "compare", "tournament": "tournament"}


def read(path) -> tuple[dict, list[dict]]:
    """The settings and the finished runs' records of the results file at ``path``."""
    settings, records, _ = _read(Path(path))
    return settings, records


class ResultsFile:
    """The results file of a running comparison: :meth:`append` writes one finished run.

    ``resume=False`` starts a new file (an existing one is refused: it holds someone's results);
    ``resume=True`` continues one made with the same ``settings`` (any other is refused with the first
    setting that differs) and :attr:`done` holds the records it already has, by ``key_of(record)`` (default
    :func:`key` of a comparison's run).
    """

    def __init__(self, path, settings: dict, *, resume: bool = False, option: str = "--out", key_of=None):
        self.path = Path(path)
        self.settings = settings
        self.done: dict[tuple, dict] = {}
        self.appended = 0  # runs written by this process
        if resume:
            old, records, length = _read(self.path)
            if kind(old) != kind(settings):
                raise InputError(f"--resume {self.path}: {whose(kind(old))} results file, not a {kind(settings)}'s "
                                 f"(ekm {COMMAND.get(kind(settings))} --out writes those)")
            difference = _difference(old, settings)
            if difference:
                raise InputError(f"--resume {self.path}: made with other settings ({difference})")
            key_of = key_of or (lambda r: key(r["given"], r["label"], r["trial"]))
            try:
                self.done = {key_of(r): r for r in records}
            except (KeyError, TypeError, ValueError):
                raise InputError(f"--resume {self.path}: its lines are not runs of this command") from None
            with open(self.path, "r+b") as f:  # drop a last line cut short by a crash
                f.truncate(length)
            self._file = open(self.path, "a", encoding="utf-8")
            return
        if self.path.exists():
            raise InputError(f"{option} {self.path}: exists; continue it with --resume {self.path}, or remove it")
        if not self.path.parent.is_dir():
            raise InputError(f"{option} {self.path}: no such directory {self.path.parent}")
        try:  # the header first, whole (a file without its header is no results file), then the runs
            with atomic_write(self.path) as tmp:
                tmp.write_text(json.dumps({"ekm_results": FORMAT, "settings": settings}, separators=(",", ":")) + "\n")
            self._file = open(self.path, "a", encoding="utf-8")
        except OSError as exc:
            raise InputError(f"{option} {self.path}: cannot write ({exc.strerror})") from None

    def _write(self, entry: dict) -> None:
        self._file.write(json.dumps(entry, separators=(",", ":")) + "\n")
        self._file.flush()
        os.fsync(self._file.fileno())

    def append(self, job: dict, record: dict) -> None:
        """Write one finished run: its job's identity and its record."""
        self._write({"job": job, "outcome": record})
        self.appended += 1

    def close(self) -> None:
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def whose(what: str) -> str:
    """``"a tournament's"``, ``"another command's"``: the article and the possessive of :func:`kind`'s answer."""
    return f"{'' if what.startswith('another') else 'a '}{what}'s"


#: The settings in the order a difference is reported: the first that differs is the one a user changed.
ORDER = ("worlds", "labels", "trials", "seed", "architectures", "engine", "config", "map", "ekm_version")


#: Settings a file may not say, and what its silence means: files made before ``ekm compare --engine`` ran on pymunk.
UNSAID = {"engine": "pymunk"}


def _difference(old: dict, new: dict) -> str:
    """The first setting that differs between a results file's ``old`` settings and ``new`` ones, as
    ``"NAME: OLD in the file, NEW now"`` (for a list, the first item that differs; for the scenario config, the
    first field); "" if none does."""
    for name in ORDER + tuple(sorted(set(old) | set(new) - set(ORDER))):
        a, b = old.get(name, UNSAID.get(name)), new.get(name, UNSAID.get(name))
        if a == b:
            continue
        if isinstance(a, dict) and isinstance(b, dict):
            field = next(k for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k))
            name, a, b = f"{name}.{field}", a.get(field), b.get(field)
        elif isinstance(a, list) and isinstance(b, list):
            if len(a) != len(b) or name in ("worlds", "labels"):
                a, b = ",".join(map(str, a)), ",".join(map(str, b))
            else:
                a, b = next((x, y) for x, y in zip(a, b) if x != y)
        return f"{name}: {_short(a)} in the file, {_short(b)} now"
    return ""


def _short(value) -> str:
    text = value if isinstance(value, str) else json.dumps(value)
    return text if len(text) <= 120 else text[:117] + "..."
