"""The trend verdict (`bbmc.dem.verdict.Trend`) on a run at rest whose motion does not decay."""

from bbmc.dem.verdict import DECIDING_WINDOWS, RESTING_FRACTION, STABLE, Trend


def test_a_resting_run_that_does_not_decay_is_not_projected_to_fail():
    """Windows each moving 0.1 x the resting movement (r = 1, contact chatter): no decay projects an
    infinite remainder, which must not call it "projected" (issue 36's lift-off wedge, whose trials
    that had moved 2e-6 m of a 7 m failure displacement were, FS -5.3 %); it is at rest: stable."""
    failure = 7.0
    trend = Trend(failure, 1e-5)
    chatter = 0.1 * RESTING_FRACTION * failure
    verdicts = [trend.observe(chatter, 2e-6, 1e-3) for _ in range(DECIDING_WINDOWS + 1)]
    assert verdicts[-1] == (STABLE, "decaying")
    assert all(v is None for v in verdicts[:-1])
