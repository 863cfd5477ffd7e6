"""Claims of chapter 5 (terrain classification on Puppy II). Experiments not built yet.

Every check here is a placeholder (``fn=None``): ``Claim.check`` answers "missing
datasets: ..." until the artifacts exist and "check not implemented: experiment not built"
after. The ``requires`` name the natural artifacts ``table5_3`` (LR and RC per sensor
selection), ``table5_4`` (LR, ELM, RC by hidden nodes on touch and minimal), ``table5_5``
(SFA2 and RC-SFA per selection), ``table5_6`` (ELM-SFA and RC-SFA by hidden nodes) and
``fig5_3`` (generalisation confusion matrices). To implement one, write its check in this
module with the helpers of :mod:`thesis.claims.stats` and pass it as ``fn``.
"""

from __future__ import annotations

from thesis.claims.types import Claim

_SEL = ("useful", "reduced", "minimal", "leg", "agt", "imu", "joints", "touch")


def _t53(selections, methods=("lr", "rc"), split="test"):
    return tuple(f"table5_3/selection={s}/split={split}/method={m}/accuracy"
                 for s in selections for m in methods)


CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="ch5.limited_sensor_selection_suffices", chapter=5, section="§5.5",
        quote="In this paper, we showed that a limited but appropriate selection of input "
              "sensors is sufficient to perform terrain classification on our legged robot.",
        summary="RC test accuracy with the 18-signal 'minimal' selection is not below that with "
                "the 55-signal 'useful' selection.",
        paper_keys=_t53(("useful", "minimal")) + ("sec5.4.1.2/minimal_dimensions",),
        requires=("ch5/table5_3",),
    ),
    Claim(
        id="ch5.nonlinearity_needed", chapter=5, section="§5.5",
        quote="The fact that linear regression performed badly on the data, indicates the "
              "importance of adding non-linearities.",
        summary="RC (and ELM) test accuracy exceeds LR's for every sensor selection; LR has over "
                "10 % more misclassifications than any technique with 100 hidden nodes.",
        paper_keys=_t53(_SEL) + ("table5_4/nodes=100/lr_extra_misclassification",
                                 "table5_4/accuracy"),
        requires=("ch5/table5_3", "ch5/table5_4"),
    ),
    Claim(
        id="ch5.reservoir_beats_quadratic_expansion", chapter=5, section="§5.5",
        quote="For these non-linearities, we found that reservoirs perform better than "
              "quadratically expanding, as is demonstrated by the unsupervised classification "
              "method.",
        summary="RC-SFA test accuracy exceeds SFA2's for every sensor selection (thesis: 10 to "
                "20 points; SFA2 near a random sensor).",
        paper_keys=tuple(f"table5_5/selection={s}/split=test/method={m}/accuracy"
                         for s in _SEL for m in ("sfa2", "rc_sfa"))
        + ("table5_5/random_sensor_accuracy", "table5_5/rc_sfa_gain_low",
           "table5_5/rc_sfa_gain_high"),
        requires=("ch5/table5_5",),
    ),
    Claim(
        id="ch5.reservoir_better_with_few_sensors", chapter=5, section="§5.5",
        quote="For supervised learning, reservoir computing led to drastic better performance "
              "when using few sensors, which indicates that the richness of the non-linear "
              "temporal expansion is beneficial for classification with less information.",
        summary="On the 4-signal 'touch' selection RC test accuracy exceeds ELM's (thesis: by "
                "about 10 points; Tab. 5.4 itself is unavailable).",
        paper_keys=("table5_4/selection=touch/rc_minus_elm_accuracy", "table5_4/accuracy"),
        requires=("ch5/table5_4",),
    ),
    Claim(
        id="ch5.rc_and_elm_equal_with_enough_inputs", chapter=5, section="§5.4.1.2",
        quote="The results also show that given enough input signals (minimal: 18 dimensions), "
              "RC and ELM achieve virtually the same performance.",
        summary="On 'minimal', RC and ELM test accuracies are equivalent within a margin "
                "(supervised Tab. 5.4; unsupervised Tab. 5.6).",
        paper_keys=("sec5.4.1.2/minimal_dimensions", "table5_4/accuracy")
        + tuple(f"table5_6/selection=minimal/split=test/method={m}/nodes={n}/accuracy"
                for m in ("elm_sfa", "rc_sfa") for n in (50, 100, 200)),
        requires=("ch5/table5_4", "ch5/table5_6"),
    ),
    Claim(
        id="ch5.tactile_sensors_important", chapter=5, section="§5.4.1.1",
        quote="This clearly indicates the importance of the tactile sensors for supervised "
              "terrain classification.",
        summary="Test accuracy of the selections without tactile sensors (imu, joints) is below "
                "that of their counterparts with them (agt, leg), for LR and RC.",
        paper_keys=_t53(("leg", "agt", "imu", "joints")), requires=("ch5/table5_3",),
    ),
    Claim(
        id="ch5.generalises_to_frequencies_not_gaits", chapter=5, section="§5.5",
        quote="However, when trained on a single gait, the methods studied here were not very "
              "effective at generalizing to unseen gaits.",
        summary="Trained on 'bound right' at 1 Hz, RC classifies terrains at unseen frequencies "
                "(where training data suffice) better than under unseen gaits (Fig. 5.3).",
        requires=("ch5/fig5_3",),
    ),
)
