"""``python -m presag_opt.cli`` runs the ``presag`` command line."""

import sys

from presag_opt.cli import main

sys.exit(main())
