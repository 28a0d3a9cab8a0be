"""Tests of synergrasp.hand: the paper's hand file, kinematics, hand points and Jacobians."""

import json
import re
from pathlib import Path

import numpy as np
from scipy.optimize import brentq
import pytest
from scipy.optimize import linprog
from scipy.spatial.transform import Rotation

from synergrasp.hand import SKIN_ALONG, SKIN_AROUND, HandGeometry, SynergyHand, rotation_xyz

# The paper's Tables 1 and 2, typed in independently of the data file.
TABLE1 = {"T": (46, 32, 27), "I": (47, 25, 20), "M": (48, 28, 21), "R": (46, 27, 21), "L": (40, 21, 20)}
MEAN_POSE = np.array([1.2140, 0.4030, 0.6616, 0.7145, 0.7723, 0.8875])
SYNERGIES = np.array([[-0.2137, 0.0490, 0.0676, 0.2573, 0.2991, 0.3279],
                      [-0.1731, -0.1318, -0.3853, -0.4756, -0.4316, -0.3440]]).T
PRECISION_LABELS = ["T0", "I0", "M0", "R0", "L0"]
POWER_LABELS = [f"{f}{k}" for f in "TIMRL" for k in (1, 2, 3)] + ["P"]


@pytest.fixture(scope="module")
def hand():
    return SynergyHand.default()


def random_configs(n, n_syn=2, seed=0):
    rng = np.random.default_rng(seed)
    return [np.r_[rng.uniform(-200, 200, 3), rng.uniform(-np.pi, np.pi, 3), rng.uniform(-1, 1, n_syn)]
            for _ in range(n)]


def at(z1, z2):
    return np.r_[np.zeros(6), z1, z2]


def angle_deg(a, b):
    return np.degrees(np.arccos(a @ b / np.linalg.norm(a) / np.linalg.norm(b)))


# ---------------------------------------------------------------- shapes and labels

def test_shapes_and_labels(hand):
    u = random_configs(1)[0]
    assert hand.n_syn == 2 and hand.n_u == 8 and len(hand.u_labels) == 8
    assert hand.points(u, "precision").shape == (5, 3)
    assert hand.points(u, "power").shape == (16, 3)
    assert hand.points_jacobian(u, "precision").shape == (5, 3, 8)
    assert hand.points_jacobian(u, "power").shape == (16, 3, 8)
    assert hand.point_labels("precision") == PRECISION_LABELS
    assert hand.point_labels("power") == POWER_LABELS
    np.testing.assert_array_equal(hand.synergy_limits, [[-1, 1], [-1, 1]])
    geo = hand.segments(u)
    assert isinstance(geo, HandGeometry)
    assert geo.capsules.shape == (15, 2, 3) and geo.labels == POWER_LABELS[:-1]
    assert geo.radius == hand.finger_radius > 0
    assert geo.palm_corners.shape == (8, 3)


def test_points_and_jacobian_agree_with_points(hand):
    for u in random_configs(3):
        for kind in ("precision", "power"):
            x, jac = hand.points_and_jacobian(u, kind)
            np.testing.assert_allclose(x, hand.points(u, kind), atol=1e-12)
            np.testing.assert_array_equal(jac, hand.points_jacobian(u, kind))


# ---------------------------------------------------------------- Jacobian

@pytest.mark.parametrize("kind", ["precision", "power"])
@pytest.mark.parametrize("u", random_configs(6, seed=1))
def test_jacobian_matches_central_differences(hand, kind, u):
    step = 1e-6
    jac = hand.points_jacobian(u, kind)
    for k in range(hand.n_u):
        du = np.zeros(hand.n_u)
        du[k] = step
        fd = (hand.points(u + du, kind) - hand.points(u - du, kind)) / (2 * step)
        np.testing.assert_allclose(jac[:, :, k], fd, atol=1e-6, err_msg=f"column {hand.u_labels[k]}")


# ---------------------------------------------------------------- couplings and Table 2

