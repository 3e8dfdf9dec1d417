"""Studies and result datasets: xarray datasets of the report's figures (``datasets``), track
characterisation, the closure, stability and convergence studies and the report's conclusions.
Computes through rail.chain; never plots (rail.plotting does)."""
