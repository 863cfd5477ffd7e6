"""Chapter 4 (transfer learning of gaits): Tab. 4.2, 4.3, 4.4 and prose numbers.

The chapter-4 experiments are not built yet; the artifact ids used here (``table4_2``,
``table4_3``, ``table4_4``, ``fig4_5``, ``fig4_7``, ``fig4_8``, ``fig4_10``) are the
natural ones. Table cells are keyed ``table4_2/grade=9/transfer=1/<column>``.

Transcription notes: the "transfer learning" column prints a cross (x) for "without" and a
check mark rendered as "1" in thesis.txt for "with". In Tab. 4.3 the last header reads
"Euclidear distance" (sic). The thesis writes the p-values of the Wilcoxon rank-sum tests
(combined with Fisher's method) as "rho".
"""

from __future__ import annotations

from thesis.paper.types import PaperValue, entry

#: (name, unit) of the 14 numeric columns shared by Tab. 4.2, 4.3 and 4.4, in order.
_COLS = (
    ("f", "Hz"), ("a", "mm"), ("x0", "mm"), ("y0r", "mm"), ("y0f", "mm"),
    ("t_stance", "1"), ("l0f", "mm"), ("l1f", "mm"), ("l0r", "mm"), ("l1r", "mm"),
    ("l2", "mm"), ("l3", "mm"), ("speed", "m/s"), ("euclidean_distance", "1"),
)

_NORMAL = "\t×\t1.98\t95.3\t137.0\t-16.39\t0.00\t0.54\t67.1\t10.4\t4.39\t65.3\t58.8\t24.1\t0.76\t0"
_NORMAL_VALUES = (1.98, 95.3, 137.0, -16.39, 0.00, 0.54, 67.1, 10.4, 4.39, 65.3, 58.8, 24.1,
                  0.76, 0.0)

#: (coords, row as printed, index of the first parameter among the row's numbers, values)
_T42 = (
    ((("grade", 0), ("transfer", 0)), "flat" + _NORMAL, 0, _NORMAL_VALUES),
    ((("grade", 9), ("transfer", 0)),
     "9%\t×\t2.00\t87.9\t141.8\t-11.88\t0.00\t0.60\t70.0\t3.13\t0.00\t47.6\t69.4\t4.53\t0.67\t4.13",
     1, (2.00, 87.9, 141.8, -11.88, 0.00, 0.60, 70.0, 3.13, 0.00, 47.6, 69.4, 4.53, 0.67, 4.13)),
    ((("grade", 9), ("transfer", 1)),
     "9%\t1\t2.00\t90.6\t140.1\t-11.71\t0.00\t0.54\t65.7\t4.06\t23.9\t70.0\t70.0\t26.2\t0.74\t1.72",
     2, (2.00, 90.6, 140.1, -11.71, 0.00, 0.54, 65.7, 4.06, 23.9, 70.0, 70.0, 26.2, 0.74, 1.72)),
    ((("grade", 18), ("transfer", 0)),
     "18%\t×\t1.71\t84.4\t143.9\t-8.87\t0.00\t0.56\t52.6\t34.8\t0.00\t51.6\t66.2\t4.51\t0.53\t6.64",
     1, (1.71, 84.4, 143.9, -8.87, 0.00, 0.56, 52.6, 34.8, 0.00, 51.6, 66.2, 4.51, 0.53, 6.64)),
    ((("grade", 18), ("transfer", 1)),
     "18%\t1\t2.00\t86.3\t142.8\t-9.77\t0.00\t0.58\t70.0\t3.77\t50.3\t39.9\t70.0\t0.00\t0.60\t9.05",
     2, (2.00, 86.3, 142.8, -9.77, 0.00, 0.58, 70.0, 3.77, 50.3, 39.9, 70.0, 0.00, 0.60, 9.05)),
)

