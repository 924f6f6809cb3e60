"""Small builders shared by the tests."""
from __future__ import annotations

import numpy as np

from fpd.mechanics.geometry import G_ACC, DeviceGeometry
from fpd.loading.ground_motion import GroundMotion, ground_motion_from_samples, read_record
from fpd.schema.scene import SCENES_DIR


def dfp(pad_mass=30.0, mass=1.0e5, R1=2.2, R2=2.2, h=0.10, D=0.25, kind="DFP") -> DeviceGeometry:
    return DeviceGeometry(kind, R1, R2, h, D, pad_mass, mass)


def at_rest(dt: float, duration: float) -> GroundMotion:
    n = int(round(duration / dt))
    z = np.zeros(n + 1)
    return GroundMotion("rest", dt, np.arange(n + 1) * dt, z, z.copy(), z.copy(), np.zeros(n))


def elcentro(dt: float, scale: float = 1.0, duration=None) -> GroundMotion:
    rec = read_record(SCENES_DIR / "records" / "IELC180.AT2")
    return ground_motion_from_samples("elcentro", rec.t, rec.a_g * G_ACC * scale, dt, duration)


def run(stepper, mu1, mu2, record=("theta",)):
    out = {k: np.empty(stepper.n_steps + 1) for k in record}
    for k in record:
        out[k][0] = getattr(stepper, k)
    for n in range(1, stepper.n_steps + 1):
        stepper.step(mu1, mu2)
        for k in record:
            out[k][n] = getattr(stepper, k)
    return out


def refusal(scene, overrides=()) -> str:
    """The message of the SceneError that loading the scene (a packaged name,
    a path or a dict, as fpd.schema.scene.load takes it) with the overrides
    raises, checked to be one line."""
    import pytest
    from fpd.schema.scene import SceneError, load
    with pytest.raises(SceneError) as e:
        load(scene, list(overrides))
    msg = str(e.value)
    assert "\n" not in msg, msg
    return msg
