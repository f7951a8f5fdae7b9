"""`twinlink search`: twins and the features that match a query."""

from __future__ import annotations

import click

from twinlink.cli.common import client_for, emit


@click.command()
@click.argument("query", nargs=-1)
@click.option("-k", "--keyword", help="Only twins with a feature of this keyword.")
@click.option("-n", "--limit", default=20, show_default=True, help="Most hits to show.")
@click.option("--json", "as_json", is_flag=True, help="Print the raw JSON answer.")
@click.pass_context
def search(
    ctx: click.Context, query: tuple[str, ...], keyword: str | None, limit: int, as_json: bool
) -> None:
    """Find twins and the features that match QUERY."""
    answer = client_for(ctx).json(
        "GET", "/api/v1/search", params={"q": " ".join(query), "keyword": keyword, "limit": limit}
    )
    if as_json:
        emit(answer, True)
        return
    for hit in answer["hits"]:
        features = [m["feature"] for m in hit["matches"] if m["feature"]]
        where = f"  features: {', '.join(features)}" if features else ""
        click.echo(f"{hit['slug']:<24} {hit['name']}{where}")
    click.echo(f"({answer['total']} twin{'s' if answer['total'] != 1 else ''})")
