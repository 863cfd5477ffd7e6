"""Chapter 7 (differentiable physics engine): Tab. 7.1 and the prose numbers of §7.2-7.3, §8.1.

Result artifacts: ``ch7/ball`` (``method`` = ``gradient`` | ``cmaes``: ``iterations``,
``wall_seconds``), ``ch7/table7_1`` (``device`` = ``cpu`` | ``gpu``, ``batch`` = 1 | 128,
``n_params`` = 1296 | 1147904, ``gradient`` = 0 | 1: ``seconds`` to simulate the batch for
10 model seconds; the second sub-table ``step_milliseconds`` per time step per robot),
``ch7/arm_fixed``, ``ch7/arm_random``, ``ch7/quadruped_gait``, ``ch7/pendulum_pixels``.

Transcription note: Tab. 7.1's header is garbled in thesis.txt ("with g radient with
without gradient"); the column order is with gradient (CPU, GPU), without gradient (CPU,
GPU), as the ratios and the second sub-table confirm. The batch-1 rows of the two
sub-tables are printed identically (10 s at a 10 ms step is 1000 steps, so s and ms agree).
"""

from __future__ import annotations

from thesis.paper.types import PaperValue, entry

_CELLS = (("cpu", 1), ("gpu", 1), ("cpu", 0), ("gpu", 0))  # (device, gradient) per column
_HEAD = ("with gradient CPU", "with gradient GPU", "without gradient CPU",
         "without gradient GPU")

#: (batch, n_params, row as printed, index of the first time among the row's numbers, times)
_T71_S = (
    (1, 1296, "1\t1296\t8.17\t69.6\t1.06\t9.69", 2, (8.17, 69.6, 1.06, 9.69)),
    (1, 1147904, "\t1147904\t13.2\t75.0\t2.04\t9.69", 1, (13.2, 75.0, 2.04, 9.69)),
    (128, 1296, "128\t1296\t263\t128\t47.7\t17.8", 2, (263.0, 128.0, 47.7, 17.8)),
    (128, 1147904, "\t1147904\t311\t129\t50.4\t18.3", 1, (311.0, 129.0, 50.4, 18.3)),
)
_T71_MS = (
    (1, 1296, "1\t1296\t8.17\t69.6\t1.06\t9.69", 2, (8.17, 69.6, 1.06, 9.69)),
    (1, 1147904, "\t1147904\t13.2\t75.0\t2.04\t9.69", 1, (13.2, 75.0, 2.04, 9.69)),
    (128, 1296, "128\t1296\t2.05\t1.00\t0.372\t0.139", 2, (2.05, 1.00, 0.372, 0.139)),
    (128, 1147904, "\t1147904\t2.43\t1.01\t0.394\t0.143", 1, (2.43, 1.01, 0.394, 0.143)),
)


def _table7_1() -> list[PaperValue]:
    out = []
    for variable, unit, rows, note in (
        ("seconds", "s", _T71_S, "computing time to simulate the batch for 10 model seconds; "
                                 "CPU i7 5930K, GPU GTX 1080"),
        ("step_milliseconds", "ms", _T71_MS, "computing time per time step per robot "
                                             "(second sub-table)"),
    ):
        for batch, n_params, source, first, times in rows:
            for i, ((device, gradient), header, value) in enumerate(zip(_CELLS, _HEAD, times)):
                coords = (("device", device), ("batch", batch), ("n_params", n_params),
                          ("gradient", gradient))
                out.append(entry(
                    table="Tab. 7.1", artifact="table7_1", variable=variable, coords=coords,
                    value=value, unit=unit, source=source, pos=first + i,
                    row=f"#robots {batch}, #parameters {n_params}", column=header, note=note,
                ))
    return out


_BALL_GD = ("Optimizing the six parameters in v_0 and ω_0 took only 88 iterations with gradient "
            "descent and backpropagation through time.")
_BALL_CMA = ("Optimizing this problem with CMA-ES [21], a state of the art derivative-free "
             "optimization method, took 2422 iterations.")
_BALL_T = ("Even when taking the time to compute the gradient into account, the optimization with "
           "gradient descent takes 16.3 s, compared to 59.9 s with CMA-ES.")
_FACTOR = ("Although backpropagating the gradient through physics slows down the computations by "
           "roughly a factor 10, this factor only barely increases with the number of parameters "
           "in our controller.")
