"""Departures of chapter 5 from the thesis (see :class:`thesis.departures.types.Departure`).

The recordings are simulated, so every physical value of the robot and the terrains is a
choice (docs/sources.md#puppy: no public source gives Puppy II's dimensions, the
terrains' materials or the dataset); the classification protocol follows §5.2-5.3 where it
is stated.
"""

from __future__ import annotations

from thesis.departures.types import Departure

_VARIANTS = ("ch5/table5_3_blocks", "ch5/table5_3_parts")
_TABLES = ("ch5/table5_3", "ch5/table5_4", "ch5/table5_5", "ch5/table5_6") + _VARIANTS
_ALL = _TABLES + ("ch5/fig5_3", "ch5/separability", "model/puppy_heldout")
_SUP = ("ch5/table5_3", "ch5/table5_4", "ch5/fig5_3") + _VARIANTS
_UNSUP = ("ch5/table5_5", "ch5/table5_6")

DEPARTURES: tuple[Departure, ...] = (
    Departure(
        id="ch5.simulated_recordings", kind="deviation", results=_ALL,
        thesis="§5.3.1: the dataset was recorded on the real Puppy II at the University of "
               "Zurich (118 trials, Tab. 5.1).",
        ours="The trials of Tab. 5.1 (same gait, terrain and frequency counts, 3000-6500 "
             "samples at 50 Hz) are simulated on the project's engine with an invented "
             "Puppy II model.",
        why="The dataset is not public (docs/sources.md#puppy).",
        config=("ch5.recordings",),
    ),
    Departure(
        id="ch5.puppy_morphology", kind="choice", results=_ALL,
        thesis="§5.3.1 gives the structure (four identical legs, one hip servo each, passive "
               "spring knees, paw force sensors, IMU) but no dimension, mass, spring rate or "
               "servo parameter.",
        ours="1.5 kg; 0.22 x 0.11 x 0.05 m trunk, hips 0.18 m apart; 0.065 m femur and tibia "
             "with the knee pointing backward; 3 N m/rad knee spring without preload (rest "
             "angle at the build pose, so the knee flexes under the standing load); "
             "hobby-servo hips (1 N m, 6 rad/s, gain 50 1/s); 12 mm paws "
             "(thesis.physics.models.puppy docstring gives the reasons). The time step and "
             "solver (ch5.model: dt 1.25 ms, 120 block-Jacobi sweeps) are those the Puppy "
             "II's convergence table (model/puppy_convergence, 3 % tolerance) is run on; at "
             "5 ms and again at 2.5 ms it found cells moved beyond 3 % under dt / 2; at "
             "1.25 ms every cell stayed within 3 %.",
        why="No public source (docs/sources.md#puppy-body); chosen for a small servo robot, and "
            "so that the "
            "model stands and walks (a forward knee or a softer spring turned it over); a "
            "preload above the ~0.08 N m standing load would hold the knees on their stops, "
            "where the Puppy II's passive knees flex in stance (§5.3.1).",
        config=("ch5.model",),
    ),
    Departure(
        id="ch5.paw_skin", kind="choice", results=_ALL,
        thesis="§5.3.1: 'Underneath the feet there is an adhesive skin attached with "
               "asymmetrical friction'; no coefficients.",
        ours="Directional Coulomb friction at the paws along the robot's forward axis: the "
             "terrain's coefficient against sliding backward and sideways, half of it "
             "(ch5.model.skin_ratio 0.5) against sliding forward.",
        why="No source gives the skin's ratio; directional skins grip two to several times "
            "harder against their grain, and 0.5 is the mild end (reasons in "
            "thesis.physics.models.puppy).",
        config=("ch5.model.skin_ratio",),
    ),
    Departure(
        id="ch5.terrain_materials", kind="choice", results=_ALL,
        thesis="§5.3.1 names the terrains (blue foil, Styrofoam, linoleum, cardboard, rubber) "
               "and nothing of their physics.",
        ours="Each terrain is a floor material: the paw-floor contact a spring-damper in "
             "physical units from docs/sources.md#ch5-terrain-contact (one paw's stiffness "
             "under m g / 4: F 14.66 kN/m, the silicone paw alone, geometric middle of "
             "8.6-25; R 13.51, rubber mat in series with the paw, of 7.6-24; S 4.12, the "
             "elastic secant of Styrofoam's plastic crush, of 2.7-6.3; L and C 14.66, the "
             "paw alone, their own modulus not found; damping ratio tan(delta) / 2 on the "
             "paw's share m / 4 of the mass: paw 0.087, rubber 0.079, S 1.0), restitution 0, "
             "and the chosen friction coefficients (F 0.35, S 0.65, L 0.5, C 0.45, R 0.9); "
             "fixed before any classifier ran; every parameter is jittered by +-10 % per "
             "trial; no roughness (thesis.ch5.recordings gives the derivations).",
        why="The dataset's floors are not described (docs/sources.md#ch5-terrain-contact: "
            "each is its common form, chosen). Where a range is sourced and nothing selects "
            "within it, its geometric middle; where only the paw's bound exists (L, C), "
            "the paw alone, since a floor compliance without a source would be invented. "
            "Styrofoam crushes plastically, which the engine's elastic contact cannot do: "
            "its secant stiffness is the declared approximation, critically damped (its "
            "crush returns no energy). Restitution 0: the sourced damping is the contact's "
            "energy loss (the engine's restitution is a velocity target that would replace "
            "the spring at each touchdown). No friction of a rubber or silicone skin on "
            "these floors was found, so the friction stays chosen. At the 5-ms step the "
            "contact is an implicit spring (stable at any stiffness), and the touchdown "
            "force rise (6-10 ms by the sources) spans one or two steps: unresolved "
            "(thesis bench puppy-contact). In simulation the terrains' separability is "
            "entirely this choice; it is never tuned to a score.",
        config=("ch5.terrains", "ch5.jitter"),
    ),
    Departure(
        id="ch5.sensor_noise", kind="choice", results=_ALL,
        thesis="§5.2.1: 'The sensor signals are very noisy', without a figure; §5.3.1: a "
               "tactile sensor on each paw, sampled at 50 Hz, type not given.",
        ours="White Gaussian noise per sensor (profile ch5.noise: 0.02 rad, 0.3 m/s^2, "
             "0.05 rad/s, 3 % of the field, 5 mm, 0.03 rad, 2 cm). The paw sensors are "
             "force-sensing resistors (ch5.touch, docs/sources.md#ch5-touch, Interlink FSR "
             "402): a point sample of the paw's force every 20 ms, 0 below 0.1 N, clipped "
             "at 10 N, a per-sample gain error of sd 2 % (the sheet's +-2 % repeatability "
             "read as one standard deviation) and +10 % while the force falls (hysteresis); "
             "no further noise (ch5.noise.touch 0).",
        why="Typical of the sensor types; the paw sensor's type is not published, the FSR is "
            "the low-cost kind of the time with a data sheet; fixed with the terrains, before "
            "any classifier ran.",
        config=("ch5.noise", "ch5.touch"),
    ),
    Departure(
        id="ch5.gait_parameters", kind="choice", results=_ALL,
        thesis="§5.3.1: sine waves per hip with 'a different offset, amplitude and phase for "
               "each motor', left legs 'slightly higher' (bound right), right hind 'much "
               "larger' (turn left), random gait 'sufficiently smooth'; no numbers.",
        ours="Amplitude 0.25 rad, fore pair in phase and hind pair half a period later, left "
             "legs x1.1 (bound right), right hind x1.5 (turn left), offsets 0; random: "
             "Gaussian noise low-passed at the trial frequency, clipped to 0.4 rad; commands "
             "fade in over 1 s.",
        why="No numbers in the thesis; larger amplitudes (0.3 rad, right hind x2) turned the "
            "model over.",
        config=("ch5.gaits",),
    ),
    Departure(
        id="ch5.trial_stops_when_turned_over", kind="choice", results=_ALL,
        thesis="The thesis does not say what happened when the robot fell in a trial.",
        ours="A trial's recording stops at the first sample with the trunk's up axis below "
             "0.5 (turned over); such trials are shorter than planned (listed in the "
             "recordings' attribute stopped_trials).",
        why="Without it most random-gait trials ended on the robot's back for most of their "
            "length, a degenerate recording.",
        config=("ch5.recordings.fallen_up",),
    ),
    Departure(
        id="ch5.other_signals", kind="choice", results=("ch5/table5_3", "ch5/table5_5"),
        thesis="Tab. 5.2 lists 'Other/derivative sensors' in the useful group (55 of the 64 "
               "signals) without naming them.",
        ours="The 31 other/derivative signals are per-sample differences of the joint, paw, "
             "IMU and magnetometer signals, the 4 hip commands and their differences, and the "
             "differences of velocity and compass; 9 signals outside every group (camera "
             "position, orientation quaternion, lateral velocity, time) complete the 64 "
             "(thesis.ch5.sensors).",
        why="Chosen to meet the thesis's counts with signals such a robot provides.",
    ),
    Departure(
        id="ch5.selection_protocol", kind="choice", results=_TABLES,
        thesis="§5.3.1: five selections of 3000 samples per terrain, threefold tuning, twofold "
               "verification, remaining trials added to the test set, parts of 281-562 "
               "samples; how samples are selected and what a fold trains on are not stated.",
        ours="Threefold = train on two selections, validate on the third; twofold = train on "
             "one, test on the other plus the untouched trials; a segment of L samples "
             "becomes round(L / 375) parts; normalisation over all the experiment's trials "
             "before selection; how the selections are drawn: departure "
             "ch5.trial_disjoint_folds.",
        why="The most direct reading of §5.3.1 (thesis.ch5.protocol docstring).",
        config=("ch5.protocol",),
    ),
    Departure(
        id="ch5.trial_disjoint_folds", kind="choice", results=_TABLES,
        thesis="§5.3.1: 'Then we select a total of 3000 samples for each terrain type and do "
               "this five times ... Any remaining relevant trials are added to the test set "
               "during verification. We split all trials into parts as a final step'; "
               "§5.4.1.1: 'Only some of these combinations are included in the training "
               "set'. Whether a recording may feed two selections is not stated.",
        ours="Primary (ch5.protocol.selection 'trials'): per terrain the shuffled trials are "
             "dealt whole to the five selections in turn (a selection takes its samples "
             "from the start of one or two trials; the unused rest of its last trial is "
             "dropped), so no recording is on both sides of any tuning or verification "
             "fold. A terrain with too few trials for five disjoint selections keeps the "
             "three tuning and the two verification selections disjoint among themselves "
             "and lets the verification reuse tuning recordings ('stages'; at default "
             "cardboard's three trials); with fewer still (the smoke profile's one-trial "
             "terrains) it falls back to the previous blocks ('cut'); the datasets record "
             "the level per terrain and the share of evaluation samples whose recording "
             "also feeds training. Sensitivity variants of Tab. 5.3: 'blocks' (the "
             "previous protocol: consecutive blocks of the concatenated trials, a trial cut "
             "across selections) as ch5/table5_3_blocks, and 'parts' (parts of about 375 "
             "samples drawn across trials, whole trials assigned to one selection, parts "
             "drawn within it) as ch5/table5_3_parts.",
        why="Chosen from the text before any result of either protocol existed: 'remaining "
            "relevant trials' makes the trial the unit a selection is built from, parts "
            "are cut 'as a final step' (after selecting, so selections are not drawn from "
            "parts), and 'only some of these combinations are included in the training "
            "set' fits one or two whole recordings per selection, not parts of many. "
            "Cutting a trial across selections is not in the text and lets the tuning "
            "reward memorising a recording (its per-trial constants) instead of "
            "recognising a terrain.",
        config=("ch5.protocol.selection",),
    ),
    Departure(
        id="ch5.separability", kind="choice", results=("ch5/separability",),
        thesis="No such measurement in the thesis: Tab. 5.3-5.6 mix the question whether the "
               "terrains can be told apart with whether the classifier generalises across "
               "gaits and frequencies (§5.4.1.1, Fig. 5.3).",
        ours="Per (gait, frequency) cell of Tab. 5.1 with at least two terrains, "
             "leave-one-trial-out accuracy of LR, ELM, RC, SFA2, ELM-SFA and RC-SFA on the "
             "minimal, touch and imu groups, with the cell's majority share and chance; "
             "fixed hyper-parameters at the CMA-ES start point (no tuning), no PCA (every "
             "normalised input of the group enters the expansion), parts and readouts as in "
             "the tables; the smoke and default profiles draw the hidden layers of one seed.",
        why="Measures what the simulated recordings give a classifier before any protocol "
            "question arises; fixed a-priori hyper-parameters keep it cheap and "
            "free of tuning, and without PCA every fold's features are those of the whole "
            "cell, so the linear readouts and SFA are refitted per fold from per-trial "
            "sums; one seed (about 5 minutes on a core) keeps ch5 within its budget.",
        config=("ch5.separability",),
    ),
    Departure(
        id="ch5.heldout_gait_test", kind="choice", results=("model/puppy_heldout",),
        thesis="No such test in the thesis: the real recordings carried the terrain across "
               "gaits (Fig. 5.3, §5.4.1.3); whether the simulated ones do is the question "
               "the chapter's comparisons rest on.",
        ours="On the F, S and L trials (every gait has them): the reservoir on the touch "
             "group, trained on the other gaits' trials, tested on one held-out gait; "
             "fixed hyper-parameters at the CMA-ES start point with PCA (no tuning); "
             "5 reservoir draws; pooled difference to the held-out majority share decides "
             "(mean >= 15 points, lower 95 % t bound > 5); a linear discriminant on "
             "per-part mean and std beside it; within each gait x frequency cell the first "
             "half of each trial trains and the second half tests (>= 80 %).",
        why="A rule fixed before the run tells whether the terrains the "
            "sourced contact physics gives are a property of the floor or of the gait; "
            "the first-half/second-half split exists at one trial per cell.",
        config=("physics.puppy_heldout",),
    ),
    Departure(
        id="ch5.method_details", kind="choice", results=_ALL,
        thesis="§5.2 gives the equations but not the node count of Tab. 5.3/5.5, the input "
               "weights' probabilities, a bias, the number of SFA/ICA components, the "
               "histogram bins, nor whether SFA2's inputs are filtered.",
        ours="100 nodes; input weights uniform on {-1, 0, 1} for ELM and RC alike; no bias "
             "in the tanh; 4 slow features and ICA components; 20 bins between the 1st and "
             "99th percentile with add-one smoothing; SFA2 gets the EMA low-pass of LR; no "
             "washout, every time step scored.",
        why="The plainest reading of each unstated detail (no preference among the input "
            "weights' values, the readout's bias instead of one per node, every step "
            "scored); the SFA2 low-pass also gives CMA-ES the two parameters it needs.",
        config=("ch5.methods",),
    ),
    Departure(
        id="ch5.tuning_once", kind="deviation", results=_TABLES + ("ch5/fig5_3",),
        thesis="§5.4.1.1: 'All parameters of the different techniques are optimized using "
               "CMA-ES for each combination of sensors' (for every selection).",
        ours="In the default profile each (group, method, node count) is tuned once, on the "
             "first seed's threefold folds, with a fixed budget of CMA-ES generations, and "
             "those hyper-parameters are verified on every seed; the smoke and paper "
             "profiles tune every seed.",
        why="The 40-minute budget of the default profile on two cores.",
        config=("ch5.tuning.per_seed", "ch5.tuning.generations"),
    ),
    Departure(
        id="ch5.cma_search_space", kind="choice", results=_TABLES + ("ch5/fig5_3",),
        thesis="§5.2.5 fixes lambda = floor(4 + 3 ln M) but not the parameters' ranges, the "
               "start or the stopping rule.",
        ours="Unit-cube search (start 0.5, sigma0 0.3) mapped to PCA rate 0.1-1, leak "
             "0.003-1 and input scaling 0.01-3 (log), spectral radius 0-1.5; a fixed number "
             "of generations.",
        why="Ranges wide enough to contain the usual optima of leaky ESNs at 50 Hz.",
        config=("ch5.search", "ch5.tuning.generations"),
    ),
)
