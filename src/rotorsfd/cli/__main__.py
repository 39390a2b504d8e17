"""``python -m rotorsfd.cli``: the command line."""

import sys

from rotorsfd.cli import main

sys.exit(main())
