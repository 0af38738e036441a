# Independent reference for euler_attitude_test.cpp: plain Python floats, no numpy, no Eigen.
import math, cmath
PI = math.pi
def wrap(a):
    a = math.remainder(a, 2*PI)
    return a + 2*PI if a <= -PI else a
def mm(A, B): return [[sum(A[i][k]*B[k][j] for k in range(len(B))) for j in range(len(B[0]))] for i in range(len(A))]
def T(A): return [list(r) for r in zip(*A)]
def madd(A, B, s=1.0): return [[A[i][j] + s*B[i][j] for j in range(len(A[0]))] for i in range(len(A))]
def mv(A, v): return [sum(A[i][k]*v[k] for k in range(len(v))) for i in range(len(A))]
def inv3(M):
    a,b,c = M[0]; d,e,f = M[1]; g,h,i = M[2]
    det = a*(e*i-f*h) - b*(d*i-f*g) + c*(d*h-e*g)
    adj = [[e*i-f*h, c*h-b*i, b*f-c*e], [f*g-d*i, a*i-c*g, c*d-a*f], [d*h-e*g, b*g-a*h, a*e-b*d]]
    return [[adj[r][s]/det for s in range(3)] for r in range(3)]
def I3(): return [[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]
def Rx(a): c, s = math.cos(a), math.sin(a); return [[1,0,0],[0,c,-s],[0,s,c]]
def Ry(a): c, s = math.cos(a), math.sin(a); return [[c,0,s],[0,1,0],[-s,0,c]]
def Rz(a): c, s = math.cos(a), math.sin(a); return [[c,-s,0],[s,c,0],[0,0,1]]

def measure(f, m, decl):
    phi = math.atan2(-f[1], -f[2])                                   # (1)
    theta = math.atan2(f[0], math.sqrt(f[1]**2 + f[2]**2))           # (2)
    ml = mv(mm(Ry(theta), Rx(phi)), m)                               # (3)
    psi = math.atan2(-ml[1], ml[0]) + decl                           # (4), psi0 = -decl
    return [wrap(phi), theta, wrap(psi)]

def rates(x, w):  # works on complex x (complex-step differentiation)
    p, q, r = w
    ph, th = x[0], x[1]
    return [p + q*cmath.sin(ph)*cmath.tan(th) + r*cmath.cos(ph)*cmath.tan(th),
            q*cmath.cos(ph) - r*cmath.sin(ph),
            (q*cmath.sin(ph) + r*cmath.cos(ph))/cmath.cos(th)]
def predict(x, w, dt): return [(x[i] + rates(x, w)[i]*dt).real for i in range(3)]
def predict_jac(x, w, dt):  # complex step: exact to round-off, no hand derivative
    h = 1e-30
    J = [[0.0]*3 for _ in range(3)]
    for j in range(3):
        xc = [complex(v) for v in x]; xc[j] += 1j*h
        fx = [xc[i] + rates(xc, w)[i]*dt for i in range(3)]
        for i in range(3): J[i][j] = fx[i].imag/h
    return J
def normalise(x):
    ph, th, ps = x[0], wrap(x[1]), x[2]
    flip = False
    if th > PI/2: th, flip = PI - th, True
    elif th < -PI/2: th, flip = -PI - th, True
    if flip: ph += PI; ps += PI
    return [wrap(ph), th, wrap(ps)], flip

def ekf_step(x, P, w, dt, z, Rp, Qm):
    xp = predict(x, w, dt)
    A = predict_jac(x, w, dt)
    Pp = madd(mm(mm(A, P), T(A)), Rp)
    S = madd(Pp, Qm)
    K = mm(Pp, inv3(S))
    y = [wrap(z[i] - xp[i]) for i in range(3)]
    xn = [xp[i] + mv(K, y)[i] for i in range(3)]
    Pn = madd(Pp, mm(K, Pp), -1.0)        # paper's P = P- - K H P-
    xn, flip = normalise(xn)
    assert not flip
    return xn, Pn

def chol(M):
    L = [[0.0]*3 for _ in range(3)]
    for i in range(3):
        for j in range(i+1):
            s = M[i][j] - sum(L[i][k]*L[j][k] for k in range(j))
            L[i][j] = math.sqrt(s) if i == j else s/L[j][j]
    return L
def ukf_step(x, P, w, dt, z, Rp, Qm, kappa):
    n = 3
    W = [kappa/(n+kappa)] + [1.0/(2*(n+kappa))]*(2*n)
    L = chol([[(n+kappa)*P[i][j] for j in range(3)] for i in range(3)])
    X = [list(x)] + [[x[i] + L[i][j] for i in range(3)] for j in range(3)] \
                  + [[x[i] - L[i][j] for i in range(3)] for j in range(3)]
    Y = [predict(Xi, w, dt) for Xi in X]
    off = [[wrap(Yi[i] - Y[0][i]) for i in range(3)] for Yi in Y]
    moff = [sum(W[k]*off[k][i] for k in range(7)) for i in range(3)]
    xm = [wrap(Y[0][i] + moff[i]) for i in range(3)]
    dev = [[off[k][i] - moff[i] for i in range(3)] for k in range(7)]
    C = [[sum(W[k]*dev[k][i]*dev[k][j] for k in range(7)) for j in range(3)] for i in range(3)]
    Pp = madd(C, Rp); Pz = madd(C, Qm); Pxz = C
    K = mm(Pxz, inv3(Pz))
    y = [wrap(z[i] - xm[i]) for i in range(3)]
    xn = [xm[i] + mv(K, y)[i] for i in range(3)]
    Pn = madd(Pp, mm(mm(K, Pz), T(K)), -1.0)
    xn, flip = normalise(xn)
    assert not flip
    return xn, Pn

def cf_step(x, b, d, w, dt, z, kp, ki):
    xd = [v.real for v in rates(x, w)]
    xn = [x[i] + (xd[i] - b[i])*dt for i in range(3)]
    dn = [wrap(xn[i] - z[i]) for i in range(3)]
    bn = [b[i] - kp*d[i] + (kp + ki*dt)*dn[i] for i in range(3)]
    xn, flip = normalise(xn)
    assert not flip
    return xn, bn, dn

def show(name, v):
    if isinstance(v[0], list):
        print(name, "= {", ", ".join(repr(e) for r in v for e in r), "}")
    else:
        print(name, "= {", ", ".join(repr(e) for e in v), "}")

if __name__ == "__main__":
    import sys
    exec(open(sys.argv[1]).read())