def test_couplings_and_pose(hand):
    for u in random_configs(5, seed=2):
        q = hand.joint_angles(u)
        assert list(q) == hand.joint_names and len(q) == 16
        assert q["T_mcp"] == pytest.approx(q["T_abd"], abs=1e-12)
        for f in "IMRL":
            assert q[f"{f}_pip"] == pytest.approx(q[f"{f}_mcp"], abs=1e-12)
        for name in ["T_ip", "I_dip", "M_dip", "R_dip", "L_dip"]:
            assert q[name] == pytest.approx(np.radians(20), abs=1e-12)
        psi = MEAN_POSE + SYNERGIES @ u[6:]
        np.testing.assert_allclose(hand.pose(u), psi, atol=1e-12)
        np.testing.assert_allclose([q[n] for n in hand.actuated_names], psi, atol=1e-12)
    assert hand.actuated_names == ["T_rot", "T_abd", "I_mcp", "M_mcp", "R_mcp", "L_mcp"]


def test_segment_lengths_are_table1(hand):
    for u in random_configs(3, seed=3):
        geo = hand.segments(u)
        lengths = np.linalg.norm(geo.capsules[:, 1] - geo.capsules[:, 0], axis=1)
        np.testing.assert_allclose(lengths, [v for f in "TIMRL" for v in TABLE1[f]], atol=1e-9)
        chains = geo.capsules.reshape(5, 3, 2, 3)
        np.testing.assert_allclose(chains[:, 1:, 0], chains[:, :-1, 1], atol=1e-9)   # joints connect
        # hand points sit contact_offset mm from the axis: on the pad beside a segment's midpoint
        # (perpendicular to it), and on the front of the pad at a fingertip (45 degrees round the cap)
        cases = ((chains[:, -1, 1], hand.points(u, "precision"), chains[:, -1, 1] - chains[:, -1, 0], np.sqrt(0.5)),
                 (geo.capsules.mean(axis=1), hand.points(u, "power")[:-1], geo.capsules[:, 1] - geo.capsules[:, 0], 0.0))
        for ends, pts, axis, along in cases:
            offset = pts - ends
            np.testing.assert_allclose(np.linalg.norm(offset, axis=1), hand.contact_offset, atol=1e-9)
            unit = axis / np.linalg.norm(axis, axis=1)[:, None]
            np.testing.assert_allclose(np.einsum("ij,ij->i", offset, unit), along * hand.contact_offset, atol=1e-9)


# ---------------------------------------------------------------- rigid motion

def test_translation_moves_all_points(hand):
    u = random_configs(1, seed=4)[0]
    shift = np.array([12.0, -40.0, 7.5])
    for kind in ("precision", "power"):
        moved = hand.points(u + np.r_[shift, np.zeros(5)], kind)
        np.testing.assert_allclose(moved - hand.points(u, kind), np.broadcast_to(shift, moved.shape), atol=1e-9)


def test_rotation_is_intrinsic_xyz(hand):
    for u in random_configs(4, seed=5):
        rot = Rotation.from_euler("XYZ", u[3:6]).as_matrix()
        np.testing.assert_allclose(rotation_xyz(u[3:6]), rot, atol=1e-12)
        local = hand.points(np.r_[np.zeros(6), u[6:]], "power")
        np.testing.assert_allclose(hand.points(u, "power"), u[:3] + local @ rot.T, atol=1e-9)
        geo = hand.segments(u)
        np.testing.assert_allclose(geo.palm_axes, rot, atol=1e-12)


# ---------------------------------------------------------------- anthropomorphic layout

def test_fingertips_in_front_of_palm_in_mean_pose(hand):
    tips = hand.points(at(0, 0), "precision")
    assert np.all(tips[:, 2] > hand.palm_half_extents[2] + 40)
    assert 0 < hand.palm_point[2] <= hand.palm_half_extents[2] + 1e-9


def test_opening_and_closing(hand):
    """Raising z2 lowers every mcp angle (Table 2) and opens the hand."""
    for z1 in (-1.0, 0.0, 1.0):
        spread, reach = [], []
        for z2 in np.linspace(-1, 1, 5):
            tips = hand.points(at(z1, z2), "precision")
            spread.append(np.linalg.norm(tips[:, :2], axis=1).mean())      # from the palm normal axis
            reach.append(np.linalg.norm(tips - hand.palm_point, axis=1).mean())
        assert np.all(np.diff(spread) > 5) and np.all(np.diff(reach) > 5)


