"""The metadata store (and its search index) in PostgreSQL: PostgresMetadataStore."""

from twinlink.store.postgres.metadata.store import PostgresMetadataStore

__all__ = ["PostgresMetadataStore"]
