"""synergrasp: reach-to-grasp planning for a synergy-controlled robotic hand.

Grasp quality by the pseudo-distance formulation (separation and penetration
distances, the Q distance in wrench space) with exact dual-based derivatives,
on interchangeable LP backends (``synergrasp.lp``); the synergy hand
(``SynergyHand``), objects (``synergrasp.objects``) and the reach-to-grasp
planner (``plan``), whose result includes an executable reach checked for
collisions (``PlanResult.path``); physics validation of a grasp in MuJoCo
(``validate``, ``replay_reach``, ``synergrasp.physics``, with the ``sim``
extra).
"""

from . import batch, lp, objects
from .hand import SynergyHand
from .physics import Replay, Validation, replay_reach, validate
from .planner import PlanResult, plan
from .pseudo_distance import PseudoDistance, pseudo_distance, regular_simplex
from .quality import QDistance, contact_wrenches, force_closure_by_hull, friction_cone_edges, q_distance

__version__ = "0.1.0"

__all__ = [
    "PlanResult",
    "PseudoDistance",
    "QDistance",
    "Replay",
    "SynergyHand",
    "batch",
    "Validation",
    "contact_wrenches",
    "force_closure_by_hull",
    "friction_cone_edges",
    "lp",
    "objects",
    "plan",
    "pseudo_distance",
    "q_distance",
    "regular_simplex",
    "replay_reach",
    "validate",
]
