"""One logic per sentence form: which decision rule reads which kind of thesis sentence.

A claim is decided by the rule of its sentence's *form*, never by the rule that happens to
give a wanted verdict. :data:`FORMS` lists the forms and their rules
(:mod:`thesis.claims.stats`); :data:`CLAIM_FORMS` lists each claim's form with the words
of its sentence that decide it. Chapter 6 is filled in here; the other chapters' claims
are added by their owners with the same forms.

=============  ======================================  ===================================
form           the sentence says                       rule (:mod:`thesis.claims.stats`)
=============  ======================================  ===================================
existential    "was found", "can", "is possible",      ``decide_exists``: reproduced when
               "we have shown that ... can"            more seeds show it, repeated by
                                                       their twin, than runs passing by
                                                       chance would give
usual          what the method does as a rule:         a majority shown: "in most runs"
               "learns in", "works", "fails",          (rule 10), "reached within N"
               "reached within N evaluations"          (rule 7) or chapter 6's
                                                       ``judge_usual`` (a rate shown above
                                                       / below 1/2, unclear between)
some_config    it holds for some setting of a sweep    Holm over the settings
                                                       (``decide_any``, ``ch6.holm_works``)
comparative    A beats / outperforms / is faster       rule 4, ``decide_beats``
similar        A is like / comparable to B             rule 5, ``decide_equivalent``
                                                       (ratios on their logarithm)
bound          X is below / above a number             rule 6, ``decide_threshold``
relation       X goes with / determines Y              rule 6 on a per-seed rank
                                                       correlation (one value per seed)
conjunction    several sentences at once               ``combine``: all parts; a part
                                                       contradicts after Holm
=============  ======================================  ===================================

Runs that can fail (fell, at chance, diverged) are read with their failure indicator
(rule 3b, :func:`~thesis.claims.stats.mixture_interval`) whatever the form.
"""

from __future__ import annotations

#: Sentence form -> the rule that decides it (see the module text).
FORMS: dict[str, str] = {
    "existential": "stats.decide_exists: more seeds show it, repeated by their twin run, "
                   "than runs passing by chance at 5 % would give; rate beside it",
    "usual": "a majority shown: stats.decide_majority (rule 10), "
             "stats.decide_within_budget (rule 7) or ch6.judge_usual (works / fails / "
             "unclear against a rate of 1/2)",
    "some_config": "Holm's correction over the settings (stats.decide_any, ch6.holm_works)",
    "comparative": "rule 4, stats.decide_beats",
    "similar": "rule 5, stats.decide_equivalent (ratios on their logarithm)",
    "bound": "rule 6, stats.decide_threshold",
    "relation": "rule 6 on a per-seed rank correlation (one value per seed)",
    "conjunction": "stats.combine: all parts; a part contradicts after Holm over the parts",
}

#: Claim id -> (forms, the words that decide the form and why).
CLAIM_FORMS: dict[str, tuple[tuple[str, ...], str]] = {
    "ch6.trot_h50_b5_stable": (
        ("existential",), "'an attractor was found': one seed that finds it shows it"),
    "ch6.phase1_only_fails": (
        ("usual", "conjunction"),
        "'it fails to find a stable attractor': what stage 1 alone does as a rule (rate "
        "rule), contrasted with both stages, which work (rate rule)"),
    "ch6.memoryless_feedback_trots": (
        ("existential",),
        "'we demonstrated how ... memory-less nonlinear feedback can generate a trot': a "
        "possibility the thesis showed with one run per configuration; the rate per H and "
        "which H work (Holm) are reported beside it, the H needed is the next claims'"),
    "ch6.learns_in_a_couple_of_strides": (
        ("usual", "some_config"),
        "'learns ... in the time span of only a couple of strides': what the controller "
        "does as a rule, so a stage length of about two strides must work (rate rule), for "
        "some short stage length (Holm over them)"),
    "ch6.extends_to_walk": (
        ("existential", "comparative"),
        "'we have shown that this method can be extended ... to a walk': existence of a "
        "walk with the larger settings; 'when increasing the training time and the model "
        "complexity': the larger settings walk more often than the trot's (Fisher exact)"),
    "ch6.memory_and_nonlinearity_interchangeable": (
        ("some_config", "similar"),
        "'either additional memory or additional non-linearities contribute approximately "
        "equally': each sweep reaches a working configuration (rate rule, Holm over the "
        "sweep) with minimal N within a factor 2"),
    "ch6.signal_count_determines_performance": (
        ("relation", "conjunction"),
        "'the parameter that mainly determines the performance is the number of signals': "
        "per seed, N against the training MSE and against success across the settings "
        "('mainly' is not tested)"),
    "ch6.mse_drops_rapidly": (
        ("bound",), "'the MSE drops rapidly during the first seconds': the MSE ratio after "
                    "2 s below 0.1 (on its logarithm)"),
    "ch6.linear_feedback_insufficient": (
        ("usual", "comparative"),
        "'it was not stable and did not always return to its limit cycle': what linear "
        "feedback does as a rule, so most seeds fail (rule 10 on the failures; stable in 30 "
        "of 40 is not 'not stable'); as the section's case for the ELM controller, "
        "comparative: linear feedback succeeds less often than the trot controller (Fisher "
        "exact)"),
    "ch8.ch6_stable_trot_in_few_periods_without_memory": (
        ("usual", "some_config"),
        "the summary of §6.7's 'learns ... in the time span of only a couple of strides': "
        "one finding, one verdict, so the chapter claim's rate rule on the same runs "
        "(ch6.learns_in_a_couple_of_strides)"),
    "ch8.ch6_signal_count_most_important": (
        ("relation",),
        "'the most important factor is the number of signals': per seed, N against the "
        "training MSE and against success (the check of "
        "ch6.signal_count_determines_performance; 'most important' is not tested)"),
}
