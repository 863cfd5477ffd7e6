"""Chapter 4: transfer learning of Oncilla gaits with PSO across slopes, compliant legs and
pebbles.

Modules: :mod:`~thesis.ch4.transfer_runs` (the PSO runs with and without transfer under
each condition, registered as ``ch4/flat``, ``ch4/transfer_*`` and ``ch4/tether``) and
:mod:`~thesis.ch4.transfer_artifacts` (Tab. 4.2-4.4 and Fig. 4.3-4.10 from those runs).
The conditions, gait families and the gait runner are the shared library
:mod:`thesis.gaits`.
"""
