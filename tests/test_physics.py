"""Physics validation in MuJoCo: the model, the protocol's verdicts on grasps of known physics, bad input."""

import json
import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

import synergrasp as sg
from synergrasp.cli import main
from synergrasp.physics import (AXIS_TURNS, DIRECTIONS, PRESETS, Protocol, Validation, ball_pinch,
                                build_model, hand_without, moving_joints, pinch_grasp, plot_validation, protocol,
                                render_still, squeeze_targets, turned_scene, validate, validate_turns)

HAND = sg.SynergyHand.default()
#: A palm pose away from the world frame, so that frame mistakes show.
POSE = dict(position=(10.0, 20.0, 30.0), angles=(0.3, -0.2, 0.5))


@pytest.fixture(scope="module")
def pinch():
    return pinch_grasp(HAND, **POSE)


@pytest.fixture(scope="module")
def pinch_check(pinch):
    return validate(*pinch)


def pinch_result(u, obj, labels=("T0", "I0"), hand=HAND):
    """A PlanResult of the pinch (no planner): the fingertips' nearest points on the object."""
    tips = hand.points(np.asarray(u)[: hand.n_u])[[0, 1]]  # a 9-entry u: a result of another hand
    near = obj.contact_distance(tips)
    return sg.PlanResult(success=True, reason="built by hand", iterations=0, u=np.asarray(u, float),
                         trajectory=np.asarray(u, float)[None], status=np.zeros((1, 6)), target=np.zeros(6),
                         q_history=np.array([-0.1]), contact_points=near.nearest, contact_normals=near.normal,
                         contact_labels=list(labels), penetration=0.0, time_s=0.0, lp_solves=0, backend="highs",
                         grasp="precision", object_name=obj.name)


# ---------------------------------------------------------------------- the model


def test_mujoco_capsules_and_palm_match_the_hand_kinematics():
    """MuJoCo's forward kinematics of the MJCF hand reproduces SynergyHand.segments (an independent chain)."""
    rng = np.random.default_rng(7)
    for _ in range(3):
        u = np.r_[rng.uniform(-50, 50, 3), rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 2)]
        _, ball = ball_pinch(HAND)
        mujoco, model, scene = build_model(HAND, ball, u, PRESETS["synergrasp"])
        data = mujoco.MjData(model)
        for name, angle in HAND.joint_angles(u).items():
            if name in scene.joints:
                data.joint(name).qpos[0] = angle
        mujoco.mj_forward(model, data)
        geo = HAND.segments(u)
        assert scene.capsules == geo.labels
        for label, ends in zip(geo.labels, geo.capsules):
            axis = data.geom(label).xmat.reshape(3, 3)[:, 2] * model.geom(label).size[1]
            got = 1e3 * (data.geom(label).xpos + np.array([-axis, axis]))
            assert min(np.abs(got - ends).max(), np.abs(got[::-1] - ends).max()) < 1e-9
            assert model.geom(label).size[0] * 1e3 == pytest.approx(HAND.finger_radius)
        assert 1e3 * data.geom("palm").xpos == pytest.approx(geo.palm_center, abs=1e-9)
        assert data.geom("palm").xmat.reshape(3, 3) == pytest.approx(geo.palm_axes, abs=1e-12)
        assert 1e3 * model.geom("palm").size == pytest.approx(geo.palm_half_extents)


def test_moving_joints_are_the_eleven_of_the_paper():
    assert moving_joints(HAND) == ["T_rot", "T_abd", "T_mcp", "I_mcp", "I_pip", "M_mcp", "M_pip", "R_mcp", "R_pip",
                                   "L_mcp", "L_pip"]


def test_object_mass_from_density_or_fixed(pinch):
    u, box = pinch
    _, model, _ = build_model(HAND, box, u, PRESETS["synergrasp"])
    assert model.body("object").mass[0] == pytest.approx(1000.0 * box.volume * 1e-9, rel=1e-6)  # MuJoCo stores meshes in float32
    _, model, _ = build_model(HAND, box, u, PRESETS["dexgraspbench"])
    assert model.body("object").mass[0] == pytest.approx(0.1, rel=1e-6)


