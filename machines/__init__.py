"""The bearing-test machines of the DFP and the SFP: the planar machine (a
seated pendulum driven by a displacement programme, through a compliant
link if asked, under an axial-load programme; seated.py, seated_kernel.py)
and the orbit machine (orbit.py, stepped by the kernel of the stepper in
both directions), each as the compiled engine sees it (dev_*.py). The TFP
and the flat bearing carry a machine mode in their own kernels
(mechanics/). Imports loading/, tribology/ and mechanics/."""