def test_fingertips_as_the_hand_format_page_states(hand):
    """docs/hand_format.md's figures of the paper's hand: fingertips on the axes and on the pads, their distances and
    the opposition angles (to the page's rounding)."""
    ends = hand.segments(at(0, 0)).capsules.reshape(5, 3, 2, 3)[:, -1, 1]
    pads, jac = hand.points_and_jacobian(at(0, 0), "precision")
    assert np.abs(ends - [[16, 24, 78], [30, 86, 73], [9, 83, 80], [-11, 72, 79], [-28, 50, 69]]).max() < 0.5
    assert np.abs(pads - [[15, 32, 75], [29, 80, 78], [9, 76, 84], [-10, 65, 83], [-27, 43, 70]]).max() < 0.5
    assert np.linalg.norm(ends[0] - ends[1:3], axis=1).round().tolist() == [64.0, 59.0]
    assert np.linalg.norm(pads[0] - pads[1:3], axis=1).round().tolist() == [50.0, 46.0]
    for z, degrees in (((0, 0), 124), ((0, 0.5), 135)):
        t = hand.segments(at(*z)).capsules.reshape(5, 3, 2, 3)[:, -1, 1]
        assert round(angle_deg(t[0] - t.mean(0), (t[1] + t[2]) / 2 - t.mean(0))) == degrees, z
    h = 1e-6
    closing = (hand.segments(at(0, -h)).capsules - hand.segments(at(0, h)).capsules).reshape(5, 3, 2, 3)[:, -1, 1]
    assert round(angle_deg(closing[0], closing[1:].mean(axis=0))) == 133
    assert round(angle_deg(-jac[0, :, 7], -jac[1:, :, 7].mean(axis=0))) == 125


def test_thumb_opposes_fingers(hand):
    tips, jac = hand.points_and_jacobian(at(0, 0), "precision")
    for finger in (1, 2):                                       # index and middle
        assert 40 < np.linalg.norm(tips[0] - tips[finger]) < 90
    for z in [(0, 0), (0, 0.5), (-0.5, 0.5)]:
        t = hand.segments(at(*z)).capsules.reshape(5, 3, 2, 3)[:, -1, 1]  # fingertips on the axes
        assert angle_deg(t[0] - t.mean(0), (t[1] + t[2]) / 2 - t.mean(0)) > 120, z
    # closing the hand (z2 down) drives the thumb tip and the fingertips towards each other
    closing = -jac[:, :, 7]
    assert angle_deg(closing[0], closing[1:].mean(axis=0)) > 120


def q_distance_margin(points, normals, centre, length, mu=0.3, edges=8):
    """Penetration of the origin into the primitive wrench hull, gauged by the regular 6-simplex."""
    wrenches = []
    for p, n in zip(points, normals):
        e1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n, e1)
        for t in 2 * np.pi * np.arange(edges) / edges:
            d = n + mu * (np.cos(t) * e1 + np.sin(t) * e2)
            wrenches.append(np.r_[d, np.cross(p - centre, d) / length])
    w = np.array(wrenches)
    simplex = np.eye(7) - 1 / 7
    simplex = simplex @ np.linalg.svd(simplex)[2][:6].T
    simplex /= np.linalg.norm(simplex, axis=1, keepdims=True)
    depth = []
    for q in simplex:                       # max rho with rho q in conv(w)
        a_eq = np.zeros((7, len(w) + 1))
        a_eq[:6, :-1], a_eq[:6, -1], a_eq[6, :-1] = w.T, -q, 1.0
        res = linprog(np.r_[np.zeros(len(w)), -1.0], A_eq=a_eq, b_eq=np.r_[np.zeros(6), 1.0])
        if res.status != 0:
            return np.inf
        depth.append(-res.fun)
    return -min(depth)


def nearest_on_ellipsoid(x, axes):
    """Nearest point (and inward normal) on an origin-centred ellipsoid, inside or out.

    The nearest point is ``y = a^2 x / (a^2 + t)`` with t the root of
    ``sum (a x / (a^2 + t))^2 = 1`` above ``-min(a)^2``, where the function decreases.
    """
    def excess(t):
        return np.sum((axes * x / (axes**2 + t)) ** 2) - 1.0

    low = -np.min(axes) ** 2 * (1 - 1e-12)
    t = brentq(excess, low, 1e6)
    y = axes**2 * x / (axes**2 + t)
    n = -y / axes**2
    return y, n / np.linalg.norm(n)


