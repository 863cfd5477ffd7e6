"""Chapter 2: spatial chirp-Z transformer networks on cluttered MNIST sequences.

Modules (one job each):

- :mod:`~thesis.ch2.czt`: the chirp-Z transform layer (Alg. 2.1, eq. 2.1, §2.3-§2.4);
- :mod:`~thesis.ch2.transforms`: bilinear (6 parameters), bilinear no-skew (4),
  chirp-Z (4) and "none" behind one interface (``TRANSFORMS``, ``get_transform``);
- :mod:`~thesis.ch2.data` and :mod:`~thesis.ch2.idx`: the cluttered MNIST sequence
  synthesiser (§2.5) and the MNIST IDX reader;
- :mod:`~thesis.ch2.nets`: FFN-SPN and RNN-SPN of Tab. 2.1 in plain JAX;
- :mod:`~thesis.ch2.train`: the training loop (§2.5, docs/sources.md#rstn-training);
- :mod:`~thesis.ch2.experiments`: the registered experiments ``ch2/cluttered_mnist``,
  ``ch2/table2_2_ffn_spn``, ``ch2/table2_2_rnn_spn`` (one model's part; the workflow runs
  one job per model and seed), ``ch2/table2_2`` (the parts joined) and
  ``ch2/chirpz_scaling`` (``thesis bench chirpz``).
"""

from thesis.ch2.czt import chirpz_resample, direct_resample
from thesis.ch2.transforms import TRANSFORMS, Transform, bilinear_sample, get_transform

__all__ = ["chirpz_resample", "direct_resample", "TRANSFORMS", "Transform", "bilinear_sample",
           "get_transform"]