@pytest.mark.parametrize("overlap", [2.0, 7.0])
def test_initial_penetration_is_the_overlap_and_agrees_with_fcl(overlap):
    """The fingertips cut ``overlap`` mm into the box's faces; python-fcl measures the same depth."""
    u, box = pinch_grasp(HAND, gap=-overlap, **POSE)
    check = validate(u, box)
    geo = HAND.segments(u)
    assert check.initial_penetration == pytest.approx(overlap, abs=0.01)
    assert check.initial_penetration == pytest.approx(box.penetration(geo.capsules, geo.radius).depth, abs=0.01)
    assert check.penetration_body in ("T3", "I3")
    if overlap > PRESETS["synergrasp"].max_penetration:  # too deep: reported, not simulated
        assert (check.outcome, check.held) == ("penetration", False)
        assert "max_penetration 5 mm" in check.reason and np.isnan(check.displacement).all()


def test_squeeze_moves_the_contacts_into_the_object_by_the_squeeze_on_average(pinch):
    """First order: a squeeze of s mm moves the contacts s mm along their inward normals, on average."""
    u, box = pinch
    s = 1e-3
    z, labels = squeeze_targets(HAND, box, u, s, 5.0)
    assert labels == ["T0", "I0", "I3"]
    squeezed = np.r_[u[:6], z]
    points = {**dict(zip(HAND.point_labels("precision"), HAND.points(u))),
              **dict(zip(HAND.point_labels("power"), HAND.points(u, "power")))}
    moved = {**dict(zip(HAND.point_labels("precision"), HAND.points(squeezed))),
             **dict(zip(HAND.point_labels("power"), HAND.points(squeezed, "power")))}
    start = np.array([points[k] for k in labels])
    normals = box.contact_distance(start).normal
    inward = np.einsum("ij,ij->i", np.array([moved[k] for k in labels]) - start, normals)
    assert inward.mean() == pytest.approx(s, rel=1e-4)


# ---------------------------------------------------------------------- verdicts on known physics


def test_box_pinched_by_two_opposed_fingertips_holds(pinch, pinch_check):
    u, box = pinch
    c = pinch_check
    assert c.held and c.outcome == "held", c.reason
    assert (c.displacement < 1.0).all() and (c.rotation < 1.0).all()
    assert c.held_per_direction.all() and c.directions == DIRECTIONS
    assert {"T3", "I3"} <= set(c.contact_bodies)
    assert c.contact_bodies == ["T3", "I3"]
    assert c.contact_normals[0] @ c.contact_normals[1] < -0.99  # opposed
    centre = c.object_pose[:3]  # settled
    for point, normal in zip(c.contact_points, c.contact_normals):
        assert normal @ (centre - point) > 10.0  # into the box, towards its centre
    assert c.grip_force > 2 * c.object_mass * 9.81 / c.settings.mu  # enough to hold its weight by friction
    assert c.object_mass == pytest.approx(box.volume * 1e-6, rel=1e-6)  # 1000 kg/m^3
    assert c.initial_penetration == 0.0 and c.penetration_body == ""


def test_the_same_hand_40mm_back_does_not_hold(pinch, pinch_check):
    u, box = pinch
    c = validate(u, box, retreat=40.0)
    assert not c.held and c.outcome == "no contact", c.reason
    assert (c.displacement > c.settings.max_displacement).all()
    normal = sg.hand.rotation_xyz(u[3:6])[:, 2]
    assert c.u[:3] == pytest.approx(u[:3] - 40.0 * normal)
    assert c.squeeze_z == pytest.approx(pinch_check.squeeze_z)  # the squeeze of the grasp itself


def test_a_hand_touching_nothing_never_holds(pinch):
    """A push too short to move a free object far is no verdict of holding: without contacts, no contact."""
    u, box = pinch
    c = validate(u, box, retreat=100.0, push_time=0.04)
    assert (c.displacement < c.settings.max_displacement).all() and not c.contact_bodies
    assert not c.held and c.outcome == "no contact" and "did not move it far enough to say" in c.reason


def test_a_validation_is_the_same_whatever_was_solved_before():
    """The squeeze's LPs start cold, as a plan's do: a second validation is the first, bit for bit (the cup's pieces
    keep warm starts between cP queries, which moved the squeeze by about 1e-16 and the pushes by 1e-3 mm)."""
    result = sg.plan("cup", "power")
    cup = sg.objects.get("cup")  # a new instance: its pieces' warm starts are empty
    first = validate(result, cup)
    again = validate(result, cup)  # after the first one's solves
    np.testing.assert_array_equal(first.squeeze_z, again.squeeze_z)
    np.testing.assert_array_equal(first.displacement, again.displacement)


