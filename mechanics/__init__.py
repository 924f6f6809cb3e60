"""The devices' mechanics: geometry, friction laws, each device's stepper and
kernel, and each device as the compiled engine sees it (dev_*.py). Imports
nothing of fpd but itself and loading/ (the records and programmes it is
driven by; docs/architecture.md, "The layers")."""
