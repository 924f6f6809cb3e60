"""What a sliding surface does (layer 0: imports nothing of the project):
the friction laws mu(T, p, v) (``friction.py``) and their evaluation, the
breakaway coefficient (static, grown by the time stuck) and Archard wear
(``friction_kernel.py``, a kernel module), the liner presets with the
source of every value. The devices' steppers (``mechanics``) and the
coupled loop take their coefficients from here."""
