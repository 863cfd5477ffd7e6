"""Numerical success criteria of §6.4 and the classification of a run's outcome.

The thesis looks for controllers that "run stably for 30 seconds, and ... return to its
gait after the motors have been powered off and are powered back on", and names three
undesired behaviours: the output dies out (a fixed point), the robot moves erratically
(a wrong limit cycle or none), or it cannot return to its gait after leaving it (a basin
of attraction too small). It gives no numbers; ours (config ``ch6.criteria``, fixed
before any result was looked at):

* **fallen**: the trunk centre lower than ``fall_height`` or its up axis tilted more
  than 60 degrees (z component < 0.5), or an unphysical simulation, at any time from
  the start of the first training stage to the end of the running stage;
* **amplitude**: on the last ``window`` seconds of running, the mean over the 8 hip
  and knee outputs of std(output) / std(teacher) must lie in
  [``amplitude_min``, ``amplitude_max``]: below, the output "dies out"; above, it is
  erratic;
* **periodic**: on the same window, the dominant frequency of the hip and knee outputs
  within ``frequency_tolerance`` (relative) of the teacher's (computed the same way) and
  the output's normalised autocorrelation at a lag of one teacher period at least
  ``autocorrelation_min``; else erratic;
* **recovered**: after power-on, on the recovery window (from ``recovery_within``
  seconds after power-on to the end of the recovery phase), the trunk upright and above
  ``fall_height`` throughout, the amplitude and periodicity criteria met and the trunk
  moving forward faster than ``min_speed``; else "no return".

Outcome of a run (first that applies): ``fallen``, ``dies_out``, ``erratic``,
``no_return``, ``stable``. Success = ``stable``.
"""

from __future__ import annotations

import numpy as np

from thesis.ch6 import protocol as PR

#: Outcomes of a run, in order of precedence (the last one is success).
OUTCOMES = ("fallen", "dies_out", "erratic", "no_return", "stable")
#: Trunk height [m] and speed [m/s] beyond which the simulation is unphysical (as ch3's
#: ``thesis.gaits.runner.exploded``).
EXPLODED_HEIGHT = 0.4
EXPLODED_SPEED = 10.0
#: Lowest frequency [Hz] searched for the dominant one (below it: drift, not a gait).
MIN_FREQUENCY = 0.3
#: Up-axis z component below which the trunk counts as tipped over (60 degrees).
MIN_UP = 0.5


def fallen(trunk_pos, trunk_up, fall_height: float, dt: float) -> bool:
    """True when the trunk ever drops below ``fall_height`` [m], tilts more than 60 deg,
    or moves unphysically (``trunk_pos`` (T, 3) [m], ``trunk_up`` (T,))."""
    z = trunk_pos[:, 2]
    v = np.linalg.norm(np.diff(trunk_pos, axis=0), axis=-1) / dt if len(z) > 1 else np.zeros(1)
    return bool((z < fall_height).any() or (trunk_up < MIN_UP).any()
                or (z > EXPLODED_HEIGHT).any() or (v > EXPLODED_SPEED).any())


def amplitude_ratio(output, teacher) -> float:
    """Mean over joints of std(output_j) / std(teacher_j); ``output``, ``teacher`` (T, J)."""
    ref = teacher.std(axis=0)
    return float(np.mean(output.std(axis=0) / np.maximum(ref, 1e-9)))


def dominant_frequency(signals, dt: float, min_frequency: float = MIN_FREQUENCY) -> float:
    """Frequency [Hz] of the largest peak of the summed power spectrum of ``signals``
    (T, J) sampled every ``dt`` [s], each with its mean removed; zero-padded to at least
    8 x T (and 4096) points so the peak is located finer than 1 / (T dt)."""
    x = signals - signals.mean(axis=0)
    n = int(2 ** np.ceil(np.log2(max(8 * len(x), 4096))))
    power = (np.abs(np.fft.rfft(x, n=n, axis=0)) ** 2).sum(axis=1)
    freq = np.fft.rfftfreq(n, dt)
    band = freq >= min_frequency
    if not band.any() or power[band].max() <= 0:
        return float("nan")
    return float(freq[band][np.argmax(power[band])])


def autocorrelation(signals, lag: int) -> float:
    """Normalised autocorrelation of ``signals`` (T, J) at ``lag`` steps, pooled over
    joints: (sum_j sum_t x_j(t) x_j(t + lag) / (T - lag)) / (sum_j sum_t x_j(t)^2 / T)
    with means removed, so a periodic signal scores about 1 at its period whatever the
    window's length (0 for a constant signal or a lag as long as the window)."""
    x = signals - signals.mean(axis=0)
    den = float((x * x).sum())
    if lag <= 0 or lag >= len(x) or den <= 0:
        return 0.0
    return float((x[:-lag] * x[lag:]).sum() / den * len(x) / (len(x) - lag))


def forward_speed(trunk_pos, dt: float) -> float:
    """Mean forward (x) speed [m/s] of the trunk over a window (T, 3)."""
    if len(trunk_pos) < 2:
        return float("nan")
    return float((trunk_pos[-1, 0] - trunk_pos[0, 0]) / ((len(trunk_pos) - 1) * dt))


