#!/usr/bin/env python3
"""Independent reference for presets/takeup-lever.toml (seed 001).

Written from the seed's equations (3)-(23), numpy only, without using
stitchkin.  Writes reference.csv (one row per degree of the main-shaft angle
phi, 0..359) and prints a summary.  Run it from this directory:

    python3 generate_reference.py

Conventions (see README.md):
  * phi is the main-shaft angle of the preset, 0 = the needle's top dead
    centre equivalent (crank pin P2 straight up).  The seed's crank angle of
    eq. (3), measured counter-clockwise from +x, is phi1 = phi + 90 deg.
  * W = W_2_3_4 = -1 (assembly variant of the dyad 2-3-4, eqs. 7-8).
  * P(phi) = l_F(phi) - l_F(phi0) + dP  (eqs. 22-23), phi0 = 0, dP = 6 mm.
"""
import numpy as np

# ---- dimensions (mm, deg): the preset's nominal values -------------------
P1 = np.array([0.0, 0.0])          # main shaft (crank centre)
P4 = np.array([-5.0, 40.0])        # rocker pivot
l1_2, l2_3, l4_3 = 13.0, 37.0, 21.0
W = -1                             # W_2_3_4
l3_5, U2_3_5 = 20.0, 205.0         # coupler eyelet P5
l3_6, U4_3_6 = 8.0, 140.0          # rocker eyelet P6
l3_7, U4_3_7 = 10.0, 155.0         # rocker eyelet P7
l5_6, l5_7 = 5.0, 5.0              # z offsets of P6 (-) and P7 (+)
N1 = np.array([-22.0, -4.0, -10.0])  # fixed thread guide, tension side
N2 = np.array([-35.0, -4.0, 10.0])   # fixed thread guide, needle side
dP = 6.0                           # elongation allowance (eq. 23)
PHASE = 90.0                       # phi1 = phi + PHASE
PHI0 = 0.0                         # phi0 of eq. (22)


def positions(phi_deg):
    """Seed eqs. (3)-(18), literally; phi_deg is an array of preset angles."""
    phi1 = np.radians(np.asarray(phi_deg, float) + PHASE)
    # (3)
    P2x = P1[0] + l1_2*np.cos(phi1)
    P2y = P1[1] + l1_2*np.sin(phi1)
    # (4), (5)
    P4_2x = P2x - P4[0]
    P4_2y = P2y - P4[1]
    l4_2 = np.sqrt(P4_2x**2 + P4_2y**2)
    # (6): angle at P4 between P4->P2 and P4->P3
    U2_4_3 = np.arccos((l4_2**2 + l4_3**2 - l2_3**2)/(2*l4_2*l4_3))
    # (7), (8)
    a = W*U2_4_3
    P3x = P4[0] + l4_3/l4_2*(P4_2x*np.cos(a) - P4_2y*np.sin(a))
    P3y = P4[1] + l4_3/l4_2*(P4_2x*np.sin(a) + P4_2y*np.cos(a))
    # (9), (10)
    P4_3x, P4_3y = P3x - P4[0], P3y - P4[1]
    P2_3x, P2_3y = P3x - P2x, P3y - P2y
    # (11), (12)
    u = np.radians(U2_3_5)
    P5x = P3x + l3_5/l2_3*(-P2_3x*np.cos(u) + P2_3y*np.sin(u))
    P5y = P3y + l3_5/l2_3*(-P2_3x*np.sin(u) - P2_3y*np.cos(u))
    # (14)-(17)
    u6, u7 = np.radians(U4_3_6), np.radians(U4_3_7)
    P6x = P3x + l3_6/l4_3*(-P4_3x*np.cos(u6) + P4_3y*np.sin(u6))
    P6y = P3y + l3_6/l4_3*(-P4_3x*np.sin(u6) - P4_3y*np.cos(u6))
    P7x = P3x + l3_7/l4_3*(-P4_3x*np.cos(u7) + P4_3y*np.sin(u7))
    P7y = P3y + l3_7/l4_3*(-P4_3x*np.sin(u7) - P4_3y*np.cos(u7))
    # (18)
    z = np.zeros_like(phi1)
    return dict(
        P2=np.column_stack([P2x, P2y]),
        P3=np.column_stack([P3x, P3y]),
        P5=np.column_stack([P5x, P5y, z]),
        P6=np.column_stack([P6x, P6y, z - l5_6]),
        P7=np.column_stack([P7x, P7y, z + l5_7]),
        # transmission angle at P3 between P3->P2 and P3->P4
        mu=np.degrees(np.arccos(((P2x - P3x)*(P4[0] - P3x) + (P2y - P3y)*(P4[1] - P3y))/(l2_3*l4_3))),
        rocker=np.degrees(np.arctan2(P4_3y, P4_3x)),
    )


