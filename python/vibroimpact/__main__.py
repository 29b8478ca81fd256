"""python -m vibroimpact: the command `vibroimpact` (cli.py)."""
import sys

from .cli import main

sys.exit(main())
