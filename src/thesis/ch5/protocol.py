"""Selection, cross-validation and scoring protocol of chapter 5 (§5.3.1-5.3.2).

The thesis: "We normalize each sensor signal to a zero mean and a unit variance. Then we
select a total of 3000 samples for each terrain type and do this five times. Three of
these are used for threefold cross-validation while optimizing the parameters, the other
two are used for twofold cross-validation during the verification of the parameters. Any
remaining relevant trials are added to the test set during verification. We split all
trials into parts as a final step, with lengths varying from 281 to 562 samples. Most of
these are about 375 samples long (7.5s)."

Decisions where the text is open (each a declared choice, thesis.departures.ch5):

* **Normalisation** over every trial the experiment uses, before selection (as stated;
  the test trials' statistics enter the scaling, a mild leak the thesis has too).
* **Selections**: drawn by :mod:`thesis.ch5.selections` (whole trials per selection,
  the primary protocol, or its variants). :func:`make_selections` here is the previous
  protocol, kept as the ``"blocks"`` variant: per terrain the trials are shuffled
  (seeded) and laid end to end and the five selections are five consecutive blocks of
  ``samples`` time steps, so a trial can be cut across two selections (and then feeds
  both sides of a fold). Trials no block touched are the "remaining relevant trials"; the
  untouched rest of a trial that a block cut is dropped.
* **Folds**: tuning uses selections 0-2, threefold (train on two, validate on the
  third); verification uses selections 3 and 4, twofold (train on one, test on the
  other plus the remaining trials). TRAIN is the accuracy on the verification training
  selection, TEST on its test set, each averaged over the two folds.
* **Parts**: every segment of L samples is cut into ``max(1, round(L / part_target))``
  near-equal parts (with part_target 375 this gives lengths in [281, 562) for L >= 281,
  the thesis's range); a part is an independent sequence (reservoir state reset).
* **Score** (§5.3.2): the percentage of valid time steps classified correctly, pooled
  over every part of the set.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Segment", "Parts", "Split", "normalise", "split_lengths", "make_selections",
           "tuning_folds", "verification_folds", "to_parts", "valid_mask", "flat",
           "accuracy", "confusion"]


@dataclass(frozen=True)
class Segment:
    """Samples ``[start, stop)`` of trial ``trial``."""

    trial: int
    start: int
    stop: int

    @property
    def length(self) -> int:
        return self.stop - self.start


@dataclass(frozen=True)
class Parts:
    """Padded independent sequences.

    Attributes:
        x: (P, T, D) signals, zero after each part's length.
        length: (P,) valid steps; label: (P,) terrain index; trial: (P,) source trial.
    """

    x: np.ndarray
    length: np.ndarray
    label: np.ndarray
    trial: np.ndarray

    @property
    def n_samples(self) -> int:
        return int(self.length.sum())

    def labels(self) -> np.ndarray:
        """(n_samples,) label of every valid time step, in :func:`flat` order."""
        return np.repeat(self.label, self.length)

    def take(self, idx) -> "Parts":
        """The parts ``idx`` (indices or boolean mask)."""
        return Parts(self.x[idx], self.length[idx], self.label[idx], self.trial[idx])


@dataclass(frozen=True)
class Split:
    """One fold: training segments and evaluation segments."""

    train: tuple[Segment, ...]
    test: tuple[Segment, ...]


def normalise(signals: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Zero-mean unit-variance signals (§5.3.1). Returns (normalised, mean, std); a
    constant signal keeps std 1 (it stays 0 after centring)."""
    s = np.asarray(signals, np.float64)
    mean = s.mean(axis=0)
    std = s.std(axis=0)
    std = np.where(std > 0, std, 1.0)
    return (s - mean) / std, mean, std


def split_lengths(length: int, target: int) -> np.ndarray:
    """Lengths of the near-equal parts a segment of ``length`` samples is cut into."""
    n = max(1, int(round(length / float(target))))
    return np.array([len(a) for a in np.array_split(np.arange(length), n)], int)


