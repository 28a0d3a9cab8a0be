"""The bad-input catalogue: every public entry point (API and command line) fed input it must refuse.

Each case is run by tests/test_catalogue.py and listed on the documentation page "What
synergrasp checks" (docs/checks.md, generated from this list by ``python -m tests.doc_pages
--write``; a test fails if the page and the list differ). A case ends either in the documented
exception type with a message that contains ``says`` (raised by synergrasp itself, never from
inside numpy, a solver, trimesh, fcl or coacd), or, for ``raises=None``, in a result that
``check`` accepts. Command-line cases run ``synergrasp`` with ``argv`` and expect exit status 2
and ``says`` on stderr.

Planner-option cases (``PlannerOptions`` and ``AnnealingOptions`` fields, the method) belong in
``PLANNER_OPTIONS`` below.
"""

from __future__ import annotations

import json
from decimal import Decimal
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
import trimesh

import synergrasp as sg
import synergrasp.objects as so
from synergrasp import viz
from synergrasp.lp.clarabel import ClarabelBackend
from synergrasp.lp.cvxpy import CvxpyBackend
from synergrasp.physics import probes
from synergrasp.objects.contact_distance import group_contact_distance
from synergrasp.planner import check_grasp, executable_reach, grasp_status, hand_clearance, path_clearance, recess


@dataclass(frozen=True)
class Case:
    """One bad input: where it goes, what it is, and how synergrasp must answer."""

    entry: str
    what: str
    call: Callable | None = None  # (folder) -> result; ``folder`` is an empty temporary folder
    raises: type | None = ValueError
    says: str = ""
    argv: list | None = None  # a command-line case: synergrasp's arguments (``{tmp}`` is the folder)
    check: Callable | None = field(default=None, repr=False)  # for results: result -> bool

    @property
    def id(self) -> str:
        return f"{self.entry}: {self.what}"


def _cloud(n=300, radius=30.0, seed=0):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return radius * d / np.linalg.norm(d, axis=1, keepdims=True)


def _box_corners(half=10.0):
    return np.array([[x, y, z] for x in (-half, half) for y in (-half, half) for z in (-half, half)])


def _inside_out_box():
    box = trimesh.creation.box((60.0, 50.0, 70.0))
    box.invert()
    return box


def _two_balls():
    ball = trimesh.creation.icosphere(radius=25.0)
    return trimesh.util.concatenate([ball.copy().apply_translation([-100.0, 0.0, 0.0]), ball.copy().apply_translation([100.0, 0.0, 0.0])])


def _write(folder, name, text=None, data=None):
    path = Path(folder) / name
    if text is not None:
        path.write_text(text) if isinstance(text, str) else path.write_bytes(text)
    elif data is not None:
        np.save(path, data)
    return path


def _folder(path):
    """``path`` made a folder (with its parents)."""
    Path(path).mkdir(parents=True)
    return Path(path)


def _npz_mesh(folder, faces_of):
    ball = trimesh.creation.icosphere(subdivisions=1, radius=30.0)
    path = Path(folder) / "m.npz"
    np.savez(path, vertices=ball.vertices, faces=faces_of(ball.faces))
    return path


def _hand_dict():
    return sg.SynergyHand.default().to_dict()


def _with_joint_field(key, value):
    data = _hand_dict()
    data["fingers"][1]["joints"][0][key] = value
    return data


def _with_synergy(row, column, value):
    data = _hand_dict()
    data["synergies"][row][column] = value
    return data


def _in_metres():
    """The paper's hand with every length divided by 1000."""
    data = _hand_dict()
    palm = data["palm"]
    for key in ("center", "size", "point"):
        palm[key] = [v / 1000.0 for v in palm[key]]
    data["finger_radius"] /= 1000.0
    data["contact_offset"] = data.get("contact_offset", 0.0) / 1000.0
    for finger in data["fingers"]:
        finger["base"]["position"] = [v / 1000.0 for v in finger["base"]["position"]]
        for joint in finger["joints"]:
            joint["length"] /= 1000.0
    return data


def _nan_obj(folder):
    ball = trimesh.creation.icosphere(subdivisions=1, radius=30.0)
    v = ball.vertices.copy()
    v[5] = np.nan
    text = "".join(f"v {x} {y} {z}\n" for x, y, z in v) + "".join(f"f {a} {b} {c}\n" for a, b, c in ball.faces + 1)
    return _write(folder, "ball.obj", text)


def _arch():
    """Half a tube: an open surface whose rim is not planar and which encloses nothing."""
    tube = trimesh.creation.cylinder(radius=30.0, height=80.0, sections=32)
    keep = (np.abs(tube.face_normals[:, 2]) < 0.5) & (tube.triangles_center[:, 1] > 0)
    return trimesh.Trimesh(tube.vertices, tube.faces[keep])


def _kilometre_reach():
    """A replay of a straight reach 1e6 mm long to a pinch of a box (its fingertips 1 mm from the faces)."""
    u, box = probes.pinch_grasp()
    far = u.copy()
    far[1] -= 1e6
    return sg.replay_reach(np.array([far, u]), box)


def _plan_file(folder, **changes):
    """A saved PlanResult (3 iterations) with some fields changed."""
    path = sg.plan("ellipsoid", "precision", max_iter=3).save(Path(folder) / "plan.json")
    data = json.loads(path.read_text())
    data.update(changes)
    path.write_text(json.dumps(data))
    return path


