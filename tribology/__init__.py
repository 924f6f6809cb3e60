"""What a sliding surface and its rim do (layer 0: imports nothing of the
project): the friction laws mu(T, p, v) (``friction.py``) and their
evaluation, the breakaway coefficient (static, grown by the time stuck)
and Archard wear (``friction_kernel.py``, a kernel module), the liner
presets with the source of every value, and the contact of a slider with
its plate's restraining rim (``rim_law.py``, a kernel module: the rim of
finite stiffness and its dashpot, the rigid rim's impact law). The
devices' steppers (``mechanics``) and the coupled loop take their
coefficients and laws from here."""
