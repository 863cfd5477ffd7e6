"""Model-level checks of the simulated robots, apart from any chapter's experiments: the
measuring instruments that decide a model revision (``thesis bench oncilla``), kept out
of the chapters' code so that they never change a chapter's results or their hashes; and
the Oncilla's validation on the thesis's published gaits against targets written before
any model change (``thesis validate oncilla``: :mod:`thesis.modelcheck.targets`,
:mod:`thesis.modelcheck.validation`)."""
