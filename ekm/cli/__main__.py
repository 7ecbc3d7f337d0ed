"""``python -m ekm.cli …``: the same as the ``ekm`` console script."""

import sys

from ekm.cli import main

sys.exit(main())
