"""``python -m ekm.cli …``: the same as the ``ekm`` console script (:mod:`ekm.__main__`)."""

from ekm.__main__ import console

console()
