"""The teacher gaits of §6.4: fixed gaits of the configuration, or a screen that chooses them.

"As target signals, we use motor signals for stable gaits resulting from previous work
[24, 25]. We have the robot trot at a frequency of 1.7 Hz" (§6.4): the teacher is an
open-loop gait of the chapter 3/4 foot-locus families (:mod:`thesis.gaits.trajectories`)
at ``teacher.frequency``, given to the chapter, not found by it. The thesis's own gait
parameters do not carry over to this model (its published gaits fall, validation target
V3 of ``thesis validate oncilla``), so ``teacher.source`` takes one of two:

* ``fixed``: the trot and the walk of ``teacher.fixed`` (family and loci parameters; the
  frequency is ``teacher.frequency``, the walk's duty factor ``walk.duty``). Like the
  thesis's teacher, they do not depend on what another chapter's optimiser found on this
  host: a particle swarm is chaotic at the rounding level, so a screen of its optima picks
  another teacher under another instruction set, and the controllers learn another gait.
* ``screen``: candidates are the chapter 3 optimum of every loci family in
  ``teacher.families`` and every chapter 3 seed (``results/<profile>/ch3/table3_1.nc``),
  with its frequency set to ``teacher.frequency`` and its stride (semi-axis a) scaled by
  each factor of ``teacher.stride_scales``; for the walk the same loci with the walk's
  phase offsets and duty factor (``walk.phase_offsets``, ``walk.duty``).

Either way each candidate (with ``fixed``, the two teachers) drives the robot open loop
through the whole protocol of its gait (settle, normalisation, both training stages,
running, motors off, recovery) before any controller is trained, and:

* it passes when the robot does not fall before the motors go off and, after power-on,
  stands upright above the fall height and walks forward faster than
  ``criteria.min_speed`` in the recovery window (the criteria of
  :mod:`thesis.ch6.criteria` that apply to an open-loop gait);
* the teacher is the passing candidate with the highest forward speed in the running
  window; if none passes, the one that stays up longest (then the fastest), and the
  dataset records that no candidate passed.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np

from thesis.gaits import runner as R
from thesis.gaits import trajectories as T

#: Loci families a teacher may come from: dataset name (as in ``ch3/table3_1``) -> class.
FAMILIES = {"half_ellipse": T.EllipseGait, "spline": T.SplineGait}
#: Gaits the chapter learns.
GAITS = ("trot", "walk")
#: Parameter names of the teacher vectors in result datasets, per family (thesis table
#: order of the family's ``names``).
PARAM_NAMES = {name: cls.names for name, cls in FAMILIES.items()}
#: Parameters a fixed teacher takes from elsewhere in the config, per gait: the frequency
#: (``teacher.frequency``) and, for the walk, the duty factor (``walk.duty``).
FROM_CONFIG = {"trot": ("f",), "walk": ("f", "duty")}


@functools.lru_cache(maxsize=8)
def family(name: str, phase_offsets: tuple = T.TROT_PHASE):
    """The loci family ``name`` with the given leg phase offsets (one instance per pair,
    so compiled command tables are reused)."""
    if name not in FAMILIES:
        raise ValueError(f"teacher family {name!r} is not one of {sorted(FAMILIES)}")
    return FAMILIES[name](phase_offsets=tuple(float(x) for x in phase_offsets))


def candidate_params(table, fam_name: str, seed, frequency: float, stride_scale: float,
                     duty: float | None = None) -> np.ndarray:
    """(P,) parameters of one candidate: ch3's optimum of ``fam_name`` for ``seed`` (from a
    ``table3_1`` dataset) at ``frequency`` [Hz], stride a scaled by ``stride_scale``,
    projected on the family's feasible set; then the duty factor set to ``duty`` if given
    (the walk's 0.75 lies outside the trot's Tab. 4.1 range, so it is set after the
    projection)."""
    fam = family(fam_name)
    v = table["value"].sel(gait=fam_name, seed=seed)
    label = lambda n: "t_stance_f" if n == "duty" else n  # noqa: E731 (ch3's column name)
    p = np.array([float(v.sel(parameter=label(n))) for n in fam.names])
    p[fam.index("f")] = frequency
    p[fam.index("a")] *= stride_scale
    p = fam.project(p)
    p[fam.index("f")] = frequency  # project clips f to Tab. 4.1's [1.5, 2.0]
    if duty is not None:
        p[fam.index("duty")] = duty
    return p


def fixed_params(spec: dict, gait: str, frequency: float,
                 duty: float | None = None) -> tuple[str, np.ndarray]:
    """(family name, (P,) parameters) of the fixed teacher ``spec`` =
    ``teacher.fixed.<gait>`` (``{family, params: {name: value}}``, thesis units: mm, 1):
    the loci parameters as given, in the family's order, with ``f`` = ``frequency`` [Hz]
    and, for the walk, ``duty`` = the walk's duty factor.

    Raises:
        ValueError: naming the key, when ``params`` lacks or adds a name, or a value lies
            outside the family's feasible set (Tab. 4.1 and its dependent ranges).
    """
    key = f"ch6.teacher.fixed.{gait}"
    fam_name = spec["family"]
    fam = family(fam_name)
    want = [n for n in fam.names if n not in FROM_CONFIG[gait]]
    got = spec["params"]
    missing, extra = sorted(set(want) - set(got)), sorted(set(got) - set(want))
    if missing or extra:
        raise ValueError(f"{key}.params: the {fam_name} {gait} teacher takes exactly "
                         f"{want} (missing {missing}, not allowed {extra}; "
                         f"{list(FROM_CONFIG[gait])} come from teacher.frequency / walk.duty)")
    p = np.array([float(got[n]) if n in got else 0.0 for n in fam.names])
    p[fam.index("f")] = frequency
    if duty is not None:
        p[fam.index("duty")] = duty
    q = fam.project(p)
    off = [n for n in want if not np.isclose(q[fam.index(n)], p[fam.index(n)],
                                             rtol=1e-12, atol=1e-9)]
    if off:
        raise ValueError(f"{key}.params: {off} lie outside the {fam_name} family's feasible "
                         f"set; the nearest feasible values are "
                         f"{ {n: float(q[fam.index(n)]) for n in off} }")
    return fam_name, p


@functools.lru_cache(maxsize=16)
def _table_fn(fam, settle: float):
    def one(params, t):
        return R.protocol_commands(fam, params, params, t, settle, 1.0)

    return jax.jit(jax.vmap(one, in_axes=(None, 0)))


def command_table(fam, params, n_steps: int, dt: float, settle: float) -> np.ndarray:
    """(n_steps, 12) teacher commands [rad] at t_k = k ``dt``: eased from the build pose
    into the gait's pose during ``settle`` [s], then the gait from phase 0
    (:func:`thesis.gaits.runner.protocol_commands`)."""
    t = jnp.arange(n_steps, dtype=jnp.float32) * jnp.float32(dt)
    return np.asarray(_table_fn(fam, float(settle))(jnp.asarray(params, jnp.float32), t))


def choose(passed, up_seconds, speed) -> int:
    """Index of the teacher among screened candidates (see the module docstring)."""
    passed = np.asarray(passed, float) == 1
    speed = np.asarray(speed, float)
    speed = np.where(np.isfinite(speed), speed, -np.inf)
    up = np.asarray(up_seconds, float)
    pool = np.flatnonzero(passed) if passed.any() else np.flatnonzero(up == up.max())
    return int(pool[np.argmax(speed[pool])])
