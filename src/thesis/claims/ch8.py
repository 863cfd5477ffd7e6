"""Claims of §8.1, the dissertation's conclusions per chapter.

Each restates a chapter's result in new words; where that chapter's check exists it is
reused (same data, same rule), so a §8.1 verdict never disagrees with the chapter's own
claim for the same reason. Where §8.1's sentence has another form than the chapter's
(:mod:`thesis.claims.forms`), the form decides: §8.1's "we demonstrated that in as little
as a couple of periods ... already finds stable parameters" is existential, §6.7's
"learns ... in the time span of only a couple of strides" a rate, on the same data.
"""

from __future__ import annotations

from thesis.claims import ch2, ch3, ch4, ch5, ch6, ch7
from thesis.claims.types import Claim

CLAIMS: tuple[Claim, ...] = (
    Claim(
        id="ch8.ch2_prior_in_architecture_beats_cnn", chapter=8, section="§8.1",
        quote="We showed that this approach indeed outperforms standard convolutional neural "
              "networks.",
        summary="Chirp-Z spatial transformer (mean over model and d) has lower test error than "
                "the plain network (rule 4; rule 3b with networks at chance as failed, the "
                "check of ch2.spatial_transformers_beat_plain).",
        paper_keys=tuple(f"table2_2/model={m}/d={d}/transform={t}/test_error"
                         for m in ("ffn_spn", "rnn_spn") for d in (1, 2, 3)
                         for t in ("chirp_z", "none")),
        requires=(ch2.KEY,), reads=ch2.READS, units=ch2.MEASURED_UNITS,
        fn=lambda r: ch2.spatial_beats_plain(r, ["chirp_z"]),
    ),
    Claim(
        id="ch8.ch3_biological_trajectory_beats_sine", chapter=8, section="§8.1",
        quote="Firstly, we observed that a more biologically inspired trajectory outperforms a "
              "sine-based approach, especially for higher speeds.",
        summary="Half-ellipse and spline gaits are both faster than the sine gait above 1 Hz "
                "(rule 4 for each).",
        paper_keys=(ch3.KNEE_KEY, "fig3_4/gait=sine/speed_compared",
                    "fig3_4/gait=half_ellipse/speed_compared",
                    "fig3_4/gait=spline/frequency=1.5/speed"),
        requires=(ch3.FIG,), reads=(f"{ch3.FIG}:speed",),
        fn=ch3.trajectories_beat_sine_high_speed,
    ),
    Claim(
        id="ch8.ch3_scapulae_help_maintain_speed", chapter=8, section="§8.1",
        quote="Secondly, we showed that having scapulae for turning helps maintain speed, "
              "although it is also possible for legged robots to turn without.",
        summary="Turning with the scapulae is faster than step-size turning (rule 4) and "
                "keeps the straight-line speed (as ch3.scapulae_maintain_speed), and a stable "
                "step-size turn happened in some seed ('possible to turn without': existence).",
        paper_keys=("table3_2/strategy=step_size/speed", "table3_2/strategy=scapulae/speed",
                    "table3_2/forward_speed"),
        requires=(ch3.TURN,), reads=(f"{ch3.TURN}:speed", f"{ch3.TURN}:forward_speed",
                                     f"{ch3.TURN}:stable"),
        fn=ch3.scapulae_help_keep_speed,
    ),
    Claim(
        id="ch8.ch4_transfer_better_except_rocky", chapter=8, section="§8.1",
        quote="Although an important footnote, in one of the cases the warm start did not make "
              "a significant difference, namely when transfer learning from a flat terrain to a "
              "rocky one.",
        summary="Transfer significantly better (p < 0.05) on both slopes and with compliant "
                "legs, and no significant difference either way on pebbles (two-sided p > "
                "0.05) (rule 9 for each; all must hold).",
        paper_keys=("fig4_5/grade=9/p_value_upper_bound", "fig4_5/grade=18/p_value_upper_bound",
                    "fig4_7/p_value_upper_bound", "fig4_8/p_value_lower_bound"),
        requires=(ch4.SLOPES, ch4.SOFT, ch4.PEBBLES),
        reads=tuple(f"{k}:score" for k in (ch4.SLOPES, ch4.SOFT, ch4.PEBBLES)),
        fn=ch4.better_except_rocky,
    ),
    Claim(
        id="ch8.ch4_reduced_exploration", chapter=8, section="§8.1",
        quote="We found that the main aspect which made these warm starts perform better was "
              "the reduced amount of exploration in the parameter space.",
        summary="Causal ('the main aspect which made these warm starts perform better'): "
                "untestable without an intervention on the search volume, as "
                "ch4.speedup_from_reduced_search_space; the correlations it rests on are shown.",
        paper_keys=("fig4_10/search_space_ratio",), requires=(ch4.F410, ch4.SLOPES),
        reads=(f"{ch4.F410}:search_space_size", f"{ch4.SLOPES}:score"),
        fn=ch4.reduced_search_space,
    ),
    Claim(
        id="ch8.ch5_memory_important", chapter=8, section="§8.1",
        quote="More interestingly, from the comparison of extreme learning machines to "
              "reservoirs, it seems clear that memory is an important element.",
        summary="'Important': reservoirs (with memory) beat leaky ELMs (without) when few "
                "sensors are used, by more than 5 points: on touch, RC test accuracy with 100 "
                "nodes minus the ELM's (Tab. 5.4, rule 6; the same check as "
                "ch5.reservoir_better_with_few_sensors).",
        paper_keys=("table5_4/selection=touch/rc_minus_elm_accuracy",),
        requires=(ch5.T54,), reads=(f"{ch5.T54}:accuracy",), fn=ch5.rc_beats_elm_on_touch,
    ),
    Claim(
        id="ch8.ch6_stable_trot_in_few_periods_without_memory", chapter=8, section="§8.1",
        quote="We demonstrated that in as little as a couple of periods of the gait, this "
              "system already finds stable feedback control parameters for trotting without "
              "requiring any memory.",
        summary="The summary of §6.7's 'learns ... in the time span of only a couple of "
                "strides', one finding with one verdict: ch6.learns_in_a_couple_of_strides's "
                "rule on the same runs (with B = 0 and H = 250, some stage length <= 1.18 s "
                "+ 25 % works for a majority of seeds, shown; Holm over the short stages).",
        paper_keys=("minimal_training/stage_seconds", "minimal_training/hidden_neurons"),
        requires=(ch6.TRAINING,),
        reads=(f"{ch6.TRAINING}:success", f"{ch6.TRAINING}:stage1_seconds"),
        fn=ch6.finds_stable_in_couple_of_periods,
    ),
    Claim(
        id="ch8.ch6_signal_count_most_important", chapter=8, section="§8.1",
        quote="We found that the most important factor is the number of signals fed to the "
              "linear transformation.",
        summary="Per seed, Spearman's rho across the ELM settings (H, B): N = (B + 1) H + 1 "
                "against the training MSE (negative) and against success (positive), each "
                "decided on its per-seed values (rule 6 against 0; the check of "
                "ch6.signal_count_determines_performance). 'Most important' (N more than H "
                "or B alone) is not tested.",
        requires=(ch6.FIG66,),
        reads=(f"{ch6.FIG66}:train_mse", f"{ch6.FIG66}:success", f"{ch6.FIG66}:n_signals"),
        fn=ch6.signal_count_determines_performance,
    ),
    Claim(
        id="ch8.ch7_pendulum_from_pixels", chapter=8, section="§8.1",
        quote="By using backpropagation through time, through physics and through the "
              "renderer, we were able to find a deep neural network controller for the inverted "
              "pendulum from pixels.",
        summary="Existential ('we were able to find'): at least one seed swings up and "
                "balances within twice the thesis's episode count (pendulum_pixels/episodes) "
                "and its final controller keeps it up to "
                "the end of the test run; k of n seeds reported.",
        paper_keys=("pendulum_pixels/episodes",),
        requires=(ch7.PEND,), reads=ch7.PEND_READS, fn=ch7.pendulum_found,
    ),
    Claim(
        id="ch8.ch7_gait_in_500_evaluations", chapter=8, section="§8.1",
        quote="For a quadruped legged robot model, we were able to use deep neural networks to "
              "find a stable gait in only 500 model evaluations.",
        summary="Existential ('we were able to ... find a stable gait'): at least one "
                "seed's gait within the thesis's evaluation budget is as fast as its "
                "hand-tuned trot (paper keys below), with the thesis's episodes and controller "
                "(rule 11); k of n seeds reported.",
        paper_keys=("quadruped_gait/evaluations_to_stable_gait",
                    "quadruped_gait/hand_tuned_speed", "quadruped_gait/episode_s",
                    "quadruped_gait/n_params"),
        requires=(ch7.GAIT,), reads=(f"{ch7.GAIT}:speed",),
        fn=ch7.gait_found,
    ),
)
