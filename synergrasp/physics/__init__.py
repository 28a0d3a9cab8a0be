"""Physics validation: does a planned grasp hold the object in MuJoCo?

`validate` places the synergy hand at a configuration around the object in a
MuJoCo scene (`synergrasp.physics.model`), closes the synergies a step
further, lets the grasp settle, and pushes the object with its weight along
six directions (`synergrasp.physics.simulate`); the `Validation` says whether
it held, and why not; `validate_turns` repeats it with the whole scene turned
(a grasp near a threshold can change verdict with the world frame). `replay_reach` runs a plan's executable reach with the
object free and says how far the hand moved it before closing (`Replay`).
The settings are a `Protocol`, from one of two `PRESETS`: the project's own
(default) and DexGraspBench-like ones. Grasps
built by construction (`pinch_grasp`, `ball_pinch`) check the simulation
itself.

Importing this package does not import ``mujoco``; the first validation
does, and says how to install it if it is missing
(``pip install "synergrasp[sim]"``).
"""

from .figure import RenderingUnavailable, plot_validation, render_still
from .model import GraspScene, grasp_mjcf, moving_joints
from .probes import PINCH_Z, ball_pinch, hand_without, pinch_grasp
from .protocol import DIRECTIONS, PRESETS, Protocol, protocol
from .replay import Replay, replay_reach
from .result import OUTCOMES, Validation
from .simulate import INSTALL_HINT, build_model, mujoco_module, simulate_reach
from .turns import AXIS_TURNS, turned_scene, validate_turns
from .validate import NoContact, check_match, retreat_distance, squeeze_targets, validate

__all__ = [
    "AXIS_TURNS",
    "NoContact",
    "retreat_distance",
    "DIRECTIONS",
    "GraspScene",
    "INSTALL_HINT",
    "OUTCOMES",
    "PINCH_Z",
    "PRESETS",
    "Protocol",
    "RenderingUnavailable",
    "Replay",
    "Validation",
    "ball_pinch",
    "build_model",
    "check_match",
    "grasp_mjcf",
    "hand_without",
    "moving_joints",
    "mujoco_module",
    "pinch_grasp",
    "plot_validation",
    "protocol",
    "render_still",
    "replay_reach",
    "simulate_reach",
    "squeeze_targets",
    "turned_scene",
    "validate",
    "validate_turns",
]