def _grasp_file(folder, source=None, deep=None):
    """A saved PlanResult with a grasp and its executable reach, its reach's source or one row's clearance changed."""
    path = sg.plan("ellipsoid", "precision").save(Path(folder) / "grasp.json")
    data = json.loads(path.read_text())
    if source is not None:
        data["reach"]["source"] = source
    if deep is not None:
        data["clearance"][len(data["clearance"]) // 2] = -deep
    path.write_text(json.dumps(data))
    return path


P2, N2 = [[0.0, 0.0, 10.0], [0.0, 0.0, -10.0]], [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]
A3, B3 = 10.0 * np.eye(3), 10.0 * np.eye(3) + 50.0
HAND = sg.SynergyHand.default()


def _q(**kw):
    args = {"points": P2, "normals": N2, **kw}
    return lambda tmp: sg.q_distance(args.pop("points"), args.pop("normals"), **args)


def _pd(A=A3, B=B3, **kw):
    return lambda tmp: sg.pseudo_distance(A, B, **kw)



def _far_status(kind="precision"):
    """The status of the paper's ellipsoid at the planner's first start."""
    from synergrasp.planner import start_configuration

    obj = so.ellipsoid()
    return grasp_status(HAND, obj, start_configuration(HAND, obj), kind)


API = [
    # ------------------------------------------------------------ pseudo_distance, regular_simplex
    Case("sg.pseudo_distance", "A is a string", _pd(A="abc"), TypeError, "A must be a numeric array of shape (n, d)"),
    Case("sg.pseudo_distance", "A is one flat vector", _pd(A=[1.0, 2.0, 3.0]), ValueError, "A must have shape (n, d)"),
    Case("sg.pseudo_distance", "A and B of different dimensions", _pd(B=np.ones((3, 2))), ValueError, "B has points of dimension 2, expected 3"),
    Case("sg.pseudo_distance", "points of dimension 1", _pd(A=[[1.0]], B=[[2.0]]), ValueError, "A has dimension 1, at least 2 is required"),
    Case("sg.pseudo_distance", "a NaN coordinate", _pd(A=[[np.nan, 0.0, 0.0]]), ValueError, "A contains NaN or inf at rows [0]"),
    Case("sg.pseudo_distance", "an infinite coordinate", _pd(B=[[np.inf, 0.0, 0.0]]), ValueError, "B contains NaN or inf at rows [0]"),
    Case("sg.pseudo_distance", "an empty set", _pd(A=np.zeros((0, 3))), ValueError, "A is empty"),
    Case("sg.pseudo_distance", "complex coordinates", _pd(A=A3 + 1j), TypeError, "got an array of dtype complex128"),
    Case("sg.pseudo_distance", "a ragged nested list", _pd(A=[[0.0, 0.0, 0.0], [1.0, 0.0]]), TypeError, "got a ragged list"),
    Case("sg.pseudo_distance", "text in an array of objects (read as numbers)", _pd(A=np.array([["0", "0", "1"]], dtype=object)),
         TypeError, "A must be a numeric array of shape (n, d), got an array of dtype object"),
    Case("sg.pseudo_distance", "dates (read as days)", _pd(A=np.array([["2026-01-01"] * 3], dtype="datetime64[D]")), TypeError,
         "got an array of dtype datetime64[D]"),
    Case("sg.pseudo_distance", "points of dimension 1001", _pd(A=np.zeros((1, 1001)), B=np.ones((1, 1001))), ValueError, "at most 1000 is supported"),
    Case("sg.pseudo_distance", "a simplex of the wrong shape", _pd(simplex=np.eye(3)), ValueError, "simplex must have d+1 = 4 vertices"),
    Case("sg.pseudo_distance", "a simplex not around the origin", _pd(simplex=sg.regular_simplex(3) + 5.0), ValueError, "simplex must contain the origin strictly inside"),
    Case("sg.pseudo_distance", "a simplex flattened to 1e-9 of its size (HiGHS called the LP infeasible, Clarabel was 27 % off)",
         _pd(simplex=sg.regular_simplex(3) * [1.0, 1.0, 1e-9]), ValueError, "simplex is degenerate or nearly so"),
    Case("sg.pseudo_distance", "an integer coordinate beyond a float's range", _pd(A=[[10**400, 0, 0]]), ValueError,
         "A has an entry beyond a float's range"),
    Case("sg.pseudo_distance", "a coordinate that is a Decimal", _pd(A=[[Decimal(1), 0.0, 0.0]]), TypeError,
         "A must be a numeric array of shape (n, d), got list with an entry of type Decimal"),
    Case("sg.pseudo_distance", "an unknown backend", _pd(backend="glpk"), ValueError, "unknown LP backend 'glpk'"),
    Case("sg.pseudo_distance", "sets 1e-300 across: solved rescaled", _pd(A=A3 * 1e-300, B=B3 * 1e-300), None, "value 1.2e-298",
         check=lambda r: r.kind == "separation" and abs(r.value / 1.2e-298 - 1) < 1e-9),
    Case("sg.pseudo_distance", "sets 1e300 away: solved rescaled", _pd(A=A3 * 1e300, B=B3 * 1e300), None, "value 1.2e302",
         check=lambda r: abs(r.value / 1.2e302 - 1) < 1e-9),
    Case("sg.pseudo_distance", "values that overflow the float range", _pd(A=[[-1.7e308, 0.0]], B=[[1.7e308, 0.0]]), ValueError, "overflows the float range"),
    Case("sg.pseudo_distance", "301 + 301 points in 300 dimensions (gigabytes)",
         lambda tmp: sg.pseudo_distance(np.ones((301, 300)), np.zeros((301, 300))), ValueError,
         "make a penetration LP of 5.46e+07 nonzeros, more than the 1e+07 synergrasp builds"),
    Case("sg.regular_simplex", "d = 0", lambda tmp: sg.regular_simplex(0), ValueError, "d must be an integer from 2 to 1000"),
    Case("sg.regular_simplex", "d is a string", lambda tmp: sg.regular_simplex("3"), ValueError, "d must be an integer from 2 to 1000"),
    Case("sg.regular_simplex", "d = 10**6 (terabytes)", lambda tmp: sg.regular_simplex(10**6), ValueError, "d must be an integer from 2 to 1000"),
    # ------------------------------------------------------------ quality
    Case("sg.q_distance", "a zero-length normal", _q(normals=[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]]), ValueError, "normals has zero-length rows [0]"),
    Case("sg.q_distance", "a zero normal beside one of 1e200", _q(normals=[[0.0, 0.0, -1e200], [0.0, 0.0, 0.0]]), ValueError,
         "normals has zero-length rows [1]"),
    Case("sg.q_distance", "an integer friction coefficient beyond a float's range", _q(mu=10**400), ValueError,
         "mu must be a finite number > 0"),
    Case("sg.q_distance", "fewer normals than points", _q(normals=[[0.0, 0.0, 1.0]]), ValueError, "one normal per contact"),
    Case("sg.q_distance", "a friction coefficient of True", _q(mu=True), TypeError, "mu must be a number, got bool"),
    Case("sg.q_distance", "a complex friction coefficient", _q(mu=np.complex128(0.3)), TypeError,
         "mu must be a number, got complex128"),
    Case("sg.q_distance", "points written as text", _q(points=[["0", "0", "1"], ["1", "0", "0"]]), TypeError,
         "points must be a numeric array of shape (n, d), got a list of text"),
    Case("sg.q_distance", "points with masked entries",
         _q(points=np.ma.masked_array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]], mask=[[1, 0, 0], [0, 0, 0]])), TypeError,
         "got a masked array with masked entries"),
    Case("sg.q_distance", "a NaN contact point", _q(points=[[0.0, 0.0, np.nan], [1.0, 0.0, 0.0]]), ValueError, "points contains NaN"),
    Case("sg.q_distance", "2-D contact points", _q(points=[[0.0, 0.0], [1.0, 0.0]]), ValueError, "dimension 2, expected 3"),
    Case("sg.q_distance", "no contacts", _q(points=np.zeros((0, 3)), normals=np.zeros((0, 3))), ValueError, "points is empty"),
    Case("sg.q_distance", "mu = 0", _q(mu=0.0), ValueError, "mu must be a finite number > 0"),
    Case("sg.q_distance", "mu = NaN", _q(mu=np.nan), ValueError, "mu must be a finite number > 0"),
    Case("sg.q_distance", "mu = 1e300", _q(mu=1e300), ValueError, "mu must be a number in (0, 1000]"),
    Case("sg.q_distance", "mu is a string", _q(mu="0.3"), TypeError, "mu must be a number, got str"),
    Case("sg.q_distance", "2 cone edges", _q(edges=2), ValueError, "edges must be an integer from 3 to 1000"),
    Case("sg.q_distance", "4.5 cone edges", _q(edges=4.5), ValueError, "edges must be an integer"),
    Case("sg.q_distance", "10**9 cone edges (gigabytes)", _q(edges=10**9), ValueError, "edges must be an integer from 3 to 1000"),
    Case("sg.q_distance", "a 2-D centre", _q(center=[0.0, 0.0]), ValueError, "center must have shape (3,)"),
    Case("sg.q_distance", "torque_scale = 0", _q(torque_scale=0.0), ValueError, "torque_scale must be a finite number > 0"),
    Case("sg.q_distance", "torque_scale = 1e-9 for contacts 10 mm from the centre", _q(torque_scale=1e-9), ValueError,
         "torque_scale 1e-09 is more than 10000 times smaller than the contacts' largest lever arm"),
    Case("sg.q_distance", "every contact at the centre", _q(points=[[0.0, 0.0, 0.0]], normals=[[0.0, 0.0, 1.0]]), ValueError, "pass torque_scale"),
    Case("sg.q_distance", "an unknown backend", _q(backend="glpk"), ValueError, "unknown LP backend"),
    Case("sg.q_distance", "30,000 contacts (built gigabytes of wrenches before the LP was refused)",
         lambda tmp: sg.q_distance(np.tile(P2, (15000, 1)), np.tile(N2, (15000, 1))), ValueError,
         "30000 contacts of 8 cone edges make a Q-distance LP of more than the 1e+07 nonzeros synergrasp builds"),
    Case("sg.q_distance", "checked=True without center", _q(checked=True), ValueError,
         "checked=True is for arrays the library made, with center and torque_scale given"),
    Case("sg.q_distance", "checked=True with fewer normals than points (the last contact was dropped silently)",
         _q(points=[[0.0, 0.0, 10.0], [0.0, 0.0, -10.0], [10.0, 0.0, 0.0]], normals=[[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]],
            center=np.zeros(3), torque_scale=10.0, checked=True), ValueError, "one normal per contact point"),
    Case("sg.q_distance", "checked = \"yes\"", _q(checked="yes"), TypeError, "checked must be True or False, got str 'yes'"),
    Case("sg.q_distance", "one contact: a result, not force-closed", _q(points=[[0.0, 0.0, 10.0]], normals=[[0.0, 0.0, -1.0]]), None,
         "Q > 0", check=lambda r: r.value > 0 and not r.force_closure),
    Case("sg.q_distance", "the same contact four times: a result", _q(points=[[0.0, 0.0, 10.0]] * 4, normals=[[0.0, 0.0, -1.0]] * 4),
         None, "the value of one contact", check=lambda r: abs(r.value - sg.q_distance([[0.0, 0.0, 10.0]], [[0.0, 0.0, -1.0]]).value) < 1e-9),
    Case("sg.friction_cone_edges", "one flat normal vector", lambda tmp: sg.friction_cone_edges([0.0, 0.0, 1.0]), ValueError, "normals must have shape (n, d)"),
    Case("sg.friction_cone_edges", "a negative mu", lambda tmp: sg.friction_cone_edges([[0.0, 0.0, 1.0]], mu=-1.0), ValueError, "mu must be a finite number > 0"),
    Case("sg.contact_wrenches", "more points than normals", lambda tmp: sg.contact_wrenches(P2, N2[:1]), ValueError, "one normal per contact"),
    Case("sg.force_closure_by_hull", "3-D wrenches", lambda tmp: sg.force_closure_by_hull(np.ones((10, 3))), ValueError, "wrenches has points of dimension 3, expected 6"),
    Case("sg.force_closure_by_hull", "NaN wrenches", lambda tmp: sg.force_closure_by_hull(np.full((8, 6), np.nan)), ValueError, "wrenches contains NaN or inf"),
    Case("sg.force_closure_by_hull", "5 contacts of 64 cone edges (320 wrenches: qhull takes seconds to minutes)", lambda tmp: sg.force_closure_by_hull(np.random.default_rng(0).normal(size=(320, 6))), ValueError, "it takes at most 256"),
    Case("sg.force_closure_by_hull", "a string tolerance", lambda tmp: sg.force_closure_by_hull(np.eye(6), tol="0"), ValueError, "tol must be a finite number >= 0"),
    # ------------------------------------------------------------ plan and its results
    Case("sg.plan", "an unknown grasp type", lambda tmp: sg.plan("ellipsoid", "pinch"), ValueError, "grasp must be 'precision' or 'power', got 'pinch'"),
    Case("sg.plan", "an object that is a number", lambda tmp: sg.plan(3), TypeError, "obj must be a GraspObject, a built-in name or a file path"),
    Case("sg.plan", "a trimesh mesh, not yet an object", lambda tmp: sg.plan(trimesh.creation.box((60.0, 40.0, 30.0))), TypeError,
         "a mesh in memory becomes one with sg.objects.from_mesh(mesh)"),
    Case("sg.plan", "a point array, not yet an object", lambda tmp: sg.plan(np.random.default_rng(0).normal(size=(50, 3))), TypeError,
         "a point cloud becomes one with sg.objects.from_points(points)"),
    Case("sg.plan", "an unknown object name", lambda tmp: sg.plan("teapot"), ValueError, "unknown object 'teapot'"),
    Case("sg.plan", "an object 1 mm wide (metres?)", lambda tmp: sg.plan(so.ellipsoid(0.5, 0.5, 0.5)), sg.planner.ObjectRefused, "too small to grasp"),
    Case("sg.plan", "a card 85 x 54 x 1 mm (a sheet, not metres)", lambda tmp: sg.plan(so.from_mesh(trimesh.creation.box((85.0, 54.0, 1.0)), name="card", cache=False)),
         sg.planner.ObjectRefused, "card is too thin to grasp: it is 1 mm thin"),
    Case("sg.plan", "a precision grasp of a 4 mm object (a file in inches?)", lambda tmp: sg.plan(so.ellipsoid(1.5, 1.5, 2.0), "precision"),
         sg.planner.ObjectRefused, "is too small for a pinch: it is at most 4 mm across, while the thumb and the index and "
                                   "middle fingertips close to no less than 15 mm apart"),
    Case("sg.plan", "an object 600 mm wide", lambda tmp: sg.plan(so.ellipsoid(300.0, 300.0, 300.0)), sg.planner.ObjectRefused, "too large for the hand"),
    Case("sg.plan", "u0 of 3 numbers", lambda tmp: sg.plan("ellipsoid", u0=[0.0, 0.0, 1.0]), ValueError, "u0 must have shape (8,)"),
    Case("sg.plan", "a NaN u0", lambda tmp: sg.plan("ellipsoid", u0=[np.nan] * 8), ValueError, "u0 contains NaN or inf"),
    Case("sg.plan", "a u0 a light-year away", lambda tmp: sg.plan("ellipsoid", u0=[1e12] + [0.0] * 7), ValueError,
         "u0 places the palm 1e+12 mm from ellipsoid 30/40/50's centre, farther than 10000 mm"),
    Case("sg.plan", "u0's Euler angles in degrees", lambda tmp: sg.plan("ellipsoid", u0=[0.0, 0.0, 150.0, 180.0, 0.0, 90.0, 0.0, 0.0]),
         ValueError, "u0's Euler angles [180.0, 0.0, 90.0] go beyond 2 pi: they are radians (degrees?"),
    Case("sg.plan", "both u0 and approach", lambda tmp: sg.plan("ellipsoid", u0=[0.0, 0.0, 150.0] + [0.0] * 5,
                                                                 approach=[0.0, 0.0, 1.0]), ValueError,
         "give u0 or approach, not both"),
    Case("sg.plan", "a zero approach direction", lambda tmp: sg.plan("ellipsoid", approach=[0.0, 0.0, 0.0]), ValueError, "approach must be a non-zero direction"),
    Case("sg.plan", "an approach of 1e300 (its norm overflows)",
         lambda tmp: sg.plan("ellipsoid", approach=[1e300, 1e300, 0.0], max_iter=3, executable_reach=False), None,
         "planned from the direction (1, 1, 0)",
         check=lambda r: np.allclose(r.trajectory[0], sg.plan("ellipsoid", approach=[1.0, 1.0, 0.0], max_iter=3,
                                                                executable_reach=False).trajectory[0])),
    Case("sg.plan", "validation settings named by numbers", lambda tmp: sg.plan("ellipsoid", validate={1: 2}, max_iter=1),
         TypeError, "validate's settings are named by strings (as synergrasp.validate's keywords), got [1]"),
    Case("sg.plan", "an unknown validation setting", lambda tmp: sg.plan("ellipsoid", validate={"foo": 1}, max_iter=1),
         ValueError, "unknown protocol settings ['foo']"),
    Case("sg.plan", "an unknown validation setting: the others are listed, validate's own too",
         lambda tmp: sg.plan("ellipsoid", validate={"foo": 1}, max_iter=1), ValueError, "'noslip_iterations', 'preset',"),
    Case("sg.plan", "a hand with two fingers",
         lambda tmp: sg.plan("ellipsoid", hand=sg.SynergyHand({**_hand_dict(), "fingers": _hand_dict()["fingers"][:2]})),
         ValueError, "the planner needs a thumb (the first chain) and at least two fingers"),
    Case("sg.plan", "an approach that is a word", lambda tmp: sg.plan("ellipsoid", approach="up"), TypeError, "approach must be a numeric vector"),
    Case("sg.plan", "an unknown option", lambda tmp: sg.plan("ellipsoid", foo=1), ValueError, "unknown planner options ['foo']"),
    Case("sg.plan", "a loading option (a file's scale)", lambda tmp: sg.plan("ellipsoid", scale=1000), ValueError,
         "['scale'] is an option of loading the object, not of planning: load it first, e.g. "
         "sg.plan(sg.objects.load(path, scale=1000), grasp)"),
    Case("sg.plan", "units= (the command line's)", lambda tmp: sg.plan("ellipsoid", units="m"), ValueError,
         "'units' is the command line's --units, not a planner option: in Python a file's units are the scale it is "
         "loaded with: sg.plan(sg.objects.load(path, scale=1000), grasp)"),
    Case("sg.plan", "max_iter = 0", lambda tmp: sg.plan("ellipsoid", max_iter=0), ValueError, "PlannerOptions.max_iter must be in [1, inf), got 0"),
    Case("PlanResult.save", "a path that is a number", lambda tmp: sg.plan("ellipsoid", max_iter=1).save(3), TypeError, "an output path must be a str or os.PathLike"),
    Case("PlanResult.save", "a path that is a folder", lambda tmp: sg.plan("ellipsoid", max_iter=1).save(tmp), IsADirectoryError, "it is a folder; give a file name"),
    Case("sg.PlanResult.load", "None as the path", lambda tmp: sg.PlanResult.load(None), TypeError,
         "the PlanResult file must be a str or os.PathLike, got NoneType"),
    Case("sg.PlanResult.load", "a missing file", lambda tmp: sg.PlanResult.load(Path(tmp) / "none.json"), FileNotFoundError, "PlanResult file not found"),
    Case("sg.PlanResult.load", "an empty name (it said '.' is a folder)", lambda tmp: sg.PlanResult.load(""), ValueError,
         "the PlanResult file is an empty name (an unset variable?): give a path"),
    Case("sg.objects.load", "an empty name", lambda tmp: so.load(""), ValueError,
         "the object file is an empty name (an unset variable?): give a path"),
    Case("sg.PlanResult.load", "a folder", lambda tmp: sg.PlanResult.load(tmp), FileNotFoundError, "is a folder, not a PlanResult file"),
    Case("sg.PlanResult.load", "a file that is not JSON", lambda tmp: sg.PlanResult.load(_write(tmp, "p.json", "{oops")), ValueError, "cannot read a PlanResult from"),
    Case("sg.PlanResult.load", "JSON of something else", lambda tmp: sg.PlanResult.load(_write(tmp, "p.json", "[1, 2]")), ValueError, "is not a saved synergrasp PlanResult"),
    Case("sg.PlanResult.load", "a reach of an unknown source", lambda tmp: sg.PlanResult.load(_grasp_file(tmp, source="teleport")),
         ValueError, "a summary whose source is one of ['approach', 'closing approach', 'trajectory']"),
    Case("sg.PlanResult.load", "a reach called collision-free whose clearance goes deeper than its tolerance",
         lambda tmp: sg.PlanResult.load(_grasp_file(tmp, deep=20.0)), ValueError,
         "field 'collision_free' must be false: the clearance along path goes to -20 mm, deeper than its tolerance of 3 mm"),
    Case("sg.PlanResult.load", "a hand that is no hand's identity",
         lambda tmp: sg.PlanResult.load(_plan_file(tmp, hand="not a hand")), ValueError,
         "field 'hand' must be the planning hand's identity, 'NAME sha256:<16 hex digits>' (SynergyHand.identity)"),
    Case("sg.PlanResult.load", "u = \"garbage\"", lambda tmp: sg.PlanResult.load(_plan_file(tmp, u="garbage")), ValueError, "field 'u' must be an array of numbers of shape (n,)"),
    Case("sg.PlanResult.load", "numbers written as strings in u", lambda tmp: sg.PlanResult.load(_plan_file(tmp, u=["1"] * 8)),
         ValueError, "field 'u' must be an array of numbers of shape (n,), got ['1', '1'"),
    Case("sg.PlanResult.load", "true/false in u", lambda tmp: sg.PlanResult.load(_plan_file(tmp, u=[True] * 8)),
         ValueError, "field 'u' must be an array of numbers of shape (n,), got [True, True"),
    Case("sg.PlanResult.load", "success = \"maybe\"", lambda tmp: sg.PlanResult.load(_plan_file(tmp, success="maybe")), ValueError, "field 'success' must be true or false"),
    Case("sg.PlanResult.load", "iterations = -3", lambda tmp: sg.PlanResult.load(_plan_file(tmp, iterations=-3)), ValueError, "field 'iterations' must be an integer >= 0"),
    Case("sg.PlanResult.load", "a time of 10**400 s (an int no float holds)", lambda tmp: sg.PlanResult.load(_plan_file(tmp, time_s=10**400)),
         ValueError, "field 'time_s' must be a finite number >= 0.0"),
    Case("sg.PlanResult.load", "a NaN penetration", lambda tmp: sg.PlanResult.load(_plan_file(tmp, penetration=float("nan"))), ValueError, "field 'penetration' must be a finite number"),
    # ------------------------------------------------------------ objects: files
    Case("sg.objects.load", "a missing file", lambda tmp: so.load(Path(tmp) / "none.stl"), FileNotFoundError, "object file not found"),
    Case("sg.objects.load", "a folder", lambda tmp: so.load(tmp), FileNotFoundError, "is a folder, not an object file"),
    Case("sg.objects.load", "an unknown extension", lambda tmp: so.load(_write(tmp, "o.abc", "1 2 3\n")), ValueError, "unknown format '.abc'; supported extensions"),
    Case("sg.objects.load", "a PLY file named .stl", lambda tmp: so.load(_write(tmp, "box.stl", trimesh.exchange.ply.export_ply(
        trimesh.creation.box((40.0, 40.0, 40.0))))), ValueError, "it is a .ply file by its first bytes; rename it with the .ply extension"),
    Case("sg.objects.load", "a binary STL cut short", lambda tmp: so.load(_write(tmp, "cut.stl", trimesh.exchange.stl.export_stl(
        trimesh.creation.box((40.0, 40.0, 40.0)))[:300])), ValueError,
         "as a binary STL its header declares 12 triangles, 684 bytes, and the file has 300 bytes"),
    Case("sg.objects.load", "an .stl of garbage bytes", lambda tmp: so.load(_write(tmp, "g.stl", b"\x00\x01garbage" * 7)), ValueError, "could not read"),
    Case("sg.objects.load", "an .xyz with a short row", lambda tmp: so.load(_write(tmp, "r.xyz", "0 0 0\n30 0\n0 30 0\n")),
         ValueError, "the number of columns changed from 3 to 2 at row 2"),
    Case("sg.objects.load", "an .npz mesh with negative face indices", lambda tmp: so.load(_npz_mesh(tmp, lambda f: -f - 1)),
         ValueError, "'faces' must be an (m, 3) array of integer vertex indices from 0 to 41"),
    Case("sg.objects.load", "an .npz mesh with fractional face indices", lambda tmp: so.load(_npz_mesh(tmp, lambda f: f + 0.5)),
         ValueError, "'faces' must be an (m, 3) array of integer vertex indices"),
    Case("sg.objects.load", "an .xyz of words", lambda tmp: so.load(_write(tmp, "w.xyz", "no numbers here\n")), ValueError, "could not read"),
    Case("sg.objects.load", "an empty .glb file", lambda tmp: so.load(_write(tmp, "e.glb", "")), ValueError, "the file is empty"),
    Case("sg.objects.load", "an empty .npy", lambda tmp: so.load(_write(tmp, "e.npy", data=np.zeros((0, 3)))), ValueError, "it contains no points"),
    Case("sg.objects.load", "an .obj with a NaN vertex", lambda tmp: so.load(_nan_obj(tmp), cache=False), ValueError, "ball.obj vertices contains NaN or inf at rows [5]"),
    Case("sg.objects.load", "an .npy of NaN points", lambda tmp: so.load(_write(tmp, "n.npy", data=np.full((10, 3), np.nan)), cache=False), ValueError, "contains NaN or inf"),
    Case("sg.objects.load", "scale = 0", lambda tmp: so.load(_write(tmp, "c.npy", data=_cloud()), scale=0), ValueError, "scale must be a finite number > 0"),
    Case("sg.objects.get", "an unknown name", lambda tmp: so.get("teapot"), ValueError, "not a built-in (ellipsoid, cup, bell, goblet) and no such file"),
    Case("sg.objects.get", "a folder", lambda tmp: so.get(tmp), ValueError, "is a folder: give a mesh or point-cloud file in it"),
    Case("sg.objects.get", "a number", lambda tmp: so.get(3), TypeError, "an object is a built-in name"),
    Case("sg.objects.get", "an option the built-in lacks", lambda tmp: so.get("cup", foo=1), TypeError, "unexpected keyword argument 'foo'"),
    # ------------------------------------------------------------ objects: arrays and meshes
    Case("sg.objects.from_points", "no points", lambda tmp: so.from_points(np.zeros((0, 3))), ValueError, "points is empty"),
    Case("sg.objects.from_points", "a scan with a third of its 30,000 rows NaN (the message listed all 10,000)",
         lambda tmp: so.from_points(np.where(np.arange(30000)[:, None] % 3 == 0, np.nan, np.random.default_rng(0).normal(size=(30000, 3)))),
         ValueError, "points contains NaN or inf at rows [0, 3, 6, 9, 12, 15, 18, 21, 24, 27, ...] (10000 of 30000; keep "
                     "the finite ones with points[np.isfinite(points).all(axis=1)])"),
    Case("sg.objects.from_points", "an infinite point", lambda tmp: so.from_points([[0, 0, 0], [1, 0, 0], [0, np.inf, 0], [0, 0, 1]]), ValueError, "NaN or inf"),
    Case("sg.objects.from_points", "points on a plane", lambda tmp: so.from_points(np.c_[_cloud()[:, :2], np.zeros(300)]), ValueError, "no volume: all its points lie on a plane"),
    Case("sg.objects.from_points", "points on a line", lambda tmp: so.from_points(np.outer(np.arange(10.0), [1.0, 2.0, 3.0])), ValueError, "no volume: all its points lie on a line"),
    Case("sg.objects.from_points", "one point ten times", lambda tmp: so.from_points([[1.0, 2.0, 3.0]] * 10), ValueError, "only 1 distinct point(s)"),
    Case("sg.objects.from_points", "4 rows of 10 columns (points as columns?)", lambda tmp: so.from_points(np.ones((4, 10))), ValueError, "dimension 10, expected 3"),
    Case("sg.objects.from_points", "x y z and normals (6 columns): a result", lambda tmp: so.from_points(np.c_[_cloud(), -_cloud() / 30.0], cache=False),
         None, "the pieces of its x y z", check=lambda o: abs(o.volume - so.from_points(_cloud(), cache=False).volume) < 1e-9),
    Case("sg.objects.from_points", "a trimesh.PointCloud: a result", lambda tmp: so.from_points(trimesh.PointCloud(_cloud()), cache=False),
         None, "the pieces of its vertices", check=lambda o: abs(o.volume - so.from_points(_cloud(), cache=False).volume) < 1e-9),
    Case("sg.objects.from_points", "max_parts = 0", lambda tmp: so.from_points(_cloud(), max_parts=0), ValueError, "max_parts must be an integer >= 1"),
    Case("sg.objects.from_points", "a cloud 1e200 mm across", lambda tmp: so.from_points(_cloud() * 1e198), ValueError, "mm across, outside the 1e-06-1e+06 mm"),
    Case("sg.objects.from_points", "a cloud 1e-200 mm across", lambda tmp: so.from_points(_cloud() * 1e-202), ValueError, "rescale it (scale=1000 for metres)"),
    Case("sg.objects.from_points", "a centre outside the cloud", lambda tmp: so.from_points(_cloud(), center=[500.0, 0.0, 0.0]), ValueError, "is outside point cloud"),
    Case("sg.objects.from_points", "every point twice: a result", lambda tmp: so.from_points(np.vstack([_cloud(), _cloud()]), cache=False),
         None, "the pieces of the points once", check=lambda o: o.n_pieces == 1 and abs(o.volume - so.from_points(_cloud(), cache=False).volume) < 1e-9),
    Case("sg.objects.from_mesh", "None", lambda tmp: so.from_mesh(None), TypeError, "mesh must be a trimesh.Trimesh or Scene"),
    Case("sg.objects.from_mesh", "a mesh without faces", lambda tmp: so.from_mesh(trimesh.Trimesh(vertices=np.eye(3))), ValueError, "has no faces"),
    Case("sg.objects.from_mesh", "a trimesh.PointCloud", lambda tmp: so.from_mesh(trimesh.PointCloud(_cloud())), TypeError, "not a mesh: load it with from_points(cloud)"),
    Case("sg.objects.from_mesh", "a scene holding only a point cloud", lambda tmp: so.from_mesh(trimesh.Scene([trimesh.PointCloud(_cloud())])), ValueError,
         "is a scene without faces (its geometry: PointCloud): pass a point cloud to from_points"),
    Case("sg.objects.from_mesh", "a flat mesh", lambda tmp: so.from_mesh(trimesh.Trimesh([[0, 0, 0], [50, 0, 0], [50, 50, 0], [0, 50, 0]], [[0, 1, 2], [0, 2, 3]])),
         ValueError, "no volume"),
    Case("sg.objects.from_mesh", "a NaN vertex", lambda tmp: so.from_mesh(trimesh.Trimesh(np.r_[_box_corners(), [[np.nan] * 3]], [[0, 1, 8]], process=False)),
         ValueError, "mesh vertices contains NaN or inf at rows [8]"),
    Case("sg.objects.from_mesh", "a face naming a vertex the mesh does not have", lambda tmp: so.from_mesh(trimesh.Trimesh(_box_corners(), [[0, 1, 2], [0, 1, 99]], process=False)),
         ValueError, "has faces that name vertices it does not have (indices 0 to 99, 8 vertices)"),
    Case("sg.objects.from_mesh", "an open surface that encloses nothing", lambda tmp: so.from_mesh(_arch(), name="arch", cache=False), ValueError,
         "arch is not watertight and cannot be capped"),
    Case("sg.objects.from_mesh", "a closed mesh wound inside out: a result", lambda tmp: so.from_mesh(_inside_out_box(), cache=False),
         None, "the box, its faces turned outward (with a warning)", check=lambda o: abs(o.mesh.volume - 60 * 50 * 70) < 1e-6),
    Case("sg.objects.from_mesh", "two balls 150 mm apart in one mesh: a result", lambda tmp: so.from_mesh(_two_balls(), cache=False),
         None, "one object of both balls, with a warning that they are separate parts", check=lambda o: o.n_pieces == 2),
    Case("sg.objects.from_mesh", "a negative scale", lambda tmp: so.from_mesh(trimesh.creation.box((30.0, 30.0, 30.0)), scale=-1.0), ValueError, "scale must be a finite number > 0"),
    Case("sg.objects.GraspObject", "no pieces", lambda tmp: so.GraspObject([]), ValueError, "pieces is empty"),
    Case("sg.objects.GraspObject", "a flat piece", lambda tmp: so.GraspObject([np.eye(3)]), ValueError, "pieces[0] has no volume"),
    Case("sg.objects.GraspObject", "a ragged piece", lambda tmp: so.GraspObject([[[0, 0, 0], [1, 0]]]), TypeError, "pieces[0] must be a numeric array"),
    Case("sg.objects.GraspObject", "a centre outside", lambda tmp: so.GraspObject([_box_corners()], center=[30.0, 0.0, 0.0]), ValueError, "is outside object"),
    Case("sg.objects.GraspObject", "a negative torque scale", lambda tmp: so.GraspObject([_box_corners()], torque_scale=-1.0), ValueError, "torque_scale must be a finite number > 0"),
    Case("sg.objects.GraspObject", "a torque scale in metres", lambda tmp: so.GraspObject([_box_corners()], torque_scale=0.04), ValueError, "torque_scale 0.04 is far from the size of object: it is a length in the object's units (mm)"),
    Case("sg.objects.GraspObject", "info that is not a dict", lambda tmp: so.GraspObject([_box_corners()], info="scan"), TypeError, "info must be a dict"),
    Case("sg.objects.GraspObject", "surface points and a mesh", lambda tmp: so.GraspObject([_box_corners()], points=np.random.default_rng(0).normal(size=(20, 3)), mesh=trimesh.creation.box((60.0, 60.0, 60.0))), ValueError, "give an object a mesh or surface points, not both"),
    Case("sg.objects.GraspObject", "too few surface points", lambda tmp: so.GraspObject([_box_corners()], points=_box_corners()), ValueError, "a point surface needs at least 16 distinct points"),
    Case("sg.objects.GraspObject", "a mesh in metres beside pieces in mm",
         lambda tmp: so.GraspObject([_box_corners()], mesh=trimesh.creation.box((0.02, 0.02, 0.02))), ValueError,
         "the mesh of object span 0.02 mm and lie up to 0 mm outside its pieces, which span 20 mm: give the mesh in "
         "the pieces' units (mm) and frame"),
    Case("sg.objects.GraspObject", "None for the pieces", lambda tmp: so.GraspObject(None), TypeError,
         "pieces must be a list of (k, 3) vertex arrays (the object's convex pieces), got NoneType"),
    Case("sg.objects.GraspObject", "a file name for the mesh", lambda tmp: so.GraspObject([_box_corners()], mesh="box.stl"),
         TypeError, "mesh must be a trimesh.Trimesh (the object's true surface) or None, got str"),
    Case("sg.objects.GraspObject", "surface points in metres", lambda tmp: so.GraspObject([_box_corners()], points=trimesh.sample.sample_surface(trimesh.creation.box((60.0, 50.0, 90.0)), 200, seed=0)[0] / 1000.0), ValueError, "give the points in the pieces' units (mm) and frame"),
    Case("sg.objects.GraspObject", "surface points with NaN", lambda tmp: so.GraspObject([_box_corners()], points=np.full((20, 3), np.nan)), ValueError, "points contains NaN or inf"),
    Case("sg.objects.revolve", "one knot", lambda tmp: so.revolve([[10.0, 0.0]]), ValueError, "profile needs at least 2 knots"),
    Case("sg.objects.revolve", "heights going down", lambda tmp: so.revolve([[10.0, 10.0], [10.0, 0.0]]), ValueError, "strictly increasing"),
    Case("sg.objects.revolve", "a negative radius", lambda tmp: so.revolve([[-10.0, 0.0], [10.0, 10.0]]), ValueError, "negative radii at knots [0]"),
    Case("sg.objects.revolve", "a tolerance of 1e-9 mm (minutes of work)", lambda tmp: so.revolve([[30.0, 0.0], [30.0, 90.0]], tolerance=1e-9),
         ValueError, "tolerance 1e-09 mm is finer than synergrasp builds a shape to"),
    Case("sg.objects.ellipsoid", "a negative semi-axis", lambda tmp: so.ellipsoid(-1.0), ValueError, "a must be a finite number > 0"),
    Case("sg.objects.ellipsoid", "a tolerance finer than its finest polytope", lambda tmp: so.ellipsoid(tolerance=1e-6),
         ValueError, "tolerance 1e-06 mm is finer than synergrasp builds a shape to"),
    Case("GraspObject.contact_distance", "a NaN hand point", lambda tmp: so.ellipsoid().contact_distance([[np.nan, 0.0, 0.0]]), ValueError, "points contains NaN or inf"),
    Case("GraspObject.contact_distance", "2-D hand points", lambda tmp: so.ellipsoid().contact_distance([[0.0, 0.0]]), ValueError, "hand points must be an (n, 3) array in mm"),
    Case("GraspObject.contact_distance", "a hand point 1000 km away", lambda tmp: so.ellipsoid().contact_distance([[1e9, 0.0, 0.0]]), ValueError, "farther than 1e+06 mm"),
    Case("GraspObject.scaled_contacts", "a hand point 1000 km away", lambda tmp: so.cup().scaled_contacts([[0.0, 0.0, 1e157]]), ValueError, "farther than 1e+06 mm"),
    Case("GraspObject.distance_grid", "2-D hand points", lambda tmp: so.ellipsoid().distance_grid(np.zeros((6, 2))), ValueError, "points must have shape (..., 3)"),
    Case("DistanceGrid.posed", "floors of the wrong length", lambda tmp: so.ellipsoid().distance_grid.posed(np.zeros((1, 4, 3)), np.eye(3)[None], np.zeros((1, 3)), floors=[0.0]), ValueError, "floors must have shape (4,)"),
    Case("GraspObject.scaled_contacts", "a point at the centre", lambda tmp: so.ellipsoid().scaled_contacts([[0.0, 0.0, 0.0]]), ValueError, "coincide with the object's centre"),
    Case("GraspObject.penetration", "a negative capsule radius", lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), -1.0), ValueError, "radius must be a finite number > 0"),
    Case("GraspObject.penetration", "a radius that is a word", lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), "thick"), TypeError, "radius must be a number"),
    Case("GraspObject.penetration", "a radius of True", lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), True), TypeError,
         "radius must be a number or an array of (1,) numbers, got bool"),
    Case("GraspObject.penetration", "a radius of 3 m (minutes of distance queries)",
         lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), 3000.0), ValueError,
         "a capsule radius of 3000 mm is more than the 500 mm a hand's phalanx could have"),
    Case("GraspObject.penetration", "a box with a NaN centre", lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), 1.0, box=([np.nan, 0, 0], np.eye(3), [1, 1, 1])), ValueError, "box contains NaN or inf"),
    Case("GraspObject.penetration", "a box with a zero half extent", lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), 1.0, box=([0, 0, 0], np.eye(3), [1, 0, 1])), ValueError, "box half_extents must be > 0"),
    Case("GraspObject.penetration", "a box whose axes are not a rotation", lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), 1.0, box=([0, 0, 0], 2.0 * np.eye(3), [1, 1, 1])), ValueError, "box axes must be a rotation matrix"),
    Case("GraspObject.penetration", "a box of the wrong shapes", lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), 1.0, box=([0, 0], np.eye(3), [1, 1, 1])), ValueError, "box must be (centre (3,), axes (3, 3), half_extents (3,))"),
    Case("GraspObject.penetration", "a box that is a word", lambda tmp: so.ellipsoid().penetration(np.zeros((1, 2, 3)), 1.0, box="palm"), TypeError, "box must be (centre (3,), axes (3, 3), half_extents (3,)) of numbers"),
    Case("SynergyHand.palm_jacobian", "points of shape (3,)", lambda tmp: sg.SynergyHand.default().palm_jacobian(np.zeros(8), np.zeros(3)), ValueError, "points must be a finite (n, 3) array"),
    Case("SynergyHand.palm_jacobian", "a NaN point", lambda tmp: sg.SynergyHand.default().palm_jacobian(np.zeros(8), [[np.nan, 0.0, 0.0]]), ValueError, "points must be a finite (n, 3) array"),
    Case("GraspObject.transformed", "a matrix that is a word", lambda tmp: so.ellipsoid().transformed("identity"), TypeError, "matrix must be a (4, 4) array of real numbers"),
    Case("GraspObject.transformed", "a complex matrix (its imaginary parts were dropped)",
         lambda tmp: so.ellipsoid().transformed(np.eye(4) + 5j * np.eye(4)[0:1].T @ np.eye(4)[3:4]), TypeError,
         "matrix must be a (4, 4) array of real numbers, got ndarray"),
    Case("GraspObject.transformed", "a scaling matrix", lambda tmp: so.ellipsoid().transformed(np.diag([2.0, 2.0, 2.0, 1.0])), ValueError, "must be a rigid transform"),
    Case("GraspObject.transformed", "a NaN matrix", lambda tmp: so.ellipsoid().transformed(np.full((4, 4), np.nan)), ValueError, "it contains NaN or inf"),
    Case("planner.grasp_status", "an object given by name", lambda tmp: grasp_status(HAND, "ellipsoid", np.zeros(8), "precision"), TypeError, "obj must be a GraspObject"),
    Case("objects.group_contact_distance", "far distances of the wrong length", lambda tmp: group_contact_distance(so.ellipsoid(), [[0.0, 0.0, 70.0], [0.0, 0.0, 60.0]], [0, 1], far=[5.0]), ValueError, "far must be one distance per group (2)"),
    Case("planner.grasp_status", "far distances of the wrong length", lambda tmp: grasp_status(HAND, so.ellipsoid(), np.zeros(8), "precision", far=[5.0, 5.0]), ValueError, "far must be 16 distances (one per cP row of a precision status)"),
    Case("planner.check_grasp", "no status", lambda tmp: check_grasp(so.ellipsoid(), None, "precision"), TypeError, "check_grasp takes a GraspObject and a Status"),
    Case("planner.check_grasp", "an unknown grasp kind",
         lambda tmp: check_grasp(so.ellipsoid(), _far_status(), "grip"), ValueError, "kind must be 'precision' or 'power', got 'grip'"),
    Case("planner.check_grasp", "a precision status judged as power",
         lambda tmp: check_grasp(so.ellipsoid(), _far_status(), "power"), ValueError,
         "the status is of a precision grasp, not a power one"),
    Case("planner.check_grasp", "a NaN contact threshold",
         lambda tmp: check_grasp(so.ellipsoid(), _far_status(), "precision", eps_c=np.nan), ValueError,
         "eps_c must be a finite number > 0"),
    Case("planner.check_grasp", "no fingertip steered",
         lambda tmp: check_grasp(so.ellipsoid(), _far_status(), "precision", steered=0), ValueError,
         "steered must be an integer >= 1 (the fingertips the attempt steers), got 0"),
    Case("planner.check_grasp", "a fraction of a fingertip steered",
         lambda tmp: check_grasp(so.ellipsoid(), _far_status(), "precision", steered=3.5), ValueError,
         "steered must be an integer >= 1"),
    Case("planner.check_grasp", "steered fingertips for a power grasp",
         lambda tmp: check_grasp(so.ellipsoid(), _far_status("power"), "power", steered=3), ValueError,
         "steered counts the fingertips of a precision grasp: leave it out for a power grasp"),
    Case("planner.recess", "a NaN point", lambda tmp: recess(so.ellipsoid(), [[np.nan, 0.0, 0.0]], [[1.0, 0.0, 0.0]]), ValueError, "points contains NaN or inf at rows [0]"),
    Case("planner.recess", "two points, one normal", lambda tmp: recess(so.ellipsoid(), np.zeros((2, 3)), [[1.0, 0.0, 0.0]]), ValueError, "recess needs one normal per point"),
    Case("planner.recess", "a zero normal", lambda tmp: recess(so.ellipsoid(), [[0.0, 0.0, 50.0]], [[0.0, 0.0, 0.0]]), ValueError,
         "recess needs unit normals; rows [0]"),
    Case("planner.recess", "normals of dimension 2", lambda tmp: recess(so.ellipsoid(), np.zeros((1, 3)), [[1.0, 0.0]]), ValueError, "normals has points of dimension 2, expected 3"),
    # ------------------------------------------------------------ the executable reach
    Case("planner.hand_clearance", "a hand given by name", lambda tmp: hand_clearance("paper_hand", so.ellipsoid(), np.zeros(8)), TypeError, "hand must be a SynergyHand"),
    Case("planner.hand_clearance", "u of 7 numbers", lambda tmp: hand_clearance(HAND, so.ellipsoid(), np.zeros(7)), ValueError, "u must have shape (8,)"),
    Case("planner.hand_clearance", "a NaN u", lambda tmp: hand_clearance(HAND, so.ellipsoid(), np.full(8, np.nan)), ValueError, "u contains NaN or inf"),
    Case("planner.path_clearance", "200,001 rows of one pose (blamed on its turns)",
         lambda tmp: path_clearance(HAND, so.ellipsoid(), np.tile(np.r_[0.0, -150.0, np.zeros(6)], (200_001, 1))), ValueError,
         "the path has 200001 rows, more than the 1e+05 pieces synergrasp checks"),
    Case("planner.path_clearance", "a trimesh for the object", lambda tmp: path_clearance(HAND, trimesh.creation.box(), [np.zeros(8)]), TypeError, "obj must be a GraspObject"),
    Case("planner.path_clearance", "poses of 7 numbers", lambda tmp: path_clearance(HAND, so.ellipsoid(), np.zeros((2, 7))), ValueError, "path has points of dimension 7, expected 8"),
    Case("planner.path_clearance", "an infinite pose", lambda tmp: path_clearance(HAND, so.ellipsoid(), [np.zeros(8), np.r_[np.zeros(7), np.inf]]), ValueError, "path contains NaN or inf at rows [1]"),
    Case("planner.path_clearance", "max_angle = 1e-9 (1e9 poses for a turn of 1 rad)", lambda tmp: path_clearance(HAND, so.ellipsoid(), [np.zeros(8), np.r_[0.0, 0, 0, 1, 0, 0, 0, 0]], max_angle=1e-9),
         ValueError, "more than the 1e+05 synergrasp checks"),
    Case("planner.path_clearance", "a synergy moved by 1e6", lambda tmp: path_clearance(HAND, so.ellipsoid(), [np.zeros(8), np.r_[np.zeros(6), 1e6, 0.0]]),
         ValueError, "give a path of plausible poses"),
    Case("planner.path_clearance", "resolution = 0", lambda tmp: path_clearance(HAND, so.ellipsoid(), [np.zeros(8)], resolution=0.0), ValueError, "resolution must be a finite number > 0"),
    Case("planner.path_clearance", "stop_below of two numbers", lambda tmp: path_clearance(HAND, so.ellipsoid(), [np.zeros(8)], stop_below=[0.0, 1.0]), ValueError, "stop_below must be a number or one per shape (16"),
    Case("planner.executable_reach", "u_grasp of 6 numbers", lambda tmp: executable_reach(HAND, so.ellipsoid(), np.zeros(6)), ValueError, "u_grasp must have shape (8,)"),
    Case("planner.executable_reach", "a negative margin", lambda tmp: executable_reach(HAND, so.ellipsoid(), np.zeros(8), margin=-1.0), ValueError, "margin must be a finite number > 0"),
    Case("planner.executable_reach", "a margin of 400 mm with max_retreat 300 mm", lambda tmp: executable_reach(HAND, so.ellipsoid(), np.zeros(8), margin=400.0),
         ValueError, "margin (400 mm) is more than max_retreat (300 mm)"),
    Case("planner.executable_reach", "a negative tolerance", lambda tmp: executable_reach(HAND, so.ellipsoid(), np.zeros(8), tolerance=-1.0), ValueError, "tolerance must be a finite number >= 0"),
    Case("planner.executable_reach", "budget = 0", lambda tmp: executable_reach(HAND, so.ellipsoid(), np.zeros(8), budget=0), ValueError, "budget must be an integer >= 1"),
    Case("planner.executable_reach", "an opening of 1.5", lambda tmp: executable_reach(HAND, so.ellipsoid(), np.zeros(8), openings=[0.5, 1.5]), ValueError, "openings must be fractions in [0, 1]"),
    Case("planner.executable_reach", "a trajectory of points", lambda tmp: executable_reach(HAND, so.ellipsoid(), np.zeros(8), trajectory=np.zeros((4, 3))), ValueError, "trajectory has points of dimension 3, expected 8"),
    Case("sg.replay_reach", "a plan without a grasp", lambda tmp: sg.replay_reach(sg.plan("ellipsoid", max_iter=1), so.ellipsoid()), ValueError, "the result has no executable reach"),
    Case("sg.replay_reach", "speed = 0", lambda tmp: sg.replay_reach([np.zeros(8)], so.ellipsoid(), speed=0.0), ValueError, "speed must be a finite number > 0"),
    Case("sg.replay_reach", "speed = 0.1 (m/s meant?)", lambda tmp: sg.replay_reach([np.zeros(8)], so.ellipsoid(), speed=0.1), ValueError, "speed is in mm/s (default 100), not m/s"),
    Case("sg.replay_reach", "a path of 7 columns", lambda tmp: sg.replay_reach(np.zeros((2, 7)), so.ellipsoid()), ValueError, "path has points of dimension 7, expected 8"),
    Case("sg.replay_reach", "a path a kilometre long to a pinch (ran for minutes)", lambda tmp: _kilometre_reach(),
         ValueError, "more than the 5e+06 synergrasp runs: is the path in mm"),
    Case("sg.replay_reach", "synergies outside the hand's limits",
         lambda tmp: sg.replay_reach(np.array([[0.0, -200.0, 0, 0, 0, 0, 0, 0], [0.0, -150.0, 0, 0, 0, 0, 50.0, 0]]), so.ellipsoid()),
         ValueError, "the path's synergies [50.0, 0.0] lie outside the hand's limits"),
    Case("sg.replay_reach", "a trimesh for the object", lambda tmp: sg.replay_reach([np.zeros(8)], trimesh.creation.box()), TypeError, "obj must be a GraspObject"),
    Case("physics.pinch_grasp", "a hand's name for the hand", lambda tmp: probes.pinch_grasp(hand="paper"), TypeError,
         "hand must be a SynergyHand (None: the paper's hand), got str 'paper'"),
    Case("physics.pinch_grasp", "a NaN gap", lambda tmp: probes.pinch_grasp(gap=np.nan), ValueError,
         "gap must be a finite number of mm (negative: the fingertips overlap the object), got nan"),
    Case("physics.pinch_grasp", "a gap wider than the fingertips' room (a box turned inside out)",
         lambda tmp: probes.pinch_grasp(gap=100.0), ValueError, "gap 100 mm leaves no room between the fingertips"),
    Case("physics.pinch_grasp", "side = 0", lambda tmp: probes.pinch_grasp(side=0.0), ValueError,
         "side (mm of the box's cross-section) must be a finite number > 0, got 0.0"),
    Case("physics.Protocol", "a name that is a number", lambda tmp: sg.physics.Protocol(name=3), ValueError,
         "protocol setting name must be a string"),
    Case("physics.ball_pinch", "a hand without the thumb (the index and middle pinched)",
         lambda tmp: probes.ball_pinch(probes.hand_without(HAND, "T")), ValueError,
         "a pinch is between the thumb 'T' and the index 'I'; hand 'paper_hand without T' has no finger ['T']"),
    Case("physics.ball_pinch", "a position of 2 numbers", lambda tmp: probes.ball_pinch(position=(0.0, 0.0)), ValueError,
         "position (mm) must have shape (3,), got shape (2,)"),
    # ------------------------------------------------------------ hand, LP, figures
    Case("SynergyHand.points", "u of 3 numbers", lambda tmp: HAND.points([0.0, 0.0, 0.0]), ValueError, "u must have shape (8,)"),
    Case("SynergyHand.points", "an unknown kind of points", lambda tmp: HAND.points(np.zeros(8), "grip"), ValueError, "kind must be 'precision' or 'power', got 'grip'"),
    Case("SynergyHand.points", "a NaN u", lambda tmp: HAND.points(np.full(8, np.nan)), ValueError, "u contains NaN or inf"),
    Case("SynergyHand.segments", "u is a word", lambda tmp: HAND.segments("open"), TypeError, "u must be a numeric vector of 8 numbers"),
    Case("SynergyHand.from_file", "None as the path", lambda tmp: sg.SynergyHand.from_file(None), TypeError,
         "the hand file must be a str or os.PathLike, got NoneType"),
    Case("SynergyHand.from_file", "a missing file", lambda tmp: sg.SynergyHand.from_file(Path(tmp) / "none.json"), FileNotFoundError, "hand file not found"),
    Case("SynergyHand.from_file", "a folder", lambda tmp: sg.SynergyHand.from_file(tmp), FileNotFoundError,
         "is a folder, not a hand file: give the hand's .json file"),
    Case("SynergyHand.from_file", "a file that is not JSON", lambda tmp: sg.SynergyHand.from_file(_write(tmp, "h.json", "{")), ValueError, "not valid JSON"),
    Case("SynergyHand", "a hand without a name", lambda tmp: sg.SynergyHand({}), ValueError, "field 'name' is missing"),
    Case("SynergyHand", "a finger radius of a metre", lambda tmp: sg.SynergyHand({**_hand_dict(), "finger_radius": 1000.0}),
         ValueError, "field 'finger_radius' must be smaller than the palm's largest side, 95 mm, got 1000"),
    Case("SynergyHand", "a finger radius given as a string", lambda tmp: sg.SynergyHand({**_hand_dict(), "finger_radius": "8"}),
         ValueError, "field 'finger_radius' must be numbers of shape (), got '8'"),
    Case("SynergyHand", "a null name", lambda tmp: sg.SynergyHand({**_hand_dict(), "name": None}), ValueError,
         "field 'name' must be a non-empty string, got None"),
    Case("SynergyHand", "a contact offset beyond the finger radius (points in the air)", lambda tmp: sg.SynergyHand({**_hand_dict(), "contact_offset": 50.0}),
         ValueError, "field 'contact_offset' must be between 0 (the segment axes) and finger_radius, 8 (the skin), got 50"),
    Case("SynergyHand", "a description that is a number", lambda tmp: sg.SynergyHand({**_hand_dict(), "description": 3}),
         ValueError, "field 'description' must be a string, got 3"),
    Case("SynergyHand", "a misspelt optional field",
         lambda tmp: sg.SynergyHand({**{k: v for k, v in _hand_dict().items() if k != "contact_offset"}, "contact_ofset": 8.0}),
         ValueError, "field 'contact_ofset' is not a field of a hand file (did you mean 'contact_offset'?)"),
    Case("SynergyHand", "a joint axis whose length overflows", lambda tmp: sg.SynergyHand(_with_joint_field("axis", [1e308, 1e308, 0.0])),
         ValueError, "field 'fingers[1].joints[0].axis' must be a direction of moderate length (its length overflows)"),
    Case("SynergyHand", "a joint axis along its link", lambda tmp: sg.SynergyHand(_with_joint_field("axis", [0.0, 2.0, 0.0])),
         ValueError, "field 'fingers[1].joints[0].axis' must not be along the link"),
    Case("SynergyHand", "a synergy entry of 1e10 (LinAlgError in the planner's step)",
         lambda tmp: sg.SynergyHand(_with_synergy(2, 1, 1e10)), ValueError,
         "moves joint 'I_mcp' by 1e+10 rad over synergy 2's range [-1.0, 1.0], more than 12.6 rad"),
    Case("SynergyHand", "a link of 1e100 mm (the cP LP failed)", lambda tmp: sg.SynergyHand(_with_joint_field("length", 1e100)),
         ValueError, "field 'fingers[1].joints[0].length' must be at most 2000 mm in size (a hand's span), got 1e+100"),
    Case("SynergyHand", "a coupling of 1e10 (blamed on a path the user never gave)",
         lambda tmp: sg.SynergyHand(_with_joint_field("coupling", {"I_mcp": 1e10})), ValueError,
         "field 'fingers[1].joints[0].coupling.I_mcp' must be at most 10 in size"),
    Case("SynergyHand", "a hand file in metres (refused later as 'opens at most 0 mm')",
         lambda tmp: sg.SynergyHand(_in_metres()), ValueError, "field 'palm.size' is at most 0.095 mm, less than 20 mm"),
    Case("SynergyHand", "a mean pose in degrees", lambda tmp: sg.SynergyHand({**_hand_dict(), "mean_pose": [
         70.0] + _hand_dict()["mean_pose"][1:]}), ValueError, "field 'mean_pose' must be at most 12.6 rad in size (two turns), got 70"),
    Case("SynergyHand", "an unknown field of a joint",
         lambda tmp: sg.SynergyHand(_with_joint_field("lenght", 1.0)), ValueError,
         "field 'fingers[1].joints[0].lenght' is not a field of a hand file (did you mean 'length'?)"),
    Case("SynergyHand.clip_synergies", "three synergies for a hand of two", lambda tmp: HAND.clip_synergies([0.0, 0.0, 0.0], "z"),
         ValueError, "z must have shape (2,), got shape (3,)"),
    Case("SynergyHand.clip_synergies", "a NaN synergy (returned as it was)", lambda tmp: HAND.clip_synergies([np.nan, 0.5], "z"),
         ValueError, "z contains NaN or inf"),
    Case("SynergyHand.points", "u of numbers written as text", lambda tmp: HAND.points(["0"] * 6 + ["0.5", "-0.3"]), TypeError,
         "u must be a numeric vector of 8 numbers [p (3), phi (3), z (2)], got list"),
    Case("SynergyHand.points", "a list of kinds", lambda tmp: HAND.points(np.zeros(8), kind=["precision"]), ValueError,
         "kind must be 'precision' or 'power', got ['precision']"),
    Case("sg.lp.get_backend", "an unknown name", lambda tmp: sg.lp.get_backend("gurobi"), ValueError, "unknown LP backend 'gurobi'; available"),
    Case("sg.lp.get_backend", "a number, not a name", lambda tmp: sg.lp.get_backend(3), TypeError,
         "an LP backend is a name (['highs'"),
    Case("ClarabelBackend", "a negative tolerance", lambda tmp: ClarabelBackend(tol=-1.0), ValueError, "tol must be a finite number > 0"),
    Case("ClarabelBackend", "a tolerance of 0.5 (a Q 6 % off)", lambda tmp: ClarabelBackend(tol=0.5), ValueError, "tol must be a number in (0, 1e-05]"),
    Case("CvxpyBackend", "a solver cvxpy does not have (refused at the first solve)", lambda tmp: CvxpyBackend(solver="NOPE"), ValueError,
         "cvxpy has no solver 'NOPE' installed"),
    Case("Backend.solve", "mismatched shapes", lambda tmp: sg.lp.get_backend("highs").solve([1.0, 1.0], [[1.0, 1.0, 1.0]], [1.0]), ValueError, "LP data of mismatched shapes"),
    Case("Backend.solve", "a NaN cost", lambda tmp: sg.lp.get_backend("highs").solve([np.nan, 1.0], [[1.0, 1.0]], [1.0]), ValueError, "LP data contains NaN or inf"),
    Case("Backend.solve", "a cost that is a word", lambda tmp: sg.lp.get_backend("highs").solve("cheap", [[1.0, 1.0]], [1.0]), TypeError, "LP data c, A and b must be arrays of real numbers"),
    Case("Backend.solve", "a complex cost (its imaginary part was dropped)",
         lambda tmp: sg.lp.get_backend("native").solve(np.array([1.0 + 1j, 1.0]), [[1.0, 1.0]], [1.0]), TypeError,
         "must be arrays of real numbers, not text, booleans or complex numbers"),
    Case("Backend.solve", "a CSC matrix with a row outside it (crashed the native solver)",
         lambda tmp: sg.lp.get_backend("native").solve([1.0, 1.0], sg.lp.CSC(np.array([0, 1, 2]), np.array([0, 5]),
                                                                             np.array([1.0, 1.0]), (1, 2)), [1.0]),
         ValueError, "malformed CSC matrix of shape (1, 2)"),
    Case("viz.plot_status", "an empty label", lambda tmp: viz.plot_status(sg.plan("ellipsoid", max_iter=1), Path(tmp) / "s.png", labels=["", "I0"]), ValueError,
         "labels must be a list of non-empty names"),
    Case("viz.plot_status", "one string for the labels", lambda tmp: viz.plot_status(sg.plan("ellipsoid", max_iter=1), Path(tmp) / "s.png", labels="T0"), ValueError,
         "labels must be a list of non-empty names, one per cP row, got 'T0'"),
    Case("viz.plot_status", "None for the path", lambda tmp: viz.plot_status(sg.plan("ellipsoid", max_iter=1), None), TypeError,
         "the image path must be a str or os.PathLike, got NoneType"),
    Case("viz.plot_poses", "the plan of another object", lambda tmp: viz.plot_poses(sg.plan("ellipsoid", max_iter=1), so.cup(), HAND,
                                                                                     Path(tmp) / "p.png"), ValueError,
         "the result was planned for object 'ellipsoid 30/40/50', not for 'cup': pass the object it was planned for"),
    Case("viz.plot_poses", "None for the hand", lambda tmp: viz.plot_poses(sg.plan("ellipsoid", max_iter=1), so.ellipsoid(), None,
                                                                            Path(tmp) / "p.png"), TypeError, "hand must be a SynergyHand, got NoneType"),
    Case("viz.write_html", "an image name for the page", lambda tmp: viz.write_html(so.ellipsoid(), HAND, np.r_[0.0, 0.0, 150.0, np.zeros(5)],
                                                                                    Path(tmp) / "w.png"), ValueError,
         ".png is not a supported format; use one of .html, .htm"),
    Case("viz.plot_status", "not a PlanResult", lambda tmp: viz.plot_status("plan.json", Path(tmp) / "s.png"), TypeError, "result must be a PlanResult"),
    Case("viz.plot_status", "an unknown image format", lambda tmp: viz.plot_status(sg.plan("ellipsoid", max_iter=1), Path(tmp) / "s.xyz"), ValueError, ".xyz is not a supported format"),
    Case("viz.plot_status", "a missing folder", lambda tmp: viz.plot_status(sg.plan("ellipsoid", max_iter=1), Path(tmp) / "no" / "s.png"), FileNotFoundError, "does not exist"),
    Case("viz.animate", "rows of another name", lambda tmp: viz.animate(sg.plan("ellipsoid", max_iter=1), so.ellipsoid(), HAND, Path(tmp) / "a.gif", rows="reach"), ValueError, "rows must be 'trajectory'"),
    Case("viz.animate", "the path of a plan without a grasp", lambda tmp: viz.animate(sg.plan("ellipsoid", max_iter=1), so.ellipsoid(), HAND, Path(tmp) / "a.gif", rows="path"), ValueError, "the plan has no executable reach"),
    Case("viz.animate", "an .mp4 file", lambda tmp: viz.animate(sg.plan("ellipsoid", max_iter=1), so.ellipsoid(), HAND, Path(tmp) / "a.mp4"), ValueError, "use one of .gif"),
]