def test_a_contact_on_a_phalanx_skin_is_squeezed(pinch):
    """The planner reads a fingertip's contact anywhere on its distal phalanx's skin: a bead 2 mm off the index's
    distal skin, beside it, is 20 mm from every hand point, and the squeeze takes the skin points instead of refusing."""
    u, _ = pinch
    skin, _, _, _ = HAND.skin_and_jacobian(u)
    k = HAND.point_labels("power").index("I3")
    a, b = HAND.segments(u).capsules[k]
    point = skin[k][0]  # at the segment's start, on a lateral side
    foot = a + (point - a) @ (b - a) / ((b - a) @ (b - a)) * (b - a)
    outward = (point - foot) / np.linalg.norm(point - foot)
    bead = sg.objects.from_mesh(trimesh.creation.icosphere(3, 5.0).apply_translation(point + 7.0 * outward), name="bead",
                                cache=False)
    points = np.vstack([HAND.points(u, kind) for kind in ("precision", "power")])
    assert bead.contact_distance(points).value.min() > 5.0
    z, labels = squeeze_targets(HAND, bead, u, 10.0, 5.0)
    assert labels and set(labels) <= set(HAND.point_labels("power")) and not np.array_equal(z, u[6:])


def test_a_power_grasp_touching_by_skin_alone_is_squeezed_and_holds():
    """A box's power grasp touches it with the palm point and the phalanges' skin, no other named point:
    the squeeze reads the skin and closes the fingers on it (it once read the palm point alone and did not move)."""
    box = sg.objects.from_mesh(trimesh.creation.box((60, 40, 30)), name="box", cache=False)
    result = sg.plan(box, "power")
    u = result.u
    named = np.vstack([HAND.points(u), HAND.points(u, "power")])
    touching = box.contact_distance(named).value < 5.0
    assert result.success and [lab for lab, t in zip(HAND.point_labels("precision") + HAND.point_labels("power"),
                                                       touching) if t] == ["P"]
    z, labels = squeeze_targets(HAND, box, u, 10.0, 5.0)
    assert set(labels) - {"P"} and np.abs(z - u[6:]).max() > 0.01
    assert validate(result, box).held


def test_a_plan_keeps_searching_past_a_grasp_the_simulation_refuses(monkeypatch):
    def refuse(*args, **kwargs):
        raise sg.physics.NoContact("no hand point is within 5 mm")

    monkeypatch.setattr(sg.physics, "validate", refuse)
    result = sg.plan("ellipsoid", "precision", validate=True, restarts=2)
    assert result.success and result.held is False
    judged = [a for a in result.attempts if "held" in a]
    assert len(judged) == 2 and all(a["physics"] == "not simulated: no hand point is within 5 mm" for a in judged)
    with pytest.raises(ValueError, match="retreat must be a finite number of mm, got 'x'"):  # before any planning
        sg.plan("ellipsoid", "precision", validate={"retreat": "x"})


def test_ball_pinch_slips_without_either_finger():
    u, ball = ball_pinch(HAND, **POSE)
    two = hand_without(HAND, "M", "R", "L")
    assert validate(u, ball, hand=two).held
    for finger in ("T", "I"):
        check = validate(u, ball, hand=hand_without(two, finger))
        assert not check.held and check.outcome in ("no contact", "slip"), (finger, check.reason)


def test_dexgraspbench_preset_holds_the_pinch_and_not_its_negative_control(pinch):
    c = validate(*pinch, preset="dexgraspbench")
    assert c.held and c.object_mass == pytest.approx(0.1) and c.settings.mu == 0.6, c.reason
    assert not validate(*pinch, preset="dexgraspbench", retreat=40.0).held


def test_unstable_simulation_is_reported_with_its_reason(pinch):
    with pytest.warns(UserWarning, match="timestep 0.05 s is coarser than 0.001 s"):
        c = validate(*pinch, timestep=0.05, kp=1e4)  # stiff servos, coarse step: MuJoCo diverges
    assert (c.held, c.outcome) == (False, "unstable")
    assert "MuJoCo's instability warning" in c.reason and "QACC" in c.reason


def test_object_thrown_faster_than_max_speed_is_an_explosion():
    u, box = pinch_grasp(HAND, gap=-15.0, **POSE)  # 15 mm overlaps, released undamped
    c = validate(u, box, max_penetration=np.inf, settle_damping=0.0, max_speed=0.2)
    assert (c.held, c.outcome) == (False, "unstable")
    assert "explosion during the squeeze" in c.reason


