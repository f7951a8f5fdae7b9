"""The search API's tests (tests/integration/test_search.py: ranking, prefixes, facets, the
keyword filter, privacy, paging, query syntax) on a `twinlink up` server whose store is
PostgreSQL (_postgres_server.py)."""

from __future__ import annotations

import pytest

from tests.conftest import Server
from tests.integration import test_search
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import count, drop_tests_without_server
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import server as server

pytestmark = pytest.mark.integration


def test_the_twins_searched_are_in_postgresql(
    server: Server, examples: None, database: str
) -> None:
    assert count(database, "SELECT count(*) FROM search_parts") > 0
    assert not list(server.data_dir.glob("*.sqlite3"))  # and not in a SQLite file


rerun_on_postgres(test_search, globals())
drop_tests_without_server(globals())
