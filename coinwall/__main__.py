"""``python -m coinwall``: the command line."""

import sys

from coinwall.cases.cli import main

if __name__ == "__main__":
    sys.exit(main())
