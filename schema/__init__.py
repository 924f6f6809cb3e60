"""Scenes: TOML loading, defaults, validation (one line per error: SceneError),
--set overrides. May import fpd.mechanics and fpd.thermal."""
