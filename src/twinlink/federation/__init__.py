"""The Digital Twin Web (docs/federation.md): documents fetched from other instances behind
an SSRF guard, remote twins kept read-only, Twinbase sites mirrored, relations that cross
instances."""