# ---------------------------------------------------------------------- bad input


def test_result_of_another_object_or_hand_is_refused(pinch):
    u, box = pinch
    result = pinch_result(u, box)
    assert validate(result, box).held  # the result itself is fine
    moved = box.transformed(np.r_[np.c_[np.eye(3), [50.0, 0, 0]], [[0, 0, 0, 1]]])
    with pytest.raises(ValueError, match="planned for another scale or pose of it") as refused:  # the same name
        validate(result, moved)
    # the distance it names is Euclidean, to the moved box (not the planner's cP, up to 2.8 times larger): here
    # against 40 000 points spread on the box's faces (about 0.3 mm apart)
    surface = trimesh.sample.sample_surface_even(moved.to_mesh(), 40000, seed=0)[0]
    farthest = np.linalg.norm(np.asarray(result.contact_points)[:, None] - surface, axis=2).min(axis=1).max()
    named = float(re.search(r"lie up to ([0-9.]+) mm from the surface", str(refused.value)).group(1))
    assert named == pytest.approx(farthest, abs=0.3)
    with pytest.raises(ValueError, match="another hand"):
        validate(pinch_result(np.r_[u, 0.0], box), box)
    with pytest.raises(ValueError, match=r"another hand.*hand="):
        validate(pinch_result(u, box, labels=("X0", "I0")), box)


def test_a_result_of_an_object_of_another_name_on_this_objects_surface_is_validated_with_a_warning(pinch):
    """A pen's grasp validated on a slightly thicker marker passed the contacts' check and held, with no word that the
    result named another object: it warns now (the contacts still decide whether it is refused)."""
    from synergrasp.physics.validate import check_match

    u, box = pinch
    result = pinch_result(u, box)
    result.object_name = "pen.stl"
    with pytest.warns(UserWarning, match=r"planned for an object named 'pen.stl', not '.+': its contacts lie within "
                                         r"2 mm of this object's surface"):
        check_match(result, box, HAND, 2.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_match(pinch_result(u, box), box, HAND, 2.0)  # its own object: silent



def test_result_of_a_hand_of_the_same_shape_but_other_lengths_is_refused(pinch):
    """Fingers 30 % longer, the same joints and labels: only the hand's identity the result records tells."""
    u, box = pinch
    data = HAND.to_dict()
    data["name"] = "long fingers"
    for finger in data["fingers"]:
        for joint in finger["joints"]:
            joint["length"] *= 1.3
    long_hand = sg.SynergyHand(data)
    result = pinch_result(u, box)
    result.hand = long_hand.identity
    with pytest.raises(ValueError, match=r"planned with hand 'long fingers sha256:[0-9a-f]{16}', not with this hand "
                                         r"'paper_hand sha256:"):
        validate(result, box)
    result.hand = HAND.identity
    assert validate(result, box).held
    result.hand = ""  # a result saved before results recorded their hand: not checked
    assert validate(result, box).held


def test_configuration_away_from_the_object_is_refused(pinch):
    u, box = pinch
    with pytest.raises(ValueError, match="no hand point is within 5 mm"):
        validate(u + np.r_[300.0, 0, 0, 0, 0, 0, 0, 0], box)
    failed = sg.plan("ellipsoid", "precision", max_iter=3)  # a plan without a grasp says so
    with pytest.raises(ValueError, match=r"no hand point is within 5 mm .*; the plan found no grasp \(no stable grasp"):
        validate(failed, sg.objects.get("ellipsoid"))


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(mu=-1.0), ValueError, "mu must be a finite number > 0"),
    (dict(mu=1e9), ValueError, "mu must be at most 10 .as the planner.s., got 1000000000.0"),
    (dict(push_time=np.inf), ValueError, "push_time must be a finite number > 0"),
    (dict(squeeze=np.inf), ValueError, "squeeze must be a finite number > 0"),
    (dict(friction=0.5), ValueError, "unknown protocol settings"),
    (dict(preset="isaac"), ValueError, "unknown protocol preset"),
    (dict(measure_from="start"), ValueError, "measure_from"),
    (dict(solref=(0.005,)), ValueError, "solref must be 2 finite numbers"),
    (dict(solref=(0.0, 1.0)), ValueError, "solref must be two numbers > 0 .* or two < 0"),  # MuJoCo: "mixed format"
    (dict(solref=(-1000.0, 1.0)), ValueError, "solref must be two numbers > 0"),
    (dict(solimp=(2.0, 3.0, 0.0)), ValueError, r"solimp must be \(dmin, dmax, width\) with dmin and dmax in \[0.0001, 0.9999\]"),
    (dict(solimp=(0.5, 0.99, 0.0)), ValueError, "and width > 0"),
    (dict(timestep=1e-9), ValueError, "simulates 1.25e.10 time steps .* more than the 5e.06"),  # hours, not a verdict
    (dict(settle_time=1e6), ValueError, "simulates 1e.09 time steps"),
    (dict(mass=0.0), ValueError, "mass must be None or a finite number > 0"),
    (dict(retreat=float("nan")), ValueError, "retreat must be a finite number"),
    (dict(retreat="40"), ValueError, "retreat must be a finite number of mm, got '40'"),
    (dict(retreat=True), ValueError, "retreat must be a finite number of mm, got True"),
    (dict(hand="paper_hand"), TypeError, "hand must be a SynergyHand"),
])
def test_bad_settings_are_refused(pinch, kwargs, error, match):
    with pytest.raises(error, match=match):
        validate(*pinch, **kwargs)


