"""The devices' mechanics: geometry, each device's stepper and kernel, and
each device as the compiled engine sees it (dev_*.py). Imports nothing of
fpd but itself, loading/ (the records and programmes it is driven by) and
tribology/ (the friction coefficients; docs/architecture.md, "The layers")."""
