"""``python -m linkgen``: the command line."""

import sys

from linkgen.cli.main import main

sys.exit(main())
