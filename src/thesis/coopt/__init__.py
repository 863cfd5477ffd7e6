"""§8.2 made real: controller and morphology co-optimised by gradient through the engine.

Modules: :mod:`~thesis.coopt.morphology` (the chapter-7 quadruped's body as bounded,
differentiable parameters), :mod:`~thesis.coopt.objective` (closed-loop controller and
the gait objective on a body), :mod:`~thesis.coopt.estimators` (score-function and
evolution-strategies estimates of the same gradient), :mod:`~thesis.coopt.experiments`
(the registered experiments ``coopt/arms`` and ``coopt/gradients``).

Imports :mod:`thesis.ch7` (the chapter-7 networks, optimiser and trot) and the
engine; no chapter imports this package.
"""
