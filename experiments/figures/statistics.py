"""The statistics of a comparison over runs: the mean with a bootstrap interval, and the
interquartile mean with a stratified-bootstrap interval, as rliable reports it (Agarwal et al.,
"Deep RL at the edge of the statistical precipice", 2021). Written here, not imported from
rliable: its release (1.2.0) needs ``arch < 8``, which does not import beside pandas 3."""

from __future__ import annotations

import numpy as np

BOOTSTRAP_RESAMPLES, CONFIDENCE = 10_000, 0.95


def iqm(values: np.ndarray) -> float:
    """The interquartile mean: the mean of the runs left when a quarter (rounded down) is cut
    from each end, as ``scipy.stats.trim_mean(values, 0.25)`` and rliable's
    ``aggregate_iqm`` compute it (all runs for fewer than four)."""
    ordered = np.sort(values.ravel())
    cut = int(0.25 * ordered.size)
    return float(ordered[cut:ordered.size - cut].mean())


def iqm_interval(values: np.ndarray) -> tuple[float, float, float] | None:
    """(IQM, and the bounds of its 95% stratified-bootstrap percentile interval), or None:
    runs resampled with replacement within each task (a comparison holds one setting, so one
    stratum: the runs), 10,000 times, seeded, as rliable's ``get_interval_estimates`` does."""
    if not values.size:
        return None
    rng = np.random.default_rng(0)
    samples = np.sort(rng.choice(values, (BOOTSTRAP_RESAMPLES, values.size)), axis=1)
    cut = int(0.25 * values.size)
    estimates = samples[:, cut:values.size - cut].mean(axis=1)
    tail = 100 * (1 - CONFIDENCE) / 2
    low, high = np.percentile(estimates, [tail, 100 - tail])
    return iqm(values), float(low), float(high)


def mean_std(values: np.ndarray) -> tuple[float, float, float, float] | None:
    """(mean, std, and the bounds of a 95% percentile-bootstrap interval of the mean over
    runs), or None. The bootstrap resamples the runs (seeded, so a report is reproducible);
    with the 3-5 seeds these comparisons have it is narrow-tailed and optimistic, which is
    why the std is kept beside it; one run gives a zero-width interval."""
    if not values.size:
        return None
    rng = np.random.default_rng(0)
    means = rng.choice(values, (BOOTSTRAP_RESAMPLES, values.size)).mean(axis=1)
    tail = 100 * (1 - CONFIDENCE) / 2
    low, high = np.percentile(means, [tail, 100 - tail])
    return float(values.mean()), float(values.std()), float(low), float(high)
