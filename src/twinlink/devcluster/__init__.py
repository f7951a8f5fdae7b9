"""A local cluster for development and tests: PostgreSQL, a Kafka broker, haproxy and
`twinlink up` nodes on this machine, on loopback (`twinlink cluster up`, `make cluster`,
docs/scale-out.md).

Each launcher starts one real server as a child of the calling process that dies with it
(PR_SET_PDEATHSIG), waits until it answers, and has a `stop`. Nothing else in twinlink
imports this package but the `twinlink cluster` command (the layers contract,
pyproject.toml): a server never starts its own infrastructure.
"""
