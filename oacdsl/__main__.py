"""``python -m oacdsl`` runs the ``oacc`` command line."""

import sys

from oacdsl.cli import main

sys.exit(main())
