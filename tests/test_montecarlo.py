"""Monte Carlo error of an interval end against a brute-force repetition of the draws."""

from __future__ import annotations

import numpy as np
import pytest

from thermocal.montecarlo import interval_end_error, quantile_standard_error


@pytest.mark.parametrize("draws", [30, 200, 2000])
def test_interval_end_error_matches_the_spread_over_repeated_draws(draws):
    """Draw ``draws`` values from a skewed distribution 2,000 times: the standard deviation
    of the 5 % and 95 % quantiles over the repetitions is what the formula gives from one
    set of draws (on average, within 25 %)."""
    rng = np.random.default_rng(draws)
    repeats = rng.lognormal(0.0, 0.5, size=(2000, draws))
    lows, highs = np.quantile(repeats, [0.05, 0.95], axis=1)
    brute = max(lows.std(), highs.std())
    formula = np.mean([interval_end_error(row, 0.9) for row in repeats[:300]])
    assert formula == pytest.approx(brute, rel=0.25), (formula, brute)


def test_quantile_standard_error_shrinks_with_the_effective_draws():
    values = np.random.default_rng(0).normal(size=(4000, 2))
    wide = quantile_standard_error(values, 0.05, 100)
    narrow = quantile_standard_error(values, 0.05, 4000)
    assert np.all(narrow < wide) and np.all(narrow > 0)
    assert interval_end_error([1.0], 0.9) == 0.0
