"""A Scenario for the tests, from hand-written parameters (Table 1 values and reduced numerics),
independent of config/config.yaml, so that the tests check the physics against fixed inputs."""

from rail import contact as C
from rail import growth as G
from rail import halfspace
from rail import interaction as I
from rail import scenario as S
from rail import wear as W

STEEL = halfspace.ElasticMaterial(2.1e11, 0.3, 7850.0)
WEAR = W.WearLaw(7850.0, 2.5e-9)


def scenario(track, material, spring, *, positions=(0.0,), K=48, nodes=41, passages=20000, step=10000, save_every=None,
             vary_grid=True, tol=0.05, closure_scale=1.0):
    """One wheel set of 1350 kg, radius 0.575 m, 100 kN each, at ``positions`` (m)."""
    return S.Scenario(
        name="test", track=track, track_numerics=S.TrackNumerics(K, 1e-4),
        wheels=I.Wheels(1350.0, 0.575, 1e5, tuple(positions)), spring=spring, material=material, elastic=STEEL,
        wear_law=WEAR, contact_numerics=C.ContactNumerics(nodes, "default", closure_scale, "report", "wheel"),
        growth=G.GrowthSettings(passages, step, step if save_every is None else save_every, vary_grid, tol),
        roughness=S.InitialRoughness("smooth", 0.0, 0.0, None, None), speeds=(40.0,), axles_per_day=20000.0,
    )