_T43 = (
    ((("stiffness", "normal"), ("transfer", 0)), "normal" + _NORMAL, 0, _NORMAL_VALUES),
    ((("stiffness", "compliant"), ("transfer", 0)),
     "$\\operatorname{compliant}$\t×\t1.73\t96.2\t136.4\t-24.16\t0.00\t0.50\t0.00\t1.74\t0.00"
     "\t40.7\t70.0\t25.2\t0.66\t12.98",
     0, (1.73, 96.2, 136.4, -24.16, 0.00, 0.50, 0.00, 1.74, 0.00, 40.7, 70.0, 25.2, 0.66,
         12.98)),
    ((("stiffness", "compliant"), ("transfer", 1)),
     "$\\operatorname{compliant}$\t1\t2.00\t105.7\t129.1\t-5.27\t0.00\t0.60\t70.0\t0.00\t0.00"
     "\t70.0\t70.0\t70.0\t0.75\t7.16",
     1, (2.00, 105.7, 129.1, -5.27, 0.00, 0.60, 70.0, 0.00, 0.00, 70.0, 70.0, 70.0, 0.75, 7.16)),
)

_T44 = (
    ((("terrain", "normal"), ("transfer", 0), ("rank", 1)), "normal" + _NORMAL, 0,
     _NORMAL_VALUES),
    ((("terrain", "pebbly"), ("transfer", 0), ("rank", 1)),
     "pebbly\t×\t2.00\t87.3\t142.2\t3.44\t0.00\t0.49\t0.00\t70.0\t60.6\t70.0\t70.0\t70.0\t0.69"
     "\t25.82",
     0, (2.00, 87.3, 142.2, 3.44, 0.00, 0.49, 0.00, 70.0, 60.6, 70.0, 70.0, 70.0, 0.69, 25.82)),
    ((("terrain", "pebbly"), ("transfer", 1), ("rank", 1)),
     "pebbly\t1\t2.00\t89.3\t141.0\t-18.48\t0.00\t0.59\t54.6\t34.9\t0.08\t64.9\t55.2\t22.0\t0.74"
     "\t2.44",
     1, (2.00, 89.3, 141.0, -18.48, 0.00, 0.59, 54.6, 34.9, 0.08, 64.9, 55.2, 22.0, 0.74, 2.44)),
    ((("terrain", "pebbly"), ("transfer", 1), ("rank", 2)),
     "pebbly\t1\t2.00\t94.8\t137.3\t-8.29\t0.00\t0.57\t70.0\t29.0\t0.00\t63.2\t56.4\t28.7\t0.74"
     "\t1.25",
     1, (2.00, 94.8, 137.3, -8.29, 0.00, 0.57, 70.0, 29.0, 0.00, 63.2, 56.4, 28.7, 0.74, 1.25)),
)

_NOTES = {
    "Tab. 4.4": "rank is the printed order of the two transfer-learning rows; the caption says "
                "one of them is the second-best particle (the best was in the first "
                "generation) but not which",
}


def _table(table: str, artifact: str, rows) -> list[PaperValue]:
    out = []
    for coords, source, first, values in rows:
        assert len(values) == len(_COLS), (table, coords)
        label = source.split("\t")[0] + (" with transfer" if ("transfer", 1) in coords else "")
        for i, ((name, unit), value) in enumerate(zip(_COLS, values)):
            note = _NOTES.get(table, "") if ("rank", 2) in coords or (
                ("transfer", 1) in coords and table == "Tab. 4.4") else ""
            if name == "euclidean_distance":
                note = (note + "; " if note else "") + (
                    "distance to the best flat-terrain particle after normalisation")
            out.append(entry(
                table=table, artifact=artifact, variable=name, coords=coords, value=value,
                unit=unit, source=source, pos=first + i, row=label, column=name, note=note,
            ))
    return out


_S_SLOPES = ("We find that the particles in the optimization with transfer learning on average "
             "outperform the particles without transfer learning significantly on both "
             "inclinations ($\\rho < 0.001$).")
_S_STIFF = ("Using the same statistical method as before, we find that the particles in the "
            "optimization process with transfer learning run significantly larger distances "
            "($\\rho < 0.05$).")
_S_PEBBLY = ("Over all generations together, the particles optimized with transfer learning do "
             "not perform significantly better than the particles without transfer learning "
             "($\\rho > 0.05$).")
_S_FASTER = ("we can see that the best particles from transfer learning have a gait with a speed "
             "9% and 14% faster on the 9% and 18% grades respectivey.")
_P_NOTE = ("Wilcoxon rank-sum tests per generation, p-values combined with Fisher's method; "
           "a bound, not a value")

