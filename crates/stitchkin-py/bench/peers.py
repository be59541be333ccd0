"""stitchkin beside its peers, timed in one run: a four-bar and the
MF-7923D take-up.

    python crates/stitchkin-py/bench/peers.py [--repeat N]

Runs from a checkout (it reads the engine benchmark's four-bar from
crates/stitchkin/benches/four_bar.toml). Needs the package installed
(docs/python.md), NumPy, and pylinkage for its row (`pip install
pylinkage`; without it the row says so). Prints two tables.

1. Each way of computing the four-bar of the engine benchmark (crank 15 mm,
   coupler 50 mm, rocker 40 mm, frame 60 mm, a coupler point 20 mm from A
   at 30°) over one turn of 360 positions, its time per turn and its ratio
   to stitchkin's Rust core doing the same call.
2. The MF-7923D preset's take-up over one turn of 360 positions: its two
   mechanisms (the spatial RSSR take-up lever, the needle slider-crank) and
   its six thread paths (three needles, contours A and B, each past the
   one-sided pin G4), P at the needle eye and at B; stitchkin's Rust core
   and Python call against a plain NumPy implementation of the same
   equations, written out below.

Before timing, each NumPy result is checked against stitchkin's numbers.
"""

import argparse
import math
import os
import statistics
import time

import numpy as np

import stitchkin
from stitchkin import _native

# The engine benchmark's four-bar, from the file it reads too.
FOUR_BAR_FILE = os.path.join(os.path.dirname(__file__), "..", "..", "stitchkin", "benches", "four_bar.toml")

R1, L2, L3, L0, DP, GAMMA = 15.0, 50.0, 40.0, 60.0, 20.0, math.radians(30.0)


def timed(call, repeat):
    """The median time of `call` over `repeat` runs after one warm-up, s."""
    call()
    times = []
    for _ in range(repeat):
        began = time.perf_counter()
        call()
        times.append(time.perf_counter() - began)
    return statistics.median(times)


def numpy_four_bar():
    """Positions of A, B and P over one turn, vectorised: the RRR dyad's
    circle intersection on the left of A→O2, as stitchkin's `branch = "left"`."""
    phi = np.radians(np.arange(360.0))
    ax, ay = R1 * np.cos(phi), R1 * np.sin(phi)
    dx, dy = L0 - ax, -ay
    d2 = dx * dx + dy * dy
    d = np.sqrt(d2)
    a = (L2 * L2 - L3 * L3 + d2) / (2.0 * d)
    h = np.sqrt(np.maximum(L2 * L2 - a * a, 0.0))
    bx = ax + (a * dx - h * dy) / d
    by = ay + (a * dy + h * dx) / d
    ux, uy = (bx - ax) / L2, (by - ay) / L2
    c, s = math.cos(GAMMA), math.sin(GAMMA)
    px = ax + DP * (c * ux - s * uy)
    py = ay + DP * (s * ux + c * uy)
    return bx, by, px, py


def pylinkage_four_bar():
    """The same four-bar in pylinkage, stepped through one turn; None when
    pylinkage is not installed."""
    try:
        from pylinkage.actuators import Crank
        from pylinkage.components import Ground
        from pylinkage.dyads import FixedDyad, RRRDyad
        from pylinkage.simulation import Linkage
    except ImportError:
        return None
    o1, o2 = Ground(0.0, 0.0, name="O1"), Ground(L0, 0.0, name="O2")
    crank = Crank(anchor=o1, radius=R1, angular_velocity=2 * math.pi / 360)
    b = RRRDyad(crank.output, o2, distance1=L2, distance2=L3, name="B")
    p = FixedDyad(crank.output, b, distance=DP, angle=GAMMA, name="P")
    linkage = Linkage([o1, o2, crank, b, p], name="four-bar")
    return lambda: list(linkage.step(iterations=360))


# The MF-7923D's thread contours (seed 000 eqs. 3-6), node names without
# the needle's suffix `_j`: G4 is the one-sided thin pin (axis w, clockwise),
# T1 rides on the take-up arm, T2, T3, G8 and N on the needle bar.
MF_CONTOURS = {
    "A": ["G0", "G1", "G2", "G3", "T1", "G4", "T2", "G5", "G6", "G7", "G8", "N"],
    "B": ["G0", "G1", "G2", "G3", "T1", "G4", "T2", "G6", "T3", "G8", "N"],
}
MF_NEEDLES = (1, 2, 3)
MF_ON_NEEDLE_BAR = ("T2", "T3", "G8", "N")


