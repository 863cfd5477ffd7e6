"""Departures of chapter 3 from the thesis (see :class:`thesis.departures.types.Departure`).

The thesis's numbers are referred to by ``thesis.paper`` key; the pipeline's values are the
config paths named (recorded with every result).
"""

from __future__ import annotations

from thesis.departures.types import Departure

ALL = ("ch3/table3_1_part", "ch3/table3_1", "ch3/fig3_4", "ch3/robustness", "ch3/table3_2",
       "ch3/fig3_5")

DEPARTURES: tuple[Departure, ...] = (
    Departure(
        id="ch3.simulated_oncilla", kind="deviation", results=ALL,
        thesis="§3.2: every gait was optimised and measured on the real Oncilla robot, on a "
               "treadmill, without a model of the robot.",
        ours="Every gait runs on a simulated Oncilla on the shared engine "
             "(thesis.physics.models.oncilla).",
        why="The robot is not available; a simulation is the only way to rerun the "
            "experiments. Claims about gaits are then claims about the model.",
    ),
    Departure(
        id="ch3.oncilla_model", kind="choice", results=ALL,
        thesis="§3.2.1 describes the Oncilla qualitatively (pantographic legs, cable-driven "
               "knees with springs, scapulae); it gives no dimensions, masses, spring rates, "
               "motor limits or friction.",
        ours="Hip placement (0.35 m apart, scapula axes +-0.069 m), scapula servos, mass and "
             "motor placement are taken from the official AMARSi simulation and the Oncilla "
             "paper (docs/sources.md#oncilla-hips, #oncilla-mass); the leg's outboard offset (its "
             "0.20 m track agrees within "
             "about 10 % with the official simulation's render, measured through the render's "
             "floor lattice), trunk shell, motor masses, "
             "segment lengths, the drives' time constant and foot friction are assumed, "
             "each with its reason in thesis.physics.models.oncilla; the time step and the "
             "solver (ch3.model: dt, sweeps, the momentum order) are the candidate that the "
             "Oncilla's convergence table (model/convergence, its verdict shown beside every "
             "verdict) was run on before any chapter ran on them; that table finds the step "
             "not converged, and half of it (twice the CPU) not converged either on the "
             "slow gaits, so the chapters keep it; the feet are the render's "
             "plates (ch4.foot_plates) and the knee spring, the drives' stiffness and the "
             "plates' size are fitted (ch4.oncilla_fit). The hind "
             "legs are the fore legs scaled to a 182 mm reach (the hind feet of Tab. "
             "4.2-4.4's optima reach 181.9 mm from the hip) with 2200/1850 of their knee "
             "range (the robot backend's knee motor counts): the scaling and reading counts "
             "as angle are choices (leg_geometry.oncilla_hind_geometry).",
        why="The thesis and public sources give only part of the robot (docs/sources.md#oncilla); "
            "of the values no source gives, only the knee spring, the drives' stiffness and "
            "the plates' size are fitted to results of the thesis (ch4.oncilla_fit).",
        config=("ch3.model.dt", "ch3.model.solver_iterations", "ch3.model.sweep_order",
                "ch3.model.relaxation", "ch3.model.contact_relaxation",
                "ch3.model.row_relaxation", "ch3.model.momentum", "ch3.model.restart"),
    ),
    Departure(
        id="ch3.knee_spring_fitted", kind="choice", results=ALL,
        thesis="§3.2.1: the knees are cable-driven against springs; no spring rate is given "
               "(nor by any public source: docs/sources.md#oncilla-knee-spring). §3.3.1.2 "
               "explains the speed below the "
               "feet's theoretical one by the legs' compression under the robot's weight.",
        ours="The knee's extension spring (ch3.model.knee_spring) is FITTED: with the other "
             "unsourced values by thesis.modelcheck.fit to the split's fitted side "
             "(ch4.oncilla_fit, model/fit), which includes the validation's target V1 (Tab. "
             "3.1a's half ellipse at 1.5 Hz); model/calibration, the earlier fit of the "
             "spring alone to V1 (thesis.modelcheck.calibration), still runs and shows "
             "whether the configured spring is its fit. A claim whose thesis number is a "
             "fitted speed is marked as resting on a calibration target.",
        why="The spring sets the stance compression that makes the robot walk below the "
            "feet's theoretical speed; with the sweep ladder's solver and the model's assumed "
            "default of 10 N m/rad it walks Tab. 3.1a at its theoretical speed, 1.6x the "
            "robot's.",
        config=("ch3.model.knee_spring",),
    ),
    Departure(
        id="ch3.simulated_treadmill", kind="deviation", results=ALL,
        thesis="§3.2.4-§3.2.5: on the treadmill the gaits run one after another with a "
               "transition in between; the belt speed keeps the robot in place, the walked "
               "distance is the integrated belt speed, and the robot's camera tracks an LED at "
               "the front of the treadmill.",
        ours="Each robot starts standing, eases into the outgoing gait's pose (ch3.protocol."
             "settle), makes the §3.2.5 transition from the previous particle's gait and is "
             "measured over its window on a flat floor; distance is the trunk's displacement, "
             "and the simulated camera sees an LED kept at a fixed distance ahead "
             "(ch3.protocol.led_distance, led_height).",
        why="A batched simulation evaluates a generation in parallel rather than one robot "
            "after another; a fixed LED distance is what the treadmill's regulation provides.",
        config=("ch3.protocol.settle", "ch3.protocol.led_distance", "ch3.protocol.led_height"),
    ),
    Departure(
        id="ch3.fall_handling", kind="deviation", results=ALL,
        thesis="Eq. 3.3 scores a gait by the distance walked minus the LED's wobble; on the "
               "real treadmill an assistant intervened when a robot was about to fall.",
        ours="A robot whose trunk drops below ch3.protocol.fall_height or tilts over is ranked "
             "below every robot that stays up (its fitness is a large negative constant plus "
             "the fraction of its window it stayed up); an unphysical simulation scores -inf.",
        why="A robot lying on its side barely moves and keeps the LED still, so its eq. 3.3 "
            "value beats every walking gait whose wobble costs more than its distance gains; "
            "without the rule PSO selects fallen robots.",
        config=("ch3.protocol.fall_height",),
    ),
    Departure(
        id="ch3.sine_optimised", kind="deviation", results=ALL,
        thesis="§3.3.1.1: the sine-based gait was tuned by hand.",
        ours="The sine gait is optimised by the same PSO as the half-ellipse gait "
             "(ch3.pso.sine).",
        why="Hand tuning cannot be repeated by a pipeline; the same optimiser for every family "
            "makes the comparison of the families fair.",
        config=("ch3.pso.sine.particles", "ch3.pso.sine.generations",
                "ch3.pso.sine.run_seconds", "ch3.pso.sine.transition_seconds"),
    ),
    Departure(
        id="ch3.pso_budget", kind="deviation", results=ALL,
        thesis="§3.3.1.2 and §3.3.1.3 give the swarm sizes, generations, run and transition "
               "durations of the half-ellipse and spline optimisations (the spline's five-second "
               "runs with one-second transitions in words).",
        ours="The profile's PSO sizes and durations (the default and paper profiles use the "
             "thesis's; the smoke profile tiny ones).",
        why="The smoke profile must run every rule in minutes.",
        config=("ch3.pso.half_ellipse.particles", "ch3.pso.half_ellipse.generations",
                "ch3.pso.half_ellipse.run_seconds", "ch3.pso.half_ellipse.transition_seconds",
                "ch3.pso.spline.particles", "ch3.pso.spline.generations",
                "ch3.pso.spline.run_seconds", "ch3.pso.spline.transition_seconds"),
        paper_keys=("sec3.3.1.2/pso_particles", "sec3.3.1.2/pso_generations",
                    "sec3.3.1.2/run_seconds", "sec3.3.1.2/transition_seconds",
                    "sec3.3.1.3/pso_particles", "sec3.3.1.3/pso_generations"),
        thesis_config=(("ch3.pso.spline.run_seconds", 5.0),
                       ("ch3.pso.spline.transition_seconds", 1.0)),
    ),
    Departure(
        id="ch3.sweep_protocol", kind="choice", results=("ch3/fig3_4",),
        thesis="Fig. 3.4 plots speed against frequency for each optimised gait; the thesis "
               "does not say at which frequencies or for how long each was measured.",
        ours="The frequencies of ch3.sweep.frequencies, each run for ch3.sweep.run_seconds "
             "after a transition from the optimised gait.",
        why="The thesis is silent; the grid spans Fig. 3.4's frequency axis.",
        config=("ch3.sweep.frequencies", "ch3.sweep.run_seconds",
                "ch3.sweep.transition_seconds"),
    ),
    Departure(
        id="ch3.robustness_protocol", kind="choice", results=("ch3/robustness",),
        thesis="The chapter abstract and §3.3.1.1 speak of robustness against (small) "
               "parameter changes without defining a perturbation or a criterion.",
        ours="Random uniform perturbations of every gait parameter by ch3.robustness.scale of "
             "its range; a perturbed gait counts as walking when the robot stays up and moves "
             "faster than ch3.robustness.min_speed.",
        why="The thesis is silent; the criterion is fixed in the config before any result.",
        config=("ch3.robustness.perturbations", "ch3.robustness.scale",
                "ch3.robustness.run_seconds", "ch3.robustness.transition_seconds",
                "ch3.robustness.min_speed"),
    ),
    Departure(
        id="ch3.turning_parameters", kind="choice", results=("ch3/table3_2",),
        thesis="§3.3.2.2 and §3.3.2.4 describe step-speed and torque turning without values; "
               "§3.3.3 measures turning without giving the measurement time or a stability "
               "criterion.",
        ours="The inner-side stance fraction ch3.turning.slow_duty, the torque factor "
             "ch3.turning.torque_scale, the run and transition times, and a turn counts as "
             "stable when the robot stays up and yaws faster than "
             "ch3.turning.min_angular_speed in the commanded direction.",
        why="The thesis is silent; the values are fixed in the config before any result.",
        config=("ch3.turning.slow_duty", "ch3.turning.torque_scale",
                "ch3.turning.run_seconds", "ch3.turning.transition_seconds",
                "ch3.turning.min_angular_speed"),
    ),
    Departure(
        id="ch3.tracking_controller", kind="choice", results=("ch3/fig3_5",),
        thesis="§3.3.3: a P-controller on the LED's bearing, hand-tuned for the best tracking; "
               "no gain is given.",
        ours="Fixed gains ch3.tracking.gain_step_size and gain_scapulae, an initial sideways "
             "offset ch3.tracking.lateral_offset and the run time ch3.tracking.run_seconds.",
        why="The thesis gives no gain; the pipeline does not hand-tune.",
        config=("ch3.tracking.gain_step_size", "ch3.tracking.gain_scapulae",
                "ch3.tracking.lateral_offset", "ch3.tracking.run_seconds"),
    ),
    Departure(
        id="ch3.seeds", kind="choice", results=ALL,
        thesis="The thesis reports one optimisation per gait family.",
        ours="Every seed of ch3.seeds runs its own PSO of each family and every later "
             "experiment on its optima.",
        why="A claim is decided on a spread over independent runs (thesis.claims.stats).",
        config=("ch3.seeds",),
    ),
)
