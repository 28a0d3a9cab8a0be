"""Figures and animations of plans: status histories, hand poses, a GIF and an HTML scene.

All functions draw headless (importing this module selects matplotlib's Agg backend) and
write files, each atomically (a temporary file beside it, then a rename: a failed write leaves
no partial file); each returns the path it wrote. ``synergrasp plan`` on the command line writes
all four for a plan.
"""

from __future__ import annotations


import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import trimesh  # noqa: E402
from matplotlib import animation  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from ._checks import as_path, integer  # noqa: E402
from ._files import atomic_path, image_path  # noqa: E402

__all__ = ["animate", "plot_grasps", "plot_poses", "plot_status", "scene", "status_figure", "write_html"]

#: Colours of a hand's fingers, in the order of `SynergyHand.finger_names` (cycled beyond them).
_CHAIN_COLORS = ["tab:red", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:blue", "tab:pink", "tab:olive",
                 "tab:cyan"]
_FINGER_NAMES = {"T": "thumb", "I": "index", "M": "middle", "R": "ring", "L": "little", "P": "palm"}


def _finger_and_phalanx(label):
    """A status row's label as (finger name, phalanx index): the name and the one digit `SynergyHand.point_labels`
    appends (``"I2"``: ``("I", 2)``; ``"f12"``, finger ``f1``: ``("f1", 2)``); (label, None) for the palm's."""
    return (label[:-1], int(label[-1])) if len(label) > 1 and label[-1].isdigit() else (label, None)


def _segment_colors(hand):
    """The colour of each phalanx of ``hand`` (`SynergyHand.segments` order), by its finger."""
    return [_CHAIN_COLORS[c % len(_CHAIN_COLORS)] for c in hand.point_chains("power")[:-1]]


def plot_status(result, path, labels=None, attempts=None):
    """The status vector against iterations, like the paper's Figs. 7b-14b (`status_figure`, written to ``path``).

    Parameters
    ----------
    result : PlanResult
    path : str or Path
        Output image (.png, .svg, .pdf).
    labels : list of str, optional
        See `status_figure`.
    attempts : {"all", "last"}, optional
        See `status_figure`.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    TypeError
        If ``result`` is not a PlanResult.
    ValueError
        If the file's extension is not an image format matplotlib writes, or ``attempts`` is unknown.
    FileNotFoundError
        If the folder of ``path`` does not exist.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import synergrasp as sg
    >>> from synergrasp import viz
    >>> result = sg.plan(sg.objects.get("ellipsoid"), "precision", max_iter=3)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = viz.plot_status(result, Path(folder) / "status.png")
    ...     path.name, path.stat().st_size > 0
    ('status.png', True)
    """
    path = image_path(path)
    return _save(status_figure(result, labels, attempts), path, dpi=120)


