"""The example twins: every DT document under the examples folder, applied as the admin."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import click

from twinlink.app import Services
from twinlink.auth.rights import Principal
from twinlink.domain.errors import ConflictError, DocumentError
from twinlink.registry.documents import parse_documents

# A twin of several documents (the crane's privacy parts) was "created" when any part was.
_OUTCOMES = ("created", "updated", "unchanged")


def example_files(folder: Path) -> list[Path]:
    """The DT documents under `folder`; not the library's twin packages (`library/`), which
    are templates pushed to the library, not documents."""
    return sorted(
        p
        for p in folder.rglob("*")
        if p.suffix in (".yaml", ".yml")
        and p.is_file()
        and "library" not in p.relative_to(folder).parts[:1]
    )


async def admin_principal(services: Services) -> Principal | None:
    """The user `admin`, whom the demo acts as; None when there is no such user."""
    admin = await services.store.get_user_by_name("admin")
    return None if admin is None else Principal(user=admin)


async def load_examples(
    services: Services,
    folder: Path,
    rewrite: Callable[[str], str] | None = None,
    skip: tuple[Path, ...] = (),
) -> list[str]:
    """Apply every example document as the admin (each through `rewrite` first, when given)
    but those in `skip`; already-loaded ones stay unchanged. One "slug (outcome)" per twin."""
    principal = await admin_principal(services)
    if principal is None:
        return []
    outcomes: dict[str, set[str]] = {}
    for path in (p for p in example_files(folder) if p not in skip):
        try:
            text = path.read_text("utf-8")
            body = (rewrite(text) if rewrite else text).encode()
            docs = parse_documents(body, "application/yaml", 1 << 24)
            for result in await services.registry.apply(principal, docs):
                outcomes.setdefault(result.twin.slug, set()).add(result.outcome)
        except (DocumentError, ConflictError, UnicodeDecodeError) as err:
            click.echo(f"example {path} was not loaded: {err}", err=True)
    return [
        f"{slug} ({next((o for o in _OUTCOMES if o in seen), '/'.join(sorted(seen)))})"
        for slug, seen in outcomes.items()
    ]
