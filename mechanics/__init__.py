"""The devices' mechanics: geometry, loadings and record readers, friction laws,
each device's stepper and kernel, and each device as the compiled engine sees
it (dev_*.py). Imports nothing of fpd but itself (docs/architecture.md, "The
layers")."""
