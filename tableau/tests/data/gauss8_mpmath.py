# Provenance of gauss8_100digits.txt: Gauss–Legendre s = 8 on [0, 1] computed
# independently of tableau with mpmath (arbitrary precision floating point at
# 130 digits): nodes by mpmath.polyroots of the shifted Legendre polynomial
# (coefficients from mpmath.legendre's recurrence via mpmath.taylor), weights
# and A by solving the Vandermonde systems B(s) and C(s) (Σ_j b_j c_j^(k−1)
# = 1/k, Σ_j a_ij c_j^(k−1) = c_i^k/k) with mpmath.lu_solve; printed to 100
# significant digits. Run: python3 gauss8_mpmath.py > gauss8_100digits.txt
import mpmath as mp
mp.mp.dps = 130
s = 8
# shifted Legendre P_s(2x-1) coefficients, highest first
coeffs = mp.taylor(lambda x: mp.legendre(s, 2 * x - 1), 0, s)[::-1]
roots = sorted(mp.re(r) for r in mp.polyroots(coeffs, maxsteps=500, extraprec=400))
c = roots
V = mp.matrix(s, s)
for k in range(s):
    for j in range(s):
        V[k, j] = c[j] ** k
b = mp.lu_solve(V, mp.matrix([mp.mpf(1) / (k + 1) for k in range(s)]))
A = []
for i in range(s):
    row = mp.lu_solve(V, mp.matrix([c[i] ** (k + 1) / (k + 1) for k in range(s)]))
    A.append([row[j] for j in range(s)])
out = lambda x: mp.nstr(x, 100, strip_zeros=False, min_fixed=-mp.inf, max_fixed=mp.inf)
for i in range(s):
    print("c", i, out(c[i]))
for i in range(s):
    print("b", i, out(b[i]))
for i in range(s):
    for j in range(s):
        print("a", i, j, out(A[i][j]))
