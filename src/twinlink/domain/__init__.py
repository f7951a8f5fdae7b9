"""Pure data model and rules: DT documents, privacy, relations. No I/O."""
