"""The package from Python and from the command line: rail.app.api (keyword-only functions that take
a scenario and return datasets) and rail.app.cli (``railgrowth run``, ``railgrowth check``)."""