def test_bad_configuration_or_object_is_refused(pinch):
    u, box = pinch
    with pytest.raises(ValueError, match=r"u must have shape \(8,\)"):
        validate(u[:7], box)
    with pytest.raises(ValueError, match="NaN"):
        validate(np.r_[u[:7], np.nan], box)
    with pytest.raises(TypeError, match="GraspObject"):
        validate(u, box.pieces[0])
    with pytest.raises(TypeError, match="PlanResult or a configuration"):
        validate({"u": u}, box)
    with pytest.raises(ValueError, match=r"synergies \[6.0, .*\] lie outside the hand's limits"):
        validate(np.r_[u[:6], 6.0, u[7]], box)  # a pose the hand cannot take is not judged


def test_a_name_or_a_file_path_is_refused_with_the_function_that_reads_it(pinch, tmp_path):
    u, box = pinch
    with pytest.raises(TypeError, match=r"obj must be a GraspObject, got the str 'cup': load the object first, "
                                        r"sg.objects.get\('cup'\)"):
        validate(u, "cup")
    with pytest.raises(TypeError, match=r"got the \w*Path '.*plan.json': read a saved result first, "
                                        r"sg.PlanResult.load\(path\)"):
        validate(tmp_path / "plan.json", box)
    result = sg.plan("ellipsoid", "precision", max_iter=3)
    with pytest.raises(TypeError, match=r"got a PlanResult: the result comes first, validate\(result, obj\)"):
        validate(sg.objects.get("ellipsoid"), result)
    with pytest.raises(ValueError, match="has no finger"):
        hand_without(HAND, "X")


def test_missing_mujoco_names_the_extra(pinch, monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # `import mujoco` now raises ImportError
    with pytest.raises(ImportError, match=r'pip install "synergrasp\[sim\]"'):
        validate(*pinch)


def test_a_rendering_backend_that_is_not_there_is_named():
    code = "from synergrasp.physics import mujoco_module; mujoco_module()"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "MUJOCO_GL": "no-such-gl"}, cwd=Path(__file__).resolve().parents[1])
    assert run.returncode != 0 and "ImportError: importing mujoco failed with MUJOCO_GL='no-such-gl'" in run.stderr
    assert "unset MUJOCO_GL" in run.stderr


def test_importing_synergrasp_does_not_import_mujoco():
    code = "import sys, synergrasp; print('mujoco' in sys.modules, callable(synergrasp.validate))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=Path(__file__).resolve().parents[1]).stdout
    assert out.split() == ["False", "True"]


# ---------------------------------------------------------------------- results, figures, command line


def test_validation_round_trips_through_json(pinch_check, tmp_path):
    again = Validation.load(pinch_check.save(tmp_path / "v.json"))
    for name, value in vars(pinch_check).items():
        if isinstance(value, np.ndarray):
            assert np.array_equal(getattr(again, name), value), name
        else:
            assert getattr(again, name) == value, name
    not_simulated = validate(*pinch_grasp(HAND, gap=-7.0))
    again = Validation.load(not_simulated.save(tmp_path / "nan.json"))
    assert np.isnan(again.displacement).all() and again.outcome == "penetration"
    (tmp_path / "other.json").write_text(json.dumps({"format": "synergrasp.PlanResult/1"}))
    with pytest.raises(ValueError, match="not a saved synergrasp Validation"):
        Validation.load(tmp_path / "other.json")
    assert pinch_check.hand == HAND.identity
    data = json.loads((tmp_path / "v.json").read_text())
    del data["hand"]  # a file saved before validations recorded their hand
    (tmp_path / "old.json").write_text(json.dumps(data))
    assert Validation.load(tmp_path / "old.json").hand == ""


