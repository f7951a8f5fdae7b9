"""The server tests of tests/integration/test_processors.py on a `twinlink up` server whose
store is PostgreSQL (_postgres_server.py)."""

from __future__ import annotations

import pytest

from tests.integration import test_processors
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import drop_tests_without_server, server_on_postgres
from tests.integration._processors import processor_server

pytestmark = pytest.mark.integration

server = server_on_postgres(processor_server)

rerun_on_postgres(test_processors, globals())
drop_tests_without_server(globals())