def status_figure(result, labels=None, attempts=None):
    """The figure of `plot_status`: the status vector against iterations, and the clearance along the reach.

    Top: every cP row (mm) with the contact threshold eps_c; middle: g_sQ and
    g_Q with the -0.1 level of a good grasp. With every attempt shown, the
    attempts follow one another along the iteration axis, separated by grey
    lines and numbered; g_Q is known for the returned (last) attempt only.
    Bottom, when the result has an executable reach (`PlanResult.path`): the
    smallest signed distance of the phalanx capsules and the palm box to the
    object along the path, with the tolerance it must stay above.

    Parameters
    ----------
    result : PlanResult
    labels : list of str, optional
        Names of the cP rows plotted, the first ``len(labels)`` (non-empty
        names); default the paper's hand's point labels of ``result.grasp``
        (the five fingertips for a precision grasp, every segment and the palm
        for a power grasp; pass ``hand.point_labels(result.grasp)`` for
        another hand).
    attempts : {"all", "last"}, optional
        Show every attempt's status trace, or the returned reach only. Default:
        every attempt for a plan that found no grasp (so the figure shows what
        each attempt did), the returned reach for a successful one. Results
        without per-attempt traces (saved by older versions) show the returned
        reach.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes (cP rows, Q distances), three with the clearance along the
        executable reach; close it with ``plt.close(fig)``.

    Raises
    ------
    ValueError
        If ``attempts`` is not "all", "last" or None, or without ``labels``
        for a result of another hand than the paper's (`PlanResult.hand`), or
        with more labels than the status has cP rows, an empty one, or a
        string instead of a list.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import synergrasp as sg
    >>> result = sg.plan(sg.objects.get("ellipsoid"), "precision", max_iter=6, iterations_per_attempt=3)
    >>> fig = status_figure(result)            # a failed plan: both attempts, one after the other
    >>> [len(a["status"]) for a in result.attempts], bool(fig.axes[1].get_xlim()[1] > 7)
    ([4, 4], True)
    >>> plt.close(fig)
    """
    from .hand import SynergyHand

    _check(result=result)
    if attempts not in (None, "all", "last"):
        raise ValueError(f"attempts must be 'all', 'last' or None, got {attempts!r}")
    if labels is None:
        paper = SynergyHand.default()
        if not paper.made(result.hand):
            raise ValueError(f"the result was planned with hand {result.hand!r}, whose status rows are not the paper "
                             "hand's: pass labels=hand.point_labels(result.grasp) of that hand")
        labels = paper.point_labels(result.grasp)
    if not isinstance(labels, str) and hasattr(labels, "__iter__"):
        labels = list(labels)  # (a generator is read once: listed before it is checked)
    if not isinstance(labels, list) or not all(isinstance(label, str) and label for label in labels):
        raise ValueError(f"labels must be a list of non-empty names, one per cP row, got {labels!r}: pass the planning "
                         "hand's hand.point_labels(result.grasp)")
    if len(labels) >= np.shape(result.status)[1]:
        raise ValueError(f"{len(labels)} labels for the {np.shape(result.status)[1] - 1} cP rows of the result's status: "
                         "pass the planning hand's hand.point_labels(result.grasp)")
    traces = [a["status"] for a in result.attempts if "status" in a]
    if attempts is None:
        attempts = "last" if result.success else "all"
    if attempts == "last" or len(traces) != len(result.attempts) or len(traces) < 2:
        traces = [np.asarray(result.status)]
    traces = [np.asarray(t, dtype=float) for t in traces]
    starts = np.cumsum([0] + [len(t) for t in traces[:-1]])
    # one polyline per row, broken (NaN) between attempts
    k = np.concatenate([np.r_[s + np.arange(len(t)), np.nan] for s, t in zip(starts, traces)])[:-1]
    status = np.vstack([np.vstack([t, np.full((1, t.shape[1]), np.nan)]) for t in traces])[:-1]
    reach = len(result.path) > 0
    fig, axes = plt.subplots(3 if reach else 2, 1, figsize=(8, 9.0 if reach else 6.5),
                             gridspec_kw={"height_ratios": [3, 2, 2] if reach else [3, 2]})
    top, bottom = axes[0], axes[1]
    bottom.sharex(top)
    top.tick_params(labelbottom=False)
    rows = [_finger_and_phalanx(label) for label in labels]
    colours = {name: _CHAIN_COLORS[c % len(_CHAIN_COLORS)]  # the fingers in their order, as the poses figure's
               for c, name in enumerate(dict.fromkeys(name for name, j in rows if j is not None))}
    for i, (label, (name, j)) in enumerate(zip(labels, rows)):
        top.plot(k, status[:, i], color=colours.get(name, "black"), lw=1.4,
                 ls=["-", "--", ":", "-."][j % 4] if j is not None else "-", label=f"$g_{{{label}}}$")
    eps_c = result.options.get("eps_c", 5.0)
    top.axhline(eps_c, color="k", lw=0.8, ls="--", label=r"$\varepsilon_c$")
    top.axhline(0.0, color="gray", lw=0.6)
    top.set_ylabel("cP (mm)")
    top.set_yscale("symlog", linthresh=10.0)
    top.legend(ncol=6 if len(labels) > 6 else 4, fontsize=7, loc="upper right")
    outcome = "success" if result.success else "no grasp"
    if len(traces) > 1:
        top.set_title(f"{result.object_name}, {result.grasp} grasp: {outcome}; attempts 1-{len(traces)}, "
                      f"{sum(len(t) - 1 for t in traces)} iterations", pad=14)
        every = max(1, int(np.ceil(len(traces) / 20)))
        for number, start in enumerate(starts, 1):
            for ax in (top, bottom):
                ax.axvline(start, color="0.6", lw=0.6)
            if (number - 1) % every == 0:
                top.annotate(str(number), (start, 1.0), xycoords=("data", "axes fraction"), xytext=(2, 2),
                             textcoords="offset points", fontsize=7, color="0.35", va="bottom")
    else:
        top.set_title(f"{result.object_name}, {result.grasp} grasp: {outcome} after {result.iterations} iterations")
    bottom.plot(k, status[:, -1], color="tab:blue", lw=1.6, label=r"$g_{sQ}$")
    last = starts[-1] + np.arange(len(traces[-1]))
    bottom.plot(last, np.asarray(result.q_history)[-len(last):], color="tab:red", lw=1.2,
                label=r"$g_Q$ (real contacts" + (", last attempt)" if len(traces) > 1 else ")"))
    bottom.axhline(-0.1, color="k", lw=0.8, ls="--", label="-0.1")
    bottom.axhline(0.0, color="gray", lw=0.6)
    bottom.set_ylabel("Q distance")
    bottom.set_xlabel("iteration k" + (" (attempts one after another)" if len(traces) > 1 else ""))
    bottom.legend(fontsize=8, loc="upper right")
    if reach:
        _plot_clearance(axes[2], result)
    fig.tight_layout()
    return fig


