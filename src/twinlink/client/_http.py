"""The HTTP side shared by every part of the client: one connection pool, the token, and
refusals turned into ApiError."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import httpx

from twinlink.client.errors import ApiError


class Transport:
    def __init__(self, url: str, token: str | None, timeout: float) -> None:
        self.url = url.rstrip("/")
        self.token = token
        self.headers = {"Authorization": f"Bearer {token}"} if token else {}
        self.http = httpx.Client(base_url=self.url, headers=self.headers, timeout=timeout)

    def request(self, method: str, path: str, **kwargs: Any) -> httpx.Response:
        try:
            response = self.http.request(method, path, **kwargs)
        except httpx.HTTPError as err:
            raise ApiError(f"cannot reach twinlink at {self.url}: {err}") from err
        if response.status_code >= 400:
            raise ApiError.from_response(response)
        return response

    def json(self, method: str, path: str, **kwargs: Any) -> Any:
        return self.request(method, path, **kwargs).json()

    @contextmanager
    def stream(self, method: str, path: str, **kwargs: Any) -> Iterator[httpx.Response]:
        """A response whose body is read as it comes (downloads of any size, in constant
        memory); a refusal is read whole (it is small) and raised."""
        try:
            with self.http.stream(method, path, **kwargs) as response:
                if response.status_code >= 400:
                    response.read()
                    raise ApiError.from_response(response)
                yield response
        except httpx.HTTPError as err:
            raise ApiError(f"cannot reach twinlink at {self.url}: {err}") from err

    def ws_url(self, path: str) -> str:
        if self.url.startswith("https://"):
            return "wss://" + self.url.removeprefix("https://") + path
        return "ws://" + self.url.removeprefix("http://") + path

    def close(self) -> None:
        self.http.close()
