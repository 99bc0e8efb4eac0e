"""`python -m jaxdamp.cli ...` (the same as the `jaxdamp` console script)."""

import sys

from . import main

sys.exit(main())
