"""Deployments of twin packages: plan, create, start, stop, reconfigure, terminate, and their
lifecycle runs with logs (followed live over the run's log WebSocket)."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from typing import Any

from twinlink.client._http import Transport
from twinlink.client.errors import ApiError

FINISHED = ("succeeded", "failed", "cancelled")
Writer = Callable[[str], Any]


class Deployments:
    def __init__(self, transport: Transport) -> None:
        self._t = transport

    def plan(
        self,
        package: str,
        name: str,
        parameters: dict[str, Any] | None = None,
        *,
        scope: str | None = None,
    ) -> dict[str, Any]:
        """What creating the deployment would do (create/update/delete/keep); nothing stored."""
        body = _body(package, name, parameters, scope)
        return dict(
            self._t.json("POST", "/api/v1/deployments", params={"dry_run": "true"}, json=body)[
                "plan"
            ]
        )

    def create(
        self,
        package: str,
        name: str,
        parameters: dict[str, Any] | None = None,
        *,
        scope: str | None = None,
        start: bool = False,
        planned: bool = False,
    ) -> dict[str, Any]:
        """Create the deployment (all or nothing): `{deployment, plan, device_tokens}`, the
        device tokens shown this once. `start` also starts it; `planned` only records it."""
        body = _body(package, name, parameters, scope)
        if start:
            body["start"] = True
        if planned:
            body["state"] = "planned"
        return dict(self._t.json("POST", "/api/v1/deployments", json=body))

    def ls(self) -> list[dict[str, Any]]:
        return list(self._t.json("GET", "/api/v1/deployments")["deployments"])

    def get(self, name: str) -> dict[str, Any]:
        return dict(self._t.json("GET", f"/api/v1/deployments/{name}"))

    def apply(self, name: str) -> dict[str, Any]:
        """Create a `planned` deployment's resources (and run its `create` phase)."""
        return self._transition(name, "create")

    def start(self, name: str) -> dict[str, Any]:
        return self._transition(name, "start")

    def stop(self, name: str) -> dict[str, Any]:
        return self._transition(name, "stop")

    def terminate(self, name: str, purge: bool = False) -> dict[str, Any]:
        """Remove what the deployment made; the twin's document and history stay unless
        `purge`."""
        return self._transition(name, "terminate", {"purge": purge})

    def update(
        self,
        name: str,
        parameters: dict[str, Any] | None = None,
        *,
        package: str | None = None,
        dry_run: bool = False,
    ) -> dict[str, Any]:
        """Reconfigure: new parameters (the others kept) and/or another package version.
        With dry_run, only the diff plan."""
        body: dict[str, Any] = {}
        if parameters:
            body["parameters"] = parameters
        if package:
            body["package"] = package
        params = {"dry_run": "true"} if dry_run else {}
        return dict(self._t.json("PATCH", f"/api/v1/deployments/{name}", params=params, json=body))

    def _transition(
        self, name: str, action: str, body: dict[str, Any] | None = None
    ) -> dict[str, Any]:
        response = self._t.request("POST", f"/api/v1/deployments/{name}/{action}", json=body)
        return dict(response.json()) if response.content else {}

    # -- runs -------------------------------------------------------------------------------

    def run(
        self, name: str, phase: str, *, follow: bool = True, out: Writer | None = None
    ) -> dict[str, Any]:
        """Start a lifecycle phase (`analyze`, `evolve`, ...) of the deployment. With follow,
        its log is written to `out` (default: stdout) as it comes, and the finished run is
        returned (its `state` and `exit_code`); else the run as queued."""
        run = dict(self._t.json("POST", f"/api/v1/deployments/{name}/runs", json={"phase": phase}))
        if not follow:
            return run
        self.follow(run["id"], out)
        return self.get_run(run["id"])

    def runs(self, name: str) -> list[dict[str, Any]]:
        """Every run of the deployment, newest first."""
        return list(self._t.json("GET", f"/api/v1/deployments/{name}/runs")["runs"])

    def get_run(self, run_id: int | str) -> dict[str, Any]:
        return dict(self._t.json("GET", f"/api/v1/runs/{run_id}"))

    def cancel(self, run_id: int | str) -> dict[str, Any]:
        response = self._t.request("POST", f"/api/v1/runs/{run_id}/cancel")
        return dict(response.json()) if response.content else {}

    def logs(self, run_id: int | str, offset: int = 0) -> str:
        """The run's log as stored so far (all of it once the run has finished)."""
        response = self._t.request("GET", f"/api/v1/runs/{run_id}/log", params={"offset": offset})
        return response.text

    def follow(self, run_id: int | str, out: Writer | None = None) -> dict[str, Any]:
        """Write the run's log to `out` as it comes, from its start, until the run ends;
        returns the last message: `{"state", "exit_code"}`."""
        from websockets.exceptions import InvalidStatus, WebSocketException
        from websockets.sync.client import connect

        write = out or _stdout
        url = self._t.ws_url(f"/api/v1/runs/{run_id}/log/ws")
        try:
            with connect(url, additional_headers=self._t.headers, open_timeout=30) as ws:
                for message in ws:
                    if isinstance(message, bytes):
                        write(message.decode("utf-8", "replace"))
                        continue
                    end = _end_message(message)
                    if end is not None:
                        return end
                    write(message)
        except InvalidStatus as err:
            status = err.response.status_code
            body = err.response.body or b""
            raise ApiError(
                f"the run's log cannot be followed ({status}): {body[:300]!r}", status
            ) from err
        except (OSError, WebSocketException) as err:
            raise ApiError(f"the run's log stream was cut: {err}") from err
        # Closed without the last message (the server went away): say how the run stands.
        return {k: self.get_run(run_id).get(k) for k in ("state", "exit_code")}


def _end_message(text: str) -> dict[str, Any] | None:
    """The WebSocket's last message, `{"state": ..., "exit_code": ...}`; None for log text."""
    if not text.startswith("{"):
        return None
    try:
        data = json.loads(text)
    except ValueError:
        return None
    if isinstance(data, dict) and data.get("state") in FINISHED and "exit_code" in data:
        return data
    return None


def _stdout(text: str) -> None:
    sys.stdout.write(text)
    sys.stdout.flush()


def _body(
    package: str, name: str, parameters: dict[str, Any] | None, scope: str | None
) -> dict[str, Any]:
    body: dict[str, Any] = {"package": package, "name": name, "parameters": parameters or {}}
    if scope:
        body["scope"] = scope
    return body
