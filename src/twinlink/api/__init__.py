"""HTTP routes: thin, one module per area. Errors are RFC 9457 problem+json."""
