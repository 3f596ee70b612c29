"""``python -m sunset.bench``: see :mod:`sunset.bench`."""

import sys

from . import main

sys.exit(main())
