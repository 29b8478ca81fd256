"""The values of the FMU's `solver` enumeration, for tests that run every solver."""
import pytest

from conftest import SOLVER

SOLVERS = {"bdf": 1, "adams": 2, "dop853": 3, "auto": 4}
# every solver; only VI_SOLVER's when the suite runs for one solver (conftest.py)
_RUN = {k: v for k, v in SOLVERS.items() if SOLVER is None or v == SOLVER}
each_solver = pytest.mark.parametrize("solver", list(_RUN.values()), ids=list(_RUN))
