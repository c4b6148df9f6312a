"""``python -m growsim.experiment --docs``: print docs/configs.md."""

import sys

from growsim.experiment.docs import main

sys.exit(main())
