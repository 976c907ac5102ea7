"""Probabilistic sweeps: sampling designs, failure statistics and their figures for `bbmc sweep`."""
