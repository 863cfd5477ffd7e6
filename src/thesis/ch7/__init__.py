"""Chapter 7: experiments with the differentiable physics engine (``thesis.physics``).

- :mod:`~thesis.ch7.ball`: §7.2.1 ball throw, BPTT gradient descent vs CMA-ES;
- :mod:`~thesis.ch7.arm`: §7.3.2 4-DoF arm, fixed target and random targets;
- :mod:`~thesis.ch7.gait`: §7.3.3 quadruped gait from a sine/cosine input;
- :mod:`~thesis.ch7.pendulum`: §7.3.3.1 cart-pole swing-up from camera pixels;
- :mod:`~thesis.ch7.nets`, :mod:`~thesis.ch7.bptt`: controllers and the BPTT
  tricks of §7.3.2; :mod:`~thesis.ch7.frames`: frame strips from the engine camera;
- ``bench_engine``, ``bench_mjx``, ``quadruped_mjcf``: Tab. 7.1.

Experiment modules are imported lazily by :mod:`thesis.registry`.
"""
