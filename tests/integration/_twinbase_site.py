"""A Twinbase-shaped static site on a loopback port: the layout Twinbase's GitHub workflow
publishes (a folder per twin with index.yaml, index.json and index.html, and a root
index.json and index.yaml listing `{url, name}` of each twin), made from the published
documents in tests/unit/fixtures/twinbase/, served by Python's http.server in a thread (which
answers If-Modified-Since with 304, as GitHub Pages does)."""

from __future__ import annotations

import http.server
import json
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import yaml

from tests.conftest import ROOT

FIXTURES = ROOT / "tests" / "unit" / "fixtures" / "twinbase"
# Published twins with dt-ids of their own (the others repeat one of these in another form).
TWINS = ("crane-ilmatar", "lab-room-K3-143", "juuso", "test-twin-3", "generated-parent",
         "generated-child")  # fmt: skip
OWNER = {"dt-id": "http://d-t.fi/juuso"}


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: Any) -> None:
        """Not on stderr: the test's output is for the test."""


@dataclass
class Site:
    url: str
    root: Path

    def folder_url(self, name: str) -> str:
        return f"{self.url}/{name}"

    def document(self, name: str) -> dict[str, Any]:
        data = json.loads((self.root / name / "index.json").read_text("utf-8"))
        assert isinstance(data, dict)
        return data

    def write_twin(self, name: str, document: dict[str, Any]) -> None:
        folder = self.root / name
        folder.mkdir(exist_ok=True)
        (folder / "index.yaml").write_text(yaml.safe_dump(document, allow_unicode=True), "utf-8")
        (folder / "index.json").write_text(json.dumps(document, default=str), "utf-8")
        page = f"<!doctype html><title>{document.get('name', name)}</title>"
        (folder / "index.html").write_text(page, "utf-8")

    def write_index(self, names: list[str]) -> None:
        """The root index as Twinbase's generate-base-yaml-json.py writes it."""
        twins = []
        for name in names:
            path = self.root / name / "index.json"
            shown = json.loads(path.read_text("utf-8")).get("name", name) if path.exists() else name
            twins.append({"url": self.folder_url(name), "name": shown})
        index = {"baseurl": self.url, "owner": OWNER, "twins": twins}
        (self.root / "index.json").write_text(json.dumps(index), "utf-8")
        (self.root / "index.yaml").write_text(yaml.safe_dump(index), "utf-8")


@contextmanager
def twinbase_site(root: Path, extra: tuple[str, ...] = ()) -> Iterator[Site]:
    """The site of TWINS, its index also listing the folders `extra` (which the test makes
    or leaves missing), served until the block ends."""
    root.mkdir(parents=True, exist_ok=True)
    handler = partial(_Quiet, directory=str(root))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    site = Site(f"http://127.0.0.1:{httpd.server_address[1]}", root)
    for name in TWINS:
        site.write_twin(name, yaml.safe_load((FIXTURES / f"{name}.yaml").read_text("utf-8")))
    site.write_index([*TWINS, *extra])
    thread = threading.Thread(target=httpd.serve_forever, name="twinbase-site", daemon=True)
    thread.start()
    try:
        yield site
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(timeout=10)