def test_force_closed_fingertip_grasp_of_the_ellipsoid_exists(hand):
    """A witness configuration (found offline by search) that the planner's target is reachable."""
    axes = np.array([30.0, 40.0, 50.0])
    u = np.array([77.58, -50.17, -43.27, 0.69, -1.34, 0.54, 0.09, 0.49])
    tips = hand.points(u, "precision")
    contacts = [nearest_on_ellipsoid(x, axes) for x in tips]
    points, normals = map(np.array, zip(*contacts))
    assert np.all(np.linalg.norm(tips - points, axis=1) < 5.0)
    assert q_distance_margin(points, normals, np.zeros(3), 40.0) < -0.1


# ---------------------------------------------------------------- files

def test_default_is_package_file(hand):
    assert hand.name == "paper_hand"
    assert hand.finger_names == list("TIMRL")


def test_from_file_round_trip(hand, tmp_path):
    data = hand.to_dict()
    data["fingers"][1]["joints"][0]["length"] = 60.0            # index proximal phalanx
    path = tmp_path / "long_index.json"
    path.write_text(json.dumps(data))
    other = SynergyHand.from_file(path)
    u = at(0.3, -0.2)
    lengths = np.linalg.norm(np.diff(other.segments(u).capsules, axis=1)[:, 0], axis=1)
    assert lengths[3] == pytest.approx(60.0)
    assert not np.allclose(other.points(u)[1], hand.points(u)[1])
    np.testing.assert_allclose(other.points(u)[[0, 2, 3, 4]], hand.points(u)[[0, 2, 3, 4]])


def test_documented_example_loads():
    doc = (Path(__file__).resolve().parents[1] / "docs" / "hand_format.md").read_text()
    example = json.loads(re.search(r"```json\n(.*?)```", doc, re.S).group(1))
    small = SynergyHand(example, source="hand_format.md")
    u = np.r_[np.zeros(6), 0.5]
    assert small.n_u == 7 and small.points(u).shape == (3, 3)
    assert small.point_labels("power") == ["T1", "T2", "I1", "I2", "M1", "M2", "P"]
    assert small.joint_angles(u)["T_ip"] == pytest.approx(0.5 * (0.5 - 0.3 * 0.5))


def test_three_synergy_hand(hand, tmp_path):
    data = hand.to_dict()
    third = [0.1, 0.0, -0.2, 0.1, 0.0, 0.3]
    data["synergies"] = [row + [s] for row, s in zip(data["synergies"], third)]
    data["synergy_limits"].append([-0.5, 2.0])
    path = tmp_path / "three.json"
    path.write_text(json.dumps(data))
    h3 = SynergyHand.from_file(path)
    assert h3.n_syn == 3 and h3.n_u == 9 and h3.synergy_limits.shape == (3, 2)
    u = np.r_[random_configs(1, seed=6)[0], 0.4]
    np.testing.assert_allclose(h3.pose(u), MEAN_POSE + SYNERGIES @ u[6:8] + 0.4 * np.array(third), atol=1e-12)
    x, jac = h3.points_and_jacobian(u, "power")
    assert jac.shape == (16, 3, 9)
    du = np.r_[np.zeros(8), 1e-6]
    fd = (h3.points(u + du, "power") - h3.points(u - du, "power")) / 2e-6
    np.testing.assert_allclose(jac[:, :, 8], fd, atol=1e-6)
    np.testing.assert_allclose(h3.points(np.r_[u[:8], 0.0]), hand.points(u[:8]), atol=1e-9)
    with pytest.raises(ValueError, match="u"):
        h3.points(u[:8])


