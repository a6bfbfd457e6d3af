"""The Mitsuba 3 references: `sss` against Mitsuba 3's path tracer.

Entry points (run by path, e.g. `python3 scripts/references/run.py --quick`):
  run.py       every reference, one table and summary.json
  profiles.py  Rd(r) of `sss simulate` against Mitsuba's volumetric path tracer
  images.py    `sss render` against Mitsuba on one scene and material

The image comparison's modules, one concern each:
  scenes    scene definitions (cameras, lights, geometry, the generated bust), the models each
            compares, a run's size and sample budgets (Setup)
  mitsuba3  building and running Mitsuba 3's renders of a scene (centred on what its camera
            looks at)
  halfspace the medium check: Mitsuba's half-space against Chandrasekhar's exact reflectance
  ours      running `sss` (`materials`, `simulate`, `fit`, `render`) and reading its outputs
  scoring   noise-corrected RMSE ± SE on 2×2 blocks, SSIM, paired block comparisons, the
            calibration test, the compared blocks (coverage, silhouettes)
  rankings  what must hold and what is reported: paired rankings and the energy checks
  budget    the error budget's terms and its printed lines
  sheets    PNGs and the labelled comparison sheet

Nothing is imported here: `import references.scoring` loads NumPy only, and Mitsuba, Matplotlib
load where they are used.
"""
