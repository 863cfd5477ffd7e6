"""Claims of chapter 6 (embodied gait with ELM + delay buffer + RLS). Experiments not built.

Every check here is a placeholder (``fn=None``): ``Claim.check`` answers "missing
datasets: ..." until the artifacts exist and "check not implemented: experiment not built"
after. The ``requires`` name the natural artifacts of the §6.5 experiments: ``trot``
(H = 50, B = 5), ``walk`` (H = 50, B = 12), ``minimal_buffer`` (smallest stable B at
H = 12), ``minimal_hidden`` (smallest stable H at B = 0), ``minimal_training`` (shortest
stages at H = 250, B = 0), ``fig6_6`` (training MSE against N = (B + 1) H + 1) and
``linear_feedback`` (no hidden layer, no buffer). To implement one, write its check in
this module with the helpers of :mod:`thesis.claims.stats` and pass it as ``fn``.
"""

from __future__ import annotations

from thesis.claims.types import Claim

CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="ch6.memoryless_feedback_trots", chapter=6, section="§6.7",
        quote="In this paper, we demonstrated how an embodied control system with memory-less "
              "nonlinear feedback can generate a dynamically balanced trot on a compliant "
              "quadrupedal robot.",
        summary="With B = 0 some H (thesis: 128 +- 32) gives a trot stable for 30 s that "
                "recovers after the motors are switched off and on.",
        paper_keys=("minimal_hidden/min_hidden_neurons",
                    "minimal_hidden/min_hidden_neurons_uncertainty", "sec6.4/stable_run_seconds"),
        requires=("ch6/minimal_hidden",),
    ),
    Claim(
        id="ch6.learns_in_a_couple_of_strides", chapter=6, section="§6.7",
        quote="Our feedback controller, based on extreme learning machines, learns the desired "
              "relation between the input and the output signals in the time span of only a "
              "couple of strides.",
        summary="With H = 250, B = 0, training stages of about two gait periods (1.18 s each) "
                "give a stable trot.",
        paper_keys=("minimal_training/hidden_neurons", "minimal_training/stage_seconds",
                    "minimal_training/total_training_seconds"),
        requires=("ch6/minimal_training",),
    ),
    Claim(
        id="ch6.extends_to_walk", chapter=6, section="§6.7",
        quote="We have shown that this method can be extended to other gaits, such as a walk, "
              "when increasing the training time and the model complexity.",
        summary="A walk is learned stably with H = 50 and a larger buffer (B = 12) and longer "
                "stages (30 s) than the trot needs.",
        paper_keys=("walk/hidden_neurons", "walk/buffer_steps", "walk/stage_seconds",
                    "trot/buffer_steps"),
        requires=("ch6/walk", "ch6/trot"),
    ),
    Claim(
        id="ch6.memory_and_nonlinearity_interchangeable", chapter=6, section="§6.7",
        quote="The incorporation of either additional memory or additional non-linearities "
              "contribute approximately equally to the controller performance.",
        summary="Fewer hidden neurons can be compensated by a longer buffer and vice versa "
                "(H = 12 needs B >= 16; B = 0 needs H ~ 128).",
        paper_keys=("minimal_buffer/hidden_neurons", "minimal_buffer/min_buffer_steps",
                    "minimal_hidden/min_hidden_neurons"),
        requires=("ch6/minimal_buffer", "ch6/minimal_hidden"),
    ),
    Claim(
        id="ch6.signal_count_determines_performance", chapter=6, section="§6.7",
        quote="The parameter that mainly determines the performance is the number of signals "
              "that is fed into the the linear transformation.",
        summary="Training MSE decreases with N = (B + 1) H + 1 across (H, B) settings, and "
                "settings with too high an MSE fail to find a stable attractor.",
        requires=("ch6/fig6_6",),
    ),
    Claim(
        id="ch6.linear_feedback_insufficient", chapter=6, section="§6.3.1",
        quote="On our robot however, we found that we could indeed generate a gait this way, "
              "but that it was not stable and did not always return to its limit cycle.",
        summary="Linear feedback from the encoders alone (no hidden layer, no buffer) does not "
                "give a stable gait.",
        requires=("ch6/linear_feedback",),
    ),
)
