"""railgrowth: rail roughness growth and corrugation on tangent track.

An implementation of Sheng, Thompson & Jones, "Modelling rail roughness growth on tangent
tracks" (ISVR). Five layers, each importing only the ones before it (tests/test_architecture.py):

* physics (``rail.*``): ``halfspace`` (sec. 3), ``track``, ``moving`` (sec. 4.1), ``interaction``
  (4.2), the package ``contact`` (4.3), ``wear`` and ``growth`` (5), the package ``growth_spectrum``
  (growth rates from the linearised wear), ``decay``; ``scenario`` gathers every input into one frozen
  Scenario and ``chain`` runs the model chain (table -> forces -> wear -> growth) from it;
* ``rail.setup``: the configuration boundary (validation, Scenario building, netCDF I/O);
* ``rail.studies``: result datasets, track characterisation and the numerical studies;
* ``rail.plotting``: one function per figure;
* ``rail.app``: the command line (``railgrowth``) and the Python API over the layers below.

From Python::

    from rail import chain
    from rail.setup import build, config
    scn = build.scenario(config.load_yaml("config/config.yaml"))
    table = chain.receptance_table(scn, 40.0)
    history = chain.grow(scn, table)
"""

__version__ = "0.1.0"
