"""Co-simulation of several FMUs: the formats (Maestro multi-model JSON, SSP, YAML) read into
one model, algebraic loops found before a run, and the master algorithms."""
