"""railgrowth: rail roughness growth and corrugation on tangent track.

An implementation of Sheng, Thompson & Jones, "Modelling rail roughness growth on tangent
tracks" (ISVR).  Modules follow the report's sections: ``halfspace`` (sec. 3) at the bottom;
``config``/``params`` turn a configuration into parameter dataclasses; ``datasets`` builds
self-describing xarray results; ``figures`` draws them.
"""

__version__ = "0.1.0"