@pytest.mark.parametrize("field, value, message", [
    ("directions", 5, "field 'directions' must be a list of push directions"),
    ("displacement", [1.0, 2.0], "field 'displacement' must be 6 numbers >= 0 or NaN"),
    ("held", None, "field 'held' must be true or false"),
    ("outcome", "exploded", "field 'outcome' must be one of"),
    ("outcome", "slip", "field 'outcome' must be 'held' exactly when field 'held' is true"),
    ("protocol", {"mu": -1.0}, "field 'protocol' is not a valid protocol: .*mu"),
    ("contact_forces", [], "field 'contact_forces' must be .* rows, one per contact body"),
    ("object_pose", [0.0, 0.0, 0.0], "field 'object_pose' must be 7 numbers"),
    ("object_mass", "heavy", "field 'object_mass' must be a finite number >= 0"),
    ("u", [1.0, 2.0], "field 'u' must be a configuration of 6 \\+ len\\(squeeze_z\\) = 8 numbers"),
    ("squeeze_z", [0.1, float("nan")], "field 'squeeze_z' must be finite numbers"),
    ("contact_bodies", "T3", "field 'contact_bodies' must be a list of hand geom names"),
    ("format", "synergrasp.Validation/2", "is a Validation of format 'synergrasp.Validation/2', which this version"),
])
def test_a_damaged_validation_file_is_refused_naming_the_field(pinch_check, tmp_path, field, value, message):
    """A file whose fields contradict the format fails on load, naming the field, not later in a figure or a batch."""
    data = json.loads(pinch_check.save(tmp_path / "v.json").read_text())
    assert data["held"] and pinch_check.contact_bodies
    data[field] = value
    (tmp_path / "v.json").write_text(json.dumps(data))
    with pytest.raises(ValueError, match=message):
        Validation.load(tmp_path / "v.json")


def test_the_axis_turns_and_a_turned_scene():
    """The 24 rotations that map the axes onto the axes, the identity first; a turned scene is the same grasp: the
    hand's points and the object's centre turn together."""
    assert len(AXIS_TURNS) == 24 and np.array_equal(AXIS_TURNS[0], np.eye(3))
    assert len({R.tobytes() for R in AXIS_TURNS}) == 24
    for R in AXIS_TURNS:
        assert np.allclose(R @ R.T, np.eye(3)) and np.isclose(np.linalg.det(R), 1.0) and set(np.abs(R).ravel()) == {0, 1}
    obj = sg.objects.get("ellipsoid")
    u = sg.planner.start_configuration(HAND, obj, (1.0, 0.5, 0.2))
    for R in AXIS_TURNS[[5, 17, 23]]:
        moved, v = turned_scene(obj, u, R)
        np.testing.assert_allclose(HAND.points(v, "power"), HAND.points(u, "power") @ R.T, atol=1e-9)
        np.testing.assert_allclose(moved.center, R @ obj.center, atol=1e-12)
        np.testing.assert_array_equal(v[6:], u[6:])


def test_validate_turns_repeats_the_test_in_turned_scenes(pinch, pinch_check):
    """The box pinch holds as built and at the next two turns (a grasp far from the thresholds); bad counts refused."""
    u, box = pinch
    checks = validate_turns(u, box, 3)
    assert [c.outcome for c in checks] == ["held"] * 3
    assert checks[0].displacement.tolist() == pinch_check.displacement.tolist()  # the first is validate's own
    for bad in (0, 25, 2.5, True):
        with pytest.raises(ValueError, match="turns must be an integer from 1 to 24"):
            validate_turns(u, box, bad)


def test_protocol_settings_round_trip():
    for p in (*PRESETS.values(), protocol(mu=0.5, mass=0.2, max_penetration=float("inf"))):
        assert Protocol(**json.loads(json.dumps(p.to_dict()))) == p
    assert protocol("dexgraspbench", mu=0.3).name == "dexgraspbench (mu=0.3)"
    assert protocol(Protocol(name="mine"), mu=0.3).name == "custom"  # (changed from settings of no preset)
    numpy_count = protocol(noslip_iterations=np.int64(3))  # a numpy integer is an integer
    assert type(numpy_count.noslip_iterations) is int and json.dumps(numpy_count.to_dict())


