"""The reach-to-grasp planner (paper Sec. 3.2): options, starts, attempts, status vector, step, stop rules, results."""

from .attempt import AttemptResult, Outcome, run_attempt, sq_request
from .core import plan
from .options import GRASPS, PlannerOptions
from .result import PlanResult
from .starts import Start, direction_starts, pinch_seeds, power_schedule, principal_directions, start_configuration, starts
from .status import Status, grasp_status, smoothed_normals, status_rows
from .stop import GraspCheck, check_grasp

__all__ = [
    "GRASPS",
    "AttemptResult",
    "GraspCheck",
    "Outcome",
    "PlanResult",
    "PlannerOptions",
    "Start",
    "Status",
    "check_grasp",
    "direction_starts",
    "grasp_status",
    "pinch_seeds",
    "plan",
    "power_schedule",
    "principal_directions",
    "run_attempt",
    "smoothed_normals",
    "sq_request",
    "start_configuration",
    "starts",
    "status_rows",
]