def mf7923d_data(model):
    """What the NumPy take-up takes from the model file: the parameters,
    the fixed points (world frame, mm) and the offsets of the points riding
    on the needle bar from its joint E, read from stitchkin at φ = 0. The
    rest, everything that moves, the NumPy code computes."""
    q = {p["name"]: p["value"] for p in model.parameters if not p["derived"]}
    fixed = ["O1", "O2", "O3"] + [f"G{i}_{j}" for j in MF_NEEDLES for i in range(8)]
    riding = [f"{name}_{j}" for j in MF_NEEDLES for name in MF_ON_NEEDLE_BAR]
    lifts = [f"T1_{j}" for j in MF_NEEDLES]
    at0 = model.run(step=360.0, analogs=False, points=fixed + riding + lifts + ["E"])
    point = {n: np.array([at0[f"{n}.{c}_mm"][0] for c in "xyz"]) for n in fixed + riding + lifts + ["E"]}
    return {
        "q": q,
        "fixed": {n: point[n] for n in fixed},
        "offset": {n: point[n] - point["E"] for n in riding},
        "lift": {j: point[f"T1_{j}"][2] for j in MF_NEEDLES},
    }


def numpy_mf7923d(data, phi_deg):
    """P at the eye and at B of the six MF-7923D paths, vectorised over the
    main-shaft angles `phi_deg`: the same equations stitchkin solves,
    written out in NumPy. Returns {"n1_A": (P_eye, P_B), ...}, mm."""
    q, fixed = data["q"], data["fixed"]
    phi = np.radians(phi_deg)
    zero = np.zeros_like(phi)
    # Eccentric O1A on the main shaft (axis x, angle 0 up): A = O1 + r1 (0, cos θ, sin θ).
    th = phi + math.radians(q["dphi"] + q["t1_phase"])
    a = fixed["O1"][:, None] + np.stack([zero, q["r1"] * np.cos(th), q["r1"] * np.sin(th)])
    # RSSR: B on the circle of radius l_o2b about the axis w through O2, in
    # the plane w = z, |AB| = l_ab: with u = A − (O2 + z w), ρ cos(β − α) = k,
    # k = (l_o2b² + |u|² − l_ab²) / (2 l_o2b); branch "right": β = α − acos(k/ρ).
    o2 = fixed["O2"]
    u = a - (o2 + np.array([0.0, 0.0, q["z"]]))[:, None]
    rho = np.hypot(u[0], u[1])
    k = (q["l_o2b"] ** 2 + (u * u).sum(axis=0) - q["l_ab"] ** 2) / (2.0 * q["l_o2b"])
    beta = np.arctan2(u[1], u[0]) - np.arccos(k / rho)
    # Take-up arm O2T1: ψ counter-clockwise from O2B, R long, at the eyelet's w.
    arm = beta + math.radians(q["psi"])
    t1 = {j: np.stack([o2[0] + q["R"] * np.cos(arm), o2[1] + q["R"] * np.sin(arm), zero + data["lift"][j]]) for j in MF_NEEDLES}
    # Needle slider-crank (seed 000 eq. 11): E_y = O3_y + r2 cos φ − √(DE² − (r2 sin φ)²).
    o3 = fixed["O3"]
    e = np.stack([zero + o3[0], o3[1] + q["r2"] * np.cos(phi) - np.sqrt(q["l_de"] ** 2 - (q["r2"] * np.sin(phi)) ** 2), zero + o3[2]])

    def track(name, j):
        full = f"{name}_{j}"
        if name == "T1":
            return t1[j]
        if name in MF_ON_NEEDLE_BAR:
            return e + data["offset"][full][:, None]
        return np.broadcast_to(fixed[full][:, None], e.shape)

    def thin_pin_cw(p, c, r):
        """p → r past the thin pin through c along w, passed clockwise:
        |r − p| when the straight thread clears it, else √(Δh² + (ρp + ρr)²)."""
        wp, wr = p - c[:, None], r - c[:, None]
        dh = wr[2] - wp[2]
        e2 = ((r - p) ** 2).sum(axis=0)
        free = (e2 - dh * dh > 0.0) & (-(wp[0] * wr[1] - wp[1] * wr[0]) >= 0.0)
        engaged = np.sqrt(dh * dh + (np.hypot(wp[0], wp[1]) + np.hypot(wr[0], wr[1])) ** 2)
        return np.where(free, np.sqrt(e2), engaged)

    out = {}
    for j in MF_NEEDLES:
        for contour, nodes in MF_CONTOURS.items():
            xi = zero.copy()
            i = 0
            while i + 1 < len(nodes):
                if nodes[i + 1] == "G4":
                    xi += thin_pin_cw(track(nodes[i], j), fixed[f"G4_{j}"], track(nodes[i + 2], j))
                    i += 2
                else:
                    xi += np.sqrt(((track(nodes[i + 1], j) - track(nodes[i], j)) ** 2).sum(axis=0))
                    i += 1
            # P = ξ(φ0) − ξ(φ), φ0 = 0 (seed 000 eq. 2); at B, the eye's top
            # position: ξ_B = ξ + u·N with u up the needle (+y).
            xi_b = xi + track("N", j)[1]
            out[f"n{j}_{contour}"] = (xi[0] - xi, xi_b[0] - xi_b)
    return out


