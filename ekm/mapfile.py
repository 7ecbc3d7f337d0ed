"""Save and load trained maps: ``.npz`` without pickle plus JSON metadata (docs/design.md §3).

A map file holds the maps of every training trial stacked along a leading axis:

- ``w`` ``(R, N², 2)`` float32 input weights (α_i rad, d_i m);
- ``M`` ``(R, N², 2, 2)`` (indirect) or ``c`` ``(R, N², 2)`` (direct) float32 outputs;
- ``metadata``: a JSON string — format version, mapping kind, lattice size, every hyper-parameter
  (:class:`ekm.config.EKMConfig` under ``"ekm"``, the training protocol, the robot), training steps,
  seed, package and JAX versions, and the training curve.

Files are written atomically (temporary file in the same directory, then rename), so an interrupted
save never leaves a half-written map. Loading checks the format version, the keys, shapes, dtypes and
finiteness and raises :class:`ekm.errors.InputError` naming the file and exactly what is wrong.
"""

from __future__ import annotations

import json
import math
import zipfile
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from ekm.config import EKMConfig
from ekm.direct import DirectEKM
from ekm.errors import InputError
from ekm.files import atomic_write
from ekm.indirect import IndirectEKM

FORMAT = "ekm-map"
# Version 2 added ``ekm.chart`` (the coordinates of the indirect maps' linear model, ``ekm.charts``).
# Version 1 files, written before it, hold maps trained in the thesis's polar coordinates and still load.
VERSION = 2
READABLE = (1, VERSION)


@dataclass(frozen=True)
class SavedMaps:
    """Maps of R trials (a stacked pytree), their configuration and metadata."""

    ekm: DirectEKM | IndirectEKM
    cfg: EKMConfig
    meta: dict
    arena: tuple[float, float] = (1.0, 1.0)  # m: the arena the maps were trained and are tested in
    curve: tuple = ()  # the training curve: ({"step", "E_mm", ...}, ...)

    @property
    def trials(self) -> int:
        return int(self.ekm.w.shape[0])


def _output_name(mapping: str) -> str:
    return "M" if mapping == "indirect" else "c"


