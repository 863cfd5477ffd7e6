"""The range a fallen robot's measured value can take in chapter 3's claims (rule 3b's
``failure_bounds`` of :mod:`thesis.claims.stats`), from what the failure is.

A fallen gait's measured forward speed (trunk displacement over the window, Fig. 3.4)
lies between 0 (it stopped where it fell) and its theoretical speed 2 a f / duty
(:func:`thesis.gaits.trajectories.theoretical_speed`: the stance foot's ground speed,
§3.3.1.2, which the thesis's measured curves stay below). The gait's own a and duty are
used where the dataset records them (``theoretical_speed`` of ``fig3_4``, per seed; the
largest over seeds, since one range serves every seed); elsewhere the family's top speed:
the largest stride the Oncilla's legs reach at the depths of Tab. 4.1 (a_max, the locus
families' bound) at the family's shortest stance (half-ellipse 0.5, spline 0.4, Tab.
4.1). The sine gait has no stride parameter and the thesis prints none of its
parameters, so its top speed is the most permissive of the locus families' (a_max, duty
0.4): its feet move inside the same legs' reach. A value a fallen seed actually recorded
outside the declared range widens it (the range bounds what failed runs give, so it must
contain what they gave).

What has no such range: the signed angular speed of a robot that fell (a tumbling trunk
can yaw at any rate, the unwrapped heading has no bound), the radius of a circle fitted
to its path (a robot lying still leaves a path whose fitted radius is anything from 0 to
infinity) and the log of its turning over straight-line speed (a stopped robot's log
speed is -infinity). Their claims keep rule 3b without a declared range: the failed
seeds' own interval, from 2 failed seeds on.
"""

from __future__ import annotations

import functools

import numpy as np
import xarray as xr

#: Shortest stance fraction t_stance f [d.u.] of each family (half ellipse: two or four
#: feet on the ground, §3.3.1.2; spline: Tab. 4.1); the sine gait takes the smallest.
SHORTEST_STANCE = {"half_ellipse": 0.5, "spline": 0.4, "sine": 0.4}


@functools.lru_cache(maxsize=1)
def largest_stride_mm() -> float:
    """The largest semi-axis a [mm] whose locus every leg of the Oncilla reaches, at the
    shallowest depth of Tab. 4.1 (where the reachable area is widest), the upper bound of
    a in the locus families (:class:`thesis.gaits.trajectories.EllipseGait`)."""
    from thesis.gaits import trajectories as T  # the leg geometry (JAX), only when needed
    return float(T.EllipseGait().upper[T.EllipseGait.names.index("a")])


def family_top_speed(gait: str, frequency) -> np.ndarray:
    """Top speed [m/s] of ``gait``'s family at ``frequency`` [Hz] (array-like): 2 a_max f
    / shortest stance (:data:`SHORTEST_STANCE`, :func:`largest_stride_mm`)."""
    from thesis.gaits.trajectories import theoretical_speed
    f = np.asarray(frequency, float)
    return np.asarray(theoretical_speed(largest_stride_mm(), f, SHORTEST_STANCE[gait]),
                      float)


def top_speed(ds: xr.Dataset, gait: str) -> np.ndarray:
    """Per frequency of ``ds`` (a ``fig3_4`` dataset), the top speed [m/s] of ``gait``:
    the largest recorded ``theoretical_speed`` over seeds where the dataset records a
    finite one for every frequency, else :func:`family_top_speed`. Shape (n_frequency,)
    in ``ds``'s frequency order."""
    freqs = np.asarray(ds["frequency"].values, float)
    if "theoretical_speed" in ds.data_vars and gait in ds["theoretical_speed"]["gait"]:
        th = ds["theoretical_speed"].sel(gait=gait)
        other = [d for d in th.dims if d != "frequency"]
        top = th.max(other, skipna=True) if other else th
        top = np.asarray(top.transpose("frequency").values, float)
        if np.all(np.isfinite(top)):
            return top
    return family_top_speed(gait, freqs)

