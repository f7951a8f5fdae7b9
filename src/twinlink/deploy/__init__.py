"""Deployments (DTaaS): twin packages planned and applied as twins with a lifecycle, and the
lifecycle phases run as isolated processes."""