_ARM1 = ("We find that the controller comes within 4 cm of the target in 100 model evaluations, "
         "and within 1 cm in 150 model evaluations, which is small compared to the 1 m arm of "
         "the robot.")
_ARM2 = ("We find that it takes 576 update steps before the millions of parameters are optimized, "
         "such that the end effector of the robot is on average less than 10 cm of target, "
         "2 563 update steps before the error is less than 5 cm.")
_GAIT = ("In only 500 model evaluations or about 1 hour of optimizing on CPU, the optimization "
         "with BPTT comes up with a solution with a speed of 1.17 m/s.")
_PEND = ("We observe that a controller with 1,065,888 parameters is able to learn to swing up and "
         "keep the pendulum stable from pixels after only 2420 episodes of 3 model seconds.")


def _e(table, artifact, variable, value, unit, source, pos, row, coords=(), note="",
       config="", form="value"):
    return entry(table=table, artifact=artifact, variable=variable, value=value, unit=unit,
                 source=source, pos=pos, row=row, coords=coords, note=note, config=config,
                 config_form=form)


_PROSE = (
    _e("§7.2.1", "ball", "iterations", 88.0, "1", _BALL_GD, 0, "gradient descent (BPTT)",
       (("method", "gradient"),)),
    _e("§7.2.1", "ball", "iterations", 2422.0, "1", _BALL_CMA, 1, "CMA-ES",
       (("method", "cmaes"),)),
    _e("§7.2.1", "ball", "wall_seconds", 16.3, "s", _BALL_T, 0, "gradient descent (BPTT)",
       (("method", "gradient"),), "including the time to compute the gradient"),
    _e("§7.2.1", "ball", "wall_seconds", 59.9, "s", _BALL_T, 1, "CMA-ES",
       (("method", "cmaes"),)),
    _e("§7.2.1", "ball", "diameter", 1.0, "m",
       "The ball has a 1 m diameter, a friction of $\\mu = 1.0$ and restitution e = 0.5.", 0,
       "ball model"),
    _e("§7.3.1", "table7_1", "gradient_slowdown_factor", 10.0, "1", _FACTOR, 0,
       "with gradient / without gradient", note="'roughly'; Tab. 7.1 ratios are 5.5 to 7.7"),
    _e("§7.3.1", "table7_1", "model_seconds_per_day", 864000.0, "s",
       "Also note that by using a batch method, a single GPU can simulate about 864 000 model "
       "seconds per day, or 86 400 000 model states.", 0, "one GPU, batched"),
    _e("§7.3.1", "table7_1", "step_milliseconds_with_gradient", 1.0, "ms",
       "takes about 1 ms on average. Without the backpropagation, this process is only about "
       "seven times faster.", 0, "one step of one robot with gradient, batched on GPU",
       note="the same sentence says the forward pass alone is 'about seven times faster'"),
    _e("§7.3.2.1", "arm_fixed", "evaluations", 100.0, "1", _ARM1, 1,
       "within 4 cm of the target", (("threshold_m", 0.04),)),
    _e("§7.3.2.1", "arm_fixed", "evaluations", 150.0, "1", _ARM1, 3,
       "within 1 cm of the target", (("threshold_m", 0.01),)),
    _e("§7.3.2.1", "arm_fixed", "n_params", 17284.0, "1",
       "This controller has 17 284 parameters in total.", 0, "arm controller, fixed target"),
    _e("§7.3.2.1", "arm_fixed", "cmaes_evaluations_without_convergence", 60000.0, "1",
       "After a week of computing and 60 000 model evaluations, CMA-ES did not show any sign of "
       "convergence, as it cannot handle the sheer amount of parameters.", 0, "CMA-ES",
       config="ch7.arm_fixed.cmaes.evaluations"),
    _e("§7.3.2.2", "arm_random", "updates", 576.0, "1", _ARM2, 0,
       "mean distance below 10 cm", (("threshold_m", 0.1),)),
    _e("§7.3.2.2", "arm_random", "updates", 2563.0, "1", _ARM2, 2,
       "mean distance below 5 cm", (("threshold_m", 0.05),)),
    _e("§7.3.2.2", "arm_random", "n_params", 2107396.0, "1",
       "We used 3 hidden layers with 1024 units each, so the controller has 2 107 396 "
       "parameters in total.", 2, "arm controller, random targets"),
    _e("§7.3.2.2", "arm_random", "batch", 128.0, "1",
       "In order to train for this task, we use a batch size of 128 robots, such that every "
       "update step takes 58 s on GPU.", 0, "robots per update", config="ch7.arm_random.batch"),
    _e("§7.3.3", "quadruped_gait", "hand_tuned_speed", 0.7, "m/s",
       "With hand tuning on the robot model shown in Figure 7.3b, we were able to obtain a "
       "trotting motion with an average forward speed of 0.7 m/s.", 1, "hand-tuned trot"),
    _e("§7.3.3", "quadruped_gait", "evaluations", 500.0, "1", _GAIT, 0,
       "BPTT optimisation budget", config="ch7.gait.evaluations"),
    _e("§7.3.3", "quadruped_gait", "speed", 1.17, "m/s", _GAIT, 2,
       "after 500 model evaluations", (("evaluations", 500),),
       "a hopping gait with a somersault every 3 steps"),
    _e("§7.3.3", "quadruped_gait", "n_params", 17952.0, "1",
       "In total, this controller has 17 952 parameters.", 0, "gait controller"),
    _e("§8.1", "quadruped_gait", "evaluations_to_stable_gait", 500.0, "1",
       "For a quadruped legged robot model, we were able to use deep neural networks to find a "
       "stable gait in only 500 model evaluations.", 0, "conclusion of chapter 7"),
    _e("§7.3.3.1", "pendulum_pixels", "episodes", 2420.0, "1", _PEND, 1,
       "episodes to swing up and balance from pixels"),
    _e("§7.3.3.1", "pendulum_pixels", "n_params", 1065888.0, "1", _PEND, 0,
       "pixel controller"),
    _e("§7.3.3.1", "pendulum_pixels", "episode_seconds", 3.0, "s", _PEND, 2,
       "model seconds per episode", config="ch7.pendulum.episode_s"),
    _e("§7.3.3.1", "pendulum_pixels", "optimisation_hours", 15.0, "h",
       "The complete optimization process took 15 hours.", 0, "whole optimisation"),
)