CLI = [
    Case("synergrasp plan", "an unknown object", argv=["plan", "--object", "teapot"], says="unknown object 'teapot'"),
    Case("synergrasp plan", "a missing file", argv=["plan", "--object", "{tmp}/none.stl"], says="unknown object"),
    Case("synergrasp plan", "an unknown backend", argv=["plan", "--backend", "gurobi"], says="unknown LP backend 'gurobi'"),
    Case("synergrasp plan", "an empty output folder name (an unset variable)", argv=["plan", "--out", ""], says="the output folder (--out) is an empty name"),
    Case("synergrasp plan", "an approach of two numbers", argv=["plan", "--approach", "1,2"], says="expected three numbers x,y,z"),
    Case("synergrasp plan", "a NaN approach", argv=["plan", "--approach", "1,nan,0"], says="expected three finite numbers"),
    Case("synergrasp plan", "--scale 0", argv=["plan", "--scale", "0"], says="expected a finite number > 0"),
    Case("synergrasp plan", "--units inch", argv=["plan", "--units", "inch"], says="invalid choice: 'inch'"),
    Case("synergrasp plan", "--scale 1e300", argv=["plan", "--object", "{tmp}/metres.npy", "--scale", "1e300"],
         says="mm at scale 1e+300: beyond the 1e+06 mm that synergrasp works with"),
    Case("synergrasp plan", "--scale and --units together", argv=["plan", "--scale", "10", "--units", "m"], says="not allowed with argument"),
    Case("synergrasp plan", "--scale for a built-in", argv=["plan", "--object", "cup", "--scale", "2"], says="applies to object files"),
    Case("synergrasp plan", "--max-iter 0", argv=["plan", "--max-iter", "0"], says="expected an integer > 0"),
    Case("synergrasp plan", "--time-limit 0", argv=["plan", "--time-limit", "0"], says="expected a finite number > 0"),
    Case("synergrasp plan", "--out is a file", argv=["plan", "--out", "{tmp}/file.txt"], says="cannot write to the output folder (--out)"),
    Case("synergrasp plan", "an .obj with a NaN vertex", argv=["plan", "--object", "{tmp}/ball.obj"], says="ball.obj vertices contains NaN or inf"),
    Case("synergrasp plan", "a cloud in metres without --units", argv=["plan", "--object", "{tmp}/metres.npy"], says="on the command line: --units m"),
    Case("synergrasp demo", "a negative mu", argv=["demo", "--mu", "-1"], says="mu must be a finite number > 0"),
    Case("synergrasp demo", "--contacts 0", argv=["demo", "--contacts", "0"], says="expected an integer > 0"),
    Case("synergrasp validate", "a missing result file", argv=["validate", "{tmp}/none.json", "--object", "ellipsoid", "--no-still"],
         says="PlanResult file not found"),
    Case("synergrasp validate", "an image for the result", argv=["validate", "{tmp}/image.png", "--object", "ellipsoid", "--no-still"],
         says="cannot read a PlanResult from"),
    Case("synergrasp validate", "a retreat of 1e200 mm", argv=["validate", "{tmp}/plan.json", "--object", "ellipsoid", "--retreat",
                                                             "1e200", "--no-still", "--out", "{tmp}/out"],
         says="retreat must be at most 1000 mm"),
    Case("synergrasp validate", "a NaN retreat", argv=["validate", "{tmp}/plan.json", "--object", "ellipsoid", "--retreat", "nan",
                                                      "--no-still", "--out", "{tmp}/out"], says="retreat must be a finite number"),
    Case("synergrasp validate", "a negative retreat", argv=["validate", "{tmp}/plan.json", "--object", "ellipsoid", "--retreat",
                                                           "-1000", "--no-still", "--out", "{tmp}/out"],
         says="retreat must be >= 0 mm (the palm is moved back, away from the object)"),
    Case("synergrasp validate", "a friction coefficient of 1e9", argv=["validate", "{tmp}/plan.json", "--object", "ellipsoid",
                                                                      "--mu", "1e9", "--no-still", "--out", "{tmp}/out"],
         says="mu must be at most 10 (as the planner's)"),
    Case("synergrasp validate", "--out is a file", argv=["validate", "{tmp}/plan.json", "--object", "ellipsoid", "--out", "{tmp}/file.txt"],
         says="cannot write to the output folder (--out)"),
    Case("synergrasp validate", "the plan of another object", argv=["validate", "{tmp}/plan.json", "--object", "cup", "--no-still",
                                                                   "--out", "{tmp}/out"], says="does not grasp the object"),
    Case("synergrasp", "no command", argv=[], says="the following arguments are required: command"),
]


