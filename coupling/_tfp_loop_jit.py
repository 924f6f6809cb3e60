"""numba chunk of the TFP's compiled loop (coupling/tfp_fast.py drives it).

Imported only on the compiled path. Its callees are the compiled kernels:
mechanics/tfp_kernel.py through fpd.kernels.compiled (the same source as the
Python loop), thermal/_plate_jit.py's plate steps and
mechanics/_two_phase_jit.law_mu (the friction laws), as in coupling/_loop_jit.py.
"""
import numba
import numpy as np

from fpd import kernels
from fpd.mechanics._two_phase_jit import law_mu
from fpd.thermal._plate_jit import plate_lost, plate_step, plate_stored

OK, FULL, REPLAY, ROW_FAILED = 0, 1, 2, 3

tk = kernels.compiled("fpd.mechanics.tfp_kernel")
advance, row_values = tk.advance, tk.row_values
S_N, S_SV, S_DW, N_ROW = tk.S_N, tk.S_SV, tk.S_DW, tk.N_ROW
FAIL_CAPACITY = tk.FAIL_CAPACITY
I_R1, I_R2, I_R3, I_R4 = tk.I_R1, tk.I_R2, tk.I_R3, tk.I_R4


@numba.njit(cache=True, nogil=True, error_model="numpy")
def run(par, S, A, U, UD, XG, machine, dt, LW, areas, eta, kinds, PP, Ks, Ws, Is, Xs, T, mu, dd,
        buf, k, n0, n_end, every, N, heat, row, out, M, w, tmp, sc, S0):
    for n in range(n0 + 1, n_end + 1):
        for i in range(4):
            mu[i] = law_mu(LW[i], T[i], S[S_N + i] / areas[i], S[S_SV + i])
        for i in range(S.shape[0]):
            S0[i] = S[i]
        fail = advance(par, S, dt, A[n - 1], mu[0], mu[1], mu[2], mu[3], machine, U[n], UD[n],
                       out, M, w, tmp, sc)
        if fail != 0:                    # capacity, or the fixed point: Python replays and raises
            for i in range(S.shape[0]):
                S[i] = S0[i]
            return n - 1, k, REPLAY
        if heat:
            fp0 = par[I_R1] * S[0]
            fp1 = par[I_R2] * S[1]
            fp2 = -par[I_R3] * S[1]
            fp3 = -par[I_R4] * S[0]
            for i in range(4):
                if kinds[i] != 0:
                    fp = fp0 if i == 0 else (fp1 if i == 1 else (fp2 if i == 2 else fp3))
                    T[i] = plate_step(kinds[i], Ks[i], Ws[i], Is[i], Xs[i], PP[i], eta[i] * S[S_DW + i] / dt, fp)
        if n % every == 0 or n == N:
            row_values(par, S, n * dt, XG[n], dd[0], dd[1], dd[2], dd[3], row)
            for i in range(4):
                row[N_ROW + i] = mu[i]
            if heat:
                st = 0.0
                lo = 0.0
                for i in range(4):
                    row[N_ROW + 4 + i] = T[i]
                    st += plate_stored(kinds[i], Ks[i], Ws[i], Is[i], PP[i])
                    lo += plate_lost(kinds[i], PP[i])
                row[N_ROW + 8] = st
                row[N_ROW + 9] = lo
            tot = 0.0
            for j in range(row.shape[0]):
                tot += row[j]
            if not np.isfinite(tot):
                return n, k, ROW_FAILED
            for j in range(row.shape[0]):
                buf[k, j] = row[j]
            k += 1
            if k == buf.shape[0]:
                return n, k, FULL
    return n_end, k, OK
