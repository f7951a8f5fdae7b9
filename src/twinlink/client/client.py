"""Client: the entry point. One connection to one server, with a token."""

from __future__ import annotations

import os
from types import TracebackType
from typing import TYPE_CHECKING, Any

from twinlink.client._http import Transport
from twinlink.client.deployments import Deployments
from twinlink.client.history import Time, read_rows, to_frame
from twinlink.client.library import Library

if TYPE_CHECKING:
    import pandas

DEFAULT_URL = "http://127.0.0.1:8000"


class Client:
    """A twinlink server's API, for notebooks and scripts.

    `url` and `token` default to TWINLINK_URL and TWINLINK_TOKEN (a lifecycle run and a
    workspace have both set), else http://127.0.0.1:8000 without a token. Every refusal
    raises ApiError with the server's explanation.

        with Client() as tl:
            frame = tl.history("tingen", start="-1h", signals=["theta"])
            tl.deployments.run("tingen", "analyze")
    """

    def __init__(
        self, url: str | None = None, token: str | None = None, *, timeout: float = 60.0
    ) -> None:
        url = url or os.environ.get("TWINLINK_URL") or DEFAULT_URL
        token = token or os.environ.get("TWINLINK_TOKEN") or None
        self._transport = Transport(url, token, timeout)
        self.library = Library(self._transport)
        self.deployments = Deployments(self._transport)

    @property
    def url(self) -> str:
        return self._transport.url

    def history(
        self,
        twin: str,
        stream: str = "telemetry",
        start: Time = None,
        end: Time = None,
        signals: list[str] | None = None,
    ) -> pandas.DataFrame:
        """Stored samples of a twin's stream as a DataFrame: a UTC DatetimeIndex named
        `time`, one column per signal (NaN where a signal has no value at that time).
        `start`/`end`: datetimes, integer ns, ISO 8601, `now` or `-1h`; all when None."""
        times, values = read_rows(self._transport, twin, stream, start, end, signals)
        return to_frame(times, values, signals)

    def streams(self, twin: str) -> list[dict[str, Any]]:
        """The twin's stored streams, each with its signals and time range."""
        return list(self._transport.json("GET", f"/api/v1/twins/{twin}/streams")["streams"])

    def search(
        self, q: str, *, keyword: str | None = None, limit: int = 20
    ) -> list[dict[str, Any]]:
        """Twins, features and library assets that match the words of `q`, best first."""
        params: dict[str, Any] = {"q": q, "limit": limit}
        if keyword:
            params["keyword"] = keyword
        return list(self._transport.json("GET", "/api/v1/search", params=params)["hits"])

    def twins(self) -> list[dict[str, Any]]:
        """Every twin the caller may see (summaries), page by page."""
        found: list[dict[str, Any]] = []
        params: dict[str, Any] = {"limit": 500}
        while True:
            page = self._transport.json("GET", "/api/v1/twins", params=params)
            found += page["items"]
            if not page.get("next_cursor"):
                return found
            params["cursor"] = page["next_cursor"]

    def twin(self, slug: str) -> dict[str, Any]:
        """A twin and its DT document."""
        return dict(self._transport.json("GET", f"/api/v1/twins/{slug}"))

    def me(self) -> dict[str, Any]:
        """Who the token belongs to: username, groups, is_admin."""
        return dict(self._transport.json("GET", "/api/v1/auth/me"))

    def close(self) -> None:
        self._transport.close()

    def __enter__(self) -> Client:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
