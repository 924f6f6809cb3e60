"""fpd compare, converge, stability, sweep (its store and cluster plumbing) and
map. May import outputs and below."""
