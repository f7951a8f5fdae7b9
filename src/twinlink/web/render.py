"""Small, dependency-free HTML rendering of DT documents (every value escaped)."""

from __future__ import annotations

import math
from collections.abc import Iterable
from datetime import date
from html import escape
from importlib import resources
from typing import Any
from urllib.parse import quote, urlparse

_STYLE = (resources.files("twinlink.web") / "page.css").read_text("utf-8")
# A list of mappings with more keys than this reads better as nested lists than as a table.
_MAX_COLUMNS = 8


def _link(value: str) -> str:
    scheme = urlparse(value).scheme
    if scheme in ("http", "https"):
        return (
            f'<a href="{escape(value, quote=True)}" rel="noopener noreferrer">{escape(value)}</a>'
        )
    return escape(value)


def number_text(value: float) -> str:
    """A float as YAML and JSON write it, at its shortest: `2.1e11`, not `210000000000.0`."""
    if value != value:
        return ".nan"
    if value in (math.inf, -math.inf):
        return ".inf" if value > 0 else "-.inf"
    text = repr(value)  # the shortest form that reads back as the same float
    if "e" in text:  # '1e-05', '1.5e+16'
        mantissa, _, exponent = text.partition("e")
        return f"{mantissa}e{int(exponent)}"
    whole, _, fraction = text.partition(".")
    if fraction != "0" or len(whole.lstrip("-")) < 7:
        return text
    digits = whole.lstrip("-")
    significant = digits.rstrip("0")
    mantissa = significant[0] + (f".{significant[1:]}" if len(significant) > 1 else "")
    scientific = f"{'-' if value < 0 else ''}{mantissa}e{len(digits) - 1}"
    return scientific if len(scientific) < len(text) else text


def _scalar(value: Any) -> str:
    """A value as the document's YAML or JSON writes it."""
    if value is None:
        return "<span class=muted>null</span>"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return number_text(value)
    if isinstance(value, date):  # a YAML timestamp
        return escape(value.isoformat())
    return _link(str(value))


def _columns(rows: Iterable[dict[str, Any]]) -> list[str] | None:
    """The columns of a table of `rows`, or None when they are too many to read as one."""
    keys = list(dict.fromkeys(str(k) for row in rows for k in row))
    return keys if 0 < len(keys) <= _MAX_COLUMNS else None


def _table(rows: list[tuple[str | None, dict[str, Any]]], columns: list[str]) -> str:
    named = any(name is not None for name, _ in rows)
    head = ("<th></th>" if named else "") + "".join(f"<th>{escape(c)}</th>" for c in columns)
    body = "".join(
        "<tr>"
        + (f"<th scope=row>{escape(name or '')}</th>" if named else "")
        + "".join(f"<td>{_value(row[c]) if c in row else ''}</td>" for c in columns)
        + "</tr>"
        for name, row in rows
    )
    return f"<table class=values><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _value(value: Any) -> str:
    """Any value of a document, its nesting kept: entries of the same shape (a list of
    mappings, or a mapping of mappings: signals, physical properties) as a table, other
    mappings as an indented list of keys and values."""
    if isinstance(value, dict):
        if not value:
            return "<span class=muted>{}</span>"
        inner = list(value.values())
        if len(inner) > 1 and all(isinstance(v, dict) for v in inner):
            columns = _columns(inner)
            if columns:
                return _table([(str(k), v) for k, v in value.items()], columns)
        rows = "".join(f"<dt>{escape(str(k))}</dt><dd>{_value(v)}</dd>" for k, v in value.items())
        return f"<dl class=nested>{rows}</dl>"
    if isinstance(value, list):
        if not value:
            return "<span class=muted>[]</span>"
        if all(isinstance(v, dict) for v in value):
            columns = _columns(value)
            if columns:
                return _table([(None, v) for v in value], columns)
        return "<ul>" + "".join(f"<li>{_value(v)}</li>" for v in value) + "</ul>"
    return _scalar(value)


