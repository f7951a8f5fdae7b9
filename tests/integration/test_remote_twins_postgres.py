"""The server tests of tests/integration/test_remote_twins.py on a `twinlink up` server whose
store is PostgreSQL (_postgres_server.py); the second instance it imports keeps SQLite."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.conftest import Server, start_server
from tests.integration import test_remote_twins
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import drop_tests_without_server, server_on_postgres

pytestmark = pytest.mark.integration


def _fetching_loopback(data_dir: Path, **env: str) -> Server:
    return start_server(data_dir, {"TWINLINK_FEDERATION_ALLOW_PRIVATE": "true", **env})


server = server_on_postgres(_fetching_loopback)

rerun_on_postgres(test_remote_twins, globals())
drop_tests_without_server(globals())