def mf7923d_rows(repeat):
    """The MF-7923D take-up timed: stitchkin's Rust core and Python call
    against NumPy, after checking that NumPy's P is stitchkin's."""
    model = stitchkin.Model.preset("mf7923d")
    # The mechanism and the thread paths alone: the preset without its
    # stitch process ([stitch] and what follows closes the file) and the
    # thread physics that needs it.
    text = model.toml
    text = text[: text.index("\n[stitch]\n")]
    physics = text.index("\n[thread.physics]\n")
    text = text[:physics] + text[text.index("\n[[thread.paths]]", physics) :]
    paths_only = stitchkin.Model.from_toml(text, "mf7923d-paths-only.toml")
    phi_deg = np.arange(360.0)
    data = mf7923d_data(model)
    mine = numpy_mf7923d(data, phi_deg)
    at_b = model.run(analogs=False, columns=["*.P_B_mm"])
    at_eye = paths_only.run(analogs=False, columns=["*.P_mm"])
    apart = max(
        max(float(np.abs(at_eye[f"{path}.P_mm"] - p_eye).max()), float(np.abs(at_b[f"{path}.P_B_mm"] - p_b).max()))
        for path, (p_eye, p_b) in mine.items()
    )
    if apart > 1e-9:
        raise SystemExit(f"the NumPy MF-7923D take-up is not stitchkin's: P {apart} mm apart")
    rows = []
    rows.append(("stitchkin, the engine's loop: mechanism and the 6 paths' lengths ξ, no table", _native._time_take_up(model, 1.0, repeat)))
    rows.append(
        (
            "stitchkin, Rust core: one lean run_cycle, P at the eye and the table",
            _native._time_run(paths_only, 1.0, False, repeat, lean=True),
        )
    )
    rows.append(
        (
            "stitchkin from Python: run(analogs=False), also wrap angles and tensions",
            timed(lambda: paths_only.run(analogs=False, columns=["*.P_mm"]), repeat),
        )
    )
    rows.append(("NumPy, vectorised: mechanism and the 6 paths' P at the eye and at B", timed(lambda: numpy_mf7923d(data, phi_deg), repeat)))
    return rows, apart


def print_rows(title, rows):
    """One table: each way's time a turn and its ratio to the first row."""
    first = rows[0][1]
    print(title)
    print(f"{'how':<82} {'time a turn':>12} {'ratio':>8}")
    for what, seconds in rows:
        print(f"{what:<82} {seconds * 1e6:>9.1f} µs {seconds / first:>8.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=200, help="runs of each, the median is shown (default 200)")
    repeat = parser.parse_args().repeat
    model = stitchkin.Model.load(FOUR_BAR_FILE)
    # The ways compute the same four-bar: NumPy's positions are stitchkin's.
    table = model.run(analogs=False)
    bx, by, px, py = numpy_four_bar()
    apart = max(
        float(np.abs(table[name] - mine).max())
        for name, mine in [("B.x_mm", bx), ("B.y_mm", by), ("P.x_mm", px), ("P.y_mm", py)]
    )
    if apart > 1e-9:
        raise SystemExit(f"the NumPy four-bar is not stitchkin's: positions {apart} mm apart")
    rows = []
    rust = _native._time_run(model, 1.0, False, repeat)
    rows.append(("stitchkin, Rust core: one run_cycle, positions, link and transmission angles", rust))
    rows.append(
        ("stitchkin from Python: model.run(analogs=False), the same and NumPy arrays", timed(lambda: model.run(analogs=False), repeat))
    )
    rust_analogs = _native._time_run(model, 1.0, True, repeat)
    rows.append(("stitchkin, Rust core: the same with first and second analogs", rust_analogs))
    rows.append(("stitchkin from Python: model.run(), with analogs", timed(model.run, repeat)))
    rows.append(("NumPy, vectorised: positions of B and P only", timed(numpy_four_bar, repeat)))
    step = pylinkage_four_bar()
    if step is not None:
        rows.append(("pylinkage 1.x, Linkage.step: positions of every joint", timed(step, max(1, repeat // 10))))
    print_rows(f"four-bar, 360 positions a turn, median of {repeat} runs; ratio to the first row", rows)
    if step is None:
        print("pylinkage: not installed (pip install pylinkage), left out")
    overhead = rows[1][1] - rust
    print(f"a call from Python costs {overhead * 1e6:.1f} µs more than in Rust ({rows[1][1] / rust:.2f}×)")
    print(f"NumPy's positions of B and P are stitchkin's within {apart:.1e} mm")
    print()
    mf_rows, mf_apart = mf7923d_rows(repeat)
    print_rows(f"MF-7923D take-up, 360 positions a turn, median of {repeat} runs; ratio to the first row", mf_rows)
    print(f"NumPy's P of the six paths, at the eye and at B, is stitchkin's within {mf_apart:.1e} mm")


if __name__ == "__main__":
    main()
