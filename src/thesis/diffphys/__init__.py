"""Chapter 7: experiments with the differentiable physics engine (``thesis.physics``).

- :mod:`~thesis.diffphys.ball`: §7.2.1 ball throw, BPTT gradient descent vs CMA-ES;
- :mod:`~thesis.diffphys.arm`: §7.3.2 4-DoF arm, fixed target and random targets;
- :mod:`~thesis.diffphys.gait`: §7.3.3 quadruped gait from a sine/cosine input;
- :mod:`~thesis.diffphys.pendulum`: §7.3.3.1 cart-pole swing-up from camera pixels;
- :mod:`~thesis.diffphys.nets`, :mod:`~thesis.diffphys.bptt`: controllers and the BPTT
  tricks of §7.3.2; :mod:`~thesis.diffphys.frames`: frame strips from the engine camera;
- ``bench_engine``, ``bench_mjx``, ``quadruped_mjcf``: Tab. 7.1.

Experiment modules are imported lazily by :mod:`thesis.registry`.
"""
