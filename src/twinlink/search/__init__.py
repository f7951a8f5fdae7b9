"""Search over twins and features: "which system holds the data I need"."""

from twinlink.search.service import SearchService

__all__ = ["SearchService"]
