"""The server tests of tests/integration/test_privacy_parts.py on a `twinlink up` server whose
store is PostgreSQL (_postgres_server.py)."""

from __future__ import annotations

import pytest

from tests.integration import test_privacy_parts
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import drop_tests_without_server
from tests.integration._postgres_server import server as server

pytestmark = pytest.mark.integration

rerun_on_postgres(test_privacy_parts, globals())
drop_tests_without_server(globals())
