"""Configuration and I/O: validate a configuration (``config``), build the Scenario from it
(``build``), write self-describing netCDF results (``io``). Imports the physics layer, never the
studies or plotting."""
