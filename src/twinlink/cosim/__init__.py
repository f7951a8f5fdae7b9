"""Co-simulation of several FMUs: the formats (Maestro multi-model JSON, SSP, YAML) read into
one model, algebraic loops found before a run, and the master algorithms.

model.py is the shape every format reads into (System and its parts); maestro.py, ssp.py and
yamlform.py read the formats (read_maestro, read_ssp, read_yaml; to_yaml writes the YAML
form), reading.py chooses among them (read_system); graph.py finds algebraic loops from the
FMUs' feedthrough. The readers open no FMU: a System names its FMUs by path, checked when
they are loaded.

session.py opens a System (Session: its instances from kinds.open_slave, wired) and steps it
for whoever drives it: runner.run (batch), pacing.py (real time), blueprint.py (beside live
data). master.py steps the instances (fixed-step Jacobi or Gauss-Seidel), varstep.py chooses
the variable step and rolls rejected steps back."""
