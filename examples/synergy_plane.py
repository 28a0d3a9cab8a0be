"""The synergy plane of the paper's hand (cf. the paper's Fig. 4).

Renders the hand at z1, z2 in {-1, 0, 1} on a 3x3 grid (z1 along the columns, z2 down the
rows) with the mean pose (z = 0) framed in blue, and writes ``synergy_plane.png`` to ``--out``
(default ``./examples-out``), or with ``--docs`` to ``docs/figures/`` (the figure of the
documentation's synergy hand page).

Usage::

    python examples/synergy_plane.py [--out DIR] [--docs]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from synergrasp.hand import SynergyHand  # noqa: E402
from synergrasp.cli import output_folder  # noqa: E402

DOCS_FIGURES = Path(__file__).resolve().parents[1] / "docs" / "figures"
FINGER_COLOURS = {"T": "tab:red", "I": "tab:orange", "M": "tab:green", "R": "tab:purple", "L": "tab:brown"}
FINGER_NAMES = {"T": "thumb", "I": "index", "M": "middle", "R": "ring", "L": "little"}
BOX_FACES = [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]]


def draw_hand(ax, hand, u):
    """Draw the palm box, the phalanx capsules (thick lines) and the fingertips.

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.Axes3D
    hand : synergrasp.hand.SynergyHand
    u : (6 + n_syn,) float
    """
    geo = hand.segments(u)
    corners = geo.palm_corners
    ax.add_collection3d(Poly3DCollection([corners[f] for f in BOX_FACES], facecolor="wheat",
                                         edgecolor="saddlebrown", linewidth=0.6, alpha=0.35))
    for (a, b), label in zip(geo.capsules, geo.labels):
        ax.plot(*np.stack([a, b]).T, color=FINGER_COLOURS.get(label[0], "k"), linewidth=5,
                solid_capstyle="round")
    tips = hand.points(u, "precision")
    ax.scatter(*tips.T, color="k", s=8, depthshade=False)
    ax.scatter(*hand.points(u, "power")[-1], color="tab:blue", s=12, depthshade=False)


def synergy_plane(hand, path, values=(-1.0, 0.0, 1.0), view=(20.0, -135.0)):
    """Render the 3x3 synergy plane of a two-synergy hand to ``path``.

    Parameters
    ----------
    hand : synergrasp.hand.SynergyHand
    path : str or pathlib.Path
    values : (3,) float
        Synergy values along each axis.
    view : (2,) float
        Camera elevation and azimuth (degrees).
    """
    grid = [(z1, z2) for z2 in values[::-1] for z1 in values]
    extent = np.concatenate([np.concatenate([g.capsules.reshape(-1, 3), g.palm_corners])
                             for g in (hand.segments(np.r_[np.zeros(6), z]) for z in grid)])
    lim = np.stack([extent.min(0), extent.max(0)], axis=1) + [-hand.finger_radius, hand.finger_radius]
    fig = plt.figure(figsize=(10.5, 10.5))
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=0.95, wspace=0.0, hspace=0.0)
    for k, (z1, z2) in enumerate(grid):
        ax = fig.add_subplot(3, 3, k + 1, projection="3d")
        draw_hand(ax, hand, np.r_[np.zeros(6), z1, z2])
        ax.set(xlim=lim[0], ylim=lim[1], zlim=lim[2])
        ax.set_box_aspect(np.ptp(lim, axis=1), zoom=1.2)
        ax.view_init(*view)
        ax.set_axis_off()
        ax.set_title(f"z1 = {z1:+.0f}, z2 = {z2:+.0f}", fontsize=10, y=0.95)
        if z1 == 0.0 and z2 == 0.0:
            box = ax.get_position()
            fig.add_artist(plt.Rectangle((box.x0, box.y0), box.width, box.height, fill=False,
                                         edgecolor="tab:blue", linewidth=3, transform=fig.transFigure))
    fig.suptitle(f"{hand.name}: synergy plane, z1 across, z2 up (mean pose in the blue box)")
    fig.legend([plt.Line2D([], [], color=c, linewidth=5) for c in FINGER_COLOURS.values()],
               FINGER_NAMES.values(), loc="lower center", ncol=5, frameon=False)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=output_folder, default="examples-out", help="output folder (default ./examples-out)")
    parser.add_argument("--docs", action="store_true", help=f"write the documentation's figure in {DOCS_FIGURES} instead")
    args = parser.parse_args(argv)
    out = (DOCS_FIGURES if args.docs else args.out) / "synergy_plane.png"
    synergy_plane(SynergyHand.default(), out)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
