"""The reach-to-grasp planner (paper Sec. 3.2): status vector, step, stop rules, results; the executable reach and its clearance."""

from .core import APPROACHES, GRASPS, POWER_APPROACHES, POWER_WIDE_APPROACHES, STANDOFF_APPROACHES, PlannerOptions, attempt_schedule, plan, power_schedule, start_configuration
from .clearance import HandClearance, PathClearance, clearance_labels, hand_and_object, hand_clearance, path_clearance
from .reach import OPENINGS, Reach, executable_reach, open_synergies, retreat_directions, widest_opening
from .result import PlanResult
from .status import Status, grasp_status, smoothed_normals
from .stop import GraspCheck, check_grasp

__all__ = [
    "APPROACHES",
    "OPENINGS",
    "POWER_APPROACHES",
    "POWER_WIDE_APPROACHES",
    "STANDOFF_APPROACHES",
    "attempt_schedule",
    "power_schedule",
    "open_synergies",
    "retreat_directions",
    "widest_opening",
    "GRASPS",
    "GraspCheck",
    "HandClearance",
    "PathClearance",
    "Reach",
    "PlanResult",
    "PlannerOptions",
    "Status",
    "check_grasp",
    "clearance_labels",
    "hand_and_object",
    "executable_reach",
    "hand_clearance",
    "path_clearance",
    "grasp_status",
    "plan",
    "smoothed_normals",
    "start_configuration",
]
