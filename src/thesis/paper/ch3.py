"""Chapter 3 (trotting and turning on the Oncilla): Tab. 3.1, Tab. 3.2 and prose numbers.

Result artifacts: ``ch3/fig3_4`` (variable ``speed`` over ``gait`` in ``sine``,
``half_ellipse``, ``spline`` and ``frequency`` [Hz]), ``ch3/table3_1`` (variable
``value`` over ``gait`` and ``parameter``), ``ch3/table3_2`` (variables ``speed``,
``angular_speed``, ``turning_radius``, ``stable`` over ``strategy``).
"""

from __future__ import annotations

from thesis.paper.types import PaperValue, entry

# ---------------------------------------------------------------- Tab. 3.1
#: Each printed row holds one half-ellipse parameter (left) and one spline parameter
#: (right); rows 9-12 hold spline parameters only.
#: (row as printed, ((gait, parameter, unit, value, pos), ...))
_T31_ROWS = (
    ("$x_0 (\\mathrm{mm})$\t138.45\t $x_0 (\\mathrm{mm})$\t139",
     (("half_ellipse", "x0", "mm", 138.45, 0), ("spline", "x0", "mm", 139.0, 1))),
    ("$y_{0,\\text{fore}} (\\text{mm})$\t0.39\t$y_{0,\\mathrm{fore}} (\\mathrm{mm})$\t0",
     (("half_ellipse", "y0_fore", "mm", 0.39, 0), ("spline", "y0_fore", "mm", 0.0, 1))),
    ("$y_{0,\\mathrm{hind}}~(\\mathrm{mm})$\t-6.83\t$y_{0,\\mathrm{hind}}~(\\mathrm{mm})$\t-18",
     (("half_ellipse", "y0_hind", "mm", -6.83, 0), ("spline", "y0_hind", "mm", -18.0, 1))),
    ("$a~({ m mm})$\t75.95\t$a \\ (mm)$\t91",
     (("half_ellipse", "a", "mm", 75.95, 0), ("spline", "a", "mm", 91.0, 1))),
    ("$b_{\\rm fore} \\ ({\\rm mm})$\t13.69\t$l_{0,\\text{fore}} (\\text{mm})$\t68",
     (("half_ellipse", "b_fore", "mm", 13.69, 0), ("spline", "l0_fore", "mm", 68.0, 1))),
    ("$b_{\\rm hind}~({\\rm mm})$\t26.12\t$l_{0,\\text{hind}} (\\text{mm})$\t11",
     (("half_ellipse", "b_hind", "mm", 26.12, 0), ("spline", "l0_hind", "mm", 11.0, 1))),
    ("$t_{\\text{stance}} f$ (d.u.)\t0.5\t$l_{1,\\text{fore}} (\\text{mm})$\t63",
     (("half_ellipse", "t_stance_f", "1", 0.5, 0), ("spline", "l1_fore", "mm", 63.0, 1))),
    ("f (Hz)\t1.94\t$l_{1,\\text{hind}} (\\text{mm})$\t32",
     (("half_ellipse", "f", "Hz", 1.94, 0), ("spline", "l1_hind", "mm", 32.0, 1))),
    ("$l_2 \\ (\\mathrm{mm})$\t63", (("spline", "l2", "mm", 63.0, 0),)),
    ("$l_3 \\ (mm)$\t32", (("spline", "l3", "mm", 32.0, 0),)),
    ("$t_{\\text{stance}} f$ (d.u.)\t0.6", (("spline", "t_stance_f", "1", 0.6, 0),)),
    ("f (Hz)\t2", (("spline", "f", "Hz", 2.0, 0),)),
)


def _table3_1() -> list[PaperValue]:
    out = []
    for source, cells in _T31_ROWS:
        for gait, param, unit, value, pos in cells:
            note = "PSO-optimised gait parameter"
            if gait == "half_ellipse" and param == "a":
                note += "; §3.3.2.1 calls it the step size (76 mm)"
            out.append(entry(
                table="Tab. 3.1", artifact="table3_1", variable="value",
                coords=(("gait", gait), ("parameter", param)), value=value, unit=unit,
                source=source, pos=pos, row=param, column=f"{gait} value", note=note,
            ))
    return out


# ---------------------------------------------------------------- Tab. 3.2
_T32_ROWS = {
    "step_size": ("Step size strategy\t$0.068{ m m/s}$\t$8.0^{\\circ}/\\mathrm{s}$"
                  "\t$0.448\\mathrm{m}$", (0.068, 8.0, 0.448)),
    "scapulae": ("Scapulae strategy\t$0.22{ m m/s}$\t$20^{\\circ}/\\mathrm{s}$"
                 "\t$0.610\\mathrm{m}$", (0.22, 20.0, 0.610)),
}
_T32_COLS = (("speed", "Speed", "m/s"), ("angular_speed", "Angular speed", "degree/s"),
             ("turning_radius", "Turning radius", "m"))


