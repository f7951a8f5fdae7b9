"""Reading stored telemetry: rights, query parameters, and keeping history tidy."""
