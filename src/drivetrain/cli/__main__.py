"""``python -m drivetrain.cli``: the same entry point as the ``drivetrain`` command."""

import sys

from drivetrain.cli import main

sys.exit(main())