@pytest.mark.parametrize("field, path", [
    ("mean_pose", ["mean_pose"]),
    ("synergy_limits", ["synergy_limits"]),
    ("finger_radius", ["finger_radius"]),
    ("palm.point", ["palm", "point"]),
    ("fingers[2].base.position", ["fingers", 2, "base", "position"]),
    ("fingers[0].joints[1].axis", ["fingers", 0, "joints", 1, "axis"]),
    ("fingers[4].joints[2].offset", ["fingers", 4, "joints", 2, "offset"]),
])
def test_missing_field_is_named(hand, tmp_path, field, path):
    data = hand.to_dict()
    parent = data
    for key in path[:-1]:
        parent = parent[key]
    del parent[path[-1]]
    file = tmp_path / "broken.json"
    file.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"broken\.json") as err:
        SynergyHand.from_file(file)
    assert f"'{field}'" in str(err.value)


@pytest.mark.parametrize("edit, field", [
    (lambda d: d.update(mean_pose=[0.0] * 5), "mean_pose"),
    (lambda d: d.update(synergy_limits=[[1.0, -1.0], [-1.0, 1.0]]), "synergy_limits"),
    (lambda d: d.update(synergies=[[0.0, 0.0] for _ in d["synergies"]]), "synergies"),  # a hand that cannot close
    (lambda d: d["fingers"][0]["joints"][0].update(axis=[0, 0, 0]), "fingers[0].joints[0].axis"),
    (lambda d: d["fingers"][1]["joints"][1].update(coupling={"X_mcp": 1.0}), "fingers[1].joints[1].coupling.X_mcp"),
    (lambda d: d["palm"].update(size="big"), "palm.size"),
    (lambda d: d.update(finger_radius=10**400), "finger_radius"),  # an integer beyond the float range
    (lambda d: d["fingers"][4]["joints"][1].update(name="palm"), "fingers[].joints[].name"),  # the physics' body
    (lambda d: d["fingers"][4]["joints"][1].update(name="object"), "fingers[].joints[].name"),
])
def test_malformed_field_is_named(hand, tmp_path, edit, field):
    data = hand.to_dict()
    edit(data)
    file = tmp_path / "bad.json"
    file.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"bad\.json") as err:
        SynergyHand.from_file(file)
    assert f"'{field}'" in str(err.value)


# ---------------------------------------------------------------- argument checks

@pytest.mark.parametrize("u", [np.zeros(7), np.zeros(9), np.zeros((2, 8)), np.r_[np.zeros(7), np.nan],
                               np.r_[np.inf, np.zeros(7)]])
def test_bad_u_raises(hand, u):
    for call in (hand.points, hand.points_jacobian, hand.points_and_jacobian):
        with pytest.raises(ValueError, match=r"\bu\b"):
            call(u)
    with pytest.raises(ValueError, match=r"\bu\b"):
        hand.joint_angles(u)
    with pytest.raises(ValueError, match=r"\bu\b"):
        hand.segments(u)


def test_unknown_kind_lists_kinds(hand):
    with pytest.raises(ValueError, match="precision.*power"):
        hand.points(np.zeros(8), "pinch")
    with pytest.raises(ValueError, match="precision.*power"):
        hand.point_labels("grip")


def test_segment_end_jacobians_match_finite_differences(hand):
    for u in random_configs(3, seed=11):
        ends, jac = hand.segments_and_jacobian(u)
        np.testing.assert_allclose(ends, hand.segments(u).capsules, atol=1e-12)
        for k in range(len(u)):
            step = np.zeros(len(u))
            step[k] = 1e-6
            fd = (hand.segments_and_jacobian(u + step)[0] - hand.segments_and_jacobian(u - step)[0]) / 2e-6
            np.testing.assert_allclose(jac[..., k], fd, atol=1e-6)