def cli_files(folder):
    """The files the command-line cases name: a plain file, an .obj with a NaN vertex, a cloud in metres, a
    saved plan of the ellipsoid (3 iterations from 400 mm away: nowhere near any other object) and an image."""
    _write(folder, "file.txt", "not a folder")
    far = sg.planner.start_configuration(HAND, so.ellipsoid(), (0.0, 1.0, 0.0), 400.0)
    sg.plan("ellipsoid", "precision", u0=far, max_iter=3).save(Path(folder) / "plan.json")
    _write(folder, "image.png", b"\x89PNG\r\n\x1a\n" + bytes(64))
    _nan_obj(folder)
    _write(folder, "metres.npy", data=_cloud(radius=0.03))


def _option(name, value, says):
    """A PlannerOptions field out of its range: refused on creation, naming the field and its range."""
    return Case("sg.planner.PlannerOptions", f"{name}={value!r}", lambda tmp: sg.planner.PlannerOptions(**{name: value}),
                ValueError, says)


def _annealing(name, value, says):
    """An AnnealingOptions field out of its range: refused on creation, naming the field and its range."""
    return Case("sg.planner.AnnealingOptions", f"{name}={value!r}",
                lambda tmp: sg.planner.AnnealingOptions(**{name: value}), ValueError, says)


