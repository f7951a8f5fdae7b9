"""Connectors: the platform reaching out to devices that cannot run the SDK (UDP datasources,
OPC UA servers), each speaking for one device of a twin."""
