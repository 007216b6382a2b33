"""A learned residual's output against the touch pads' contacts on one crossing: the figure
of docs/suite.md ("What it learned"), from a run's data file.

    proleg run configs/learned/steps_medium.simulation.xml --data run.xml --every 20
    proleg data export run.xml -o run.csv --series \\
        "Robot_Data/y_pos,Robot_Data/z_pos,Policy/Action[0..4],tactile/pressed[0..11]"
    python examples/python/policy_contacts.py run.csv --from 14 --to 30 -o contacts.png

Three panels over the same seconds: how far and how high the centre of mass is, the five
offsets the network adds to the sine (degrees, joint 0 at the head), and which of the
twelve pads touch (a dark bar while pressed, pad 0 at the head). Needs matplotlib.
"""

from __future__ import annotations

import argparse
import csv


def read(path: str) -> dict[str, list[float]]:
    """The CSV `proleg data export` writes, as columns by header."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    return {name: [float(r[i]) for r in body] for i, name in enumerate(head)}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("csv")
    p.add_argument("--from", dest="t0", type=float, default=0.0)
    p.add_argument("--to", dest="t1", type=float, default=float("inf"))
    p.add_argument("--title", default="learned residual on a held-out steps-medium course")
    p.add_argument("-o", "--out", default="contacts.png")
    args = p.parse_args()

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cols = read(args.csv)
    keep = [i for i, t in enumerate(cols["simtime_s"]) if args.t0 <= t <= args.t1]
    t = [cols["simtime_s"][i] for i in keep]
    pick = lambda name: [cols[name][i] for i in keep]  # noqa: E731
    fig, (ax1, ax2, ax3) = plt.subplots(3, 1, figsize=(10, 7.5), sharex=True,
                                        gridspec_kw={"height_ratios": [1, 1.3, 1.1]})
    ax1.plot(t, pick("Robot_Data/y_pos"), color="C0", label="ahead (m)")
    ax1.set_ylabel("centre of mass\nahead (m)", color="C0")
    twin = ax1.twinx()
    twin.plot(t, [100 * z for z in pick("Robot_Data/z_pos")], color="C3", label="height")
    twin.set_ylabel("height (cm)", color="C3")
    for j in range(5):
        ax2.plot(t, pick(f"Policy/Action[{j}]"), lw=1, label=f"joint {j}")
    ax2.set_ylabel("policy offset (deg)")
    ax2.legend(ncol=5, fontsize=8, loc="upper right")
    pads = [k for k in range(12) if f"tactile/pressed[{k}]" in cols]
    for k in pads:
        on = pick(f"tactile/pressed[{k}]")
        spans, start = [], None
        for i, v in enumerate(on):
            if v >= 0.5 and start is None:
                start = t[i]
            if (v < 0.5 or i == len(on) - 1) and start is not None:
                spans.append((start, t[i] - start))
                start = None
        ax3.broken_barh(spans, (k - 0.4, 0.8), color="0.25")
    ax3.set_yticks(pads)
    ax3.set_ylim(11.6, -0.6)
    ax3.set_ylabel("pad pressed\n(0: head)")
    ax3.set_xlabel("simulated time (s)")
    fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
