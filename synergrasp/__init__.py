"""synergrasp: reach-to-grasp planning for a synergy-controlled robotic hand.

Grasp quality by the pseudo-distance formulation (separation and penetration
distances, the Q distance in wrench space) with exact dual-based derivatives,
on interchangeable LP backends (``synergrasp.lp``).
"""

from . import lp
from .pseudo_distance import PseudoDistance, pseudo_distance, regular_simplex
from .quality import QDistance, contact_wrenches, friction_cone_edges, q_distance

__version__ = "0.1.0"

__all__ = [
    "PseudoDistance",
    "QDistance",
    "contact_wrenches",
    "friction_cone_edges",
    "lp",
    "pseudo_distance",
    "q_distance",
    "regular_simplex",
]
