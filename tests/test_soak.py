"""A one-minute soak (benchmarks/soak.py; the hour-long runs from its command line): a presenter
plays while 20 browsers join and leave every 3 s, with three hostile ones (never reads, guesses
codes, sends foreign GUI updates); memory is compared between the first half minute (SETTLE_S)
and the end.  A property, not a capacity: the hour's growth is measured by the benchmark."""

from __future__ import annotations

import pytest

from benchmarks.soak import run_soak

pytestmark = pytest.mark.slow

MAX_GROWTH_MIB = 10.0  # memory at the end against where it settled (SETTLE_S)
SETTLE_S = 30.0  # [s] memory counts as settled this long after the start
MIN_STEADY_SHARE = 0.5  # a follower that stayed all along: its frames a second over the presenter's


def test_a_minute_of_browsers_coming_and_going_with_hostile_ones() -> None:
    result = run_soak(minutes=1.0, browsers=20, churn=3.0, hostile=True, settle_s=SETTLE_S, min_joins=40)
    print(result.summary())
    assert result.joins >= 40
    assert result.errors == []
    assert result.growth_mib <= MAX_GROWTH_MIB, result.rss_mib
    assert result.steady_fps >= MIN_STEADY_SHARE * result.presenter_fps > 0, result.summary()
