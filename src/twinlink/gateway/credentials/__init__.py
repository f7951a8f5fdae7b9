"""How the gateway signs requests in to a service: one credential method per module, each a
plug-in of the `twinlink.credentials` entry-point group (docs/plugins.md). `base.py` is what a
method is made of, `methods.py` finds them; `static.py`, `oauth2.py` and `login.py` are the
built-in ones, `token.py` what the fetched-token methods share."""
