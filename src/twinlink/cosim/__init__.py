"""Co-simulation of several FMUs: the formats (Maestro multi-model JSON, SSP, YAML) read into
one model, algebraic loops found before a run, and the master algorithms.

model.py is the shape every format reads into (System and its parts); maestro.py, ssp.py and
yamlform.py read the formats (read_maestro, read_ssp, read_yaml; to_yaml writes the YAML
form); graph.py finds algebraic loops from the FMUs' feedthrough. The readers open no FMU: a
System names its FMUs by path, checked when they are loaded."""
