"""Departures of chapter 4 from the thesis (see :class:`thesis.departures.types.Departure`).

Chapter 4's results: the simulation runs ``flat`` and ``transfer_<group>`` and the tables
and figures derived from them; a departure of a run is inherited by everything derived
from it, so most entries name every result of the chapter.
"""

from __future__ import annotations

from thesis.departures import ch3 as _ch3
from thesis.departures import ch6 as _ch6
from thesis.departures.types import Departure

RUNS = ("ch4/flat", "ch4/transfer_slopes", "ch4/transfer_compliant", "ch4/transfer_pebbly",
        "ch4/tether")
DERIVED = ("ch4/table4_2", "ch4/table4_3", "ch4/table4_4", "ch4/fig4_3", "ch4/fig4_5",
           "ch4/fig4_6", "ch4/fig4_7", "ch4/fig4_8", "ch4/fig4_9", "ch4/fig4_10")
ALL = RUNS + DERIVED
SLOPES = ("ch4/transfer_slopes", "ch4/table4_2", "ch4/fig4_5", "ch4/fig4_6", "ch4/fig4_9",
          "ch4/fig4_10")
TARGETS = tuple(k for k in ALL if k not in ("ch4/flat", "ch4/fig4_3"))
#: The model checks that run ch4.model (registry.READS).
MODEL_CHECKS = ("model/oncilla", "model/solver", "model/validation", "model/convergence",
                "model/calibration", "model/pebbles")
#: Every result of the chapters that run the Oncilla (ch3, ch4, ch6) and its model checks.
ONCILLA = _ch3.ALL + ALL + _ch6.ALL + MODEL_CHECKS
#: The Oncilla's model keys that every one of those chapters has.
_CHAPTERS = ("ch3", "ch4", "ch6")

