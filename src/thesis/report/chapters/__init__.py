"""One module per chapter: ``tables(results)`` and ``figures(results, outdir)``.

See :mod:`thesis.report.model` for the contract. A chapter without a module here has
not been built; the report then shows it as "not run". ``model`` is no thesis chapter:
the simulated Oncilla's own checks (``thesis bench oncilla``, results under
``results/<profile>/model/``) and the Puppy II's paw contact (``thesis bench
puppy-contact``); its figures render with ``thesis report --figures model``.
"""

CHAPTERS = {
    "ch2": "Chapter 2 — Spatial chirp-Z transformer networks",
    "ch3": "Chapter 3 — Trotting and turning gaits of the Oncilla quadruped",
    "ch4": "Chapter 4 — Transfer learning of gaits with PSO",
    "ch5": "Chapter 5 — Terrain classification on Puppy II",
    "ch6": "Chapter 6 — An embodied closed-loop gait",
    "ch7": "Chapter 7 — A differentiable physics engine",
    "coopt": "§8.2 — Controller and morphology co-optimised; analytic and estimated gradients",
    "model": "The simulated Oncilla — model-level checks",
}
