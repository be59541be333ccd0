"""stitchkin beside its peers, timed in one run on one four-bar.

    python crates/stitchkin-py/bench/peers.py [--repeat N]

Runs from a checkout (it reads the engine benchmark's four-bar from
crates/stitchkin/benches/four_bar.toml). Needs the package installed
(docs/python.md), NumPy, and pylinkage for its row (`pip install
pylinkage`; without it the row says so). Prints one table:
each way of computing the four-bar of the engine benchmark (crank 15 mm,
coupler 50 mm, rocker 40 mm, frame 60 mm, a coupler point 20 mm from A at
30°) over one turn of 360 positions, its time per turn and its ratio to
stitchkin's Rust core doing the same call.
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
    print(f"four-bar, 360 positions a turn, median of {repeat} runs; ratio to the first row")
    print(f"{'how':<82} {'time a turn':>12} {'ratio':>8}")
    for what, seconds in rows:
        print(f"{what:<82} {seconds * 1e6:>9.1f} µs {seconds / rust:>8.2f}")
    if step is None:
        print("pylinkage: not installed (pip install pylinkage), left out")
    overhead = rows[1][1] - rust
    print(f"a call from Python costs {overhead * 1e6:.1f} µs more than in Rust ({rows[1][1] / rust:.2f}×)")
    print(f"NumPy's positions of B and P are stitchkin's within {apart:.1e} mm")


if __name__ == "__main__":
    main()
