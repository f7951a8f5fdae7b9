"""The runs' and scoped tokens' server tests (tests/integration/test_runs.py,
test_scoped_tokens.py) on a `twinlink up` server whose store is PostgreSQL
(_postgres_server.py): runs recorded there by a node of a shared store, a run's token made,
scoped, checked and revoked there. (The tests that start servers of their own stay SQLite's.)"""

from __future__ import annotations

import pytest

from tests.integration import test_runs, test_scoped_tokens
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import drop_tests_without_server
from tests.integration._postgres_server import server as server

pytestmark = pytest.mark.integration

rerun_on_postgres(test_runs, globals())
rerun_on_postgres(test_scoped_tokens, globals())
drop_tests_without_server(globals())
