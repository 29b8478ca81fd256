"""python -m vibroimpact: the command `vibroimpact` (vibroimpact.cli)."""
import sys

from .cli import main

sys.exit(main())
