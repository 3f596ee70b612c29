"""``python -m sunset``: the same as the ``sunset`` command."""

import sys

try:
    from .cli import main
except KeyboardInterrupt:                    # Ctrl-C while Python loads the command: one line, as main() says it
    print("sunset: interrupted", file=sys.stderr)
    sys.exit(130)

sys.exit(main())
