"""The twin registry: apply, read, list, delete, relations and the document views."""
