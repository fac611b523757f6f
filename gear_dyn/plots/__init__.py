"""Figures: one module per figure family; every function takes ``ax=None`` (one Axes, or a sequence
of Axes for multi-panel figures) and returns the matplotlib Figure. No backend is chosen on import:
the backend is matplotlib's own choice, and :func:`gear_dyn.io.save_figure` renders off-screen when
saving.

- :mod:`.run`: time history and spectrum of a run; :mod:`.stiffness`: mesh stiffness and its
  components; :mod:`.excitation`: eccentric excitations; :mod:`.contact`: loaded contact and
  tip relief; :mod:`.sweep`: sweep response, waterfall, stability chart; :mod:`.compare`: designs
  compared; :mod:`.bench`:
  work-precision; :mod:`.cosim`: FMU against solve_ivp.
"""