_PROSE = (
    entry(table="§4.6.1", artifact="fig4_5", variable="p_value_upper_bound",
          coords=(("grade", 9),), value=0.001, unit="1", source=_S_SLOPES, pos=0,
          row="9% grade, transfer vs random", note=_P_NOTE),
    entry(table="§4.6.1", artifact="fig4_5", variable="p_value_upper_bound",
          coords=(("grade", 18),), value=0.001, unit="1", source=_S_SLOPES, pos=0,
          row="18% grade, transfer vs random", note=_P_NOTE),
    entry(table="§4.6.2", artifact="fig4_7", variable="p_value_upper_bound", value=0.05,
          unit="1", source=_S_STIFF, pos=0, row="compliant front legs, transfer vs random",
          note=_P_NOTE),
    entry(table="§4.6.3", artifact="fig4_8", variable="p_value_lower_bound", value=0.05,
          unit="1", source=_S_PEBBLY, pos=0, row="pebbly terrain, transfer vs random",
          note=_P_NOTE + " (p > 0.05: not significant)"),
    entry(table="§4.6.1", artifact="table4_2", variable="best_speed_gain",
          coords=(("grade", 9),), value=9.0, unit="percent", source=_S_FASTER, pos=0,
          row="9% grade", note="Tab. 4.2 gives 0.74 vs 0.67 m/s: +10.4 % (or 9.5 % of 0.74)"),
    entry(table="§4.6.1", artifact="table4_2", variable="best_speed_gain",
          coords=(("grade", 18),), value=14.0, unit="percent", source=_S_FASTER, pos=1,
          row="18% grade", note="Tab. 4.2 gives 0.60 vs 0.53 m/s: +13.2 %"),
    entry(table="§4.6.2", artifact="table4_3", variable="best_speed_gain",
          coords=(("stiffness", "compliant"),), value=13.0, unit="percent", pos=0,
          row="compliant front legs",
          source="we can see that the best particle of the optimization with transfer learning "
                 "has a 13% faster gait than in the optimization process without transfer "
                 "learning.", note="Tab. 4.3 gives 0.75 vs 0.66 m/s: +13.6 %"),
    entry(table="§4.7", artifact="fig4_10", variable="search_space_ratio", value=1.7, unit="1",
          pos=0, row="18% grade, random / transfer",
          source="The size of search space with transfer learning is on average 1.7 times "
                 "smaller.",
          note="geometric mean of the principal-axis lengths of each generation's particles"),
    entry(table="§4.3", artifact="sec4.3", variable="pso_particles", value=20.0, unit="1",
          pos=0, row="swarm size",
          source="In this paper, we use a population size of 20 particles"),
    entry(table="§4.4", artifact="sec4.4", variable="transferred_particles", value=20.0,
          unit="1", pos=0, row="particles transferred",
          source="In our case, this means we take the best 20 particles over all generations "
                 "from a previous optimization of a similar problem."),
    entry(table="§4.5", artifact="sec4.5", variable="evaluation_seconds", value=4.0, unit="s",
          pos=0, row="time per gait evaluation",
          source="We test each gait for 4 seconds at a time, and have a smooth transition "
                 "between these gaits for 2 seconds."),
    entry(table="§4.5", artifact="sec4.5", variable="transition_seconds", value=2.0, unit="s",
          pos=1, row="transition between gaits",
          source="We test each gait for 4 seconds at a time, and have a smooth transition "
                 "between these gaits for 2 seconds."),
    entry(table="§4.6.1", artifact="sec4.6.1", variable="slope_angle",
          coords=(("grade", 9),), value=5.14, unit="degree", pos=2, row="9% grade",
          source="(a 9% and an 18% grade, or a 5.14° and a 10.2° slope)"),
    entry(table="§4.6.1", artifact="sec4.6.1", variable="slope_angle",
          coords=(("grade", 18),), value=10.2, unit="degree", pos=3, row="18% grade",
          source="(a 9% and an 18% grade, or a 5.14° and a 10.2° slope)"),
)

_S_PSO = ("These were set at the values $\\omega = 0.66$, $\\phi_p = 1.6$ and $\\phi_g = 0.62$")
_S_RUN = ("the Oncilla robot ran nearly 6 km during the 4 hours it spent optimizing")
_S_IMPULSE = ("We instead give these particles a small impulse in a random direction in order "
              "to have them start exploring new solutions ($r \\in \\mathcal{U}(-1, 1)$).")
