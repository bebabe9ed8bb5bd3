"""``python -m fricstab`` is the ``fricstab`` command."""

import sys

from fricstab.cli import main

sys.exit(main())
