"""The reach-to-grasp planner (paper Sec. 3.2): status vector, step, stop rules, results."""

from .core import APPROACHES, GRASPS, POWER_APPROACHES, POWER_WIDE_APPROACHES, STANDOFF_APPROACHES, PlannerOptions, attempt_schedule, plan, power_schedule, start_configuration
from .result import PlanResult
from .status import Status, grasp_status, smoothed_normals
from .stop import GraspCheck, check_grasp

__all__ = [
    "APPROACHES",
    "POWER_APPROACHES",
    "POWER_WIDE_APPROACHES",
    "STANDOFF_APPROACHES",
    "attempt_schedule",
    "power_schedule",
    "GRASPS",
    "GraspCheck",
    "PlanResult",
    "PlannerOptions",
    "Status",
    "check_grasp",
    "grasp_status",
    "plan",
    "smoothed_normals",
    "start_configuration",
]