#: Cases of the planners' options (``sg.plan(obj, method=..., **options)``, the fields of PlannerOptions and
#: AnnealingOptions).
PLANNER_OPTIONS: list[Case] = [
    _option("eps_c", -1, "PlannerOptions.eps_c must be in"),
    _option("mu", float("nan"), "PlannerOptions.mu must be a number"),
    _option("mu", 0.0, "PlannerOptions.mu must be in (0, 10.0]"),
    _option("edges", 2, "PlannerOptions.edges must be in"),
    _option("edges", 8.5, "PlannerOptions.edges must be an integer"),
    _option("contact_target", 7.0, "PlannerOptions.contact_target must be in"),
    _option("contact_target", 5.0, "PlannerOptions.contact_target must be in [0, PlannerOptions.eps_c = 5.0), got 5.0"),
    _option("contact_band", (4.0, 2.0), "PlannerOptions.contact_band must be"),
    _option("contact_band", (1.0, np.inf), "PlannerOptions.contact_band must be"),
    _option("contact_band", None, "PlannerOptions.contact_band must be (low, high) mm with 0 <= low < high <= eps_c (5), got None"),
    _option("contact_band", (10**400, 1.0), "PlannerOptions.contact_band must be (low, high) mm"),
    _option("clearance", -0.5, "PlannerOptions.clearance must be in"),
    _option("band_step", 0.0, "PlannerOptions.band_step must be in"),
    _option("band_step", float("nan"), "PlannerOptions.band_step must be a number"),
    _option("sq_step", float("nan"), "PlannerOptions.sq_step must be a number"),
    _option("sq_step", 0.0, "PlannerOptions.sq_step must be in"),
    _option("smoothing", -1.0, "PlannerOptions.smoothing must be in"),
    _option("radius", 5.0, "PlannerOptions.radius must be in"),
    _option("radius_min", 0.0, "PlannerOptions.radius_min must be in"),
    _option("radius_max", 0.001, "PlannerOptions.radius_max must be in"),
    _option("radius_min", 1.0, "PlannerOptions.radius_max must be in [PlannerOptions.radius_min = 1.0, 10.0]"),
    _option("stall_window", -3, "PlannerOptions.stall_window must be an integer in [1, inf) or a (precision, power) pair"),
    _option("stall_window", (20, 12, 4), "PlannerOptions.stall_window must be an integer in [1, inf) or a (precision, power) pair"),
    _option("crawl_window", 2.5, "PlannerOptions.crawl_window must be an integer"),
    _option("crawl_fraction", 2.0, "PlannerOptions.crawl_fraction must be in"),
    _option("touch_window", -1, "PlannerOptions.touch_window must be in"),
    _option("iterations_per_attempt", 0, "PlannerOptions.iterations_per_attempt must be in"),
    _option("restarts", 0, "PlannerOptions.restarts must be in"),
    _option("restarts", 2**63, "PlannerOptions.restarts must be in [1, 1000000], got 9223372036854775808"),
    _option("max_iter", "10", "PlannerOptions.max_iter must be an integer"),
    _option("max_iter", 0, "PlannerOptions.max_iter must be in"),
    _option("time_limit", 0, "PlannerOptions.time_limit must be in"),
    _option("time_limit", "1 s", "PlannerOptions.time_limit must be a number"),
    _option("time_limit", np.inf, "PlannerOptions.time_limit must be a number in (0, inf) or None, got inf"),
    _option("max_iter", np.inf, "PlannerOptions.max_iter must be an integer in [1, inf), got inf"),
    _option("q_margin", 0.5, "PlannerOptions.q_margin must be in"),
    _option("refine_iterations", -1, "PlannerOptions.refine_iterations must be in"),
    _option("max_penetration", -1.0, "PlannerOptions.max_penetration must be in"),
    _option("start_distance", 0.0, "PlannerOptions.start_distance must be in"),
    _option("start_clearance", np.inf, "PlannerOptions.start_clearance must be a number"),
    _option("seed_opening", -2.0, "PlannerOptions.seed_opening must be in"),
    _option("seed_retreat", "far", "PlannerOptions.seed_retreat must be a number"),
    _option("power_preshape", "open", "PlannerOptions.power_preshape must be one finite value per synergy"),
    _option("power_wide_preshape", (np.nan, 1.0), "PlannerOptions.power_wide_preshape must be one finite value per synergy"),
    _option("power_free_reach", 1, "PlannerOptions.power_free_reach must be True or False"),
    _option("power_sq_hold", "low", "PlannerOptions.power_sq_hold must be a number"),
    _option("seed", -1, "PlannerOptions.seed must be in"),
    _option("q_accept", 0.5, "PlannerOptions.q_accept must be in"),
    _option("q_margin", 0.0, "PlannerOptions.q_margin must be in"),
    Case("sg.plan", "options that are not a PlannerOptions", lambda tmp: sg.plan("ellipsoid", options={"max_iter": 3}),
         TypeError, "options of method='gradient' must be an instance of PlannerOptions"),
    Case("sg.plan", "an unknown method", lambda tmp: sg.plan("ellipsoid", method="newton"), ValueError,
         "unknown method 'newton'; known: ['annealing', 'gradient']"),
    Case("sg.plan", "an annealing option for the gradient planner", lambda tmp: sg.plan("ellipsoid", steps=100), ValueError,
         "options ['steps'] belong to method='annealing', not to method='gradient'"),
    Case("sg.plan", "a gradient option for the annealing planner",
         lambda tmp: sg.plan("ellipsoid", method="annealing", restarts=3), ValueError,
         "options ['restarts'] belong to method='gradient', not to method='annealing'"),
    Case("sg.plan", "PlannerOptions for the annealing planner",
         lambda tmp: sg.plan("ellipsoid", method="annealing", options=sg.planner.PlannerOptions()), TypeError,
         "options of method='annealing' must be an instance of AnnealingOptions"),
    Case("sg.plan", "an unknown annealing option", lambda tmp: sg.plan("ellipsoid", method="annealing", foo=1), ValueError,
         "unknown planner options ['foo']; known for method='annealing'"),
    _annealing("steps", 0, "AnnealingOptions.steps must be in"),
    _annealing("close_step", 1e-6, "AnnealingOptions.close_step must be in [0.001, 1.0], got 1e-06"),
    _annealing("legal_tries", 10**9, "AnnealingOptions.legal_tries must be in [1, 1000], got 1000000000"),
    _annealing("dims", 1.5, "AnnealingOptions.dims must be an integer"),
    _annealing("t0", float("nan"), "AnnealingOptions.t0 must be a number"),
    _annealing("cooling", -1.0, "AnnealingOptions.cooling must be in"),
    _annealing("time_limit", float("inf"), "AnnealingOptions.time_limit must be a number in (0, inf) or None, got inf"),
    _annealing("energy_scale", 0.0, "AnnealingOptions.energy_scale must be in"),
    _annealing("autograsp_energy", 0.0, "AnnealingOptions.autograsp_energy must be in"),
    _annealing("close_step", 2.0, "AnnealingOptions.close_step must be in"),
    _annealing("q_accept", 0.5, "AnnealingOptions.q_accept must be in"),
    _annealing("executable_reach", "yes", "AnnealingOptions.executable_reach must be True or False"),
    Case("sg.plan", "a hand that is not a SynergyHand", lambda tmp: sg.plan("ellipsoid", hand="paper"), TypeError,
         "hand must be a SynergyHand"),
    Case("sg.plan", "a progress that cannot be called", lambda tmp: sg.plan("ellipsoid", progress=3), TypeError,
         "progress must be callable"),
]


