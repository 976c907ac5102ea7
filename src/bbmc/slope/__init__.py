"""The jointed limestone slope of the paper's section 5: geometry, runs, measures, figures."""