@pytest.mark.parametrize("kind", ["precision", "power"])
def test_skin_points_lie_on_the_capsules_and_their_jacobians_match_finite_differences(hand, kind):
    middle = SKIN_ALONG[kind].index(0.5) * len(SKIN_AROUND) + SKIN_AROUND.index(0.0)  # the palmar middle point
    for u in random_configs(3, seed=12):
        skin, palm, jac, palm_jac = hand.skin_and_jacobian(u, kind)
        assert skin.shape == (15, len(SKIN_ALONG[kind]) * len(SKIN_AROUND), 3)
        capsules = hand.segments(u).capsules
        a, b = capsules[:, None, 0], capsules[:, None, 1]
        t = np.clip(np.einsum("kma,kma->km", skin - a, b - a) / np.einsum("kma,kma->km", b - a, b - a), 0, 1)
        to_axis = np.linalg.norm(skin - (a + t[..., None] * (b - a)), axis=-1)
        np.testing.assert_allclose(to_axis, hand.finger_radius, atol=1e-9)  # on the capsule surface
        np.testing.assert_allclose(skin[:, middle], hand.points(u, "power")[:-1], atol=1e-12)  # = the power point
        np.testing.assert_allclose(palm[0], hand.points(u, "power")[-1], atol=1e-12)  # the palm point P first
        geo = hand.segments(u)  # the rest on the rim of the palm box's front face
        local = (palm[1:] - geo.palm_center) @ geo.palm_axes
        np.testing.assert_allclose(local[:, 2], geo.palm_half_extents[2], atol=1e-9)
        assert np.all(np.abs(local[:, :2]) <= geo.palm_half_extents[:2] + 1e-9)
        np.testing.assert_allclose(np.abs(local[:, :2]).max(axis=0), geo.palm_half_extents[:2], atol=1e-9)
        for k in range(len(u)):
            step = np.zeros(len(u))
            step[k] = 1e-6
            plus, minus = hand.skin_and_jacobian(u + step, kind), hand.skin_and_jacobian(u - step, kind)
            np.testing.assert_allclose(jac[..., k], (plus[0] - minus[0]) / 2e-6, atol=1e-6)
            np.testing.assert_allclose(palm_jac[..., k], (plus[1] - minus[1]) / 2e-6, atol=1e-6)


@pytest.mark.parametrize("kind", ["precision", "power"])
def test_points_and_skin_is_the_grasps_points_and_its_skin_from_one_pass(hand, kind):
    u = random_configs(1, seed=5)[0]
    together = hand.points_and_skin(u, kind)
    for a, b in zip(together, (*hand.points_and_jacobian(u, kind), *hand.skin_and_jacobian(u, kind))):
        np.testing.assert_allclose(a, b, atol=1e-12)


@pytest.mark.parametrize("call", ["skin_and_jacobian", "points_and_skin"])
def test_skin_of_an_unknown_grasp_kind_is_refused(hand, call):
    with pytest.raises(ValueError, match="kind must be 'precision' or 'power', got 'pinch'"):
        getattr(hand, call)(np.zeros(hand.n_u), "pinch")


def hand_with_synergies(k):
    """The paper's hand with k - 2 more synergies that move nothing (zero columns)."""
    data = SynergyHand.default().to_dict()
    data["synergies"] = [row + [0.0] * (k - 2) for row in data["synergies"]]
    data["synergy_limits"] += [[-1.0, 1.0]] * (k - 2)
    return SynergyHand(data)


@pytest.mark.parametrize("k, values", [(3, 12), (4, 6), (10, 2), (11, 2)])
def test_a_grid_over_many_synergies_stays_small(k, values):
    """41 values per synergy would be 41**k hand evaluations: fewer values per synergy keep the grid within its
    bound, the limits included; past 2**k points it is a seeded draw from the 2-value grid."""
    from synergrasp.hand import SYNERGY_GRID_POINTS

    grid = hand_with_synergies(k).synergy_grid(41)
    assert len(grid) <= SYNERGY_GRID_POINTS and grid.shape[1] == k
    assert sorted(set(grid[:, -1])) == pytest.approx(np.linspace(-1.0, 1.0, values))
    np.testing.assert_array_equal(grid, hand_with_synergies(k).synergy_grid(41))
    if 2**k > SYNERGY_GRID_POINTS:  # the seeded draw from the 2-value grid
        assert len(grid) == SYNERGY_GRID_POINTS and set(np.unique(grid)) == {-1.0, 1.0}


def test_a_grid_needs_two_values_per_synergy(hand):
    for steps, max_points in ((1, 10), (0, 10), (3, 0), (2.5, 10)):
        with pytest.raises(ValueError, match=r"(steps|max_points) must be an integer >= [12] \((values per synergy|rows of the grid)\)"):
            hand.synergy_grid(steps, max_points)


