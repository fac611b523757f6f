"""FMI 2.0 (and 3.0) co-simulation export of gear_dyn models (pythonfmu) and the check through fmpy.

- :mod:`.stepper`: advance a model between communication points, keeping the solver alive
  (:mod:`gear_dyn.solvers.session`), with snapshots of the whole integrator state
- :mod:`.variables`, :mod:`.inputs`: what an FMU exposes, how its inputs change the model
- :mod:`.slave`: the pythonfmu slave (imports pythonfmu; used inside built FMUs)
- :mod:`.build`, :mod:`.staging`: ``build_fmu``, FMI 2 or 3 (vendored gear_dyn copy, completed
  modelDescription)
- :mod:`.cosim`: ``FmuSession`` (fmpy) and ``compare`` against solve_ivp
- :mod:`.slave3`, :mod:`.session3`: FMI 3.0 export (pythonfmu3) over the same
  stepper, and its fmpy session

Nothing here is imported by ``import gear_dyn``; pythonfmu and fmpy are imported where used.
"""