def _plot_clearance(ax, result):
    """The clearance along the executable reach, on its own axes."""
    rows = np.arange(len(result.clearance))
    tolerance = result.reach.get("tolerance", result.options.get("max_penetration", 3.0))
    ax.plot(rows, result.clearance, color="tab:green", lw=1.6, marker=".", ms=3, label="clearance (capsules and palm)")
    ax.axhline(0.0, color="gray", lw=0.6)
    ax.axhline(-tolerance, color="k", lw=0.8, ls="--", label=f"-{tolerance:g} mm (tolerance)")
    deepest = int(np.argmin(result.clearance))
    where = result.reach.get("deepest") or "none"
    ax.plot(deepest, result.clearance[deepest], "v", color="tab:red", label=f"deepest: {where}")
    ax.set_yscale("symlog", linthresh=10.0)
    ax.set_ylabel("clearance (mm)")
    ax.set_xlabel("row of the executable reach (pre-grasp to grasp)")
    ax.set_title(f"executable reach: {'collision-free' if result.collision_free else 'NOT collision-free'}, "
                 f"deepest {max(0.0, -float(result.clearance.min())):.1f} mm", fontsize=10)
    ax.legend(fontsize=8, loc="upper right")


#: `_check`'s default: an argument the figure does not take.
_ABSENT = object()


def _check(result=_ABSENT, obj=_ABSENT, hand=_ABSENT):
    """TypeError unless each given argument is what the figures draw: a PlanResult, a GraspObject, a SynergyHand
    (None is not); ValueError for a result planned with another hand than ``hand`` (`PlanResult.hand`) or for
    another object than ``obj`` (its name)."""
    from .hand import SynergyHand
    from .objects import GraspObject
    from .planner import PlanResult

    for name, value, kind in (("result", result, PlanResult), ("obj", obj, GraspObject), ("hand", hand, SynergyHand)):
        if value is not _ABSENT and not isinstance(value, kind):
            raise TypeError(f"{name} must be a {kind.__name__}, got {type(value).__name__}")
    if result is not _ABSENT and hand is not _ABSENT and not hand.made(result.hand):
        raise ValueError(f"the result was planned with hand {result.hand!r}, not with {hand.identity!r}: pass the "
                         "hand that made it")
    if result is not _ABSENT and obj is not _ABSENT and result.object_name != obj.name:
        raise ValueError(f"the result was planned for object {result.object_name!r}, not for {obj.name!r}: pass the "
                         "object it was planned for")


def _save(fig, path, dpi):
    """Lay out, write (atomically) and close a figure; returns ``Path(path)``."""
    fig.tight_layout()
    path = as_path(path, "the image path")
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi)
    finally:
        plt.close(fig)
    return path


#: Faces of an object's mesh drawn at most: a larger mesh is drawn as its convex pieces (matplotlib draws every
#: face in every frame, about 1.5 s per frame for 300k faces).
DRAW_FACES = 20_000


def _draw_object(ax, obj):
    """The object's mesh on a 3-D axes; its convex pieces instead when it has no mesh or more than `DRAW_FACES` faces."""
    mesh = obj.mesh if obj.mesh is not None and len(obj.mesh.faces) <= DRAW_FACES else \
        trimesh.util.concatenate(obj.piece_meshes())
    poly = Poly3DCollection(mesh.vertices[mesh.faces], facecolor=(0.85, 0.75, 0.55, 0.35), edgecolor=(0.5, 0.4, 0.3, 0.15), lw=0.2)
    ax.add_collection3d(poly)


