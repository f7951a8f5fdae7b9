"""The `udp` connector kind: a listener turning datagrams into samples (docs/connectors.md).
`config.py` its settings, `format.py` the datagram formats, `connector.py` the connector."""