def test_figure_shows_each_direction(pinch_check, tmp_path):
    path = plot_validation(pinch_check, tmp_path / "v.png")
    assert path.stat().st_size > 10_000


def test_figure_of_a_protocol_without_a_threshold_is_drawn(pinch, tmp_path):
    """A threshold of inf (no such check) is the protocol's own; the figure scaled its bars by it and failed inside
    matplotlib (leaving its figure open)."""
    import matplotlib.pyplot as plt

    open_before = len(plt.get_fignums())
    check = validate(*pinch, max_rotation=np.inf, max_displacement=np.inf)
    assert check.held and plot_validation(check, tmp_path / "v.png").stat().st_size > 10_000
    assert len(plt.get_fignums()) == open_before


def test_joint_names_with_xml_characters_are_simulated(pinch):
    """Names go into the MuJoCo model's XML: quoted, so a hand's names are its own (the parser failed on a quote)."""
    u, box = pinch
    data = HAND.to_dict()
    data["fingers"][4]["joints"][1]["name"] = 'L "pip" <&>'
    hand = sg.SynergyHand(data)
    check = validate(u, box, hand=hand)
    assert check.held and 'L "pip" <&>' in check.joint_angles


def test_figures_refuse_what_they_cannot_draw(pinch, pinch_check, tmp_path):
    """Checked before anything is drawn: the file's format, the validation itself, the object and hand it was of,
    and a still larger than MuJoCo's offscreen buffer."""
    _, box = pinch
    with pytest.raises(ValueError, match="no extension is not a supported format"):
        plot_validation(pinch_check, tmp_path / "figure")
    with pytest.raises(TypeError, match="validation must be a Validation"):
        plot_validation(pinch_result(*pinch), tmp_path / "v.png")
    with pytest.raises(ValueError, match="not of 'cup'"):
        render_still(pinch_check, sg.objects.get("cup"), tmp_path / "s.png")
    data = HAND.to_dict()
    for finger in data["fingers"]:  # the same name, fingers 30 % longer
        for joint in finger["joints"]:
            joint["length"] *= 1.3
    with pytest.raises(ValueError, match=r"with hand 'paper_hand sha256:[0-9a-f]{16}', not of .* pass the object and hand"):
        render_still(pinch_check, box, tmp_path / "s.png", hand=sg.SynergyHand(data))
    with pytest.raises(ValueError, match=r"larger than MuJoCo's offscreen buffer \(1280 x 960\)"):
        render_still(pinch_check, box, tmp_path / "s.png", width=5000, height=5000)
    with pytest.raises(ValueError, match=r"width must be an integer >= 1 \(pixels\), got 0"):
        render_still(pinch_check, box, tmp_path / "s.png", width=0)
    assert not list(tmp_path.iterdir())


def test_still_without_opengl_says_what_to_set(tmp_path):
    """No display and MUJOCO_GL=glfw: rendering is unavailable, and the error says how to get it."""
    code = ("from synergrasp.physics import *\n"
            "u, box = pinch_grasp()\n"
            "try:\n    render_still(validate(u, box), box, 'still.png')\n"
            "except RenderingUnavailable as exc:\n    print('unavailable:', exc)\n")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env.update(MUJOCO_GL="glfw", PYTHONPATH=str(Path(__file__).resolve().parents[1]))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path,
                         timeout=120).stdout
    last = out.strip().splitlines()[-1]
    assert last.startswith("unavailable:") and "MUJOCO_GL=egl" in last
    assert not (tmp_path / "still.png").exists()


