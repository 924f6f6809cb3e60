"""fpd compare, converge, stability, sweep (its store and cluster plumbing),
map, and the references runs are compared with (the TFP's closed-form
backbone and the series model's loop: tfp_backbone). May import outputs and
below."""
