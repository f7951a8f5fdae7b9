"""The asset library (DTaaS): reusable files and folders in scopes, in immutable
content-addressed versions, with tags."""
