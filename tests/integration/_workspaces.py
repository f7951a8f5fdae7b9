"""Helpers of the workspace tests: starting one, opening its link, a kernel over the proxy."""

from __future__ import annotations

import json
import uuid
from typing import Any

import httpx
import psutil
from websockets.sync.client import connect

from tests.conftest import Server

COOKIE = "twinlink_workspace"


def start(server: Server, token: str) -> dict[str, Any]:
    with server.client(token) as c:
        r = c.post("/api/v1/workspaces/me", timeout=120)
    assert r.status_code == 200, r.text
    body: dict[str, Any] = r.json()
    assert body["state"] == "running", body
    return body


def open_link(server: Server, url: str) -> tuple[str, httpx.Response]:
    """Follow the start answer's one-time link: the session cookie it sets, and the answer."""
    with httpx.Client(base_url=server.url, timeout=30) as c:
        r = c.get(url)
    assert r.status_code == 303, r.text
    cookie = r.headers["set-cookie"]
    session = cookie.split(";", 1)[0].removeprefix(f"{COOKIE}=")
    return session, r


def lab_processes(server: Server, user: str) -> list[psutil.Process]:
    """The JupyterLab processes of `user`'s workspace under the server."""
    found = []
    for proc in psutil.Process(server.process.pid).children(recursive=True):
        try:
            if f"--ServerApp.base_url=/workspaces/{user}/" in proc.cmdline():
                found.append(proc)
        except psutil.Error:
            continue
    return found


def run_code(ws_url: str, headers: dict[str, str], code: str) -> str:
    """Run `code` in the kernel at `ws_url` (jupyter's channels WebSocket); its stdout."""
    msg_id = uuid.uuid4().hex
    message = {
        "header": {"msg_id": msg_id, "username": "test", "session": uuid.uuid4().hex,
                   "msg_type": "execute_request", "version": "5.3"},
        "parent_header": {}, "metadata": {}, "channel": "shell", "buffers": [],
        "content": {"code": code, "silent": False, "store_history": False,
                    "user_expressions": {}, "allow_stdin": False, "stop_on_error": True},
    }  # fmt: skip
    out = []
    with connect(ws_url, additional_headers=headers, open_timeout=30) as ws:
        ws.send(json.dumps(message))
        while True:
            reply = json.loads(ws.recv(timeout=60))
            if reply.get("parent_header", {}).get("msg_id") != msg_id:
                continue
            kind = reply["header"]["msg_type"]
            if kind == "stream":
                out.append(reply["content"]["text"])
            elif kind == "error":
                raise AssertionError("\n".join(reply["content"]["traceback"]))
            elif kind == "status" and reply["content"]["execution_state"] == "idle":
                return "".join(out)
