"""Departures of the §8.2 co-optimisation experiments (``coopt/*``) from the thesis.

§8.2 proposes co-optimising controller and morphology by gradient descent and comparing
analytic gradients with policy-gradient estimates, and specifies nothing of either; every
setting below is therefore a choice, except the servo torque, which departs from the
§7.3.3 quadruped the experiment is built on. Ids are ``ch8.coopt_*`` (chapter 8).
"""

from __future__ import annotations

from thesis.departures.types import Departure

_ARMS = ("coopt/arms",)
_GRADS = ("coopt/gradients",)
_ALL = (*_ARMS, *_GRADS)

DEPARTURES: tuple[Departure, ...] = (
    Departure(
        id="ch8.coopt_servo_torque", kind="deviation", results=_ALL,
        thesis="§7.3.3 limits the quadruped's servos (thesis.paper "
               "quadruped_gait/servo_torque).",
        ours="coopt.body.servo_torque (20 N m by default) for every arm and the gradient "
             "comparison.",
        why="At the thesis's bound no open-loop trot of ch7's grid search moves the robot "
            "forward upright and BPTT collapses it onto its belly (ch7.gait, "
            "ch7/quadruped_gait's hand-tuned search); 20 N m is the smallest torque of that "
            "search with a walking trot, so the arms start from a gait.",
        config=("coopt.body.servo_torque",), thesis_config=(("coopt.body.servo_torque", 4.0),),
    ),
    Departure(
        id="ch8.coopt_controller", kind="choice", results=_ALL,
        thesis="§8.2 names no controller for the co-optimisation; §7.3.3's gait network reads "
               "only a sine and a cosine (open loop).",
        ours="A fixed open-loop trot of ch7's grid (coopt.trot) plus §7.3.3's skip network "
             "(coopt.hidden) closing the loop on the joint angles and the spine's IMU "
             "(thesis.coopt.objective); its output starts at zero, so every arm starts from "
             "the trot on the built body, and the morphology-only arm keeps that controller.",
        why="A closed loop is what §8.2's morphological computation is about; starting from "
            "a trot gives the body-only arm a gait to improve (a zero controller stands "
            "still, where the body's gradient tells nothing).",
        config=("coopt.trot", "coopt.hidden"),
    ),
    Departure(
        id="ch8.coopt_morphology", kind="choice", results=_ALL,
        thesis="§8.2 names no morphological parameters or bounds.",
        ours="Eight parameters, symmetric over the legs, each within declared bounds "
             "(thesis.coopt.morphology.PARAMS): femur and tibia lengths, foot radius, hip "
             "placement along and across the spine, spine mass, and the stiffness and rest "
             "angle of a passive knee spring added in parallel with each knee servo; "
             "segments keep their density, the robot starts standing on its feet.",
        why="Lengths, masses, compliance and contact geometry are the quantities a body is "
            "made of; the knee spring is the simplest morphological computation the "
            "servo-only chapter-7 quadruped lacks.",
        config=("coopt.body",),
    ),
    Departure(
        id="ch8.coopt_budget", kind="choice", results=_ARMS,
        thesis="§8.2 gives no budget or optimiser for the co-optimisation; §7.3.3's gait "
               "objective averages over episodes of thesis.paper quadruped_gait/episode_s.",
        ours="coopt.arms.evaluations gradient evaluations per arm (the same for all three), "
             "Adam per parameter group with §7.3.2's clipping and gradient decay, the body "
             "in unconstrained (sigmoid-bounded) coordinates at "
             "coopt.arms.morphology_learning_rate; chapter 7's objective over "
             "coopt.arms.episode_s.",
        why="Equal budgets make the arms comparable; the laptop profile fits 30 minutes. "
            "Episodes shorter than §7.3.3's and a tenth of ch7.gait's learning rate, because "
            "with §7.3.3's episodes and that rate every arm got slower within 15 updates "
            "(schema coopt.arms.episode_s); the paper profile keeps §7.3.3's episodes.",
        config=("coopt.arms.evaluations", "coopt.arms.morphology_learning_rate",
                "coopt.arms.episode_s"),
    ),
    Departure(
        id="ch8.coopt_estimators", kind="choice", results=_GRADS,
        thesis="§8.2 suggests comparing analytic gradients with policy-gradient "
               "approximations without naming estimators or settings.",
        ours="Parameter-space Gaussian noise (coopt.gradients.sigma): REINFORCE with a "
             "leave-one-out baseline and antithetic ES, against the engine's exact "
             "gradient (no decay) at a probe point with a non-zero network output; agreement "
             "is a median cosine above coopt.gradients.cos_threshold.",
        why="The two standard black-box estimators of a smoothed objective's gradient; "
            "the baseline and the antithetic pairs are their usual variance reductions, so "
            "the comparison is not against a strawman.",
        config=("coopt.gradients.sigma", "coopt.gradients.cos_threshold",
                "coopt.gradients.horizons_steps"),
    ),
)
