"""Small, dependency-free HTML rendering of DT documents (every value escaped)."""

from __future__ import annotations

from html import escape
from importlib import resources
from typing import Any
from urllib.parse import urlparse

_STYLE = (resources.files("twinlink.web") / "page.css").read_text("utf-8")


def _link(value: str) -> str:
    scheme = urlparse(value).scheme
    if scheme in ("http", "https"):
        return (
            f'<a href="{escape(value, quote=True)}" rel="noopener noreferrer">{escape(value)}</a>'
        )
    return escape(value)


def _value(value: Any) -> str:
    if isinstance(value, dict):
        rows = "".join(f"<dt>{escape(str(k))}</dt><dd>{_value(v)}</dd>" for k, v in value.items())
        return f"<dl>{rows}</dl>"
    if isinstance(value, list):
        return "<ul>" + "".join(f"<li>{_value(v)}</li>" for v in value) + "</ul>"
    if value is None:
        return '<span class="muted">—</span>'
    return _link(str(value))


def page(title: str, body: str) -> str:
    return (
        "<!doctype html><html lang=en><head><meta charset=utf-8>"
        '<meta name=viewport content="width=device-width,initial-scale=1">'
        f"<title>{escape(title)} · twinlink</title><style>{_STYLE}</style></head><body>"
        '<header><a href="/"><b>twinlink</b></a> · <a href="/docs">API</a></header>'
        f"<main>{body}</main></body></html>"
    )


def twin_page(doc: dict[str, Any], slug: str) -> str:
    name = str(doc.get("name") or slug)
    skip = {"name", "description", "features", "interface", "relations"}
    facts = "".join(
        f"<dt>{escape(str(k))}</dt><dd>{_value(v)}</dd>" for k, v in doc.items() if k not in skip
    )
    features = "".join(_feature(f) for f in doc.get("features") or [] if isinstance(f, dict))
    relations = "".join(
        f"<li>{escape(str(r.get('relationType')))}: "
        f"{_link(str(r.get('id') or r.get('dt-id')))}</li>"
        for r in doc.get("relations") or []
        if isinstance(r, dict)
    )
    interface = doc.get("interface")
    body = (
        f"<section><h1>{escape(name)}</h1><p>{escape(str(doc.get('description') or ''))}</p>"
        f'<p class=muted>Also as <a href="/twins/{escape(slug)}/index.yaml">YAML</a> · '
        f'<a href="/twins/{escape(slug)}/index.json">JSON</a></p></section>'
        f"<section><h2>About</h2><dl>{facts}</dl></section>"
    )
    if relations:
        body += f"<section><h2>Relations</h2><ul>{relations}</ul></section>"
    if features:
        body += f"<section><h2>Features</h2>{features}</section>"
    if isinstance(interface, dict):
        body += f"<section><h2>Interface</h2>{_value(interface)}</section>"
    return page(name, body)


def _feature(f: dict[str, Any]) -> str:
    keywords = "".join(f"<span class=kw>{escape(str(k))}</span>" for k in f.get("keywords") or [])
    rest = "".join(
        f"<dt>{escape(str(k))}</dt><dd>{_value(v)}</dd>"
        for k, v in f.items()
        if k not in ("name", "description", "keywords")
    )
    return (
        f"<h3>{escape(str(f.get('name')))}</h3><p>{escape(str(f.get('description') or ''))}</p>"
        f"<dl>{rest}</dl><div>{keywords}</div>"
    )


def index_page(twins: list[dict[str, Any]], signed_in: bool) -> str:
    rows = "".join(
        f'<tr><td><a href="/twins/{escape(t["slug"])}">{escape(t["name"])}</a></td>'
        f"<td class=muted>{escape(t['id'])}</td></tr>"
        for t in twins
    )
    note = (
        ""
        if signed_in
        else (
            "<p class=muted>Showing public twins. Sign in through the API "
            "(<code>POST /api/v1/auth/login</code> or <code>twinlink login</code>) to see more.</p>"
        )
    )
    return page(
        "Digital twins",
        (
            "<section><h1>Digital twins</h1>"
            '<p><a href="/app/"><b>Open the web app</b></a></p>'
            + note
            + f"<table><tr><th>Name</th><th>Id</th></tr>{rows}</table></section>"
            '<section><h2>API</h2><p><a href="/docs">Interactive API documentation</a> · '
            '<a href="/healthz">health</a></p></section>'
        ),
    )