def _draw_hand(ax, hand, u, alpha=1.0, lw=4.0):
    geo = hand.segments(u)
    artists = []
    for (a, b), color in zip(geo.capsules, _segment_colors(hand)):
        artists += ax.plot(*np.c_[a, b], color=color, lw=lw, alpha=alpha, solid_capstyle="round")
    corners = geo.palm_corners
    top = corners[[0, 1, 3, 2, 0]] if len(corners) == 8 else corners
    artists += ax.plot(*top.T, color="k", lw=1.0, alpha=alpha)
    return artists


def _frame_axes(ax, obj, points):
    lo = np.minimum(obj.bounds[0], points.min(axis=0))
    hi = np.maximum(obj.bounds[1], points.max(axis=0))
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")


def plot_poses(result, obj, hand, path, count=5):
    """Hand poses at several iterations around the object, like the paper's Figs. 7a-14a.

    Parameters
    ----------
    result : PlanResult
        A plan of ``obj`` with ``hand``.
    obj : GraspObject
        The planned object.
    hand : SynergyHand
        The hand that made the plan.
    path : str or Path
        Output image (.png, .svg, .pdf).
    count : int
        Number of poses drawn, evenly spread over the trajectory (last
        included; at most one per iteration).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    TypeError
        If ``result``, ``obj`` or ``hand`` is of the wrong type.
    ValueError
        If the file's extension is not an image format matplotlib writes, ``count`` < 1, or the
        result was planned for another object or with another hand.
    FileNotFoundError
        If the folder of ``path`` does not exist.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from synergrasp import SynergyHand, objects, plan
    >>> obj, hand = objects.ellipsoid(), SynergyHand.default()
    >>> result = plan(obj, "precision", max_iter=3, restarts=1)
    >>> plot_poses(result, obj, hand, pathlib.Path(tempfile.mkdtemp()) / "poses.png").exists()
    True
    """
    _check(result=result, obj=obj, hand=hand)
    path = image_path(path)
    count = integer(count, "count", what="poses drawn")
    traj = np.asarray(result.trajectory)
    picks = np.unique(np.linspace(0, len(traj) - 1, min(count, len(traj))).round().astype(int))
    fig = plt.figure(figsize=(7, 7))
    ax = fig.add_subplot(projection="3d")
    _draw_object(ax, obj)
    points = []
    for rank, k in enumerate(picks):
        alpha = 0.25 + 0.75 * (rank + 1) / len(picks)
        _draw_hand(ax, hand, traj[k], alpha=alpha, lw=2.5 + 2.0 * (k == picks[-1]))
        points.append(hand.segments(traj[k]).capsules.reshape(-1, 3))
    if len(result.contact_points):
        ax.scatter(*np.asarray(result.contact_points).T, color="k", s=18, depthshade=False)
    _frame_axes(ax, obj, np.vstack(points))
    ax.set_title(f"{result.object_name}, {result.grasp}: iterations {', '.join(map(str, picks))}\n"
                 "(fainter: earlier; the final pose is drawn thickest)", fontsize=10)
    handles = [plt.Line2D([], [], color=_CHAIN_COLORS[c % len(_CHAIN_COLORS)], lw=4) for c in range(len(hand.finger_names))]
    names = [_FINGER_NAMES.get(f, f) for f in hand.finger_names]
    handles.append(plt.Line2D([], [], color="k", lw=1))
    names.append("palm")
    if len(result.contact_points):
        handles.append(plt.Line2D([], [], color="k", marker="o", ls="", markersize=5))
        names.append("contacts")
    ax.legend(handles, names, loc="upper left", fontsize=8, frameon=False)
    return _save(fig, path, dpi=120)


