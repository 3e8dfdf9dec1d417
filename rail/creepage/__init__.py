"""Dynamic creepage (report eq 26's u_bar): one package, its modules named as the configuration names them.

* ``wheelset``: the wheelset's rotation about its axle (config ``wheelset``): rigid or torsional, its modes.
* ``modes``: longitudinal modes in the slip (LongitudinalModes): their receptance, their march and their
  periodic response to the tangential force, the quasi-steady preconditioner.
* ``rail_flexibility``: the rail head's longitudinal flexibility (config ``rail_flexibility``): the axial rod on
  the pads' shear springs and the head's e psi under moving loads, on the uniform track (RailHead, HeadOperator).
* ``rail_flexibility_cell``: the same on a track cell of N bays whose supports differ (CellHead).
* ``coupling``: the coupling of u_bar with the contact: the march of a passage with u_bar in its periodic
  steady state (march_with_creepage: Newton steps, or the growth loop's lagged coupling).
* ``choices``: the model choices (WheelsetModel, RailFlexibility) as objects, each named by its config value.

Nothing is imported here: rail.contact's march imports ``modes`` and ``coupling`` imports rail.contact, so each
module is imported by its full name (rail.creepage.coupling, ...).
"""
