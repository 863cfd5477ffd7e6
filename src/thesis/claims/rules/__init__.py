"""The decision rules of :mod:`thesis.claims.stats`, one module per kind of sentence:
:mod:`~thesis.claims.rules.means` (rules 4-6), :mod:`~thesis.claims.rules.runs` (rule 9),
:mod:`~thesis.claims.rules.counts` (rules 7 and 10, chapter 6's rate rule),
:mod:`~thesis.claims.rules.measurements` (rule 8) and :mod:`~thesis.claims.rules.common`
(rules 1, 2, 11 and the conjunction of parts)."""
