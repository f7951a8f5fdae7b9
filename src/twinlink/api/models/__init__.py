"""The API's answers as pydantic models: what /openapi.json says each route sends.

Routes whose answers this package builds from records (users, tokens, twins, devices) return
these models, and FastAPI checks and writes them. Routes whose answers a service builds on a
hot path (history, search, commands, processors, the gateway's views) name a model only for
the description and send the service's answer as is with orjson (`JSONAnswer`): checking
every answer again would cost each read for nothing. tests/integration/test_openapi_contract.py
checks those answers against their models, and test_schemathesis.py fuzzes the whole API.
"""
