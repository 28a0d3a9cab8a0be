"""The reach-to-grasp planner (paper Sec. 3.2): options, starts, attempts, status vector, step, stop rules, results; the executable reach and its clearance; the annealing baseline."""

from .._jit import clock
from .annealing import anneal, autograsp, contact_energy, contact_normals
from .attempt import AttemptResult, Outcome, judge_grasp, run_attempt, sq_request
from .clearance import HandClearance, PathClearance, clearance_labels, hand_and_object, hand_clearance, path_clearance
from .core import METHODS, ObjectRefused, forget_warm_starts, plan
from .options import GRASPS, AnnealingOptions, PlannerOptions
from .reach import OPENINGS, Reach, executable_reach, open_synergies, retreat_directions, widest_opening
from .result import PlanResult
from .starts import (Start, direction_starts, opposed_widths, pinch_fingertips, pinch_seeds, power_schedule,
                     principal_directions, recess, roll_frames, smallest_pinch, start_configuration, starts,
                     surface_samples, widest_pinch, wrap_seeds)
from .status import Status, grasp_status, read_only, smoothed_normals, status_rows
from .stop import CRITERION, GraspCheck, check_grasp

__all__ = [
    "CRITERION",
    "GRASPS",
    "METHODS",
    "OPENINGS",
    "AnnealingOptions",
    "AttemptResult",
    "GraspCheck",
    "HandClearance",
    "ObjectRefused",
    "Outcome",
    "PathClearance",
    "PlanResult",
    "PlannerOptions",
    "Reach",
    "Start",
    "Status",
    "anneal",
    "autograsp",
    "check_grasp",
    "clearance_labels",
    "clock",
    "contact_energy",
    "contact_normals",
    "direction_starts",
    "executable_reach",
    "forget_warm_starts",
    "grasp_status",
    "hand_and_object",
    "hand_clearance",
    "judge_grasp",
    "open_synergies",
    "path_clearance",
    "pinch_fingertips",
    "opposed_widths",
    "pinch_seeds",
    "plan",
    "power_schedule",
    "principal_directions",
    "read_only",
    "recess",
    "smallest_pinch",
    "retreat_directions",
    "roll_frames",
    "run_attempt",
    "smoothed_normals",
    "sq_request",
    "start_configuration",
    "starts",
    "surface_samples",
    "wrap_seeds",
    "status_rows",
    "widest_opening",
    "widest_pinch",
]
