"""``python -m sunset``: the same as the ``sunset`` command."""

import sys

from .cli import main

sys.exit(main())
