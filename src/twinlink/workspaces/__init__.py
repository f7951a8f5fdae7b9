"""Workspaces: a JupyterLab per user, run and supervised by the platform, reached through it."""