def test_a_hand_of_ten_synergies_plans(hand):
    """Its starts and grids stay small (a 41**10 grid never finished); the power pre-shapes are the user's to give."""
    import synergrasp as sg

    many = hand_with_synergies(10)
    assert sg.plan("ellipsoid", "precision", hand=many).success
    with pytest.raises(ValueError, match="power_preshape and power_wide_preshape 10 values each, or None"):
        sg.plan("ellipsoid", "power", hand=many)
    assert sg.plan("ellipsoid", "power", hand=many, power_preshape=None, power_wide_preshape=None).success


def test_fingers_of_any_names_plan_and_draw(hand, tmp_path):
    """Finger names longer than a letter ('Th', ...): the planner found a finger's rows by its labels' first letter
    (precision plans failed), the figures its colour (KeyError); the rows and colours now follow the fingers."""
    import synergrasp as sg
    from synergrasp import viz
    from synergrasp.planner import status_rows

    data = hand.to_dict()
    for finger, name in zip(data["fingers"], ["Th", "In", "Mi", "Ri", "Li"]):
        finger["name"] = name
    named = SynergyHand(data)
    assert named.point_chains("precision").tolist() == hand.point_chains("precision").tolist() == [0, 1, 2, 3, 4]
    for kind in ("precision", "power"):
        labels, contact, rows = status_rows(named, kind)
        paper_labels, paper_contact, paper_rows = status_rows(hand, kind)
        assert [lab.replace("Th", "T").replace("In", "I").replace("Mi", "M").replace("Ri", "R").replace("Li", "L")
                for lab in labels] == paper_labels
        assert contact.tolist() == paper_contact.tolist() and rows.tolist() == paper_rows.tolist()
    obj = sg.objects.ellipsoid()
    result = sg.plan(obj, "precision", hand=named)
    assert result.success and result.hand == named.identity
    assert sg.plan(obj, "precision", method="annealing", hand=named, steps=20).trajectory.shape[1] == 8
    assert viz.plot_poses(result, obj, named, tmp_path / "poses.png").stat().st_size > 0
    assert len(viz.scene(obj, named, result.u).geometry) == 17
    with pytest.raises(ValueError, match="planned with hand .* pass labels=hand.point_labels"):
        viz.plot_status(result, tmp_path / "status.png")
    assert viz.plot_status(result, tmp_path / "status.png", labels=named.point_labels("precision")).exists()


def test_a_hand_given_numpy_arrays_is_json_and_plans(hand):
    """Synergies from a PCA come as arrays: to_dict() is JSON (a plan's per-hand cache dumps it), the same hand."""
    import synergrasp as sg

    data = hand.to_dict()
    data["synergies"] = np.array(data["synergies"])
    data["finger_radius"] = np.float64(data["finger_radius"])
    from_arrays = SynergyHand(data)
    assert json.loads(json.dumps(from_arrays.to_dict())) == hand.to_dict()
    assert from_arrays.identity == hand.identity
    assert sg.plan("ellipsoid", "precision", hand=from_arrays, max_iter=5).iterations == 5


def test_the_identity_of_a_hand_does_not_depend_on_how_its_numbers_are_written():
    """A hand file rewritten with 46.0 as 46 (or 0.0 as -0.0) is the same hand (to_dict compares equal): its identity
    differed, and the results it had planned were refused by validate. A record of the digest before numbers were
    normalised is still this hand's."""
    import hashlib
    import json

    hand = SynergyHand.default()
    data = hand.to_dict()
    as_ints = json.loads(json.dumps(data), parse_float=lambda t: int(float(t)) if float(t).is_integer() else float(t))
    as_ints["palm"]["center"][0] = -0.0
    other = SynergyHand(as_ints)
    assert other.to_dict() == data and other.identity == hand.identity
    changed = SynergyHand({**data, "finger_radius": data["finger_radius"] + 0.5})
    assert changed.identity != hand.identity and not hand.made(changed.identity)
    text = json.dumps(as_ints, sort_keys=True, separators=(",", ":"))  # the digest as records kept it before
    earlier = f"{other.name} sha256:{hashlib.sha256(text.encode()).hexdigest()[:16]}"
    assert earlier != other.identity and other.made(earlier) and not hand.made(earlier)
