"""Objects to grasp: built-in shapes, mesh and point-cloud loading, cP and sQ queries.

An object is a union of convex pieces with a centre and a torque scale (`GraspObject`; the
documentation's "Use your own object" page explains how files become pieces). Units: mm.

Examples
--------
>>> import synergrasp.objects as so
>>> obj = so.get("ellipsoid")
>>> r = obj.contact_distance([[0.0, 0.0, 60.0]])
>>> bool(abs(r.value[0] - 10.0) < 0.5)   # 10 mm above the 50 mm pole, within the faceting
True
"""

from .convex import ConvexPiece
from .grasp_object import GraspObject
from .loading import MESH_FORMATS, POINT_FORMATS, SUPPORTED_FORMATS, cache_dir, from_mesh, from_points, get, load
from .collision import Penetration
from .contact_distance import ContactDistance
from .distance_grid import DistanceGrid
from .scaled_contacts import ScaledContacts
from .shapes import BUILTINS, MIN_TOLERANCE, bell, cup, ellipsoid, goblet, revolve

__all__ = [
    "BUILTINS",
    "ContactDistance",
    "ConvexPiece",
    "DistanceGrid",
    "GraspObject",
    "MESH_FORMATS",
    "MIN_TOLERANCE",
    "POINT_FORMATS",
    "Penetration",
    "SUPPORTED_FORMATS",
    "ScaledContacts",
    "bell",
    "cache_dir",
    "cup",
    "ellipsoid",
    "from_mesh",
    "from_points",
    "get",
    "goblet",
    "load",
    "revolve",
]