def page(title: str, body: str) -> str:
    return (
        "<!doctype html><html lang=en><head><meta charset=utf-8>"
        '<meta name=viewport content="width=device-width,initial-scale=1">'
        f"<title>{escape(title)} · twinlink</title>"
        '<link rel=icon type="image/svg+xml" href="/favicon.svg">'
        f"<style>{_STYLE}</style></head><body>"
        '<header><a href="/"><b>twinlink</b></a> · <a href="/app/">Web app</a> · '
        '<a href="/docs">API</a></header>'
        f"<main>{body}</main></body></html>"
    )


def twin_page(
    doc: dict[str, Any], slug: str, remotes: dict[str, dict[str, Any]] | None = None
) -> str:
    """The twin's public page; `remotes` (federation/resolve.py) are the twins of other
    instances it names, linked to their documents with their name and state."""
    name = str(doc.get("name") or slug)
    skip = {"name", "description", "features", "interface", "relations"}
    facts = "".join(
        f"<dt>{escape(str(k))}</dt><dd>{_value(v)}</dd>" for k, v in doc.items() if k not in skip
    )
    features = "".join(_feature(f) for f in doc.get("features") or [] if isinstance(f, dict))
    relations = doc.get("relations")
    interface = doc.get("interface")
    path = escape(quote(slug, safe=""), quote=True)
    body = (
        f"<section><h1>{escape(name)}</h1>"
        f"<p class=text>{escape(str(doc.get('description') or ''))}</p>"
        f'<p><a href="/app/twins/{path}"><b>Open in the web app</b></a> '
        "<span class=muted>(live data, history, commands; sign in there)</span></p>"
        f'<p class=muted>Also as <a href="/twins/{path}/index.yaml">YAML</a> · '
        f'<a href="/twins/{path}/index.json">JSON</a></p></section>'
        f"<section><h2>About</h2><dl>{facts}</dl></section>"
    )
    if isinstance(relations, list) and relations:
        body += f"<section><h2>Relations</h2>{_value(relations)}</section>"
    if remotes:
        body += _remote_section(remotes)
    if features:
        body += f"<section><h2>Features</h2>{features}</section>"
    if isinstance(interface, dict):
        body += f"<section><h2>Interface</h2>{_value(interface)}</section>"
    return page(name, body)


def _remote_section(remotes: dict[str, dict[str, Any]]) -> str:
    rows = "".join(
        f'<tr><td><a href="{escape(str(r.get("url") or ref), quote=True)}"'
        ' rel="noopener noreferrer">'
        f"{escape(str(r.get('name') or ref))}</a></td><td>{escape(ref)}</td>"
        f"<td>{escape(str(r.get('state')))}</td>"
        f"<td>{escape(str(r.get('fetched_at') or ''))}</td></tr>"
        for ref, r in remotes.items()
    )
    return (
        "<section><h2>Twins of other instances</h2>"
        "<table><tr><th>Name</th><th>Id</th><th>State</th><th>Fetched</th></tr>"
        f"{rows}</table></section>"
    )


def _feature(f: dict[str, Any]) -> str:
    keywords = "".join(f"<span class=kw>{escape(str(k))}</span>" for k in f.get("keywords") or [])
    rest = "".join(
        f"<dt>{escape(str(k))}</dt><dd>{_value(v)}</dd>"
        for k, v in f.items()
        if k not in ("name", "description", "keywords")
    )
    return (
        f"<h3>{escape(str(f.get('name')))}</h3>"
        f"<p class=text>{escape(str(f.get('description') or ''))}</p>"
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
            # Twinbase's root index: what its clients and other instances read.
            + "<p class=muted>This list in Twinbase's layout: "
            '<a href="/index.yaml">YAML</a> · <a href="/index.json">JSON</a></p>'
            + f"<table><tr><th>Name</th><th>Id</th></tr>{rows}</table></section>"
            '<section><h2>API</h2><p><a href="/docs">Interactive API documentation</a> · '
            '<a href="/healthz">health</a></p></section>'
        ),
    )
