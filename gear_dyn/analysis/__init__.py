"""Analysis: composes the solvers into studies, never the reverse.

- :mod:`.study`: a run with its error estimate and stability checks (``gear_dyn.simulate``);
- :mod:`.accuracy`: error measures and the stated error; :mod:`.stability`: periodic steady
  state, Floquet multipliers, shooting; :mod:`.chart`: stability charts;
- :mod:`.sweep`: speed sweeps over a model factory; :mod:`.compare`: designs ranked by their
  sweeps' peak force against a baseline; :mod:`.spectrum`,
  :mod:`.spectrum_labels`: spectra and labelled peaks; :mod:`.bench`: work-precision benchmarks;
- :mod:`.report`: run summaries; :mod:`.stiffness`, :mod:`.excitation`: the studies behind
  ``gear-dyn stiffness`` and ``gear-dyn excitation``.

Submodules load on import of their own name (nothing is imported here).
"""
