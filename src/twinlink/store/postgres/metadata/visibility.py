"""The SQL form of the privacy rules in twinlink.auth.rights, as the SQLite backend's
store/sqlite/visibility.py writes them, with numbered arguments."""

from __future__ import annotations

from twinlink.domain.records import Visibility
from twinlink.store.postgres.metadata.sql import Args


def part_visible(vis: Visibility, twin_col: str, privacy_col: str, args: Args) -> str:
    """A WHERE fragment true when the reader may see the part (`twin_col`, `privacy_col`).

    public: everyone. private: the twin's owners and editors. Any other level (a group):
    anyone with a role on the twin, and members of the user group of that name.
    """
    if vis.is_admin:
        return "true"
    clauses = [f"{privacy_col} = 'public'"]
    if vis.groups:
        # A user group named like a fixed level grants nothing: "private" is never a group.
        clauses.append(
            f"({privacy_col} = ANY({args(list(vis.groups))}::text[])"
            f" AND {privacy_col} NOT IN ('public', 'private'))"
        )
    if vis.user_id is not None:
        clauses.append(
            f"EXISTS (SELECT 1 FROM twin_roles r WHERE r.twin_id = {twin_col}"
            f" AND r.user_id = {args(vis.user_id)}"
            f" AND ({privacy_col} <> 'private' OR r.role IN ('owner', 'editor')))"
        )
    return "(" + " OR ".join(clauses) + ")"
