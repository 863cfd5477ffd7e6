"""Claims of chapter 4 (transfer learning of gaits with PSO). Experiments not built yet.

Every check here is a placeholder (``fn=None``): ``Claim.check`` answers "missing
datasets: ..." until the artifacts exist and "check not implemented: experiment not built"
after, so nothing is guessed about layouts that do not exist. The ``requires`` name the
natural artifacts: ``table4_2``/``table4_3``/``table4_4`` (best particles per setting, with
and without transfer), ``fig4_5``/``fig4_7``/``fig4_8`` (per-generation particle speeds with
and without transfer: the Wilcoxon rank-sum per generation combined with Fisher's method,
:func:`thesis.claims.stats.mann_whitney` and :func:`thesis.claims.stats.fisher_combine`),
``fig4_10`` (search-space size per generation). To implement one, write its check in this
module with the helpers of :mod:`thesis.claims.stats` and pass it as ``fn``.
"""

from __future__ import annotations

from thesis.claims.types import Claim

_SPEEDS = tuple(
    [f"table4_2/grade={g}/transfer={t}/speed" for g in (9, 18) for t in (0, 1)]
    + [f"table4_3/stiffness=compliant/transfer={t}/speed" for t in (0, 1)]
    + ["table4_4/terrain=pebbly/transfer=0/rank=1/speed",
       "table4_4/terrain=pebbly/transfer=1/rank=1/speed",
       "table4_4/terrain=pebbly/transfer=1/rank=2/speed"]
)

CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="ch4.transfer_gives_better_gaits_in_all_cases", chapter=4, section="§4.8",
        quote="We found that using transfer learning results in better gaits than without "
              "transfer learning in all tested cases, evaluated on a real robot.",
        summary="Best-particle speed with transfer exceeds that without, on the 9 % and 18 % "
                "slopes, with compliant front legs and on pebbles.",
        paper_keys=_SPEEDS,
        requires=("ch4/table4_2", "ch4/table4_3", "ch4/table4_4"),
    ),
    Claim(
        id="ch4.transfer_better_in_three_of_four", chapter=4, section="§4.8",
        quote="Everything considered, we conclude that transferring particles resulted in "
              "better gaits in the same amount of robot time in three out of four cases, while "
              "not harming the optimization speed in the fourth case.",
        summary="Per-generation speeds with transfer significantly exceed those without on both "
                "slopes and with compliant legs, and are not significantly worse on pebbles.",
        paper_keys=("fig4_5/grade=9/p_value_upper_bound", "fig4_5/grade=18/p_value_upper_bound",
                    "fig4_7/p_value_upper_bound", "fig4_8/p_value_lower_bound"),
        requires=("ch4/fig4_5", "ch4/fig4_7", "ch4/fig4_8"),
    ),
    Claim(
        id="ch4.transfer_significant_on_slopes", chapter=4, section="§4.6.1",
        quote="We find that the particles in the optimization with transfer learning on average "
              "outperform the particles without transfer learning significantly on both "
              "inclinations",
        summary="Fisher-combined per-generation rank-sum p < 0.001 on the 9 % and 18 % slopes.",
        paper_keys=("fig4_5/grade=9/p_value_upper_bound", "fig4_5/grade=18/p_value_upper_bound"),
        requires=("ch4/fig4_5",),
    ),
    Claim(
        id="ch4.transfer_significant_with_compliant_legs", chapter=4, section="§4.6.2",
        quote="we find that the particles in the optimization process with transfer learning "
              "run significantly larger distances",
        summary="Fisher-combined per-generation rank-sum p < 0.05 with one spring removed from "
                "each front leg.",
        paper_keys=("fig4_7/p_value_upper_bound",), requires=("ch4/fig4_7",),
    ),
    Claim(
        id="ch4.transfer_not_significant_on_pebbles", chapter=4, section="§4.6.3",
        quote="Over all generations together, the particles optimized with transfer learning do "
              "not perform significantly better than the particles without transfer learning",
        summary="Fisher-combined per-generation rank-sum p > 0.05 on pebbly terrain.",
        paper_keys=("fig4_8/p_value_lower_bound",), requires=("ch4/fig4_8",),
    ),
    Claim(
        id="ch4.speedup_from_reduced_search_space", chapter=4, section="§4.8",
        quote="We have also shown that the increased learning speed is caused by a reduction of "
              "the volume in the parameter space that is used in the exploration.",
        summary="Search-space size (geometric mean of principal-axis lengths) per generation is "
                "smaller with transfer (thesis: 1.7x on average, 18 % slope).",
        paper_keys=("fig4_10/search_space_ratio",), requires=("ch4/fig4_10",),
    ),
    Claim(
        id="ch4.steeper_slopes_shorter_steps", chapter=4, section="§4.6.1",
        quote="We notice that on steeper inclinations, the step-length is reduced while the "
              "robot spends more time with its feet on the ground.",
        summary="Best-particle step length a decreases and t_stance increases from flat to 9 % "
                "to 18 % grade.",
        paper_keys=tuple(f"table4_2/grade={g}/transfer={t}/{v}" for g, t in
                         ((0, 0), (9, 0), (9, 1), (18, 0), (18, 1)) for v in ("a", "t_stance")),
        requires=("ch4/table4_2",),
    ),
)