def save_maps(path, ekm_stack, cfg: EKMConfig, meta: dict | None = None) -> Path:
    """Write the stacked maps ``ekm_stack`` (leading trial axis) to ``path`` atomically; returns the path."""
    import jax

    from ekm import __version__

    path = Path(path)
    out = _output_name(cfg.mapping)
    arrays = {"w": np.asarray(ekm_stack.w, np.float32), out: np.asarray(ekm_stack[1], np.float32)}
    if arrays["w"].ndim == 2:  # a single map: give it a trial axis
        arrays = {k: v[None] for k, v in arrays.items()}
    metadata = {"format": FORMAT, "version": VERSION, "mapping": cfg.mapping, "neurons": cfg.neurons,
                "trials": int(arrays["w"].shape[0]), "ekm": cfg.to_dict(),
                "package_version": __version__, "jax_version": jax.__version__, **(meta or {})}
    text = json.dumps(metadata, allow_nan=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_write(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, metadata=np.array(text), **arrays)
    return path


def load_maps(path) -> SavedMaps:
    """Read a map file written by :func:`save_maps`, checking everything (see module docstring)."""
    path = Path(path)
    where = str(path)
    if not path.is_file():
        raise InputError(f"{where}: no such map file")
    if not zipfile.is_zipfile(path):
        raise InputError(f"{where}: not a map file (not an .npz archive)")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except ValueError as exc:  # e.g. an object array, which would need pickle
        raise InputError(f"{where}: refused ({_first_line(exc)})") from None
    except Exception as exc:  # noqa: BLE001 — a damaged archive or array header fails in many ways inside numpy
        raise InputError(f"{where}: not a map file (cannot read it as .npz: {exc.__class__.__name__}: "
                         f"{_first_line(exc)})") from None
    if "metadata" not in arrays:
        raise InputError(f"{where}: not an ekm map file (no 'metadata' entry)")
    try:
        meta = json.loads(str(arrays.pop("metadata")))
    except (json.JSONDecodeError, TypeError) as exc:
        raise InputError(f"{where}: metadata is not valid JSON ({exc})") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise InputError(f"{where}: not an ekm map file (metadata format is {meta.get('format')!r})"
                         if isinstance(meta, dict) else f"{where}: metadata must be a JSON object")
    if meta.get("version") not in READABLE:
        raise InputError(f"{where}: map format version {meta.get('version')!r} is not supported "
                         f"(this ekm reads versions {', '.join(map(str, READABLE))})")
    _check_read_types(meta, where)
    try:
        known = {f.name for f in fields(EKMConfig)}
        ekm_meta = {k: v for k, v in meta["ekm"].items() if k in known}
        if meta["version"] == 1:
            ekm_meta["chart"] = "polar"
        cfg = EKMConfig(**ekm_meta)
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{where}: metadata 'ekm' is invalid ({exc})") from None
    out = _output_name(cfg.mapping)
    expected = {"w": (cfg.size, 2), out: (cfg.size, 2, 2) if out == "M" else (cfg.size, 2)}
    extra = set(arrays) - set(expected)
    if extra:
        raise InputError(f"{where}: unexpected arrays {sorted(extra)} for a {cfg.mapping} map")
    trials = None
    for name, shape in expected.items():
        if name not in arrays:
            raise InputError(f"{where}: missing array {name!r} of a {cfg.mapping} map")
        a = arrays[name]
        if a.dtype.kind != "f":
            raise InputError(f"{where}: array {name!r} has dtype {a.dtype}, expected floating point")
        if a.ndim != len(shape) + 1 or a.shape[1:] != shape:
            raise InputError(f"{where}: array {name!r} has shape {a.shape}, expected (trials, {', '.join(map(str, shape))})")
        if trials is not None and a.shape[0] != trials:
            raise InputError(f"{where}: array {name!r} has {a.shape[0]} trials, 'w' has {trials}")
        trials = a.shape[0]
        if not np.all(np.isfinite(a)):
            raise InputError(f"{where}: array {name!r} contains NaN or infinite values")
        if name == "w" and np.any(np.abs(a[..., 0]) > np.float32(np.pi)):  # ekm.kohonen.wrap_once needs it
            raise InputError(f"{where}: array 'w' has directions outside [-pi, pi] (column 0 is an angle in rad)")
    if trials == 0:
        raise InputError(f"{where}: the file holds no maps (0 trials)")
    arena, curve = _checked_protocol(meta, where)
    import jax.numpy as jnp

    w, o = jnp.asarray(arrays["w"], jnp.float32), jnp.asarray(arrays[out], jnp.float32)
    ekm = IndirectEKM(w, o) if cfg.mapping == "indirect" else DirectEKM(w, o)
    return SavedMaps(ekm=ekm, cfg=cfg, meta=meta, arena=arena, curve=curve)


def _first_line(exc: BaseException) -> str:
    """An exception's message cut to its first line (numpy's can span several), so errors stay one line."""
    return str(exc).strip().splitlines()[0] if str(exc).strip() else exc.__class__.__name__


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


#: The metadata the package reads besides the protocol (:func:`_checked_protocol`), with the JSON type each must
#: have when present: the rest of the metadata is kept as a record and never read.
READ_TYPES = {"seed": int, "steps": int, "seconds": float, "world": str, "package_version": str, "jax_version": str}


def _check_read_types(meta: dict, where: str) -> None:
    """Refuse in one line a value of the wrong JSON type where the package reads it: every field of ``ekm`` (as
    :class:`EKMConfig` types it: ``true`` is no number), ``robot.name`` and :data:`READ_TYPES`."""

    def fits(value, kind) -> bool:
        if kind is float:
            return isinstance(value, (int, float)) and not isinstance(value, bool)
        return isinstance(value, kind) and not (kind is int and isinstance(value, bool))

    ekm_meta = meta.get("ekm")
    if not isinstance(ekm_meta, dict):
        raise InputError(f"{where}: metadata 'ekm' must be an object, got {json.dumps(ekm_meta)}")
    kinds = {"float": float, "int": int, "str": str, "int | None": (int, type(None))}
    for f in fields(EKMConfig):
        kind = kinds.get(f.type if isinstance(f.type, str) else f.type.__name__)
        if f.name in ekm_meta and kind is not None and not (
                fits(ekm_meta[f.name], int) or ekm_meta[f.name] is None if isinstance(kind, tuple)
                else fits(ekm_meta[f.name], kind)):
            raise InputError(f"{where}: metadata 'ekm.{f.name}' must be {f.type}, got {json.dumps(ekm_meta[f.name])}")
    robot = meta.get("robot")
    if robot is not None and not (isinstance(robot, dict) and isinstance(robot.get("name", ""), str)):
        raise InputError(f"{where}: metadata 'robot' must be an object with a name, got {json.dumps(robot)[:60]}")
    for key, kind in READ_TYPES.items():
        if key in meta and meta[key] is not None and not fits(meta[key], kind):
            raise InputError(f"{where}: metadata '{key}' must be {kind.__name__}, got {json.dumps(meta[key])[:60]}")


def _checked_protocol(meta: dict, where: str):
    """The arena (``train.arena``) and the training curve of the metadata, checked."""
    train = meta.get("train", {})
    if not isinstance(train, dict):
        raise InputError(f"{where}: metadata 'train' must be an object")
    arena = train.get("arena", [1.0, 1.0])
    if not (isinstance(arena, list) and len(arena) == 2 and all(_finite(a) and a > 0 for a in arena)):
        raise InputError(f"{where}: metadata 'train.arena' must be two positive numbers, got {arena!r}")
    curve = meta.get("curve", [])
    if not isinstance(curve, list) or not all(isinstance(p, dict) and _finite(p.get("step")) and _finite(p.get("E_mm"))
                                              for p in curve):
        raise InputError(f"{where}: metadata 'curve' must be a list of {{step, E_mm, ...}} points")
    return (float(arena[0]), float(arena[1])), tuple(curve)
