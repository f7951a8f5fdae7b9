"""Users, roles, API tokens and the rules of who may see and change what."""
