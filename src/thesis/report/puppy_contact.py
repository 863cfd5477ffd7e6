"""Report tables of the Puppy II's paw contact (``results/<profile>/model/puppy_contact.nc``,
``thesis bench puppy-contact``, :mod:`thesis.modelcheck.puppy_contact`): per terrain the
standing indentation, implied stiffness and touchdown rise beside the sourced ranges and
their checks; per gait the paws' off-ground shares and the knees' stance flexion.

Every number is read from the dataset; without one both tables say "not run".
"""

from __future__ import annotations

import numpy as np

from thesis.report.model import NOT_RUN, Table

KEY = "model/puppy_contact"


def _num(x, digits: int = 2) -> str:
    x = float(x)
    return "—" if not np.isfinite(x) else f"{x:.{digits}f}"


def _range(lo_hi, digits: int = 2) -> str:
    """'a-b', '>= a', '<= b' or 'no source' of a sourced (low, high) pair."""
    lo, hi = (float(v) for v in lo_hi)
    if np.isfinite(lo) and np.isfinite(hi):
        return f"{lo:.{digits}f}-{hi:.{digits}f}"
    if np.isfinite(lo):
        return f">= {lo:.{digits}f}"
    if np.isfinite(hi):
        return f"<= {hi:.{digits}f}"
    return "no source"


def _verdict(checks) -> str:
    """One word for a terrain's per-paw checks: the common one, or 'n of 4 pass'."""
    vals = [str(c) for c in np.ravel(checks)]
    if len(set(vals)) == 1:
        return vals[0]
    return f"{vals.count('pass')} of {len(vals)} pass"


def terrain_table(results: dict) -> Table:
    """Per terrain: standing indentation and implied stiffness, touchdown time to peak
    and 10-90 % rise (means over the four paws), each beside its sourced range and the
    check against it."""
    ds = results.get(KEY)
    cols = ["terrain", "indentation [mm] (sourced; check)", "implied stiffness [kN/m] "
            "(sourced; check)", "touchdown to peak [ms] (sourced; check)",
            "10-90 % rise [ms] (sourced; check)", "peak force [N]"]
    title = "Puppy II paw contact per terrain against the sourced values"
    ref = "§5.3.1"
    if ds is None:
        return Table(id="puppy_contact", title=title, thesis_ref=ref, columns=cols,
                     rows=[[NOT_RUN] * len(cols)])
    rows = []
    for t in ds["terrain"].values:
        d = ds.sel(terrain=t)

        def cell(name, src, chk):
            sourced = _range(d[src].values)
            if sourced == "no source":
                return f"{_num(d[name].mean())} (no source)"
            return f"{_num(d[name].mean())} ({sourced}; {_verdict(d[chk].values)})"

        rows.append([str(t), cell("indentation", "indentation_source", "indentation_check"),
                     cell("implied_stiffness", "stiffness_source", "stiffness_check"),
                     cell("time_to_peak", "time_to_peak_source", "time_to_peak_check"),
                     cell("rise_time", "rise_time_source", "rise_time_check"),
                     _num(d["peak_force"].mean(), 1)])
    total = ds["total_normal_force"].values
    note = (f"Nominal terrains of ch5.terrains; standing load per paw "
            f"{float(ds['normal_force'].mean()):.2f} N (paws together "
            f"{float(np.min(total)):.2f}-{float(np.max(total)):.2f} N, m g "
            f"{4 * float(ds.attrs['static_load_n']):.2f} N); indentation includes the "
            f"engine's contact slop of {1e3 * float(ds.attrs['contact_slop_m']):.1f} mm. "
            f"Touchdown after a drop of the standing pose; time resolution: the "
            f"{1e3 * float(ds.attrs['dt_s']):g}-ms step ('unresolved': the force jumps to "
            f"its peak within one step). Sourced ranges and their "
            f"derivations: {ds.attrs['source']}; a check passes within "
            f"+-{100 * float(ds.attrs['tolerance']):.0f} % of the range.")
    return Table(id="puppy_contact", title=title, thesis_ref=ref, columns=cols, rows=rows,
                 note=note)


def gait_table(results: dict) -> Table:
    """Per gait and frequency: on each terrain, the largest off-ground share of the four
    paws and the largest knee angle range in stance."""
    ds = results.get(KEY)
    title = "Puppy II paws off the ground and knee stance flexion per gait (no source)"
    ref = "Tab. 5.1"
    if ds is None:
        return Table(id="puppy_contact_gaits", title=title, thesis_ref=ref,
                     columns=["gait"], rows=[[NOT_RUN]])
    terrains = [str(t) for t in ds["terrain"].values]
    cols = (["gait"] + [f"{t}: off ground, most of 4 paws [%]" for t in terrains]
            + [f"{t}: knee stance range, largest [rad]" for t in terrains])
    rows = []
    for g in ds["gait"].values:
        d = ds.sel(gait=g)
        off = [d["off_ground_share"].sel(terrain=t).max() for t in terrains]
        knee = [d["knee_stance_range"].sel(terrain=t).max() for t in terrains]
        flag = [" (turned over)" if bool(d["turned_over"].sel(terrain=t)) else ""
                for t in terrains]
        rows.append([str(g)] + [_num(100 * o, 0) + f for o, f in zip(off, flag)]
                    + [_num(k) for k in knee])
    note = (f"Off the ground: normal force below {float(ds.attrs['off_ground_threshold_n']):g} N. "
            f"{ds.attrs['unloading']}. One trial per gait from standing, measured after the "
            "warm-up up to a turn-over. No source gives the Puppy II's paw unloading or knee "
            "flexion.")
    return Table(id="puppy_contact_gaits", title=title, thesis_ref=ref, columns=cols,
                 rows=rows, note=note)


def tables(results: dict) -> list[Table]:
    """Both tables of the Puppy II's paw contact."""
    return [terrain_table(results), gait_table(results)]