def plot_grasps(plans, hand, path, columns=6):
    """A gallery of final grasps: one small 3-D view per plan.

    Parameters
    ----------
    plans : sequence of (PlanResult, GraspObject, str)
        Each plan with its object and a caption (e.g. "mug: ok").
    hand : SynergyHand
        The hand that made the plans.
    path : str or Path
        Output image (.png, .svg, .pdf).
    columns : int
        Views per row.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    TypeError
        If a result, object or the hand is of the wrong type.
    ValueError
        If ``plans`` is empty or malformed, a plan is of another hand (`PlanResult.hand`), the extension is
        not an image format, or ``columns`` < 1.
    FileNotFoundError
        If the folder of ``path`` does not exist.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from synergrasp import SynergyHand, objects, plan
    >>> obj, hand = objects.ellipsoid(), SynergyHand.default()
    >>> result = plan(obj, "precision", max_iter=3, restarts=1)
    >>> plot_grasps([(result, obj, "ellipsoid")], hand, pathlib.Path(tempfile.mkdtemp()) / "g.png").exists()
    True
    """
    if isinstance(plans, np.ndarray) or not hasattr(plans, "__iter__"):
        raise TypeError(f"plans must be a list of (result, object, caption) triples, got {type(plans).__name__}")
    plans = list(plans)
    if not plans:
        raise ValueError("plot_grasps needs at least one (result, object, caption) triple")
    _check(hand=hand)
    path = image_path(path)
    for i, plan in enumerate(plans):
        if not isinstance(plan, (tuple, list)) or len(plan) != 3:
            raise ValueError(f"plans[{i}] must be a (result, object, caption) triple")
        _check(result=plan[0], obj=plan[1], hand=hand)
    columns = integer(columns, "columns")
    columns = max(1, min(int(columns), len(plans)))
    rows = -(-len(plans) // columns)
    fig = plt.figure(figsize=(2.6 * columns, 2.6 * rows))
    for i, (result, obj, caption) in enumerate(plans):
        ax = fig.add_subplot(rows, columns, i + 1, projection="3d")
        _draw_object(ax, obj)
        _draw_hand(ax, hand, np.asarray(result.u), lw=2.0)
        if len(result.contact_points):
            ax.scatter(*np.asarray(result.contact_points).T, color="k", s=6, depthshade=False)
        _frame_axes(ax, obj, hand.segments(result.u).capsules.reshape(-1, 3))
        ax.set_axis_off()
        ax.set_title(caption, fontsize=8)
    return _save(fig, path, dpi=110)


def animate(result, obj, hand, path, fps=15, max_frames=120, rows="trajectory"):
    """GIF animation of a plan: the planner's iteration, or the executable reach to execute.

    Parameters
    ----------
    result : PlanResult
        A plan of ``obj`` with ``hand``.
    obj : GraspObject
        The planned object.
    hand : SynergyHand
        The hand that made the plan.
    path : str or Path
        Output ``.gif``.
    fps : int
        Frames per second.
    max_frames : int
        Longer sequences are subsampled.
    rows : {"trajectory", "path"}
        ``"trajectory"``: the planner's iteration (`PlanResult.trajectory`,
        the search that found the grasp; each frame titled with its
        iteration k and g_sQ). ``"path"``: the executable reach
        (`PlanResult.path`, from the pre-grasp to the grasp; each frame
        titled with its row and the hand's clearance there).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    TypeError
        If ``result``, ``obj`` or ``hand`` is of the wrong type.
    ValueError
        If ``path`` does not end in .gif, ``fps`` or ``max_frames`` < 1,
        ``rows`` is neither name, or ``rows="path"`` for a plan without an
        executable reach.
    FileNotFoundError
        If the folder of ``path`` does not exist.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from synergrasp import SynergyHand, objects, plan
    >>> obj, hand = objects.ellipsoid(), SynergyHand.default()
    >>> result = plan(obj, "precision", max_iter=3, restarts=1)
    >>> animate(result, obj, hand, pathlib.Path(tempfile.mkdtemp()) / "reach.gif").exists()
    True
    """
    _check(result=result, obj=obj, hand=hand)
    path = image_path(path, [".gif"])
    fps, max_frames = integer(fps, "fps"), integer(max_frames, "max_frames")
    if rows not in ("trajectory", "path"):
        raise ValueError(f"rows must be 'trajectory' (the planner's iteration) or 'path' (the executable reach), "
                         f"got {rows!r}")
    if rows == "path" and not len(result.path):
        raise ValueError("the plan has no executable reach (no grasp was found, or it was planned with "
                         "executable_reach=False): animate its trajectory (rows='trajectory')")
    traj = np.asarray(result.trajectory if rows == "trajectory" else result.path)
    frames = np.unique(np.linspace(0, len(traj) - 1, min(len(traj), max_frames)).round().astype(int))
    fig = plt.figure(figsize=(5.5, 5.5))
    ax = fig.add_subplot(projection="3d")
    _draw_object(ax, obj)
    _frame_axes(ax, obj, np.vstack([hand.segments(traj[k]).capsules.reshape(-1, 3) for k in frames[[0, -1]]]))
    artists = []

    def draw(k):
        for artist in artists:
            artist.remove()
        artists[:] = _draw_hand(ax, hand, traj[k])
        ax.set_title(f"k = {k}   g_sQ = {result.status[k, -1]:+.3f}" if rows == "trajectory" else
                     f"reach row {k} of {len(traj)}   clearance {result.clearance[k]:+.1f} mm")
        return artists

    anim = animation.FuncAnimation(fig, draw, frames=frames, blit=False)
    try:
        with atomic_path(path) as tmp:
            anim.save(tmp, writer=animation.PillowWriter(fps=fps))
    finally:
        plt.close(fig)
    return path


def scene(obj, hand, u):
    """A trimesh scene of the object and the hand at configuration u.

    Parameters
    ----------
    obj : GraspObject
        The object (its mesh, else its convex pieces).
    hand : SynergyHand
        The hand, drawn as its phalanx capsules and palm box.
    u : (6 + n_syn,) array_like
        Hand configuration.

    Returns
    -------
    trimesh.Scene
        The object and the hand's parts as coloured meshes (``scene.show()`` opens a viewer
        where one is installed; ``scene.export("grasp.glb")`` writes a file).

    Raises
    ------
    TypeError
        If ``obj`` or ``hand`` is of the wrong type, or ``u`` not numeric.
    ValueError
        If ``u`` does not fit the hand, or its synergies lie outside the hand's limits.

    Examples
    --------
    >>> from synergrasp import SynergyHand, objects
    >>> hand = SynergyHand.default()
    >>> len(scene(objects.ellipsoid(), hand, np.r_[0.0, 0.0, 150.0, np.zeros(5)]).geometry)  # object, 15 phalanges, palm
    17
    """
    _check(obj=obj, hand=hand)
    u = hand.check_u(u)
    hand.check_synergies(u[6:], "u's synergies")  # (a pose the hand cannot take)
    meshes = [(obj.mesh if obj.mesh is not None else obj.to_mesh()).copy()]
    meshes[0].visual.face_colors = [220, 190, 140, 160]
    geo = hand.segments(u)
    for (a, b), color in zip(geo.capsules, _segment_colors(hand)):
        capsule = trimesh.creation.capsule(height=float(np.linalg.norm(b - a)), radius=geo.radius, count=[12, 12])
        capsule.apply_transform(trimesh.geometry.align_vectors([0, 0, 1], b - a))
        capsule.apply_translation((a + b) / 2)
        capsule.visual.face_colors = (np.array(matplotlib.colors.to_rgba(color)) * 255).astype(int)
        meshes.append(capsule)
    palm = trimesh.creation.box(extents=2 * geo.palm_half_extents)
    transform = np.eye(4)
    transform[:3, :3], transform[:3, 3] = geo.palm_axes, geo.palm_center
    palm.apply_transform(transform)
    palm.visual.face_colors = [90, 90, 90, 255]
    meshes.append(palm)
    return trimesh.Scene(meshes)


def write_html(obj, hand, u, path):
    """An interactive 3-D page (three.js through trimesh) of the hand around the object.

    Parameters
    ----------
    obj : GraspObject
        The object.
    hand : SynergyHand
        The hand.
    u : (6 + n_syn,) array_like
        Hand configuration, typically ``result.u`` (the final grasp).
    path : str or Path
        Output ``.html``.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    TypeError
        If ``obj`` or ``hand`` is of the wrong type.
    FileNotFoundError
        If the folder of ``path`` does not exist.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from synergrasp import SynergyHand, objects
    >>> page = pathlib.Path(tempfile.mkdtemp()) / "grasp.html"
    >>> write_html(objects.ellipsoid(), SynergyHand.default(), np.r_[0.0, 0.0, 150.0, np.zeros(5)], page).exists()
    True
    """
    from trimesh.viewer.notebook import scene_to_html

    path = image_path(path, [".html", ".htm"])
    page = scene_to_html(scene(obj, hand, u))
    with atomic_path(path) as tmp:
        tmp.write_text(page)
    return path