def _table3_2() -> list[PaperValue]:
    out = []
    for strategy, (source, values) in _T32_ROWS.items():
        for i, ((var, header, unit), value) in enumerate(zip(_T32_COLS, values)):
            out.append(entry(
                table="Tab. 3.2", artifact="table3_2", variable=var,
                coords=(("strategy", strategy),), value=value, unit=unit, source=source,
                pos=i, row=source.split("\t")[0], column=header,
                note="centre of the robot, gait at 1.5 Hz",
            ))
    return out


# ---------------------------------------------------------------- prose
_S_SPLINE = ("After optimization, the gait attained a speed of 0.41 m/s at a frequency of "
             "1.5 Hz.")
_S_OTHERS = ("it performs better than the gait based on sine-wave control signals (0.24 m/s) "
             "and the gait from our half ellipse approach (0.27 m/s).")
_S_TURN = ("Both strategies use the same gait at 1.5 Hz which had a speed of 0.30 m/s moving "
           "forwards.")
_UNSTATED_F = ("the frequency of this comparison is not stated (the spline value is at 1.5 Hz; "
               "the half-ellipse gait is said to walk 0.30 m/s at 1.5 Hz in §3.3.3, so 0.27 "
               "may be another frequency)")

_S_PSO = ("By using 10 particles, 10 generations and a duration of 10 seconds per run with 1 "
          "second transition time, the optimizationwas done in less than 30 minutes.")

