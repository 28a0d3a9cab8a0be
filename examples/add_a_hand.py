"""Add a hand: copy the paper's hand definition, lengthen its fingers, save it, load it, use it.

A synergy hand is one JSON file (see the documentation's "Hand file format" page);
``SynergyHand.default().to_dict()`` is the paper's hand as a plain dictionary. The script
makes every phalanx of the four fingers 20 % longer (the thumb is unchanged), writes the
result as ``long_fingers.json``, reads it back with ``SynergyHand.from_file``, prints how far
the fingertips moved in the mean pose (``hand.points``), and plans a precision grasp of the
ellipsoid with both hands. Nothing else changes: the kinematics, Jacobians and planner read
everything from the file.

Other changes work the same way, for instance a third synergy: append a column to every row
of ``data["synergies"]`` and a row ``[-1.0, 1.0]`` to ``data["synergy_limits"]``;
configurations ``u`` then have 6 + 3 entries.

Writes ``long_fingers.json`` and ``long_fingers_poses.png`` into ``--out``.

Usage::

    python examples/add_a_hand.py [--out DIR] [--factor F]      # default ./examples-out, 1.2
"""

import argparse
import json

import numpy as np

import synergrasp as sg
from synergrasp import viz
from synergrasp.cli import output_folder, positive


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=output_folder, default="examples-out", help="output folder (default ./examples-out)")
    parser.add_argument("--factor", type=positive(float), default=1.2, help="finger length factor (default 1.2)")
    args = parser.parse_args(argv)
    out = args.out

    paper = sg.SynergyHand.default()
    data = paper.to_dict()                                  # a deep copy: editing it is safe
    data["name"] = "long_fingers"
    data["description"] = f"The paper's hand with the phalanges of I, M, R and L {args.factor:g} times longer."
    for finger in data["fingers"]:
        if finger["name"] != "T":
            for joint in finger["joints"]:
                joint["length"] *= args.factor              # mm
    path = out / "long_fingers.json"
    path.write_text(json.dumps(data, indent=1))

    hand = sg.SynergyHand.from_file(path)
    print(f"loaded {hand} from {path}")
    u = np.zeros(hand.n_u)                                  # palm frame = world, mean pose (z = 0)
    before, after = paper.points(u, "precision"), hand.points(u, "precision")
    print("fingertips in the mean pose (palm frame, mm):")
    for label, a, b in zip(hand.point_labels("precision"), before, after):
        print(f"  {label}: {np.round(a, 1)} -> {np.round(b, 1)}  moved {np.linalg.norm(b - a):5.1f} mm")

    obj = sg.objects.get("ellipsoid")
    for h in (paper, hand):
        r = sg.plan(obj, "precision", hand=h)
        print(f"{h.name}: {'success' if r.success else 'no grasp'}: {r.reason}")
    print(f"wrote {path}, {viz.plot_poses(r, obj, hand, out / 'long_fingers_poses.png')}")


if __name__ == "__main__":
    main()
