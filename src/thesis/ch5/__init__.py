"""Chapter 5: terrain classification from simulated Puppy II recordings.

Modules, one job each:

* :mod:`~thesis.ch5.sensors`: the 64 recorded signals and the sensor groups of
  Tab. 5.2;
* :mod:`~thesis.ch5.gaits`: the hip commands of the bound-right, turn-left and random
  gaits (§5.3.1);
* :mod:`~thesis.ch5.recordings`: simulating the trials of Tab. 5.1 on the engine and
  reading them back (``data/synthetic/puppy/<profile>.h5``);
* :mod:`~thesis.ch5.reservoir`: the exponential moving average (eq. 5.2), the leaky
  ELM and the leaky echo state network (§5.2.1-5.2.3);
* :mod:`~thesis.ch5.readout`: least-squares readout and the naive-Bayes readout of
  the terrain cells (eq. 5.8-5.9);
* :mod:`~thesis.ch5.sfa`: slow feature analysis (eq. 5.3-5.6) and the quadratic
  expansion of SFA2;
* :mod:`~thesis.ch5.protocol`: normalisation, parts, the five selections and their
  folds (§5.3.1), scoring (§5.3.2);
* :mod:`~thesis.ch5.methods`: the pipelines PCA -> expansion -> readout of every
  method (LR, ELM, RC, SFA2, RC-SFA, ELM-SFA);
* :mod:`~thesis.ch5.tuning`: CMA-ES over each method's hyper-parameters (§5.2.5);
* :mod:`~thesis.ch5.experiments`: the registered experiments (Tab. 5.3-5.6,
  Fig. 5.3 and the recordings).
"""
