"""Chapter 6 (embodied gait on the Oncilla): the minimal controller sizes and times of §6.4-6.5.

H is the number of hidden (ELM) neurons, B the length of the delay buffer in controller
time steps, N = (B + 1) H + 1 the number of signals the RLS readout receives. Artifacts
(``thesis.ch6.experiments``) are named after the §6.5 experiments:
``trot`` (H = 50, B = 5), ``walk`` (H = 50, B = 12, 30 s stages), ``minimal_buffer``
(H = 12 needs B >= 16), ``minimal_hidden`` (B = 0 needs H = 128 +- 32) and
``minimal_training`` (H = 250, B = 0: 1.18 s per stage). Entries ``sec6.2/*`` and
``sec6.4/*`` are the setup of §6.2 and §6.4 that the departures refer to.
"""

from __future__ import annotations

from thesis.paper.types import PaperValue, entry

_TROT = ("To evaluate our approach, we optimized a controller with H = 50 hidden nodes and a "
         "time window B of 5 time steps (44 ms or 7.5 % of the gait period).")
_WALK = ("For this situation, we again used H = 50 hidden nodes, but we had to increase the time "
         "window B to 12 time steps (103 ms or 17.5 % of the gait period).")
_MINB = ("We found that with 12 hidden neurons, we needed B to be at least 16 time steps (115 ms "
         "or 20% of the gait period) for a stable gait.")
_MINH = "We found that without a time window, we need at least $H = 128 \\pm 32$ hidden neurons."
_MINT = ("For this, we used a controller without a buffer and with H = 250 hidden neurons. We "
         "found that 1.18 s, or two gait periods are enough for both the first and second "
         "training stage, or 2.36 s in total.")


def _e(table: str, artifact: str, variable: str, value: float, unit: str, source: str,
       pos: int, row: str, note: str = "") -> PaperValue:
    return entry(table=table, artifact=artifact, variable=variable, value=value, unit=unit,
                 source=source, pos=pos, row=row, note=note)


ENTRIES: tuple[PaperValue, ...] = (
    _e("§6.5", "trot", "hidden_neurons", 50.0, "1", _TROT, 0, "trot, stable controller"),
    _e("§6.5", "trot", "buffer_steps", 5.0, "1", _TROT, 1, "trot, stable controller"),
    _e("§6.5", "trot", "buffer_ms", 44.0, "ms", _TROT, 2, "trot, stable controller"),
    _e("§6.5", "trot", "buffer_fraction_of_period", 7.5, "percent", _TROT, 3,
       "trot, stable controller"),
    _e("§6.5", "walk", "hidden_neurons", 50.0, "1", _WALK, 0, "walk, stable controller"),
    _e("§6.5", "walk", "buffer_steps", 12.0, "1", _WALK, 1, "walk, stable controller"),
    _e("§6.5", "walk", "buffer_ms", 103.0, "ms", _WALK, 2, "walk, stable controller"),
    _e("§6.5", "walk", "buffer_fraction_of_period", 17.5, "percent", _WALK, 3,
       "walk, stable controller"),
    _e("§6.5", "walk", "stage_seconds", 30.0, "s",
       "We also needed to increase the length of the first and second training stage to 30 s.",
       0, "walk, first and second training stage each"),
    _e("§6.5", "minimal_buffer", "hidden_neurons", 12.0, "1", _MINB, 0, "H fixed at 12"),
    _e("§6.5", "minimal_buffer", "min_buffer_steps", 16.0, "1", _MINB, 1,
       "minimal B for a stable trot with H = 12", note="'at least': a lower bound found"),
    _e("§6.5", "minimal_buffer", "buffer_ms", 115.0, "ms", _MINB, 2, "H = 12, B = 16"),
    _e("§6.5", "minimal_buffer", "buffer_fraction_of_period", 20.0, "percent", _MINB, 3,
       "H = 12, B = 16"),
    _e("§6.5", "minimal_hidden", "min_hidden_neurons", 128.0, "1", _MINH, 0,
       "minimal H for a stable trot with B = 0", note="printed as 128 +- 32"),
    _e("§6.5", "minimal_hidden", "min_hidden_neurons_uncertainty", 32.0, "1", _MINH, 1,
       "uncertainty of the minimal H with B = 0"),
    _e("§6.5", "minimal_training", "hidden_neurons", 250.0, "1", _MINT, 0, "B = 0, H = 250"),
    _e("§6.5", "minimal_training", "stage_seconds", 1.18, "s", _MINT, 1,
       "each of the two training stages", note="two gait periods"),
    _e("§6.5", "minimal_training", "total_training_seconds", 2.36, "s", _MINT, 2,
       "both training stages together"),
    _e("§6.2", "sec6.2", "controller_dt", 8.2, "ms",
       "The time between consecutive updates of the sensor readings and motor actuations is on "
       "average $\\Delta t \\approx 8.2 \\,\\mathrm{ms}$.", 0, "controller time step (mean)"),
    _e("§6.4", "sec6.4", "target_gait_frequency", 1.7, "Hz",
       "We have the robot trot at a frequency of 1.7 Hz, corresponding to a speed of about "
       "0.76 m/s.", 0, "teacher trot"),
    _e("§6.4", "sec6.4", "target_gait_speed", 0.76, "m/s",
       "We have the robot trot at a frequency of 1.7 Hz, corresponding to a speed of about "
       "0.76 m/s.", 1, "teacher trot"),
    _e("§6.2", "sec6.2", "controller_dt_variation", 15.0, "percent",
       "However, this period can vary as much as 15% depending on the computational "
       "complexity of the controller.", 0, "variation of the controller time step"),
    _e("§6.2", "sec6.2", "encoders", 8.0, "1",
       "In this paper, we only use the 8 rotary encoders on the hip and knee joints of the "
       "robot.", 0, "controller inputs"),
    _e("§6.4", "sec6.4", "normalisation_seconds", 5.0, "s",
       "This stage takes 5 s.", 0, "normalisation phase"),
    _e("§6.4", "sec6.4", "stage_seconds", 10.0, "s",
       "This stage takes 10 s, unless noted differently.", 0,
       "first and second training stage each"),
    _e("§6.4", "sec6.4", "input_noise", 0.01, "1",
       "After normalization, we add Gaussian noise with an amplitude of 0.01 to each input "
       "signal for regularization during training.", 0, "training input noise"),
    _e("§6.4", "sec6.4", "stable_run_seconds", 30.0, "s",
       "In this paper, we therefore look for the minimal values of the parameters in our "
       "control system that allow our robot to run stably for 30 seconds", 0,
       "stability criterion (plus recovery after motors off/on)"),
)
