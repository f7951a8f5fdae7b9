"""The SQL form of the privacy rules in twinlink.auth.rights, for filtering in the database."""

from __future__ import annotations

from twinlink.store.records import Visibility


def part_visible(vis: Visibility, twin_col: str, privacy_col: str) -> tuple[str, list[object]]:
    """A WHERE fragment true when the reader may see the part (`twin_col`, `privacy_col`).

    public: everyone. private: the twin's owners and editors. Any other level (a group):
    anyone with a role on the twin, and members of the user group of that name.
    """
    if vis.is_admin:
        return "1", []
    clauses = [f"{privacy_col} = 'public'"]
    args: list[object] = []
    if vis.groups:
        clauses.append(f"{privacy_col} IN ({', '.join('?' * len(vis.groups))})")
        args.extend(vis.groups)
    if vis.user_id is not None:
        clauses.append(
            f"EXISTS (SELECT 1 FROM twin_roles r WHERE r.twin_id = {twin_col} AND r.user_id = ?"
            f" AND ({privacy_col} <> 'private' OR r.role IN ('owner', 'editor')))"
        )
        args.append(vis.user_id)
    return "(" + " OR ".join(clauses) + ")", args
