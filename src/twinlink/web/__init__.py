"""Server-rendered HTML: the DT-document page of a twin and the landing page."""
