"""The values of the FMU's `solver` enumeration, for tests that run every solver."""
import pytest

SOLVERS = {"bdf": 1, "adams": 2, "dop853": 3}
each_solver = pytest.mark.parametrize("solver", list(SOLVERS.values()), ids=list(SOLVERS))
