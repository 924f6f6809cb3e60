import sys, math, time; sys.path.insert(0,'tests')
import numpy as np
from test_tfp3d import *
from test_tfp3d import _kernel
from tfp3d_reference import Reference
g = WIDE
A, f = 0.12, 0.2
w = 2*math.pi*f
prog, d, res = orbit(g, A, f=f, cycles=2.0, dt=float(sys.argv[1]) if len(sys.argv)>1 else 5e-3)
n1 = prog.n_steps//2
W = sum(d[f"W{i}_J"] for i in range(1,5))
print('stepper W rev2', W[-1]-W[n1], 'regimes', set(d['regime']), 'ledger', np.max(np.abs(res))/np.max(d['E_input_J']))
s0 = TFP3DStepper(g, prog)
y0 = s0.S[0:8].copy()
ref = Reference(g, MUS, lambda t: A*np.array([math.cos(w*t), math.sin(w*t)]), lambda t: A*w*np.array([-math.sin(w*t), math.cos(w*t)]),
                lambda t: -A*w*w*np.array([math.cos(w*t), math.sin(w*t)]))
t0=time.time()
sol = ref.run(y0, 10.0)
print('ode', sol.status, sol.message, time.time()-t0, 'nfev', sol.nfev)
Wr = sol.sol(10.0)[8] - sol.sol(5.0)[8]
print('ref W rev2', Wr, 'ratio', (W[-1]-W[n1])/Wr - 1)
