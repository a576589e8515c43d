"""``python -m mimics`` runs the command line."""

import sys

from mimics.interfaces.cli import main

sys.exit(main())