_T41 = "Tab. 4.1"


def _range(row: str, name: str, unit: str, lo_pos: int, lo: float, hi: float):
    return (
        entry(table=_T41, artifact="table4_1", variable="lower", coords=(("parameter", name),),
              value=lo, unit=unit, source=row, pos=lo_pos, row=name, column="range (lower)"),
        entry(table=_T41, artifact="table4_1", variable="upper", coords=(("parameter", name),),
              value=hi, unit=unit, source=row, pos=lo_pos + 1, row=name, column="range (upper)"),
    )


_SETUP = (
    *_range("f (Hz)\t[1.5; 2.0]\tThe frequency of the gait", "f", "Hz", 0, 1.5, 2.0),
    *_range("$x_0 \\ (\\mathrm{mm})$\t[126; 158]\tThe vertical distance of the hip to the "
            "trajectory's center", "x0", "mm", 0, 126.0, 158.0),
    *_range("t_{stance} (d.u.)\t[0.4; 0.6]\tThe fraction of the period of the gait spent in the "
            "stance phase", "t_stance", "1", 0, 0.4, 0.6),
    *_range("$l_{0f}, l_{1f} (\\mathrm{mm})$\t[0;70]\tThe control points for the top of the "
            "trajectory for the fore feet", "l_fore", "mm", 0, 0.0, 70.0),
    *_range("$l_{0r}, l_{1r} ({\\rm mm})$\t[0;70]\tThe control points for the top of the "
            "trajectory for the hind feet", "l_hind", "mm", 0, 0.0, 70.0),
    *_range("$l_2, l_3 \\text{ (mm)}$\t[0;70]\tThe control points for the bot- tom of the "
            "trajectory for all four feet", "l_bottom", "mm", 0, 0.0, 70.0),
    entry(table="§4.3", artifact="sec4.3", variable="omega", value=0.66, unit="1",
          source=_S_PSO, pos=0, row="PSO inertia weight"),
    entry(table="§4.3", artifact="sec4.3", variable="phi_p", value=1.6, unit="1",
          source=_S_PSO, pos=1, row="PSO acceleration towards the particle's best"),
    entry(table="§4.3", artifact="sec4.3", variable="phi_g", value=0.62, unit="1",
          source=_S_PSO, pos=2, row="PSO acceleration towards the global best"),
    entry(table="§4.4", artifact="sec4.4", variable="impulse_lower", value=-1.0, unit="1",
          source=_S_IMPULSE, pos=0, row="transfer impulse r ~ U(-1, 1)",
          note="in the thesis's parameter units (mm, Hz, d.u.); see the departure "
               "ch4.transfer_impulse"),
    entry(table="§4.4", artifact="sec4.4", variable="impulse_upper", value=1.0, unit="1",
          source=_S_IMPULSE, pos=1, row="transfer impulse r ~ U(-1, 1)"),
    entry(table="§4.5", artifact="sec4.5", variable="distance_run", value=6.0, unit="km",
          source=_S_RUN, pos=0, row="distance run during all optimisations",
          note="'nearly 6 km'"),
    entry(table="§4.5", artifact="sec4.5", variable="optimisation_hours", value=4.0,
          unit="hour", source=_S_RUN, pos=1, row="robot time of all optimisations"),
    entry(table="§4.6.3", artifact="sec4.6.3", variable="pebble_diameter", value=1.0,
          unit="cm", pos=0, row="pebble diameter", note="'approximately 1 cm'",
          source="We attached a pebble dispenser to our treadmill, which covered the treadmill "
                 "in pebbles with a diameter of approximately 1 cm."),
    entry(table="Fig. 4.6", artifact="fig4_6", variable="top", value=50.0, unit="1", pos=0,
          row="best particles per inclination",
          source="In these figures, we have plotted the parameters of the 50 best particles "
                 "found in all our optimizations for each inclination."),
)

ENTRIES: tuple[PaperValue, ...] = (
    *_table("Tab. 4.2", "table4_2", _T42),
    *_table("Tab. 4.3", "table4_3", _T43),
    *_table("Tab. 4.4", "table4_4", _T44),
    *_PROSE,
    *_SETUP,
)
