"""Plots of result datasets that are not report figures (those are in ``rail.plotting.report``).

One function per figure: it takes a dataset and returns a matplotlib Figure; nothing here
computes physics, saves or shows.  The Agg backend is used so that figures are made the same
way on a laptop, in CI and on a cluster node.

``rail.plotting.track``: track characterisation (receptance, moving-load receptance, decay rate).
"""
