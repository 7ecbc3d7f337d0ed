"""Writing output files safely: a file is either complete or not there (docs/design.md §3, §6)."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def atomic_write(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; when the block succeeds it replaces ``path`` in one rename.

    The temporary file keeps ``path``'s suffix (so writers that infer the format from it still work) and
    is removed if the block raises: a crash or a bad input never leaves a half-written ``path`` behind.
    The final file gets the usual permissions (``0o666`` minus the umask).

    Examples
    --------
    >>> with atomic_write("map.npz") as tmp:          # doctest: +SKIP
    ...     np.savez(tmp, **arrays)
    """
    path = Path(path)
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix or ".tmp")
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