DEPARTURES: tuple[Departure, ...] = (
    Departure(
        id="ch4.simulated_oncilla", kind="deviation", results=ALL,
        thesis="§4.5: every gait was optimised and evaluated on the Oncilla robot itself.",
        ours="The Oncilla of thesis.physics.models.oncilla on the shared engine: hip "
             "placement, scapula servos and mass from the official simulation and the "
             "Oncilla paper; trunk shell, motor masses, spring rates, drive stiffness and "
             "friction are assumptions documented in that module (no public values exist "
             "for them); the hind legs are the fore legs scaled to a 182 mm reach with more "
             "knee range (a choice from Tab. 4.2-4.4's hind feet and the backend's motor "
             "counts, ch3.oncilla_model), and the feet are the render's plates "
             "(ch4.foot_plates). Time step and solver are chapter 3's (ch4.model; "
             "model/convergence's verdict shown beside every verdict); the knee spring, the "
             "drives' stiffness and the plates' size are fitted (ch4.oncilla_fit). The "
             "contact rows take their own relaxation (ch4.model.contact_relaxation): at 1.0 "
             "the pebble field's contacts explode.",
        why="The hardware is out of reach; absolute speeds differ from the robot's, so the "
            "claims compare transfer against no transfer, not speeds against the thesis's.",
        config=("ch4.model.dt", "ch4.model.solver_iterations", "ch4.model.sweep_order",
                "ch4.model.relaxation", "ch4.model.contact_relaxation",
                "ch4.model.row_relaxation", "ch4.model.momentum", "ch4.model.restart"),
    ),
    Departure(
        id="ch4.foot_plates", kind="choice", results=ONCILLA,
        thesis="The thesis does not describe the Oncilla's feet (§3.2.1, §4.5); the official "
               "simulation's render shows flat plates pointing forward under the shanks "
               "(docs/sources.md#oncilla-feet).",
        ours="In effect where ch3/ch4/ch6.model.feet is 'plate' (the schema's default, which "
             "the default and paper profiles run; the smoke profile keeps 'sphere', the point "
             "toes, and this record then says only that the option was off). Each foot is the "
             "toe sphere and a 3 mm contact sphere under each corner of a plate foot_length x "
             "foot_width, rigid on the foot segment and level in the build pose, the toe 4 mm "
             "behind its centre; measured in the render through the floor lattice: 72 +- 5 mm "
             "long (bounds 60-90 mm), 38 +- 5 mm wide but open (bounds 28-50 mm), the toe 40 "
             "mm behind the front edge; the two dimensions the chapters run are model/fit's "
             "(ch4.oncilla_fit). The plate's 0.02 kg is taken from the foot segment (each leg "
             "keeps its mass); the rounded heel is its bounding rectangle; whether the "
             "render's contact shape is the drawn plate is not shown (thesis.physics.models."
             "oncilla, Foot plates). Five contacts per foot cost about 1.6x the CPU of one. "
             "Measured against point toes on the same fitted values: the plates keep the "
             "published gaits up and make the spline faster than its theoretical speed "
             "(V2, V4 fail on it; thesis.physics.models.oncilla, Foot plates).",
        why="A point foot gives no moment about the diagonal support line of a trot, where "
            "the published gaits tip; the render is the only source of the feet's form. "
            "Where the render leaves a dimension open it is a calibration parameter "
            "(thesis.modelcheck.split) within the render's bounds.",
        config=tuple(f"{c}.model.{k}" for c in _CHAPTERS
                     for k in ("feet", "foot_length", "foot_width")),
    ),
    Departure(
        id="ch4.oncilla_fit", kind="choice", results=ONCILLA,
        thesis="No public source gives the Oncilla's knee spring, its drives' stiffness or "
               "its foot plates' size (docs/sources.md#oncilla).",
        ours="ch3/ch4/ch6.model.foot_length, foot_width, knee_spring and drive_stiffness "
             "(the drives' damping follows at 1/50 s) are FITTED by thesis.modelcheck.fit to "
             "the fitted side of the split declared in thesis.modelcheck.split before the fit "
             "ran: Tab. 3.1a's and Tab. 3.1b's speeds at 1.5 Hz, and that none of their starts "
             "falls, on the chapters' step and solver. The legs' outboard offset is held (a "
             "module constant). The fit, its objective, each value's bounds and whether it "
             "ended at one are model/fit and the report's model section; the judged side "
             "(the spline's top speed, the other frequencies, Tab. 4.2's flat optimum, the "
             "scapulae) is validation only. A claim whose thesis number is one of the fitted "
             "speeds rests on a calibration target.",
        why="These values set the speed below the feet's theoretical one and whether the "
            "published gaits stay up; no source gives them, so they are identified from "
            "published measurements declared first and the model is judged on the rest.",
        config=tuple(f"{c}.model.{k}" for c in _CHAPTERS
                     for k in ("foot_length", "foot_width", "knee_spring", "drive_stiffness")),
    ),
    Departure(
        id="ch4.knee_spring_fitted", kind="choice", results=ALL,
        thesis="No spring rate of the Oncilla's knees is given (§3.2.1; nor does any public "
               "source, docs/sources.md#oncilla-knee-spring).",
        ours="ch4.model.knee_spring is FITTED with the other unsourced values "
             "(ch4.oncilla_fit, model/fit), as in chapter 3 (ch3.knee_spring_fitted).",
        why="The spring sets the stance compression that makes the robot walk below the "
            "feet's theoretical speed (§3.3.1.2); chapter 4's speeds are on the same robot.",
        config=("ch4.model.knee_spring",),
    ),
    Departure(
        id="ch4.seeds", kind="deviation", results=ALL, config=("ch4.seeds",),
        thesis="§4.6: one optimisation per arm and condition (\"we cannot say something on "
               "the statistical significance of the experiment itself\").",
        ours="Every seed runs its own flat optimisation and both arms of every condition; "
             "the claims are decided over seeds (rule 9 of thesis.claims.stats) and each "
             "seed's own per-generation rank-sum statistic is reported.",
        why="A verdict about the method, not about one pair of runs.",
    ),
    Departure(
        id="ch4.generations", kind="choice", results=ALL, config=("ch4.pso.generations",),
        thesis="§4.3 and §4.5 give the swarm size, the 4 s evaluations and 2 s transitions, "
               "and that the robot ran nearly 6 km in the 4 hours of optimisation, but not "
               "the number of generations.",
        ours="13 generations: 4 h at 6 s per evaluation is 2 400 evaluations, over 9 "
             "optimisations of the thesis's swarm that is 13.3 generations each.",
        why="The thesis's own budget, so that the comparison has the thesis's robot time.",
        paper_keys=("sec4.5/distance_run", "sec4.5/optimisation_hours",
                    "sec4.5/evaluation_seconds", "sec4.5/transition_seconds",
                    "sec4.3/pso_particles"),
    ),
    Departure(
        id="ch4.treadmill_protocol", kind="deviation", results=ALL,
        config=("ch4.protocol.settle", "ch4.protocol.transition_seconds",
                "ch4.protocol.run_seconds"),
        thesis="§4.5: the gaits run one after another on a treadmill whose speed keeps the "
               "robot in place, each for 4 s after a 2 s smooth transition from the previous "
               "gait; the speed is the robot's average speed.",
        ours="Every evaluation is simulated on its own on an open floor: the robot starts "
             "standing, eases into the previous particle's pose (settle), runs that gait "
             "into the 2 s transition and is measured for 4 s; the speed is the trunk's "
             "forward displacement over the window divided by its length.",
        why="Independent evaluations can be simulated as one batch, and a fallen robot does "
            "not carry over into the next gait; the transition from the previous particle "
            "keeps the treadmill's order effect.",
        paper_keys=("sec4.5/evaluation_seconds", "sec4.5/transition_seconds"),
    ),
    Departure(
        id="ch4.tether", kind="choice", results=ALL,
        config=("ch4.tether.rail_height", "ch4.tether.width", "ch4.tether.slack",
                "ch4.tether.stiffness", "ch4.tether.damping"),
        thesis="§4.5: a light thread between the robot's head and an overhead rail limits its "
               "lateral movement and is loose during normal operation; no dimensions.",
        ours="A rail 1 m above the floor along the walking direction and one tension-only "
             "thread (5000 N/m, 50 N s/m) from the middle of the head's top edge to a "
             "carriage sliding freely on it, taut beyond 0.87 m from the rail: its play "
             "covers the lowest head height reached in the walk of 9 in 10 random Tab. 4.1 "
             "trots that stay up without it, so it tightens when the head strays about "
             "0.36 m sideways or drops about 8 cm, where the trunk is near the fall height. "
             "ch4/tether reports the falls per generation of the flat run with and without "
             "it.",
        why="The thesis gives no dimensions. Whether the thread stays loose is measured, "
            "not assumed: every evaluation records the fraction of its window with the "
            "thread taut and its mean tension, shown beside the best particles and the "
            "falls.",
    ),
    Departure(
        id="ch4.fall_handling", kind="choice", results=ALL,
        config=("ch4.protocol.fall_height",),
        thesis="§4.5: an assistant intervened when a very unstable gait jeopardised the "
               "setup's safety; the fitness is the speed alone (§4.6).",
        ours="A robot whose trunk drops below fall_height or tilts beyond 60 degrees in the "
             "window has fallen: its score is -2 + the fraction of the window it stayed up, "
             "below every robot that stays up; unphysical simulations count as falls at the "
             "start of the window. The fraction of fallen evaluations is reported per "
             "generation.",
        why="Nobody intervenes in a simulation; ranking falls last keeps PSO and the rank "
            "tests on the thesis's speed ordering for every gait that walks.",
    ),
    Departure(
        id="ch4.fall_reset", kind="choice", results=ALL,
        config=("ch4.protocol.settle", "ch4.protocol.fall_height"),
        thesis="§4.5: \"We test each gait for 4 seconds at a time, and have a smooth "
               "transition between these gaits for 2 seconds\" and \"an assistant sits next "
               "to the track in order to intervene when the setup's safety is jeopardized by "
               "a very unstable gait\"; what happened to the evaluation of a gait the robot "
               "entered lying down is not stated.",
        ours="At the start of each window, a robot that is down (trunk below fall_height or "
             "tilted beyond 60 degrees) and entered from another gait is set back on its "
             "feet at its start pose, at rest; it eases into the gait under test again for "
             "settle seconds and is measured over the rest of the window. It counts as "
             "fallen only if it falls again; every evaluation records whether it was set "
             "back, and the runs count them per generation (reset_count). One reset per "
             "evaluation; a run's first particle and the re-evaluations, which enter from "
             "their own gait, are never reset.",
        why="A fall in the previous particle's gait or in the transition is not the gait "
            "under test's: charged to it, it made the next particle's fall more likely "
            "after a fall than after none. The robot starts in its build pose, so it needs "
            "the same easing as at the start of every evaluation.",
        paper_keys=("sec4.5/evaluation_seconds", "sec4.5/transition_seconds"),
    ),
    Departure(
        id="ch4.transfer_impulse", kind="choice", results=TARGETS,
        config=("ch4.transfer.impulse_divisor",),
        thesis="§4.4: the transferred particles get a small impulse in a random direction, "
               "v(0) = r with r ~ U(-1, 1), units not stated.",
        ours="v(0) = r (upper - lower) / 70 per parameter: exactly U(-1, 1) mm for the l_i "
             "(range 70 mm) and the same impulse relative to its range for every other "
             "parameter.",
        why="r in the thesis's own units would move f by up to 1 Hz and t_stance by up to 1, "
            "twice and five times their ranges, which is not a small impulse.",
        paper_keys=("sec4.4/impulse_lower", "sec4.4/impulse_upper"),
    ),
    Departure(
        id="ch4.pso_initial_velocity", kind="choice", results=ALL,
        thesis="§4.3: the PSO update with ω, φp, φg and no elitism; the random swarm's "
               "initial velocities and any velocity limit are not stated.",
        ours="Random swarms start with v ~ U(-range, range) per parameter and velocities are "
             "clamped to ±range (Pedersen 2010, the source of the thesis's coefficients); "
             "positions are clipped to the box and projected on a <= a_max(x0) and the y0 "
             "range of Tab. 4.1 (thesis.optim.pso).",
        why="The conventions of the paper the coefficients come from.",
        paper_keys=("sec4.3/omega", "sec4.3/phi_p", "sec4.3/phi_g"),
    ),
    Departure(
        id="ch4.slopes_by_gravity", kind="choice", results=SLOPES,
        config=("ch4.conditions.grades",),
        thesis="§4.6.1: the treadmill inclined to a 9 % and an 18 % grade.",
        ours="The floor stays horizontal and gravity is rotated by atan(grade), uphill "
             "forward (thesis.gaits.conditions).",
        why="For the single infinite floor plane this is the same physics seen in the "
            "belt's frame, and one compiled simulation serves every slope.",
        paper_keys=("sec4.6.1/grade=9/slope_angle", "sec4.6.1/grade=18/slope_angle"),
    ),
    Departure(
        id="ch4.front_spring", kind="choice",
        results=("ch4/transfer_compliant", "ch4/table4_3", "ch4/fig4_7", "ch4/fig4_10"),
        config=("ch4.conditions.front_spring_factor",),
        thesis="§4.6.2: one of the two springs of each front leg removed.",
        ours="The simulated knee has one extension spring; its constant in the front legs "
             "is multiplied by 0.5.",
        why="Two equal springs in parallel lose half their stiffness when one is removed; "
            "the thesis gives no spring constants.",
    ),
    Departure(
        id="ch4.pebbles", kind="choice",
        results=("ch4/transfer_pebbly", "ch4/table4_4", "ch4/fig4_8", "ch4/fig4_10",
                 "model/pebbles"),
        config=("ch4.pebbles.diameter", "ch4.pebbles.coverage", "ch4.pebbles.strip_length",
                "ch4.pebbles.strip_width", "ch4.pebbles.start_margin", "ch4.pebbles.k",
                "ch4.pebbles.contact_relaxation"),
        thesis="§4.6.3: a pebble dispenser covered the treadmill in pebbles of about 1 cm; "
               "their number, spacing and how they moved on the belt are not stated.",
        ours="A static field of equal 1-cm spheres resting on the floor (the engine's "
             "sphere field; they neither roll nor touch each other), scattered uniformly "
             "with an expected coverage of 25 % over a 20 x 0.8 m strip along the walking "
             "direction, each toe checking its 3 nearest; one layout per profile, and every "
             "evaluation starts at its own uniformly random place on the strip, so each "
             "particle meets another arrangement, set down on the pebbles from one pebble "
             "diameter above the floor. The field's contact rows take a relaxation of "
             "their own (ch4.pebbles.contact_relaxation, 0.3): at the flat floor's 0.5 the "
             "solve diverges among the pebbles.",
        why="Pebbles on a moving belt give each gait another arrangement and a noisy "
            "fitness; a random start on one long strip does the same with one compiled "
            "simulation. Pebbles that roll away under the feet are not modelled.",
        paper_keys=("sec4.6.3/pebble_diameter",),
    ),
    Departure(
        id="ch4.euclidean_normalisation", kind="choice",
        results=("ch4/table4_2", "ch4/table4_3", "ch4/table4_4"),
        thesis="§4.6.1: the Euclidean distance to the best flat particle \"after "
               "normalization of the parameters\", normalisation not stated (the printed "
               "distances exceed the square root of 12, so it was not the unit box).",
        ours="Every parameter divided by its search range (unit box); only orderings of "
             "distances are compared, never their values.",
        why="A normalisation that does not depend on the run, the same as Fig. 4.10's.",
    ),
    Departure(
        id="ch4.search_space_normalisation", kind="choice", results=("ch4/fig4_10",),
        thesis="§4.7: the geometric mean of the lengths of the principal component axes of "
               "each generation's particles; scaling of parameters of different units not "
               "stated.",
        ours="Standard deviations along the principal axes of the generation's particles "
             "with every parameter normalised to its range; axes beyond the rank dropped "
             "(thesis.optim.pso.search_space_size).",
        why="The parameters have different units; without a scaling the mean would be "
            "dominated by the millimetre ones.",
    ),
    Departure(
        id="ch4.reevaluation", kind="choice",
        results=("ch4/flat", "ch4/transfer_slopes", "ch4/transfer_compliant",
                 "ch4/transfer_pebbly", "ch4/table4_2", "ch4/table4_3", "ch4/table4_4"),
        config=("ch4.reeval.repeats", "ch4.reeval.heading_deg"),
        thesis="Tab. 4.2-4.4 give the in-run speed of each run's best particle.",
        ours="Beside the in-run speed (the thesis's), the best particle is re-evaluated "
             "from standstill in its own pose, each repeat with a random initial heading; "
             "reported, not used by any claim.",
        why="A best particle is selected from noisy evaluations, so its in-run speed is "
            "inflated; the re-evaluation shows by how much.",
    ),
    Departure(
        id="ch4.best_particles_per_seed", kind="choice", results=("ch4/fig4_6",),
        config=("ch4.fig4_6.top",),
        thesis="Fig. 4.6: the best particles (their number: paper key fig4_6/top) of all "
               "optimisations per inclination, a "
               "Gaussian fitted; panel (b)'s axes are not described.",
        ours="Per seed: as many best particles as the thesis shows, of the flat run for flat "
             "ground and of both arms of a "
             "slope for that slope; panel (b) shows x0 against y0r.",
        why="One Fig. 4.6 per seed, as one thesis experiment per seed.",
        paper_keys=("fig4_6/top",),
    ),
)
