"""Checks every answer a client gets against /openapi.json: its status is one the route
declares, its media type one the status declares, and its body conforms to the schema
(schemathesis's validator). Used as an httpx response hook by test_openapi_contract.py."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

import httpx
import schemathesis


@dataclass
class Contract:
    spec: dict[str, Any]
    # (METHOD, path template, status) of every answer checked
    seen: set[tuple[str, str, int]] = field(default_factory=set)

    def __post_init__(self) -> None:
        self.schema = schemathesis.openapi.from_dict(self.spec)
        # Literal paths first, so /api/v1/device/commands is not taken for a {slug}.
        self.templates = sorted(self.spec["paths"], key=lambda p: (p.count("{"), p))
        self.patterns = [
            (t, re.compile("^" + re.sub(r"\{[^}]+\}", "[^/]+", t) + "$")) for t in self.templates
        ]

    def operations(self) -> set[tuple[str, str]]:
        return {(m.upper(), p) for p, item in self.spec["paths"].items() for m in item}

    def template(self, method: str, path: str) -> str:
        for template, pattern in self.patterns:
            if pattern.match(path) and method.lower() in self.spec["paths"][template]:
                return str(template)
        raise AssertionError(f"{method} {path} is not in /openapi.json")

    def check(self, response: httpx.Response) -> None:
        response.read()
        method, path = response.request.method, response.request.url.path
        template = self.template(method, path)
        documented = self.spec["paths"][template][method.lower()]["responses"]
        status = str(response.status_code)
        where = f"{method} {template} answered {status}"
        assert status in documented, f"{where}, which it does not declare: {response.text[:300]}"
        content = documented[status].get("content")
        if content and response.content:
            media = response.headers.get("content-type", "").split(";")[0].strip()
            assert media in content, f"{where} as {media}, not as {sorted(content)}"
        self.schema[template][method].validate_response(response)
        self.seen.add((method, template, response.status_code))

    def client(self, base_url: str, token: str | None = None) -> httpx.Client:
        headers = {"Authorization": f"Bearer {token}"} if token else {}
        return httpx.Client(
            base_url=base_url,
            headers=headers,
            timeout=30,
            event_hooks={"response": [self.check]},
        )
