"""Figures of a validation: displacement and rotation per push direction, and a rendered still.

The bar chart is drawn by matplotlib (Agg backend, imported on first use). The still is rendered by MuJoCo
offscreen, which needs an OpenGL context without a display: start Python
with ``MUJOCO_GL=egl`` (or ``osmesa``). Where none is available,
`render_still` raises `RenderingUnavailable` with that advice, and the
command line skips the still with the message.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._checks import integer
from .._files import atomic_path, image_path
from ..hand import SynergyHand
from .protocol import Protocol
from .simulate import build_model

__all__ = ["plot_validation", "render_still", "RenderingUnavailable"]


class RenderingUnavailable(RuntimeError):
    """MuJoCo cannot render offscreen here; the message says what to set."""


def plot_validation(validation, path):
    """Bar charts of the object's largest displacement and rotation under each push.

    Parameters
    ----------
    validation : Validation
    path : str or Path
        Output image (.png, .svg, .pdf).

    Returns
    -------
    Path
        ``path``.
    """
    path = image_path(path)
    _check_validation(validation)
    plt = _pyplot()
    v = validation
    p = v.settings
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.4))
    try:
        _draw_validation(fig, axes, v, p)
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=120)
    finally:
        plt.close(fig)
    return Path(path)


def _draw_validation(fig, axes, v, p):
    """The bars of `plot_validation` on its two axes, and the title."""
    ok = v.held_per_direction
    panels = ((v.displacement, p.max_displacement, "displacement (mm)"), (v.rotation, p.max_rotation, "rotation (deg)"))
    x = np.arange(len(v.directions))
    for ax, (values, limit, label) in zip(axes, panels):
        finite = np.isfinite(limit)  # an infinite threshold (no such check): the scale of the values instead
        top = 2.0 * limit if finite else max(1.0, float(np.nanmax(values, initial=0.0)))
        shown = np.clip(np.nan_to_num(values, nan=0.0), 0.0, top)
        ax.bar(x, shown, color=np.where(ok, "tab:green", "tab:red"))
        if finite:
            ax.axhline(limit, color="k", ls="--", lw=1)
        for k, value in enumerate(values):
            text = "-" if np.isnan(value) else f"{value:.1f}"
            ax.text(k, min(shown[k], top) + 0.02 * top, text, ha="center", va="bottom", fontsize=8)
        ax.set_xticks(x, [f"push {d}" for d in v.directions], fontsize=8)
        ax.set_ylim(0, 1.15 * top)
        ax.set_ylabel(label)
    if np.isnan(v.displacement).all():
        axes[0].text(0.5, 0.5, "not simulated", transform=axes[0].transAxes, ha="center")
    verdict = "held" if v.held else f"not held ({v.outcome})"
    fig.suptitle(f"{v.object_name}: {verdict}, preset {p.name}, mu {p.mu:g}, mass {v.object_mass * 1e3:.0f} g"
                 + (f", palm moved back {v.retreat:g} mm" if v.retreat else ""), fontsize=10)
    fig.tight_layout()


def render_still(validation, obj, path, *, hand=None, width=640, height=480):
    """A picture of the settled grasp (of the planned one if it was not simulated), rendered by MuJoCo.

    Parameters
    ----------
    validation : Validation
    obj : GraspObject
        The object validated.
    path : str or Path
        Output image (.png).
    hand : SynergyHand, optional
        The hand validated (default ``SynergyHand.default()``).
    width, height : int
        Image size in pixels.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    RenderingUnavailable
        If MuJoCo cannot render offscreen here (set ``MUJOCO_GL=egl`` or
        ``MUJOCO_GL=osmesa`` before starting Python).
    ValueError
        For a path that is not an image file, a size beyond MuJoCo's offscreen
        buffer, or an object or hand other than those validated.
    """
    path = image_path(path)
    _check_validation(validation)
    hand = SynergyHand.default() if hand is None else hand
    if not isinstance(hand, SynergyHand):
        raise TypeError(f"hand must be a SynergyHand, got {type(hand).__name__}")
    if validation.object_name != obj.name or validation.hand_name != hand.name \
            or not hand.made(validation.hand):
        raise ValueError(f"the validation is of {validation.object_name!r} with hand "
                         f"{validation.hand or validation.hand_name!r}, not of {obj.name!r} with {hand.identity!r}: pass "
                         "the object and hand it validated")
    width, height = integer(width, "width", 1, "pixels"), integer(height, "height", 1, "pixels")
    mujoco, model, scene = build_model(hand, obj, validation.u, Protocol(**validation.protocol))
    most = (int(model.vis.global_.offwidth), int(model.vis.global_.offheight))
    if width > most[0] or height > most[1]:
        raise ValueError(f"a still of {width} x {height} pixels is larger than MuJoCo's offscreen buffer "
                         f"({most[0]} x {most[1]}); ask for at most that")
    data = mujoco.MjData(model)
    angles = validation.joint_angles or hand.joint_angles(validation.u)
    for name in scene.joints:
        data.joint(name).qpos[0] = angles[name]
    centre = np.asarray(obj.center, dtype=float)
    if np.isfinite(validation.object_pose).all():
        data.joint("object").qpos[:] = np.r_[validation.object_pose[:3] * 1e-3, validation.object_pose[3:]]
        centre = validation.object_pose[:3]
    mujoco.mj_forward(model, data)
    camera = mujoco.MjvCamera()
    camera.lookat[:] = centre * 1e-3
    camera.distance = 3.0 * obj.size * 1e-3
    camera.azimuth, camera.elevation = 135.0, -25.0
    try:
        renderer = mujoco.Renderer(model, height, width)
    except Exception as exc:  # noqa: BLE001 - MuJoCo raises several types when there is no OpenGL context
        raise RenderingUnavailable(
            f"MuJoCo cannot render offscreen here ({type(exc).__name__}: {exc}); start Python with MUJOCO_GL=egl "
            "or MUJOCO_GL=osmesa (an EGL or OSMesa library must be installed)") from None
    try:
        renderer.update_scene(data, camera)
        pixels = renderer.render()
    finally:
        renderer.close()
    with atomic_path(path) as tmp:
        _pyplot().imsave(tmp, pixels)
    return Path(path)


def _check_validation(validation):
    from .result import Validation

    if not isinstance(validation, Validation):
        raise TypeError(f"validation must be a Validation (sg.validate's result), got {type(validation).__name__}")


def _pyplot():
    """matplotlib.pyplot on the headless Agg backend (as `synergrasp.viz`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
