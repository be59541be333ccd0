"""Independent reference computation for the Juki MF-7923D needle-thread take-up
(seed 000), written for stitchkin's tests.  Regenerate the CSV files next to
this script with:  python3 generate_reference.py   (numpy only).

All coordinates are in the local frame UVW of Table 2 unless noted; stitchkin's
world frame is the paper's XYZ (origin O1) = UVW + (30 - e, 35 - h, 0) = UVW + (9, 3, 0).
See README.md in this directory and the header of presets/mf7923d.toml.
"""
import os
import numpy as np

D2R = np.pi / 180.0

NOMINAL = dict(r1=4.0, AB=32.0, O2B=21.5, z=0.0, t=120.0, e=21.0, h=32.0,
               r2=15.5, DE=54.5, P=127.0, R=85.0, psi=169.3, dphi=0.0, t1_phase=180.0)
# The other reading of the take-up phase (the eccentric's throw up at the
# needle's TDC): the geometry files are computed in it.
PHASE0 = dict(NOMINAL, t1_phase=0.0)

# Table 2 (UVW, mm), typos fixed: needle 2 G2 w -65 -> 65, needle 3 G2 u 8 -> -8,
# needle 3 G5 v 90 -> 55; (u, v) of the T1 and T2 columns exchanged.
TABLE2 = {
    1: dict(G0=(102, -45, 52), G1=(32, 8.5, 68), G2=(-8, 8.5, 68), G3=(-29, 0, 62),
            G4=(-145, 55, 50), G5=(-155, 55, 50), G6=(-146, -22, 35), G7A=(-146, -95, 22),
            G7B=(-146, -167, 8), G8=(-146, -177, 3), T1=(-109, -4, 40), T2=(-150, 85, 50),
            N=(-154, -210, 0)),
    2: dict(G0=(87, -11, 60), G1=(32, 8.5, 65), G2=(-8, 8.5, 65), G3=(-29, 12, 58),
            G4=(-145, 55, 44), G5=(-155, 55, 44), G6=(-150, -22, 35), G7A=(-150, -95, 22),
            G7B=(-150, -167, 8), G8=(-150, -177, 3), T1=(-109, -4, 35), T2=(-150, 85, 44),
            N=(-150, -207, 0)),
    3: dict(G0=(70, 22, 67), G1=(32, 8.5, 62), G2=(-8, 8.5, 62), G3=(-29, 24, 54),
            G4=(-145, 55, 40), G5=(-155, 55, 40), G6=(-154, -22, 35), G7A=(-154, -95, 22),
            G7B=(-154, -167, 8), G8=(-154, -177, 3), T1=(-109, -4, 32), T2=(-150, 85, 40),
            N=(-146, -203, 0)),
}
T2_w = {j: TABLE2[j]['T2'][2] for j in (1, 2, 3)}
T1_w = {j: TABLE2[j]['T1'][2] for j in (1, 2, 3)}

# Offsets of needle-bar points from E (the needle-bar joint) at TDC with nominal
# r2, DE, h: E_TDC(v) = O2v + h + r2 - DE = -35 + 32 + 15.5 - 54.5 = -42, u = -150.
E_TDC_NOM = np.array([-150.0, -42.0, 0.0])
BAR_POINTS = ('T2', 'G7B', 'G8', 'N')


def bar_offsets(j):
    return {k: np.array(TABLE2[j][k], float) - E_TDC_NOM for k in BAR_POINTS}