_SERVOS = ("The servos have a gain of 30 s^{-1} , a torque of 30 Nm and a velocity of "
           "$45^{\\circ} \\text{ s}^{-1}$.")
_ARM1_NET = ("As a controller, we use a dense neural network with 1 input, 2 hidden layers of 128 "
             "units with a rectifier activation function, and 4 outputs with an identity "
             "activation function.")
_ARM2_NET = ("We used 3 hidden layers with 1024 units each, so the controller has 2 107 396 "
             "parameters in total.")
_ARM2_SIM = "Each simulation takes 8 s with a simulation step of 0.01 s."
_GAIT_NET = ("On top of this, we added 2 hidden layers of 128 units and a rectifier activation "
             "function.")
_BALL_TASK = ("The ball starts off at position (0,0). After 5 s it should be at position (10,0) "
              "with zero velocity v and zero angular velocity ω .")
_BALL_TOL = ("We optimized the initial velocity v_0 and angular velocity ω_0 at time t = 0 s "
             "until the errors at t = 5 s are less than 0.01 m and 0.01 m/s respectively.")
_T71_CAPTION = ("The numbers are the time required in seconds for simulating the quadruped "
                "robot(s) for 10 s, with and without updating the controller parameters through "
                "gradient descent.")

#: The setup chapter 7 states, each naming the config path of the pipeline's value.
_SETUP = (
    _e("§7.2.1", "ball", "horizon_s", 5.0, "s", _BALL_TASK, 2, "time of the target",
       config="ch7.ball.horizon_s"),
    _e("§7.2.1", "ball", "target_x", 10.0, "m", _BALL_TASK, 3, "target x",
       config="ch7.ball.target_xy", form="item:0"),
    _e("§7.2.1", "ball", "target_y", 0.0, "m", _BALL_TASK, 4, "target y",
       config="ch7.ball.target_xy", form="item:1"),
    _e("§7.2.1", "ball", "tol_position_m", 0.01, "m", _BALL_TOL, 2, "position tolerance",
       config="ch7.ball.tol_position_m"),
    _e("§7.2.1", "ball", "tol_velocity_mps", 0.01, "m/s", _BALL_TOL, 3, "velocity tolerance",
       config="ch7.ball.tol_velocity_mps"),
    _e("§7.3.1", "table7_1", "simulated_seconds", 10.0, "s", _T71_CAPTION, 0,
       "simulated time per timed rollout", config="physics.bench.simulated_seconds"),
    _e("Tab. 7.1", "table7_1", "robots", 1.0, "1", _T71_S[0][2], 0, "#robots, first row",
       coords=(("batch", 1),), config="physics.bench.batches", form="contains"),
    _e("Tab. 7.1", "table7_1", "robots", 128.0, "1", _T71_S[2][2], 0, "#robots, third row",
       coords=(("batch", 128),), config="physics.bench.batches", form="contains"),
    _e("§7.3.2", "arm_fixed", "servo_torque", 30.0, "N m", _SERVOS, 2, "arm servo torque",
       config="ch7.arm_fixed.servo_torque"),
    _e("§7.3.2", "arm_random", "servo_torque", 30.0, "N m", _SERVOS, 2, "arm servo torque",
       config="ch7.arm_random.servo_torque"),
    _e("§7.3.2.1", "arm_fixed", "target", 0.5, "m", "at coordinates (0.5 m; 0.5 m; 0.5 m)", 0,
       "fixed target, every coordinate", config="ch7.arm_fixed.target", form="each"),
    _e("§7.3.2.1", "arm_fixed", "hidden_layers", 2.0, "1", _ARM1_NET, 1,
       "hidden layers of the controller", config="ch7.arm_fixed.hidden", form="length"),
    _e("§7.3.2.1", "arm_fixed", "hidden_units", 128.0, "1", _ARM1_NET, 2,
       "units per hidden layer", config="ch7.arm_fixed.hidden", form="each"),
    _e("§7.3.2.1", "arm_fixed", "learning_rate", 0.001, "1",
       "The parameters are optimized with Adam's rule [25] with a learning rate of 0.001.", 1,
       "Adam learning rate", config="ch7.arm_fixed.learning_rate"),
    _e("§7.3.2.1", "arm_fixed", "episode_s", 8.0, "s",
       "averaged over the 8 seconds we simulate our model", 0, "simulated time per evaluation",
       config="ch7.arm_fixed.episode_s"),
    _e("§7.3.2.2", "arm_random", "hidden_layers", 3.0, "1", _ARM2_NET, 0,
       "hidden layers of the controller", config="ch7.arm_random.hidden", form="length"),
    _e("§7.3.2.2", "arm_random", "hidden_units", 1024.0, "1", _ARM2_NET, 1,
       "units per hidden layer", config="ch7.arm_random.hidden", form="each"),
    _e("§7.3.2.2", "arm_random", "episode_s", 8.0, "s", _ARM2_SIM, 0,
       "simulated time per robot", config="ch7.arm_random.episode_s"),
    _e("§7.3.2.2", "arm_random", "dt", 0.01, "s", _ARM2_SIM, 1, "simulation step",
       config="ch7.arm_random.dt"),
    _e("§7.3.3", "quadruped_gait", "hidden_layers", 2.0, "1", _GAIT_NET, 0,
       "hidden layers of the controller", config="ch7.gait.hidden", form="length"),
    _e("§7.3.3", "quadruped_gait", "hidden_units", 128.0, "1", _GAIT_NET, 1,
       "units per hidden layer", config="ch7.gait.hidden", form="each"),
    _e("§7.3.3", "quadruped_gait", "frequency_hz", 1.5, "Hz",
       "a sine and a cosine signal with a frequency of 1.5 Hz", 0, "input frequency",
       config="ch7.gait.frequency_hz"),
    _e("§7.3.3", "quadruped_gait", "episode_s", 10.0, "s",
       "maximize the average velocity of the spine over the course of 10 s of time in "
       "simulation", 0, "simulated time per evaluation", config="ch7.gait.episode_s"),
    _e("§7.3.3", "quadruped_gait", "servo_torque", 4.0, "N m",
       "despite limiting the torque of the servos to 4 Nm on this 28.7 kg robot", 0,
       "servo torque bound", config="ch7.gait.servo_torque"),
    _e("§7.3.3.1", "pendulum_pixels", "pixels_width", 288.0, "1",
       "The resolution used is 288 by 96 pixels.", 0, "camera width [px]",
       config="ch7.pendulum.pixels", form="item:0"),
    _e("§7.3.3.1", "pendulum_pixels", "pixels_height", 96.0, "1",
       "The resolution used is 288 by 96 pixels.", 1, "camera height [px]",
       config="ch7.pendulum.pixels", form="item:1"),
)

ENTRIES: tuple[PaperValue, ...] = (*_table7_1(), *_PROSE, *_SETUP)