def make_selections(lengths: np.ndarray, terrain: np.ndarray, trials: np.ndarray,
                    rng: np.random.Generator, n_selections: int, samples: int,
                    terrain_names=None) -> tuple[list[list[Segment]], list[int]]:
    """The five selections of §5.3.1 as consecutive blocks (the previous protocol, see
    module docstring; :func:`thesis.ch5.selections.select` ``"blocks"``).

    Args:
        lengths, terrain: (n_trials,) per trial of the recordings.
        trials: indices of the trials the experiment uses.
        rng: the seed's generator (which trials go where).
        n_selections, samples: number of selections and time steps per terrain in each.
    Returns:
        (selections, remaining): ``selections[k]`` the segments of selection k (every
        terrain), ``remaining`` the trials no selection touched.
    Raises:
        ValueError: a terrain has fewer than ``n_selections * samples`` samples.
    """
    selections: list[list[Segment]] = [[] for _ in range(n_selections)]
    remaining: list[int] = []
    trials = np.asarray(trials, int)
    need = n_selections * samples
    for r in np.unique(terrain[trials]):
        mine = trials[terrain[trials] == r]
        mine = mine[rng.permutation(len(mine))]
        total = int(lengths[mine].sum())
        if total < need:
            name = terrain_names[r] if terrain_names is not None else r
            raise ValueError(f"terrain {name}: {total} samples in {len(mine)} trials, "
                             f"{n_selections} selections of {samples} need {need}")
        pos = 0  # position along the concatenation
        for tr in mine:
            L = int(lengths[tr])
            a = 0
            touched = False
            while a < L and pos < need:
                k = pos // samples
                take = min(L - a, (k + 1) * samples - pos)
                selections[k].append(Segment(int(tr), a, a + take))
                a += take
                pos += take
                touched = True
            if not touched:
                remaining.append(int(tr))
    return selections, sorted(remaining)


def tuning_folds(selections) -> list[Split]:
    """Threefold cross-validation over selections 0, 1, 2 (train on two, validate on one)."""
    out = []
    for v in range(3):
        train = tuple(s for k in range(3) if k != v for s in selections[k])
        out.append(Split(train=train, test=tuple(selections[v])))
    return out


def verification_folds(selections, remaining, lengths) -> list[Split]:
    """Twofold verification on selections 3 and 4; the test set adds every remaining trial."""
    rest = tuple(Segment(int(t), 0, int(lengths[t])) for t in remaining)
    return [Split(train=tuple(selections[a]), test=tuple(selections[b]) + rest)
            for a, b in ((3, 4), (4, 3))]


def to_parts(signals: np.ndarray, offset: np.ndarray, terrain: np.ndarray, segments,
             columns, part_target: int) -> Parts:
    """Cut ``segments`` into parts (see :func:`split_lengths`) of the signal ``columns``.

    Args:
        signals: (n_samples, n_signals) all trials end to end; offset: (n_trials,) start of
            each trial in ``signals``; terrain: (n_trials,) labels.
    """
    columns = np.asarray(columns, int)
    pieces, labels, trials = [], [], []
    for seg in segments:
        a = int(offset[seg.trial]) + seg.start
        for n in split_lengths(seg.length, part_target):
            pieces.append(signals[a:a + n, columns])
            labels.append(int(terrain[seg.trial]))
            trials.append(seg.trial)
            a += n
    lengths = np.array([len(p) for p in pieces], int)
    x = np.zeros((len(pieces), int(lengths.max()) if len(pieces) else 0, len(columns)))
    for i, p in enumerate(pieces):
        x[i, :len(p)] = p
    return Parts(x=x, length=lengths, label=np.array(labels, int), trial=np.array(trials, int))


def valid_mask(lengths: np.ndarray, t_max: int) -> np.ndarray:
    """(P, t_max) True where a step lies inside its part."""
    return np.arange(t_max)[None, :] < np.asarray(lengths)[:, None]


def flat(x: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """(sum(lengths), ...) the valid steps of padded ``x`` (P, T, ...), part by part."""
    return np.asarray(x)[valid_mask(lengths, x.shape[1])]


def accuracy(predicted: np.ndarray, labels: np.ndarray) -> float:
    """Percentage of time steps classified correctly (§5.3.2)."""
    predicted, labels = np.asarray(predicted), np.asarray(labels)
    if labels.size == 0:
        return float("nan")
    return 100.0 * float(np.mean(predicted == labels))


def confusion(predicted: np.ndarray, labels: np.ndarray, n_classes: int) -> np.ndarray:
    """(true, predicted) counts of time steps."""
    out = np.zeros((n_classes, n_classes), np.int64)
    np.add.at(out, (np.asarray(labels, int), np.asarray(predicted, int)), 1)
    return out