def mechanism(phi_deg, p=NOMINAL):
    """Moving points (UVW) for an array of phi (deg)."""
    phi = np.asarray(phi_deg, float) * D2R
    O2 = np.array([-30.0, -35.0, 0.0])             # Q = O2 + (30, 35, 0)
    O1 = O2 + np.array([p['e'], p['h'], 0.0])     # main shaft (along u) through O1
    O3 = O2 + np.array([-p['t'], p['h'], 0.0])    # needle crank on the main shaft
    # eccentric O1A: turns right-handed about +u; throw up (+v) at phi = -(dphi + t1_phase), like the needle crank at
    # phi = 0 (paper: dphi = phi_M1-0 - phi_M2-0); t1_phase = 180: throw down, T1 up, at the needle's TDC
    th = phi + (p['dphi'] + p['t1_phase']) * D2R
    A = O1[None, :] + p['r1'] * np.stack([np.zeros_like(th), np.cos(th), np.sin(th)], 1)
    # RSSR: B = O2 + O2B (cos b, sin b, 0) + (0, 0, z); |B - A| = AB
    c = np.array([O2[0], O2[1], p['z']])
    d = c[None, :] - A                               # c - A
    a = p['O2B']
    # |d + a(cos b, sin b, 0)|^2 = AB^2 -> K cos b + L sin b = M
    K = 2 * a * d[:, 0]
    L = 2 * a * d[:, 1]
    M = p['AB'] ** 2 - a * a - (d ** 2).sum(1)
    rho = np.hypot(K, L)
    if np.any(np.abs(M) > rho):
        raise ValueError('RSSR does not assemble')
    g = np.arctan2(L, K)
    # two roots b = g +/- acos(M/rho); branch: B clockwise about +w from A's direction
    b = g - np.arccos(M / rho)
    # pick the branch continuous with the nominal (B near the +u side of O2):
    b2 = g + np.arccos(M / rho)
    ang_A = np.arctan2(A[:, 1] - O2[1], A[:, 0] - O2[0])

    def wrap(x):
        return (x + np.pi) % (2 * np.pi) - np.pi
    # "right" = clockwise from the direction of A's projection
    cand = np.stack([b, b2], 1)
    rel = wrap(cand - ang_A[:, None])
    pick = np.where(rel[:, 0] < 0, cand[:, 0], cand[:, 1])
    beta = wrap(pick)
    B = c[None, :] + a * np.stack([np.cos(beta), np.sin(beta), np.zeros_like(beta)], 1)
    # needle slider-crank O3DE (plane u = O3u), TDC at phi = 0
    D = O3[None, :] + p['r2'] * np.stack([np.zeros_like(phi), np.cos(phi), np.sin(phi)], 1)
    Ev = O3[1] + p['r2'] * np.cos(phi) - np.sqrt(p['DE'] ** 2 - (p['r2'] * np.sin(phi)) ** 2)
    E = np.stack([np.full_like(phi, O3[0]), Ev, np.zeros_like(phi)], 1)
    out = dict(A=A, B=B, D=D, E=E, beta=beta, O1=O1, O2=O2, O3=O3)
    tdir = beta + p['psi'] * D2R
    for j in (1, 2, 3):
        out[f'T1_{j}'] = np.stack([O2[0] + p['R'] * np.cos(tdir), O2[1] + p['R'] * np.sin(tdir),
                                   np.full_like(tdir, T1_w[j])], 1)
        # T2 on the needle-bar axis, P above E
        off = bar_offsets(j)
        off['T2'] = np.array([0.0, p['P'], T2_w[j]])
        for k in BAR_POINTS:
            out[f'{k}_{j}'] = E + off[k][None, :]
    return out


def seg(a, b):
    return np.linalg.norm(b - a, axis=-1)


def contour(j, kind, pts, flat=False):
    """Return (xi, g4_engaged, w_contact) for needle j, contour kind 'A' or 'B'."""
    tb = TABLE2[j]
    n = pts['E'].shape[0]

    def fx(name):
        v = np.array(tb[name], float)
        if flat:
            v = v.copy(); v[2] = 0
        return np.broadcast_to(v, (n, 3))

    def mv(name):
        v = pts[name].copy()
        if flat:
            v[:, 2] = 0
        return v
    G0, G1, G2, G3, G4, G5, G6, G7A = (fx(k) for k in ('G0', 'G1', 'G2', 'G3', 'G4', 'G5', 'G6', 'G7A'))
    T1, T2, T3, G8, N = mv(f'T1_{j}'), mv(f'T2_{j}'), mv(f'G7B_{j}'), mv(f'G8_{j}'), mv(f'N_{j}')
    xi = seg(G0, G1) + seg(G1, G2) + seg(G2, G3) + seg(G3, T1)
    # G4: pin parallel to w through (u4, v4); engaged when G4 lies on the left of
    # the directed projection T1 -> T2 (the straight thread would pass on the
    # pin's outer (+u) side).
    d = T2[:, :2] - T1[:, :2]
    q = G4[:, :2] - T1[:, :2]
    cross = d[:, 0] * q[:, 1] - d[:, 1] * q[:, 0]
    eng = cross > 0
    d1 = np.linalg.norm(q, axis=1)
    d2 = np.linalg.norm(T2[:, :2] - G4[:, :2], axis=1)
    wrap_len = np.hypot(d1 + d2, T2[:, 2] - T1[:, 2])
    straight = seg(T1, T2)
    xi = xi + np.where(eng, wrap_len, straight)
    wc = np.where(eng, T1[:, 2] + (T2[:, 2] - T1[:, 2]) * d1 / (d1 + d2), np.nan)
    if kind == 'A':
        xi = xi + seg(T2, G5) + seg(G5, G6) + seg(G6, G7A) + seg(G7A, G8) + seg(G8, N)
    else:
        xi = xi + seg(T2, G6) + seg(G6, T3) + seg(T3, G8) + seg(G8, N)
    return xi, eng, wc, cross


