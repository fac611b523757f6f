"""Names a user picks from in scenes and on the command line, each list defined once.

Plain tuples and no imports, so that the command-line parser offers them as choices without
loading any physics (building the parser imports no numpy: tests/cli/test_cli_startup.py).
"""

#: ``[stiffness] method``, how k(t) is computed (:mod:`gear_dyn.stiffness.select`; the default
#: is chosen per pair by ``choose_stiffness``); the order numbers the items of the pythonfmu
#: FMU's enumeration
STIFFNESS_METHODS: tuple[str, ...] = ("iso6336", "rectangular", "potential_energy", "weber",
                                      "contact_line")
#: tip-relief curves (:mod:`gear_dyn.modification.relief`): the power curves of Wang et al.
#: (2024), eq. 2, then the sine curve
RELIEF_CURVES: tuple[str, ...] = ("linear", "yoshio", "walker", "parabolic", "sine")
#: single-pair stiffness methods of the loaded contact (:mod:`gear_dyn.models.relief`)
PAIR_STIFFNESS_METHODS: tuple[str, ...] = ("potential_energy", "weber")
