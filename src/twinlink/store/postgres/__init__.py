"""The PostgreSQL backend (scale-out): history, commands and properties through asyncpg.

Only the composition root picks it; only this package imports asyncpg (import contracts in
pyproject.toml). See docs/scale-out.md and docs/decisions/0011-postgresql-driver.md.
"""