_PROSE = (
    entry(table="§3.3.1.3", artifact="fig3_4", variable="speed",
          coords=(("gait", "spline"), ("frequency", 1.5)), value=0.41, unit="m/s",
          source=_S_SPLINE, pos=0, row="spline gait after optimisation"),
    entry(table="§3.3.1.3", artifact="fig3_4", variable="speed_compared",
          coords=(("gait", "sine"),), value=0.24, unit="m/s", source=_S_OTHERS, pos=0,
          row="sine gait", note=_UNSTATED_F),
    entry(table="§3.3.1.3", artifact="fig3_4", variable="speed_compared",
          coords=(("gait", "half_ellipse"),), value=0.27, unit="m/s", source=_S_OTHERS,
          pos=1, row="half-ellipse gait", note=_UNSTATED_F),
    entry(table="§3.3.1.3", artifact="fig3_4", variable="max_speed",
          coords=(("gait", "spline"),), value=0.59, unit="m/s",
          source="The maximum speed reached is 0.59 m/s at", pos=0, row="spline gait",
          note="the sentence is split by Tab. 3.1; it continues '2.6 Hz.'"),
    entry(table="§3.3.1.3", artifact="fig3_4", variable="max_speed_frequency",
          coords=(("gait", "spline"),), value=2.6, unit="Hz",
          source="2.6 Hz. The final parameters are listed in Table 3.1.", pos=0,
          row="spline gait", note="continuation of 'The maximum speed reached is 0.59 m/s at'"),
    entry(table="§3.3.1.1", artifact="fig3_4", variable="linear_up_to_frequency",
          coords=(("gait", "sine"),), value=1.0, unit="Hz",
          source="This gait's velocity is proportional to the frequency up to about 1 Hz, at "
                 "which point it flattens.", pos=0, row="sine gait (hand-tuned)"),
    entry(table="§3.3.1.2", artifact="fig3_4", variable="linear_up_to_frequency",
          coords=(("gait", "half_ellipse"),), value=2.0, unit="Hz",
          source="One can notice linear behavior, all the way up to 2 Hz.", pos=0,
          row="half-ellipse gait"),
    entry(table="§3.3.1.3", artifact="fig3_4", variable="linear_up_to_frequency",
          coords=(("gait", "spline"),), value=2.0, unit="Hz",
          source="follows the theoretical prediction almost perfectly up to 2 Hz", pos=0,
          row="spline gait"),
    entry(table="§3.3.1.2", artifact="sec3.3.1.2", variable="pso_particles", value=10.0,
          unit="1", pos=0, row="half-ellipse optimisation",
          config="ch3.pso.half_ellipse.particles",
          source="By using 10 particles, 10 generations and a duration of 10 seconds per run "
                 "with 1 second transition time, the optimizationwas done in less than 30 "
                 "minutes."),
    entry(table="§3.3.1.2", artifact="sec3.3.1.2", variable="pso_generations", value=10.0,
          unit="1", pos=1, row="half-ellipse optimisation",
          config="ch3.pso.half_ellipse.generations",
          source="By using 10 particles, 10 generations and a duration of 10 seconds per run "
                 "with 1 second transition time, the optimizationwas done in less than 30 "
                 "minutes."),
    entry(table="§3.3.1.2", artifact="sec3.3.1.2", variable="optimisation_minutes",
          value=30.0, unit="min", pos=4, row="half-ellipse optimisation (upper bound)",
          source="By using 10 particles, 10 generations and a duration of 10 seconds per run "
                 "with 1 second transition time, the optimizationwas done in less than 30 "
                 "minutes."),
    entry(table="§3.3.1.2", artifact="sec3.3.1.2", variable="run_seconds", value=10.0,
          unit="s", pos=2, row="half-ellipse optimisation: evaluation per particle",
          config="ch3.pso.half_ellipse.run_seconds", source=_S_PSO),
    entry(table="§3.3.1.2", artifact="sec3.3.1.2", variable="transition_seconds", value=1.0,
          unit="s", pos=3, row="half-ellipse optimisation: transition between particles",
          config="ch3.pso.half_ellipse.transition_seconds", source=_S_PSO),
    entry(table="§3.3.1.3", artifact="sec3.3.1.3", variable="pso_particles", value=20.0,
          unit="1", pos=0, row="spline optimisation",
          config="ch3.pso.spline.particles",
          source="we used the PSO algorithm with 20 particles, 20 generations and a duration "
                 "of five seconds per run with one second of transition time."),
    entry(table="§3.3.1.3", artifact="sec3.3.1.3", variable="pso_generations", value=20.0,
          unit="1", pos=1, row="spline optimisation",
          config="ch3.pso.spline.generations",
          source="we used the PSO algorithm with 20 particles, 20 generations and a duration "
                 "of five seconds per run with one second of transition time."),
    entry(table="§3.3.1.3", artifact="sec3.3.1.3", variable="optimisation_minutes",
          value=40.0, unit="min", pos=0, row="spline optimisation (about)",
          source="This way, we were able to optimize the gait in about 40 minutes"),
    entry(table="§3.3.2.1", artifact="sec3.3.2.1", variable="reduced_step_size", value=20.0,
          unit="mm", pos=0, row="step-size turning",
          config="ch3.turning.reduced_a",
          source="The step size on one side of the robot could be reduced to 20 mm without "
                 "causing disruptions in the gait dynamics"),
    entry(table="§3.3.2.5", artifact="sec3.3.2.5", variable="max_sidewise_step", value=4.2,
          unit="cm", pos=2, row="scapulae range",
          source="about 5° of adduction and 10° of abduction, so the maximal theoretical "
                 "sidewise step is about 4.2 cm"),
    entry(table="§3.3.2.5", artifact="sec3.3.2.5", variable="max_yaw", value=20.0,
          unit="degree", pos=0, row="scapulae turning: rotation of the foot loci",
          config="ch3.turning.yaw_deg",
          source="In our experiments, we used a maximum rotation of the foot trajectories aroud "
                 "the vertical axis of 20° ."),
    entry(table="§3.3.3", artifact="sec3.3.3", variable="turning_frequency", value=1.5,
          unit="Hz", source=_S_TURN, pos=0, row="gait frequency of both turning strategies",
          config="ch3.turning.frequency"),
    entry(table="§3.3.3", artifact="table3_2", variable="forward_speed", value=0.30,
          unit="m/s", source=_S_TURN, pos=1, row="gait used for turning, straight ahead",
          note="the gait (1.5 Hz) both turning strategies use"),
    entry(table="§3.3.3", artifact="table3_2", variable="speed_loss",
          coords=(("strategy", "scapulae"),), value=8.3, unit="percent", pos=0,
          row="scapulae turning vs forward walking",
          source="very slight speed loss compared to walking forwards (8.3%)",
          note="inconsistent with Tab. 3.2 (0.22 m/s) against 0.30 m/s forwards, a 27 % loss"),
    entry(table="§3.3.3", artifact="table3_2", variable="turning_radius_increase",
          coords=(("strategy", "scapulae"),), value=36.0, unit="percent", pos=0,
          row="scapulae vs step size",
          source="the turning radius is 36% higher compared to using a smaller step size for "
                 "turning.", note="0.610 / 0.448 = 1.36 (Tab. 3.2)"),
)

ENTRIES: tuple[PaperValue, ...] = (*_table3_1(), *_table3_2(), *_PROSE)
