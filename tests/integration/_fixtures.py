"""Fixtures shared by the integration test modules. pytest finds a fixture by its name in the
test module, so a module opts in by importing it (`... import no_server_errors as
no_server_errors`: the redundant alias marks the import as deliberate)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.conftest import Server
from tests.integration._util import last_error, unhandled_errors


@pytest.fixture(autouse=True)
def no_server_errors(server: Server) -> Iterator[None]:
    """No test in a module that imports this may make the server log an unhandled error."""
    before = unhandled_errors(server)
    yield
    assert unhandled_errors(server) == before, f"the server logged: {last_error(server)}"
