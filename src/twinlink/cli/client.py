"""A small synchronous client of the twinlink API, used by the CLI."""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import Any

import httpx
import orjson

from twinlink.domain.errors import TwinlinkError

DEFAULT_URL = "http://127.0.0.1:8000"


class ApiCallError(TwinlinkError):
    """The server refused the request, or could not be reached; the message says why.
    `problem` is the server's problem+json answer, when it sent one."""

    def __init__(self, message: str, problem: dict[str, Any] | None = None) -> None:
        super().__init__(message)
        self.problem = problem


def credentials_file() -> Path:
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "twinlink" / "credentials.json"


def saved_credentials() -> dict[str, str]:
    path = credentials_file()
    try:
        data = orjson.loads(path.read_bytes())
    except (OSError, orjson.JSONDecodeError):
        return {}
    return data if isinstance(data, dict) else {}


def save_credentials(url: str, token: str) -> Path:
    path = credentials_file()
    path.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, stat.S_IRUSR | stat.S_IWUSR)
    with os.fdopen(fd, "wb") as f:
        f.write(orjson.dumps({"url": url, "token": token}))
    return path


def forget_credentials() -> Path | None:
    path = credentials_file()
    try:
        path.unlink()
    except FileNotFoundError:
        return None
    return path


class Client:
    def __init__(self, url: str | None, token: str | None, timeout: float = 30.0) -> None:
        saved = saved_credentials()
        self.url = (url or saved.get("url") or DEFAULT_URL).rstrip("/")
        self.token = token or (
            saved.get("token") if saved.get("url", self.url) == self.url else None
        )
        headers = {"Authorization": f"Bearer {self.token}"} if self.token else {}
        self.http = httpx.Client(base_url=self.url, headers=headers, timeout=timeout)

    def request(self, method: str, path: str, **kwargs: Any) -> httpx.Response:
        try:
            response = self.http.request(method, path, **kwargs)
        except httpx.HTTPError as err:
            raise ApiCallError(f"cannot reach twinlink at {self.url}: {err}") from err
        if response.status_code >= 400:
            raise ApiCallError(explain(response), _problem(response))
        return response

    def json(self, method: str, path: str, **kwargs: Any) -> Any:
        return self.request(method, path, **kwargs).json()


def _problem(response: httpx.Response) -> dict[str, Any] | None:
    try:
        body = response.json()
    except ValueError:
        return None
    return body if isinstance(body, dict) else None


def explain(response: httpx.Response) -> str:
    """The server's refusal as a person reads it: title, detail, each error, what to do."""
    try:
        body = response.json()
    except ValueError:
        return f"HTTP {response.status_code}: {response.text[:300]}"
    if not isinstance(body, dict):
        return f"HTTP {response.status_code}"
    lines = [f"{body.get('title', 'Error')} ({response.status_code}): {body.get('detail', '')}"]
    for e in body.get("errors") or []:
        where = f"line {e['line']}, column {e['column']}: " if e.get("line") else ""
        doc = f"document {e['document'] + 1}, " if e.get("document") else ""
        path = f"{e['path']}: " if e.get("path") else ""
        lines.append(f"  - {doc}{where}{path}{e.get('message')}")
    if response.status_code == 401 and not response.request.url.path.endswith("/auth/login"):
        lines.append("  Sign in with `twinlink login` or pass --token / TWINLINK_TOKEN.")
    return "\n".join(lines)