def take_up(j, kind, phis, p=NOMINAL, flat=False, at_b=False):
    """P = xi(0) - xi(phi) at the moving eye, or at_b: past B, the eye's top
    position (phi0 = 0 is the needle's TDC), P_B = P + S(phi), S = E_v(0) - E_v(phi)."""
    pts = mechanism(np.concatenate([[0.0], phis]), p)
    xi, eng, wc, cross = contour(j, kind, pts, flat)
    P = xi[0] - xi[1:]
    if at_b:
        P = P + pts['E'][0, 1] - pts['E'][1:, 1]
    return P, eng[1:], wc[1:], xi[1:]


# ---------------------------------------------------------------------------
# Generation of the CSV files

def main():
    OUT = os.path.dirname(os.path.abspath(__file__))
    os.makedirs(OUT, exist_ok=True)
    Q_WORLD = np.array([30 - NOMINAL['e'], 35 - NOMINAL['h'], 0.0])   # Q - O1 = (9, 3, 0)
    ph = np.arange(0, 360.0, 1.0)
    f = lambda x: '%.15g' % x

    # ---------- points (the reading t1_phase = 0, at the moving eye) ----------
    m = mechanism(ph, PHASE0)
    names = ['A', 'B', 'D', 'E'] + [f'{k}_{j}' for k in ('T1', 'T2') for j in (1, 2, 3)] \
          + [f'T3_{j}' for j in (1, 2, 3)] + [f'G8_{j}' for j in (1, 2, 3)] + [f'N_{j}' for j in (1, 2, 3)]
    src = {n: n for n in names}
    for j in (1, 2, 3):
        src[f'T3_{j}'] = f'G7B_{j}'
    with open(f'{OUT}/reference_points.csv', 'w') as fh:
        cols = ['phi_deg'] + [f'{n}.{c}_mm' for n in names for c in 'xyz'] + ['angle_O2_B_deg']
        fh.write(','.join(cols) + '\n')
        for i, p in enumerate(ph):
            row = [f(p)]
            for n in names:
                row += [f(v) for v in m[src[n]][i] + Q_WORLD]
            row.append(f(np.degrees(m['beta'][i])))
            fh.write(','.join(row) + '\n')

    # ---------- P ----------
    res = {}
    for j in (1, 2, 3):
        for k in 'AB':
            P, eng, wc, xi = take_up(j, k, ph, PHASE0)
            P2, eng2, _, _ = take_up(j, k, ph, PHASE0, flat=True)
            res[(j, k)] = (P, eng, xi, P2, eng2)
    with open(f'{OUT}/reference_P.csv', 'w') as fh:
        cols = ['phi_deg'] + [f'P_n{j}_{k}_mm' for j in (1, 2, 3) for k in 'AB'] \
             + [f'g4_engaged_n{j}' for j in (1, 2, 3)] \
             + [f'xi_n{j}_{k}_mm' for j in (1, 2, 3) for k in 'AB'] \
             + [f'P2D_n{j}_{k}_mm' for j in (1, 2, 3) for k in 'AB'] \
             + ['dP_3D_minus_2D_n1_A_mm']
        fh.write(','.join(cols) + '\n')
        for i, p in enumerate(ph):
            row = [f(p)] + [f(res[(j, k)][0][i]) for j in (1, 2, 3) for k in 'AB']
            row += [str(int(res[(j, 'A')][1][i])) for j in (1, 2, 3)]
            row += [f(res[(j, k)][2][i]) for j in (1, 2, 3) for k in 'AB']
            row += [f(res[(j, k)][3][i]) for j in (1, 2, 3) for k in 'AB']
            row.append(f(res[(1, 'A')][0][i] - res[(1, 'A')][3][i]))
            fh.write(','.join(row) + '\n')
    # engagement identical for A and B (depends on T1, T2, G4 only)
    for j in (1, 2, 3):
        assert (res[(j, 'A')][1] == res[(j, 'B')][1]).all()

    # ---------- G4 switch angles by bisection ----------
    def cross_at(phi, j=1, p=PHASE0):
        mm = mechanism(np.array([phi]), p)
        T1 = mm[f'T1_{j}'][0, :2]; T2 = mm[f'T2_{j}'][0, :2]; G4 = np.array(TABLE2[j]['G4'][:2], float)
        d = T2 - T1; q = G4 - T1
        return d[0] * q[1] - d[1] * q[0]
    def bisect(a, b, p=PHASE0):
        fa = cross_at(a, p=p)
        for _ in range(60):
            c = 0.5 * (a + b); fc = cross_at(c, p=p)
            if (fc > 0) == (fa > 0): a, fa = c, fc
            else: b = c
        return 0.5 * (a + b)
    sw = [bisect(100, 120), bisect(240, 260)]
    print('G4 switch angles', sw)

    # ---------- summary ----------
    fine = np.arange(0, 360.0, 0.01)
    def intervals(mask, x, period=360.0):
        out = []; i = 0; n = len(mask)
        while i < n:
            if mask[i]:
                j = i
                while j + 1 < n and mask[j + 1]: j += 1
                out.append([x[i], x[j]]); i = j + 1
            else: i += 1
        if len(out) > 1 and out[0][0] == x[0] and out[-1][1] == x[-1]:
            out = [[out[-1][0], out[0][1]]] + out[1:-1]
        return ';'.join(f'{a:.2f}..{b:.2f}' for a, b in out)
    with open(f'{OUT}/reference_summary.csv', 'w') as fh:
        fh.write('needle,contour,xi0_mm,maxP_mm,phi_maxP_deg,minP_mm,g4_engaged_deg,flat_deg_dP_lt_0.05,within_0.5mm_of_max_deg,maxP_2D_mm,max_abs_dP_3D_2D_mm,phi_max_abs_dP_deg\n')
        for j in (1, 2, 3):
            for k in 'AB':
                P, eng, wc, xi = take_up(j, k, fine, PHASE0)
                P2 = take_up(j, k, fine, PHASE0, flat=True)[0]
                dP = np.gradient(P, 0.01)
                d = P - P2
                fh.write(','.join([str(j), k, f'{xi[0]:.6f}', f'{P.max():.6f}', f'{fine[P.argmax()]:.2f}', f'{P.min():.6f}',
                                   f'{sw[1]:.3f}..{sw[0]:.3f}' , intervals(np.abs(dP) < 0.05, fine),
                                   intervals(P > P.max() - 0.5, fine), f'{P2.max():.6f}', f'{np.abs(d).max():.6f}',
                                   f'{fine[np.abs(d).argmax()]:.2f}']) + '\n')

    # ---------- sensitivities (the default reading, t1_phase = 180, P past B) ----------
    g = np.arange(0, 360.0, 0.1)
    cases = [('r1', 4, 6), ('r1', 4, 5), ('r2', 15.5, 16.5), ('O2B', 20, 23), ('O2B', 21.5, 20), ('O2B', 21.5, 23),
             ('z', 0, -10), ('z', 0, 10), ('z', 0, -5), ('z', 0, -2), ('dphi', 0, -20), ('dphi', 0, 20)]
    pname = {'r1': 'r1', 'r2': 'r2', 'O2B': 'l_o2b', 'z': 'z', 'dphi': 'dphi'}
    with open(f'{OUT}/reference_sensitivity.csv', 'w') as fh:
        fh.write('parameter,from,to,needle,contour,maxP_B_from_mm,phi_maxP_B_from_deg,maxP_B_to_mm,phi_maxP_B_to_deg,d_maxP_B_mm,max_abs_dP_B_mm,phi_max_abs_dP_B_deg,g4_engaged_to_deg\n')
        for name, a, b in cases:
            for j in (1, 2, 3):
                for k in 'AB':
                    pa = dict(NOMINAL); pa[name] = a
                    pb = dict(NOMINAL); pb[name] = b
                    Pa = take_up(j, k, g, pa, at_b=True)[0]; Pb, eb, _, _ = take_up(j, k, g, pb, at_b=True)
                    d = Pb - Pa
                    fh.write(','.join([pname[name], f(a), f(b), str(j), k, f'{Pa.max():.4f}', f'{g[Pa.argmax()]:.1f}',
                                       f'{Pb.max():.4f}', f'{g[Pb.argmax()]:.1f}', f'{Pb.max() - Pa.max():.4f}',
                                       f'{np.abs(d).max():.4f}', f'{g[np.abs(d).argmax()]:.1f}', intervals(eb, g)]) + '\n')
    print('done')


if __name__ == '__main__':
    main()
