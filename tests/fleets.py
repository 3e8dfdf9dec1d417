"""Fleet scenario texts shared by the tests (a two-vehicle fleet at a uniform speed spread about 40 m/s)."""

TWO_VEHICLES = """fleet:
  vehicles:
    - name: loco
      positions: [0.0, 3.3]
      static_load: 1.0e+5
      unsprung_mass: 1350.0
      creepage: [-0.001, -0.001]
      share: 0.4
    - name: coach
      positions: [0.0, 2.6]
      static_load: 5.0e+4
      unsprung_mass: 800.0
      creepage: [0.0005, 0.0005]
      share: 0.6
  speeds: {distribution: uniform, low: 36.0, high: 44.0, classes: 3}
"""
