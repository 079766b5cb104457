"""``python -m smacc_py.scaffold`` is ``smacc-new``."""

import sys

from smacc_py.scaffold import main

sys.exit(main())
