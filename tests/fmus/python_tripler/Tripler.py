"""A Python FMU (pythonfmu) that imports a package the server does not have, to test
`python_requirements` (tests/integration/test_fmu_python_env.py): y = 2 x + 3, where 3 is
`more_itertools.ilen` of three items. The import is at the top, so without the package the
FMU fails at instantiation, as a real one would."""

import more_itertools
from pythonfmu import Fmi2Causality, Fmi2Initial, Fmi2Slave, Real


class Tripler(Fmi2Slave):
    author = "twinlink tests"
    description = "y = 2 x + 3, with more_itertools"

    def __init__(self, **kwargs):  # type: ignore[no-untyped-def]
        super().__init__(**kwargs)
        self.x = 0.0
        self.y = 0.0
        self.register_variable(Real("x", causality=Fmi2Causality.input))
        # exact: pythonfmu leaves calculated outputs out of InitialUnknowns, which FMPy refuses
        self.register_variable(Real("y", causality=Fmi2Causality.output, initial=Fmi2Initial.exact))

    def do_step(self, current_time, step_size):  # type: ignore[no-untyped-def]
        self.y = 2.0 * self.x + more_itertools.ilen("abc")
        return True
