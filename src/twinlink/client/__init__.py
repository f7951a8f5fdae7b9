"""The Python client of the twinlink API, for notebooks and scripts (history as pandas
DataFrames, search, deployments, library push and pull)."""