def contour(p):
    """Seed eqs. (19)-(21): the four segments and l_F."""
    s = [np.linalg.norm(p['P6'] - N1, axis=1),        # |P_N1_6|
         np.linalg.norm(p['P5'] - p['P6'], axis=1),   # |P_6_5|
         np.linalg.norm(p['P7'] - p['P5'], axis=1),   # |P_5_7|
         np.linalg.norm(N2 - p['P7'], axis=1)]        # |P_7_N2|
    return s, s[0] + s[1] + s[2] + s[3]


def main():
    phi = np.arange(360.0)
    p = positions(phi)
    seg, lF = contour(p)
    lF0 = contour(positions([PHI0]))[1][0]
    dl = lF - lF0                      # (22)
    P = dl + dP                        # (23)

    cols = ['phi_deg', 'P2_x_mm', 'P2_y_mm', 'P3_x_mm', 'P3_y_mm',
            'P5_x_mm', 'P5_y_mm', 'P5_z_mm', 'P6_x_mm', 'P6_y_mm', 'P6_z_mm',
            'P7_x_mm', 'P7_y_mm', 'P7_z_mm', 'mu_deg',
            'seg_N1_P6_mm', 'seg_P6_P5_mm', 'seg_P5_P7_mm', 'seg_P7_N2_mm',
            'xi_mm', 'dl_mm', 'P_mm']
    data = np.column_stack([phi, p['P2'], p['P3'], p['P5'], p['P6'], p['P7'], p['mu'],
                            *seg, lF, dl, P])
    with open('reference.csv', 'w') as f:
        f.write(','.join(cols) + '\n')
        for row in data:
            f.write(','.join('%.15g' % v for v in row) + '\n')

    # ---- summary on a fine grid -------------------------------------------
    fine = np.arange(0, 360, 0.001)
    pf = positions(fine)
    Pf = contour(pf)[1] - lF0 + dP
    dPf = np.gradient(Pf, fine)  # mm/deg
    rk = np.unwrap(np.radians(pf['rocker']))
    print('l_F(phi0) = %.9f mm' % lF0)
    print('P max %.6f mm at phi = %.3f deg' % (Pf.max(), fine[Pf.argmax()]))
    print('P min %.6f mm at phi = %.3f deg' % (Pf.min(), fine[Pf.argmin()]))
    print('P range (thread handled per stitch) %.6f mm' % (Pf.max() - Pf.min()))
    print('dP/dphi %.4f .. %.4f mm/deg (at %.2f, %.2f)' % (dPf.min(), dPf.max(), fine[dPf.argmin()], fine[dPf.argmax()]))
    print('mu %.4f deg (phi %.3f) .. %.4f deg (phi %.3f)' % (pf['mu'].min(), fine[pf['mu'].argmin()], pf['mu'].max(), fine[pf['mu'].argmax()]))
    print('rocker swing %.3f deg' % np.degrees(rk.max() - rk.min()))
    y5 = pf['P5'][:, 1]
    print('eye P5: y %.3f .. %.3f (travel %.3f, top at phi %.3f), x %.3f .. %.3f' % (
        y5.min(), y5.max(), y5.max() - y5.min(), fine[y5.argmax()], pf['P5'][:, 0].min(), pf['P5'][:, 0].max()))
    for name, s in zip(['N1-P6', 'P6-P5', 'P5-P7', 'P7-N2'], contour(pf)[0]):
        print('  %-6s %.3f .. %.3f mm' % (name, s.min(), s.max()))
    # Grashof check of the four-bar
    L = sorted([l1_2, l2_3, l4_3, float(np.hypot(*(P4 - P1)))])
    print('Grashof: s + l = %.3f <= p + q = %.3f, crank shortest: %s' % (L[0] + L[3], L[1] + L[2], L[0] == l1_2))


if __name__ == '__main__':
    main()
