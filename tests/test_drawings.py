"""Each device's VTK drawing is data its stepper declares (outputs/device_drawings.py)."""
import pytest

from fpd.coupling.build import build
from fpd.outputs.device_drawings import DRAWINGS, PlanarDrawing, SpatialDrawing, TFPDrawing, drawing_of
from fpd.schema import scene as scn


@pytest.mark.parametrize("name, sets, kind, series, parts", [
    ("lab-sine", ["loading.cycles=0.1"], PlanarDrawing, "device", ("lower", "upper")),
    ("sfp-harmonic", ["loading.cycles=0.1"], PlanarDrawing, "device", ("lower", "upper")),
    ("impvall-bidirectional", ["solver.duration=0.1"], SpatialDrawing, "device3d", ("lower", "upper")),
    ("tfp-lab", ["loading.cycles=0.1"], TFPDrawing, "device",
     ("lower", "slider_lower", "slider_upper", "upper")),
])
def test_the_stepper_names_its_drawing(name, sets, kind, series, parts):
    sim = build(scn.load(name, sets + ["thermal.model=lumped"]))
    assert DRAWINGS[sim.mechanics.drawing] is kind
    d = drawing_of(sim)
    assert isinstance(d, kind) and d.series == series and tuple(d.parts) == parts
    assert len(d.parts) == sim.mechanics.n_interfaces == len(sim.plates)
    assert (d.place is None) == (kind is SpatialDrawing)      # no plate fields drawn in 3D


def test_the_flat_bearing_has_no_drawing():
    sim = build(scn.load("flat-lab", ["solver.duration=0.1"]))
    assert sim.mechanics.drawing is None
    with pytest.raises(ValueError, match="no VTK drawing"):
        drawing_of(sim)