def _batch(objects=("ellipsoid",), out="out", **kw):
    return lambda tmp: sg.batch.run(list(objects), ["precision"], Path(tmp) / out, progress=False, **kw)


def _same_name_meshes(tmp):
    paths = []
    for sub in ("a", "b"):
        (Path(tmp) / sub).mkdir()
        paths.append(_write(tmp, f"{sub}/mug.obj", "v 0 0 0\n"))
    return sg.batch.run(paths, ["precision"], Path(tmp) / "out", progress=False)


def _busy_folder(tmp):
    store = sg.batch.ResultStore(Path(tmp) / "out")
    store.check_writable()
    with store.lock():  # another run holds the folder
        return sg.batch.run(["ellipsoid"], ["precision"], store.out, progress=False)


def _silent_port():
    import socket

    with socket.socket() as sock:  # a port nobody listens on
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


#: Cases of batch planning (``sg.batch``, ``synergrasp batch`` and ``synergrasp report``): all refused before planning.
BATCH = [
    Case("sg.batch.run", "two objects with one results folder", _same_name_meshes, ValueError, "would share the results folder 'mug.obj'"),
    Case("sg.batch.run", "an unknown grasp type", lambda tmp: sg.batch.run(["cup"], ["pinch"], Path(tmp)), ValueError, "each grasp type must be 'precision' or 'power', got 'pinch'"),
    Case("sg.batch.run", "no grasp type", lambda tmp: sg.batch.run(["cup"], [], Path(tmp)), ValueError, "grasps is empty"),
    Case("sg.batch.run", "a folder named summary.csv in the output folder (found after every plan)",
         lambda tmp: sg.batch.run(["cup"], ["precision"], _folder(Path(tmp) / "summary.csv").parent), ValueError,
         "summary.csv' is not a file, and the batch writes its summary.csv there"),
    Case("sg.batch.run", "a scale with a built-in object (recorded, and not applied)",
         lambda tmp: sg.batch.run(["cup"], ["precision"], Path(tmp), scale=1000.0), ValueError,
         "scale applies to object files; the built-in object 'cup' is in millimetres already"),
    Case("sg.batch.run", "an object that is a number", _batch(objects=[3]), TypeError, "an object must be a built-in name or a path"),
    Case("sg.batch.run", "None for the objects", lambda tmp: sg.batch.run(None, out=Path(tmp)), TypeError,
         "objects must be a name or a sequence of them, got NoneType"),
    Case("sg.batch.run", "None for the output folder", lambda tmp: sg.batch.run(["ellipsoid"], out=None), TypeError,
         "the output folder (out) must be a str or os.PathLike, got NoneType"),
    Case("sg.batch.run", "a list for validate", _batch(validate=["synergrasp"]), TypeError,
         "validate must be a preset's name (dexgraspbench, synergrasp) or None, got list"),
    Case("sg.batch.run", "a connect timeout of 1e300 s (waited until killed)", _batch(connect_timeout=1e300), ValueError,
         "connect_timeout (seconds) must be a number in (0, 3600], got 1e+300"),
    Case("sg.batch.run", "an empty object name (it planned every file under the current folder)", _batch(objects=[""]),
         ValueError, "an object name is empty ('': an unset shell variable?)"),
    Case("sg.batch.run", "an unknown planner option", _batch(options={"speed": 2}), ValueError, "unknown planner options ['speed']"),
    Case("sg.batch.run", "a planner option the planner refuses", _batch(options={"mu": -1.0}), ValueError, "the planner rejects the options"),
    Case("sg.batch.run", "max_iter = 0 among the options", _batch(options={"max_iter": 0}), ValueError,
         "the planner rejects the options {'max_iter': 0}: PlannerOptions.max_iter must be in [1, inf), got 0"),
    Case("sg.batch.run", "max_iter = 2.5 among the options", _batch(options={"max_iter": 2.5}), ValueError,
         "PlannerOptions.max_iter must be an integer in [1, inf), got 2.5"),
    Case("sg.batch.run", "annealing with steps = 0", _batch(options={"method": "annealing", "steps": 0}), ValueError,
         "AnnealingOptions.steps must be in [1, inf), got 0"),
    Case("sg.batch.run", "a progress callback among the options", _batch(options={"progress": print}), ValueError, "options ['progress'] are set by the batch itself"),
    Case("sg.batch.run", "an unknown backend", _batch(backend="gurobi"), ValueError, "unknown LP backend 'gurobi'"),
    Case("sg.batch.run", "a negative time limit", _batch(time_limit=-1.0), ValueError, "time_limit must be a finite number > 0"),
    Case("sg.batch.run", "scale 0", _batch(scale=0.0), ValueError, "scale must be a finite number > 0"),
    Case("sg.batch.run", "no workers", _batch(workers=0), ValueError, "workers must be a whole number >= 1"),
    Case("sg.batch.run", "workers and a scheduler", _batch(workers=2, scheduler="tcp://127.0.0.1:9"), ValueError,
         "workers sets the size of the local cluster"),
    Case("sg.batch.run", "an unknown validation preset", _batch(validate="isaac"), ValueError, "validate must be a preset"),
    Case("sg.batch.run", "an output folder that is a file", lambda tmp: _batch(out=_write(tmp, "file.txt", "x").name)(tmp),
         ValueError, "cannot write to the output folder"),
    Case("sg.batch.grasp_summary", "a row without a status", lambda tmp: sg.batch.grasp_summary([{"grasp": "power", "success": True, "time_s": 1.0}]),
         ValueError, "row 0 of the summary has no status column"),
    Case("sg.batch.grasp_summary", "success 'yes' (summary.csv writes True or False)",
         lambda tmp: sg.batch.grasp_summary([{"grasp": "power", "status": "planned", "success": "yes", "time_s": 1.0}]),
         ValueError, "success and held are True or False"),
    Case("sg.batch.run", "an output folder another batch writes to", _busy_folder, ValueError, "is writing to"),
    Case("sg.batch.run", "a scheduler that does not answer",
         lambda tmp: _batch(scheduler=f"tcp://127.0.0.1:{_silent_port()}", connect_timeout=1)(tmp), ConnectionError,
         "no Dask scheduler answered"),
    Case("sg.batch.run", "a connect timeout that is not a number", _batch(connect_timeout=float("nan")), ValueError,
         "connect_timeout (seconds) must be a finite number > 0"),
    Case("sg.batch.run", "a scheduler address that is a number", _batch(scheduler=123), TypeError,
         "scheduler must be a Dask scheduler's address"),
    Case("synergrasp batch", "--connect-timeout nan",
         argv=["batch", "cup", "--scheduler", "tcp://127.0.0.1:9", "--connect-timeout", "nan", "--out", "{tmp}/out"],
         says="connect_timeout (seconds) must be a finite number > 0"),
    Case("sg.batch.write_report", "a folder without results", lambda tmp: sg.batch.write_report(tmp), FileNotFoundError,
         "no batch results"),
    Case("sg.batch.write_report", "a negative gallery", lambda tmp: sg.batch.write_report(tmp, gallery=-1), ValueError,
         "gallery must be a whole number >= 0"),
    Case("synergrasp batch", "an empty output folder name", argv=["batch", "cup", "--out", ""], says="the output folder is an empty name"),
    Case("synergrasp batch", "--units with a built-in (the plan was in mm, the record said metres)",
         argv=["batch", "cup", "--units", "m", "--out", "{tmp}/out"], says="the built-in object 'cup' is in millimetres already"),
    Case("synergrasp batch", "an unknown backend", argv=["batch", "cup", "--backend", "gurobi", "--out", "{tmp}/out"],
         says="unknown LP backend 'gurobi'"),
    Case("synergrasp batch", "--workers 0", argv=["batch", "cup", "--workers", "0", "--out", "{tmp}/out"],
         says="workers must be a whole number >= 1"),
    Case("synergrasp batch", "--max-iter 0", argv=["batch", "cup", "--max-iter", "0", "--out", "{tmp}/out"],
         says="argument --max-iter: expected an integer > 0, got '0'"),
    Case("synergrasp batch", "--time-limit 0", argv=["batch", "cup", "--time-limit", "0", "--out", "{tmp}/out"],
         says="argument --time-limit: expected a finite number > 0, got '0'"),
    Case("synergrasp batch", "--scale and --units together", argv=["batch", "cup", "--scale", "10", "--units", "m"],
         says="not allowed with argument"),
    Case("synergrasp batch", "an unknown validation preset", argv=["batch", "cup", "--validate", "isaac"], says="invalid choice: 'isaac'"),
    Case("synergrasp batch", "--out is a file", argv=["batch", "cup", "--out", "{tmp}/file.txt"], says="cannot write to the output folder"),
    Case("synergrasp batch", "--workers with --scheduler",
         argv=["batch", "cup", "--workers", "2", "--scheduler", "tcp://127.0.0.1:9", "--out", "{tmp}/out"],
         says="workers sets the size of the local cluster"),
    Case("synergrasp report", "a folder without results", argv=["report", "{tmp}"], says="no batch results"),
]

CASES = API + PLANNER_OPTIONS + CLI + BATCH