def test_cli_validates_a_saved_result(pinch, tmp_path, capsys):
    u, box = pinch
    path = pinch_result(u, box).save(tmp_path / "pinch.json")
    mesh = tmp_path / "box.stl"
    trimesh.Trimesh(box.pieces[0], box.convex[0].facets).export(mesh)
    out = tmp_path / "out"
    assert main(["validate", str(path), "--object", str(mesh), "--out", str(out), "--no-still"]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("held (held)") and "wrote" in printed
    check = Validation.load(out / "box_stl_precision_pinch_validation.json")  # the object, as plan names it, and the file
    assert check.held and (out / "box_stl_precision_pinch_validation.png").stat().st_size > 0
    assert main(["validate", str(path), "--object", str(mesh), "--out", str(out), "--no-still",
                 "--retreat", "40"]) == 1
    assert "NOT HELD (no contact)" in capsys.readouterr().out
    # the negative control has its own files: the validation it is compared with is kept
    assert Validation.load(out / "box_stl_precision_pinch_validation.json").held
    assert not Validation.load(out / "box_stl_precision_pinch_retreat40_validation.json").held
    still = out / "box_stl_precision_pinch_validation_still.png"
    still.write_bytes(b"an earlier run's still")
    assert main(["validate", str(path), "--object", str(mesh), "--out", str(out), "--no-still"]) == 0
    assert not still.exists() and "removed an earlier run's" in capsys.readouterr().err
    assert main(["validate", str(path), "--object", "ellipsoid", "--out", str(out), "--no-still"]) == 2
    assert "planned for another object" in capsys.readouterr().err
    metres = tmp_path / "box_m.stl"  # the same box in a file in metres: validated with --units m, as it was planned
    trimesh.Trimesh(box.pieces[0] / 1000.0, box.convex[0].facets).export(metres)
    assert main(["validate", str(path), "--object", str(metres), "--out", str(out), "--no-still"]) == 2
    assert "another scale" in capsys.readouterr().err
    assert main(["validate", str(path), "--object", str(metres), "--units", "m", "--out", str(out), "--no-still"]) == 0
    other_hand = pinch_result(np.r_[u, 0.0], box).save(tmp_path / "nine.json")  # a u of another hand's size
    assert main(["validate", str(other_hand), "--object", str(mesh), "--out", str(out), "--no-still"]) == 2
    assert "another hand? Pass that hand as hand= (on the command line: --hand FILE)" in capsys.readouterr().err


def test_cli_validations_of_two_objects_results_keep_their_own_files(pinch, tmp_path, capsys):
    """A batch's results are OBJECT/GRASP.json: two objects' precision.json validated into one folder make two files."""
    u, box = pinch
    out = tmp_path / "out"
    for name in ("box_a", "box_b"):
        mesh = tmp_path / f"{name}.stl"
        trimesh.Trimesh(box.pieces[0], box.convex[0].facets).export(mesh)
        (tmp_path / name).mkdir()
        path = pinch_result(u, box).save(tmp_path / name / "precision.json")
        assert main(["validate", str(path), "--object", str(mesh), "--out", str(out), "--no-still"]) == 0
    assert sorted(p.name for p in out.glob("*.json")) == ["box_a_stl_precision_validation.json",
                                                         "box_b_stl_precision_validation.json"]
    assert Validation.load(out / "box_a_stl_precision_validation.json").object_name == "box_a.stl"
    for run in ("run1", "run2"):  # two results of one object and grasp: two files
        path = pinch_result(u, box).save(tmp_path / f"{run}.json")
        assert main(["validate", str(path), "--object", str(tmp_path / "box_a.stl"), "--out", str(out), "--no-still"]) == 0
    assert {"box_a_stl_precision_run1_validation.json", "box_a_stl_precision_run2_validation.json"} <= {
        p.name for p in out.glob("*.json")}


def test_a_verdict_names_the_push_that_moved_or_turned_the_object_most():
    """Of the pushes beyond the limits, the reason quotes the farthest (not the first in DIRECTIONS' order)."""
    from synergrasp.physics.simulate import verdict

    p = protocol()
    moved = np.array([p.max_displacement + 1.0, 0.0, 2.0 * p.max_displacement, 0.0, 0.0, 0.0])
    outcome, reason = verdict(p, moved, np.zeros(6), contacts=[0], shift=0.5)
    assert outcome == "slip" and f"moved {moved[2]:.1f} mm along -y" in reason and "along -x, -y:" in reason
    turned = np.array([0.0, 0.0, 0.0, p.max_rotation + 1.0, 0.0, 3.0 * p.max_rotation])
    outcome, reason = verdict(p, np.zeros(6), turned, contacts=[0], shift=0.5)
    assert outcome == "rotation" and f"{turned[5]:.1f} deg along +z" in reason
    outcome, reason = verdict(p, moved, np.zeros(6), contacts=[], shift=8.84)
    assert outcome == "no contact" and "moved 8.8 mm from its planned pose while the hand closed" in reason
