"""Chapter 3: trotting and turning gaits of the simulated Oncilla, optimised with PSO.

Modules: :mod:`~thesis.ch3.turning` (the five turning strategies of §3.3.2 and the
LED-tracking P-controller of §3.3.3) and :mod:`~thesis.ch3.experiments` (the registered experiments
``ch3/table3_1``, ``ch3/fig3_4``, ``ch3/robustness``, ``ch3/table3_2``, ``ch3/fig3_5``).
The gait families, leg kinematics and the gait runner are the shared library
:mod:`thesis.gaits`.
"""
