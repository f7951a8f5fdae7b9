"""The Python client of the twinlink API, for notebooks and scripts (history as pandas
DataFrames, search, deployments, library push and pull). It imports nothing else of twinlink:
a workspace or a lifecycle run can use it with only httpx (pandas for DataFrames, websockets
to follow a run's log live).

    from twinlink.client import Client
    tl = Client()                       # TWINLINK_URL, TWINLINK_TOKEN
    frame = tl.history("tingen", start="-10m")
"""

from twinlink.client.client import Client
from twinlink.client.errors import ApiError
from twinlink.client.refs import AssetRef, parse_ref

__all__ = ["ApiError", "AssetRef", "Client", "parse_ref"]
