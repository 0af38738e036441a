#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Independent reference for QuatEskfStep.SingleStepMatchesHandComputation
# (tests/unit/estimator/quat_eskf_test.cpp): one initialise and one step of the 9-state ESKF
# (quat_eskf.hpp, E1..E14) written from the header's equations with numpy, sharing no code
# with the C++: its own quaternion and rotation-matrix code, Euler-angle levelling
# (Ry(θ) Rx(φ) m_b), the heading projector from the Euler form of the third row of R_nb
# (u = (−sin θ, sin φ cos θ, cos φ cos θ)), explicit cross products, and np.linalg.inv for S.
# Run: python3 tests/unit/estimator/reference/eskf_single_step.py   (python3 + numpy, e.g.
# Debian's /usr/bin/python3 with python3-numpy) and paste its output into the test's expected
# values. The parameters below must match the test's EskfParams.
import numpy as np

g0 = 9.80665


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1*w2 - x1*x2 - y1*y2 - z1*z2, w1*x2 + x1*w2 + y1*z2 - z1*y2,
                     w1*y2 - x1*z2 + y1*w2 + z1*x2, w1*z2 + x1*y2 - y1*x2 + z1*w2])


def qexp(v):
    a = np.linalg.norm(v)
    if a == 0:
        return np.array([1.0, 0, 0, 0])
    return np.concatenate([[np.cos(a/2)], np.sin(a/2) * v / a])


def rot(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1-2*(y*y+z*z), 2*(x*y-w*z), 2*(x*z+w*y)],
                     [2*(x*y+w*z), 1-2*(x*x+z*z), 2*(y*z-w*x)],
                     [2*(x*z-w*y), 2*(y*z+w*x), 1-2*(x*x+y*y)]])


def Rx(a): c, s = np.cos(a), np.sin(a); return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
def Ry(a): c, s = np.cos(a), np.sin(a); return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
def Rz(a): c, s = np.cos(a), np.sin(a); return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def cross_matrix(v):
    # columns are v × e_i
    return np.column_stack([np.cross(v, e) for e in np.eye(3)])


def q_from_euler(r, p, y):
    return qmul(qmul(np.array([np.cos(y/2), 0, 0, np.sin(y/2)]),
                     np.array([np.cos(p/2), 0, np.sin(p/2), 0])),
                np.array([np.cos(r/2), np.sin(r/2), 0, 0]))


def euler(R):
    return np.arctan2(R[2, 1], R[2, 2]), np.arcsin(-R[2, 0]), np.arctan2(R[1, 0], R[0, 0])


def jr(phi):
    a = np.linalg.norm(phi)
    S = cross_matrix(phi)
    return np.eye(3) - (1-np.cos(a))/a**2 * S + (a-np.sin(a))/a**3 * S @ S


# The test's EskfParams: known Earth field, hard iron estimated, both magnetometer gates off.
sg, sb, st, sy, sb0, bmax, sa = 5.0e-4, 2.0e-6, 0.05, 0.1, 0.005, 0.05, 0.2
sh0, shw, sm = 3.0e-6, 1.0e-9, 1.0e-6
deg = np.pi / 180
m_n = np.array([2e-5, 0.0, 4e-5])
h_true = np.array([2e-6, -1.5e-6, 1e-6])
R_true0 = Rz(40*deg) @ Ry(-5*deg) @ Rx(10*deg)
f0 = R_true0.T @ np.array([0, 0, -g0])
m0 = R_true0.T @ m_n + h_true
# initialise: P0 eqs 1-3; the declination is that of m_n (0 here)
roll = np.arctan2(-f0[1], -f0[2])
pitch = np.arctan2(f0[0], np.hypot(f0[1], f0[2]))
ml = Ry(pitch) @ Rx(roll) @ m0
yaw = np.arctan2(-ml[1], ml[0]) + np.arctan2(m_n[1], m_n[0])
q = q_from_euler(roll, pitch, yaw)
b = np.zeros(3)
h = np.zeros(3)
R = rot(q)
P = np.zeros((9, 9))
P[:3, :3] = R.T @ np.diag([st**2, st**2, sy**2]) @ R
P[3:6, 3:6] = sb0**2 * np.eye(3)
P[6:, 6:] = sh0**2 * np.eye(3)
# step inputs: the vehicle really turned by Exp((0.01,-0.02,0.03)) from the initial attitude
omega_m = np.array([0.02, -0.01, 0.05])
dt = 0.05
R_meas = R_true0 @ rot(qexp(np.array([0.01, -0.02, 0.03])))
f1 = R_meas.T @ np.array([0, 0, -g0])
m1 = R_meas.T @ m_n + h_true
# predict E1-E5
w = omega_m - b
F = np.eye(9)
F[:3, :3] = rot(qexp(w*dt)).T
F[:3, 3:6] = -jr(w*dt) * dt
Q = np.diag([sg**2*dt]*3 + [sb**2*dt]*3 + [shw**2*dt]*3)
q = qmul(q, qexp(w*dt))
q /= np.linalg.norm(q)
P = F @ P @ F.T + Q


def update(q, b, h, P, y, H, Rm):
    S = H @ P @ H.T + Rm
    K = P @ H.T @ np.linalg.inv(S)
    dx = K @ y
    IKH = np.eye(9) - K @ H
    P = IKH @ P @ IKH.T + K @ Rm @ K.T
    q = qmul(q, qexp(dx[:3]))
    q /= np.linalg.norm(q)
    b = np.clip(b + dx[3:6], -bmax, bmax)
    h = h + dx[6:]
    G = np.eye(9)
    G[:3, :3] = np.eye(3) - 0.5 * cross_matrix(dx[:3])
    return q, b, h, G @ P @ G.T


# accel E6, E7 (no DVL)
R = rot(q)
h_a = R.T @ np.array([0, 0, -g0])
H = np.zeros((3, 9))
H[:, :3] = cross_matrix(h_a)
q, b, h, P = update(q, b, h, P, f1 - h_a, H, sa**2 * np.eye(3))
# mag E8-E12: the gate quantities of the corrected field, then the 3-D update
R = rot(q)
ph, th, ps = euler(R)
m_c = m1 - h
norm_ratio = np.linalg.norm(m_c) / np.linalg.norm(m_n)
inclination = np.arcsin((R @ m_c)[2] / np.linalg.norm(m_c))
u = np.array([-np.sin(th), np.sin(ph)*np.cos(th), np.cos(ph)*np.cos(th)])
m_pred = R.T @ m_n
H = np.zeros((3, 9))
H[:, :3] = cross_matrix(m_pred) @ np.outer(u, u)
H[:, 6:] = np.eye(3)
q, b, h, P = update(q, b, h, P, m1 - (m_pred + h), H, sm**2 * np.eye(3))
if q[0] < 0:
    q = -q
print("norm ratio:", f"{norm_ratio:.17g}", "inclination:", f"{inclination:.17g}")
print("q (w x y z):", ", ".join(f"{v:.17g}" for v in q))
print("b:", ", ".join(f"{v:.17g}" for v in b))
print("h:", ", ".join(f"{v:.17g}" for v in h))
print("P diag:", ", ".join(f"{v:.17g}" for v in np.diag(P)))
print("P(0,1):", f"{P[0,1]:.17g}", "P(2,5):", f"{P[2,5]:.17g}", "P(2,7):", f"{P[2,7]:.17g}",
      "P(6,8):", f"{P[6,8]:.17g}")
