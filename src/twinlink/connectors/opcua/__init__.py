"""The `opcua` connector kind: the platform as an OPC UA client (docs/opcua.md). `config.py`
its settings, `values.py` OPC UA values to samples and back, `connector.py` the connector;
`client.py`, `endpoints.py`, `certs.py` and `session.py` the connection it keeps."""