def gait_metrics(output, teacher, trunk_pos, dt: float, period: float) -> dict:
    """Amplitude ratio, dominant frequencies (output, teacher) [Hz], autocorrelation at one
    teacher ``period`` [s] and forward speed [m/s] on one window (outputs (T, 8))."""
    return dict(amplitude=amplitude_ratio(output, teacher),
                frequency=dominant_frequency(output, dt),
                teacher_frequency=dominant_frequency(teacher, dt),
                autocorrelation=autocorrelation(output, int(round(period / dt))),
                speed=forward_speed(trunk_pos, dt))


def gait_ok(m: dict, crit: dict) -> tuple[bool, bool]:
    """(amplitude in range, periodic at the teacher's frequency) for :func:`gait_metrics`."""
    amp = crit["amplitude_min"] <= m["amplitude"] <= crit["amplitude_max"]
    f, ft = m["frequency"], m["teacher_frequency"]
    freq = bool(np.isfinite(f) and np.isfinite(ft)
                and abs(f - ft) <= crit["frequency_tolerance"] * ft)
    return bool(amp), bool(freq and m["autocorrelation"] >= crit["autocorrelation_min"])


def amplitude_by_period(output, teacher, period_steps: int) -> np.ndarray:
    """(K,) :func:`amplitude_ratio` over each of the K whole teacher periods of
    ``period_steps`` controller steps in ``output``, ``teacher`` (T, J): the learned
    gait's amplitude as it evolves."""
    n = max(1, int(period_steps))
    k = output.shape[0] // n
    return np.array([amplitude_ratio(output[i * n:(i + 1) * n], teacher[i * n:(i + 1) * n])
                     for i in range(k)])


def cycle_multiplier(amplitudes, floor: float = 1e-6) -> float:
    """Per-period growth factor of an amplitude series (K,): exp of the least-squares
    slope of log(amplitude) against the period index. The closed loop's oscillation
    grows (> 1), is sustained (~1) or decays towards a fixed point (< 1, the "dies out"
    of §6.4) by this factor per teacher period: the dominant multiplier of the loop's
    oscillation as the running stage shows it. Amplitudes below ``floor`` (numerically
    at rest) count as ``floor``; NaN with fewer than 2 periods."""
    a = np.maximum(np.asarray(amplitudes, float), floor)
    if a.size < 2 or not np.all(np.isfinite(a)):
        return float("nan")
    return float(np.exp(np.polyfit(np.arange(a.size), np.log(a), 1)[0]))


def evaluate(output, teacher, trunk_pos, trunk_up, schedule: PR.Schedule, dt: float,
             period: float, crit: dict) -> dict:
    """Metrics and outcome of one run.

    Args:
        output: (T, 8) hip and knee motor commands sent [rad] (the controller's output
            once the teacher's share is 0).
        teacher: (T, 8) the teacher's hip and knee commands at the same steps [rad].
        trunk_pos: (T, 3) [m]; trunk_up: (T,) z component of the trunk's up axis.
        schedule, dt: the run's protocol and controller period [s].
        period: the teacher's gait period [s].
        crit: ``ch6.criteria`` (see the module docstring).

    Returns:
        dict of floats: ``fallen``, ``amplitude``, ``frequency``, ``teacher_frequency``,
        ``autocorrelation``, ``speed`` (running window), the same with prefix ``rec_``
        (recovery window), ``rec_down`` (not upright in the recovery window),
        ``stable_running``, ``recovered``, ``success``; and ``outcome`` (str).
    """
    b = schedule.bounds()
    first = PR.n_steps(b["stage1"][0], dt)
    end_run = PR.n_steps(b["running"][1], dt)
    down = fallen(trunk_pos[first:end_run], trunk_up[first:end_run], crit["fall_height"], dt)
    run = PR.window(schedule, "running", dt, last=crit["window"])
    m = gait_metrics(output[run], teacher[run], trunk_pos[run], dt, period)
    amp_ok, per_ok = gait_ok(m, crit)
    rec = PR.window(schedule, "recovery", dt, skip=crit["recovery_within"])
    r = gait_metrics(output[rec], teacher[rec], trunk_pos[rec], dt, period)
    r_amp, r_per = gait_ok(r, crit)
    r_down = fallen(trunk_pos[rec], trunk_up[rec], crit["fall_height"], dt)
    recovered = (not r_down) and r_amp and r_per and r["speed"] > crit["min_speed"]
    if down:
        outcome = "fallen"
    elif m["amplitude"] < crit["amplitude_min"]:
        outcome = "dies_out"
    elif not (amp_ok and per_ok):
        outcome = "erratic"
    elif not recovered:
        outcome = "no_return"
    else:
        outcome = "stable"
    out = {k: float(v) for k, v in m.items()}
    out.update({f"rec_{k}": float(v) for k, v in r.items()})
    out.update(fallen=float(down), rec_down=float(r_down),
               stable_running=float(not down and amp_ok and per_ok),
               recovered=float(recovered), success=float(outcome == "stable"),
               outcome=outcome)
    return out
