"""The independent check of a planned grasp, on the object's true mesh (used by every benchmark).

A plan is verified when

* every final contact lies within ``GAP`` (5 mm) of the object's true surface (its mesh, not the
  convex pieces the planner works on), measured by trimesh's closest-point query;
* the origin lies strictly inside the convex hull (qhull) of the contact wrenches built at those
  closest points of the true surface, with the true surface's normals there;
* no phalanx capsule and not the palm box is deeper than ``DEPTH`` (3 mm) in the true mesh, by
  the dense sampled check of ``reach_sampling.py`` (trimesh's signed distance, no fcl, no convex
  pieces).

Nothing here is the planner's own code but the contact wrenches (``sg.contact_wrenches``, checked
against closed forms in ``tests/test_quality.py``): neither its contacts' normals nor its
penetration depths.
"""

from __future__ import annotations

import numpy as np
import trimesh

import synergrasp as sg
from reach_sampling import sampled_clearance

#: Largest gap (mm) from a contact to the true surface for a grasp to count.
GAP = 5.0
#: Deepest penetration (mm) of a phalanx capsule or the palm box for a grasp to count.
DEPTH = 3.0


def true_surface(obj):
    """The surface a grasp must touch: the object's mesh, else the hull of each piece."""
    return obj.mesh if obj.mesh is not None else obj.to_mesh()


def verify(result, obj, hand=None):
    """Independent check of a plan's final grasp on the object's true surface.

    Parameters
    ----------
    result : PlanResult
    obj : GraspObject
    hand : SynergyHand, optional
        The hand of the plan (default the paper's).

    Returns
    -------
    dict
        ``verified`` (bool), ``gap`` (largest contact gap, mm), ``q_true`` (Q distance of the
        contacts moved to the true surface, with its normals), ``closed`` (qhull verdict),
        ``depth`` and ``palm_depth`` (deepest phalanx capsule and the palm box's depth in the
        true mesh, mm, >= 0).
    """
    out = dict(verified=False, gap=float("nan"), q_true=float("nan"), closed=False, depth=float("nan"),
               palm_depth=float("nan"))
    points = np.asarray(result.contact_points, dtype=float).reshape(-1, 3)
    if not result.success or len(points) < 2:
        return out
    mesh = true_surface(obj)
    closest, gap, triangle = trimesh.proximity.closest_point(mesh, points)
    inward = -mesh.face_normals[triangle]
    W = sg.contact_wrenches(closest, inward, center=obj.center, torque_scale=obj.torque_scale)
    closed = bool(sg.force_closure_by_hull(W))
    q_true = sg.q_distance(closest, inward, center=obj.center, torque_scale=obj.torque_scale).value
    clearance = sampled_clearance(hand or sg.SynergyHand.default(), mesh, result.u)
    depth, palm_depth = max(0.0, -float(clearance[:-1].min())), max(0.0, -float(clearance[-1]))
    out.update(gap=float(gap.max()), q_true=float(q_true), closed=closed, depth=depth, palm_depth=palm_depth)
    out["verified"] = closed and out["gap"] <= GAP and max(depth, palm_depth) <= DEPTH
    return out


if __name__ == "__main__":
    raise SystemExit(f"{__file__} is a helper module, not a script: the benchmarks (generalise.py, limits.py, ...) and "
                     "examples/paper_experiments.py import it to verify their plans")
