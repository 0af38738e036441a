# The single-step case of euler_attitude_test.cpp, section 3: python3 p0_reference.py p0_case.py
decl = 0.05
S = [((-2.99, -1.95, -9.13), (-6.65e-6, 6.44e-6, 4.38e-5), (0.1, -0.2, 0.3), 0.05),
     ((-2.71, -2.33, -9.13), (-8.15e-6, 1.17e-5, 4.24e-5), (-0.4, 0.25, 0.6), 0.1),
     ((-2.71, -2.33, -9.13), (-8.15e-6, 1.17e-5, 4.24e-5), (0.3, 0.5, 6.0), 0.1)]
for k,(f,m,w,dt) in enumerate(S): show("z%d"%(k+1), measure(f,m,decl))
ER=[[0.1,0.08,0.08],[0.08,0.1,0.08],[0.08,0.08,0.1]]; EQ=[[0.15,0.08,0.08],[0.08,0.15,0.1],[0.08,0.1,0.2]]
UR=[[0.2,0.02,0.02],[0.02,0.2,0.02],[0.02,0.02,0.15]]; UQ=[[0.1,0.07,0.07],[0.07,0.1,0.07],[0.07,0.07,0.2]]
P0=[[0.15,0,0],[0,0.15,0],[0,0,0.15]]
x=[0.0]*3; P=P0
for k,(f,m,w,dt) in enumerate(S):
    x,P=ekf_step(x,P,w,dt,measure(f,m,decl),ER,EQ); show("ekf_x%d"%(k+1),x); show("ekf_P%d"%(k+1),P)
x=[0.0]*3; P=[[0.15,0.02,-0.01],[0.02,0.12,0.03],[-0.01,0.03,0.2]]
for k,(f,m,w,dt) in enumerate(S):
    x,P=ukf_step(x,P,w,dt,measure(f,m,decl),UR,UQ,1.7); show("ukf_x%d"%(k+1),x); show("ukf_P%d"%(k+1),P)
x=[0.0]*3; b=[0.0]*3; d=[0.0]*3
for k,(f,m,w,dt) in enumerate(S):
    x,b,d=cf_step(x,b,d,w,dt,measure(f,m,decl),4.35*1.4142135623730951,0.415); show("cf_x%d"%(k+1),x); show("cf_b%d"%(k+1),b); show("cf_d%d"%(k+1),d)
