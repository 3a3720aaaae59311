"""A 90-second soak (benchmarks/soak.py; longer runs from its command line): a presenter plays
while 20 browsers join and leave every 3 s, with three hostile ones (never reads, guesses codes,
sends foreign GUI updates); memory is compared between the first minute and the end."""

from __future__ import annotations

import pytest

from benchmarks.soak import run_soak

pytestmark = pytest.mark.slow

MAX_GROWTH_MIB = 10.0  # memory at the end against where it settled after the first minute
MIN_STEADY_FPS = 20.0  # a follower that stayed all along (~57 fps measured on 2 cores)


def test_ninety_seconds_of_browsers_coming_and_going_with_hostile_ones() -> None:
    result = run_soak(minutes=1.5, browsers=20, churn=3.0, hostile=True)
    print(result.summary())
    assert result.joins >= 35
    assert result.errors == []
    assert result.growth_mib <= MAX_GROWTH_MIB, result.rss_mib
    assert result.steady_fps >= MIN_STEADY_FPS
