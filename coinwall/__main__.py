"""``python -m coinwall``: the command line."""

import sys

from coinwall.cases.cli import main

sys.exit(main())
