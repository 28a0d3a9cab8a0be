"""Running the hold test in MuJoCo: squeeze, settle, then push along six directions.

This module owns the ``mujoco`` import (`mujoco_module`) and the simulation
of one grasp (`simulate`); `synergrasp.physics.validate` prepares its inputs.
"""

from __future__ import annotations

import contextlib
import os

import numpy as np

from ..hand import rotation_xyz
from .model import MM, OBJECT, PALM, grasp_mjcf, mujoco_quat
from .protocol import DIRECTIONS, MAX_STEPS

__all__ = ["mujoco_module", "build_model", "simulate", "simulate_reach", "verdict", "INSTALL_HINT"]

INSTALL_HINT = 'pip install "synergrasp[sim]"'
#: Simulated time between two checks of the object during a push (s).
CHECK_INTERVAL = 0.01
#: A push stops once the object has moved or turned this many times its threshold: it is lost.
LOST = 5.0
#: A push also stops once every joint, the object included, has been at rest this long (s): a state at
#: rest under constant forces stays at rest. At rest: speeds under `REST_SPEED` (m/s) and `REST_SPIN` (rad/s).
REST_TIME = 0.2
REST_SPEED = 1e-4
REST_SPIN = 1e-3
#: Unit vectors of `DIRECTIONS` ("-x" -> [-1, 0, 0], ...).
_AXES = np.array([float(d[0] + "1") * np.eye(3)["xyz".index(d[1])] for d in DIRECTIONS])


def mujoco_module():
    """The ``mujoco`` package, imported on first use.

    Returns
    -------
    module

    Raises
    ------
    ImportError
        If MuJoCo is not installed (the message says how to install it), or
        cannot be imported with the rendering backend ``MUJOCO_GL`` names.
    """
    try:
        import mujoco
    except ImportError as exc:
        raise ImportError(f"physics validation needs the mujoco package: {INSTALL_HINT}") from exc
    except Exception as exc:  # noqa: BLE001 - MUJOCO_GL names a rendering library that is not there
        raise ImportError(
            f"importing mujoco failed with MUJOCO_GL={os.environ.get('MUJOCO_GL')!r} ({type(exc).__name__}: {exc}): "
            "it must name a rendering backend that is installed (egl: libEGL, osmesa: libOSMesa, glfw: a display); "
            "or unset MUJOCO_GL (validation itself renders nothing)") from exc
    return mujoco


def build_model(hand, obj, u, protocol, mocap=False):
    """Compile the MuJoCo model of a hand configuration around an object.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
    protocol : Protocol
        Friction, contact softness, servos, time step and the object's
        density (or mass).
    mocap : bool
        The palm is a mocap body (moved by a replay) instead of a static one.

    Returns
    -------
    mujoco : module
    model : mujoco.MjModel
    scene : GraspScene

    Raises
    ------
    ImportError
        If MuJoCo is not installed.
    ValueError
        If MuJoCo cannot build the model.
    """
    mujoco = mujoco_module()
    p = protocol
    density = p.density if p.mass is None else p.mass / (obj.volume * 1e-9)  # volume in m^3
    scene = grasp_mjcf(hand, obj, u, density=density, friction=(p.mu, p.torsional_friction, 0.0), solref=p.solref,
                       solimp=p.solimp, timestep=p.timestep, joint_damping=p.joint_damping, kp=p.kp,
                       impratio=p.impratio, noslip_iterations=p.noslip_iterations, mocap=mocap)
    try:
        model = mujoco.MjModel.from_xml_string(scene.xml)
    except ValueError as exc:
        raise ValueError(f"MuJoCo could not build the grasp model of {obj.name!r}: {exc}") from None
    return mujoco, model, scene


def _leg_steps(hand, path, speed, timestep) -> list[int]:
    """Time steps of each leg of a replayed path: the time its fastest capsule end or palm corner takes at ``speed``.

    Parameters
    ----------
    hand : SynergyHand
    path : (k, n_u) float
    speed : float
        mm/s.
    timestep : float
        s.

    Returns
    -------
    list of int
        k - 1 counts, each at least 1.
    """
    points = [np.vstack([g.capsules.reshape(-1, 3), g.palm_corners]) for g in map(hand.segments, path)]
    return [max(1, round(float(np.linalg.norm(b - a, axis=1).max()) / speed / timestep))
            for a, b in zip(points[:-1], points[1:])]


def simulate_reach(hand, obj, path, squeeze_angles, protocol, speed) -> dict:
    """Simulate a reach: the palm follows a path, the finger servos its synergies, then the squeeze.

    The palm is a mocap body moved along ``path`` (straight lines in ``u``
    between rows, each taking the time for the hand's fastest capsule end or
    palm corner to move at ``speed``); the servo targets follow the joint
    angles of the path. Then the targets ramp to ``squeeze_angles`` over
    ``protocol.squeeze_time`` and hold for ``protocol.settle_time``. The
    object is free and undamped throughout, without gravity.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    path : (k, 6 + n_syn) float
        The reach, pre-grasp first, grasp last.
    squeeze_angles : dict of str to float
        Servo targets of the squeeze (rad).
    protocol : Protocol
    speed : float
        mm/s.

    Returns
    -------
    dict
        ``moved`` and ``turned`` (k,): the object's displacement (mm) and
        rotation (degrees) from its planned pose when the hand reaches each
        row; ``first_contact``: the row the hand was moving to when it first
        touched the object (0: touching at the start, -1: never before the
        squeeze); ``moved_after_squeeze``, ``turned_after_squeeze``;
        ``contact_bodies``: the hand geoms touching the object at the end;
        ``duration``: simulated time (s); ``outcome`` (``"done"`` or
        ``"unstable"``) and ``reason``.

    Raises
    ------
    ImportError
        If MuJoCo is not installed.
    ValueError
        If MuJoCo cannot build the model, or the reach would take more than
        `synergrasp.physics.protocol.MAX_STEPS` time steps.
    """
    legs = _leg_steps(hand, path, speed, protocol.timestep)
    steps = sum(legs) + (protocol.squeeze_time + protocol.settle_time) / protocol.timestep
    if steps > MAX_STEPS:
        raise ValueError(f"this replay simulates {steps:.3g} time steps (the path at {speed:g} mm/s, then the squeeze "
                         f"and settling), more than the {MAX_STEPS:.0e} synergrasp runs: is the path in mm, its rows a "
                         "reach's (a few hundred mm long)?")
    return _simulated(hand, obj, path[0], protocol, True, lambda sim: sim.follow(hand, path, squeeze_angles, legs))


class _Unstable(Exception):
    """The simulation went unstable; the message says where."""


@contextlib.contextmanager
def _warnings_caught(mujoco, messages):
    """Collect MuJoCo's warnings in ``messages`` instead of printing them and writing MUJOCO_LOG.TXT."""
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(messages.append)
    try:
        yield
    finally:
        mujoco.set_mju_user_warning(previous)


def _angle(q0, q1):
    """Rotation angle (degrees) between two unit quaternions."""
    return float(np.degrees(2.0 * np.arccos(min(1.0, abs(float(np.dot(q0, q1)))))))


def simulate(hand, obj, u, start_angles, squeeze_angles, protocol) -> dict:
    """Simulate the hold test of a hand configuration around an object.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
        Configuration of the palm (its pose is welded) and start of the hinges.
    start_angles, squeeze_angles : dict of str to float
        Servo targets of the moving joints at the start and after the squeeze (rad).
    protocol : Protocol

    Returns
    -------
    dict
        What the simulation measured: the fields of `Validation` from
        ``outcome`` to ``joint_angles``.

    Raises
    ------
    ImportError
        If MuJoCo is not installed.
    ValueError
        If MuJoCo cannot build the model.
    """
    return _simulated(hand, obj, u, protocol, False, lambda sim: sim.run(start_angles, squeeze_angles))


def _simulated(hand, obj, u, protocol, mocap, phases):
    """``phases(simulation)`` on a new model of the hand at u around the object, MuJoCo's warnings collected."""
    messages = []
    mujoco = mujoco_module()
    with _warnings_caught(mujoco, messages):
        mujoco, model, scene = build_model(hand, obj, u, protocol, mocap=mocap)
        return phases(_Simulation(mujoco, model, mujoco.MjData(model), scene, protocol, messages))


def verdict(p, displacement, rotation, contacts, shift):
    """The outcome of a hold test and its reason, from the six pushes' results.

    Parameters
    ----------
    p : Protocol
    displacement, rotation : (6,) float
        The object's largest displacement (mm) and rotation (degrees) under
        each push, in the order of `DIRECTIONS`.
    contacts : sequence
        The hand's contacts with the object after the squeeze (empty: none).
    shift : float
        How far the object moved from its planned pose while the hand
        squeezed and the grasp settled (mm); quoted when no contact is left.

    Returns
    -------
    outcome : str
        ``"held"``, ``"slip"``, ``"rotation"`` or ``"no contact"``.
    reason : str
        In words; a slip or a rotation quotes the push that moved or turned
        the object most.
    """
    moved = displacement >= p.max_displacement
    turned = rotation >= p.max_rotation
    failed = moved | turned
    where = ", ".join(DIRECTIONS[k] for k in np.flatnonzero(failed))
    if not contacts:  # whatever the pushes did: a push too short or too weak can leave a free object in place
        lost = f" (lost along {where})" if where else " (the pushes did not move it far enough to say)"
        return "no contact", (f"no contact after the squeeze: the hand does not touch the object, which moved "
                              f"{shift:.1f} mm from its planned pose while the hand closed{lost}")
    if not failed.any():
        k = int(np.argmax(displacement))
        return "held", (f"held along all six directions (largest displacement {displacement[k]:.2f} mm along "
                        f"{DIRECTIONS[k]}, largest rotation {rotation.max():.2f} deg)")
    if moved.any():  # the farthest of the pushes that moved it too far
        k = int(np.argmax(np.where(moved, displacement, -np.inf)))
        return "slip", (f"slipped under the push along {where}: moved {displacement[k]:.1f} mm along {DIRECTIONS[k]} "
                        f"(max_displacement {p.max_displacement:g} mm)")
    k = int(np.argmax(np.where(turned, rotation, -np.inf)))
    return "rotation", (f"turned under the push along {where}: {rotation[k]:.1f} deg along {DIRECTIONS[k]} "
                        f"(max_rotation {p.max_rotation:g} deg)")


class _Simulation:
    """The phases of one hold test on a compiled model."""

    def __init__(self, mujoco, model, data, scene, protocol, messages):
        self.mj, self.model, self.data, self.p, self.messages = mujoco, model, data, protocol, messages
        self.body = model.body(OBJECT).id
        free = model.joint(OBJECT)
        self.qpos = slice(free.qposadr[0], free.qposadr[0] + 7)
        self.dofs = slice(free.dofadr[0], free.dofadr[0] + 6)
        self.hinges = np.array([model.joint(name).qposadr[0] for name in scene.joints], dtype=int)
        self.joints = scene.joints
        self.object_geoms = {model.geom(f"{OBJECT}/{i}").id: i for i in range(scene.pieces)}
        self.mass = float(model.body_mass[self.body])

    # ------------------------------------------------------------------ measurements

    def pose(self):
        return self.data.qpos[self.qpos].copy()

    def contacts(self):
        """Hand-object contacts: (hand geom, piece, position m, normal into the object, depth m, normal force N)."""
        out = []
        force = np.zeros(6)
        for i in range(self.data.ncon):
            c = self.data.contact[i]
            g1, g2 = int(c.geom1), int(c.geom2)
            if (g1 in self.object_geoms) == (g2 in self.object_geoms):
                continue
            # MuJoCo's frame[0:3] is the normal from geom1 to geom2
            hand_geom, piece, normal = (g2, self.object_geoms[g1], -c.frame[:3]) if g1 in self.object_geoms \
                else (g1, self.object_geoms[g2], c.frame[:3].copy())
            self.mj.mj_contactForce(self.model, self.data, i, force)
            out.append((self.model.geom(hand_geom).name, piece, c.pos.copy(), normal, -float(c.dist), float(force[0])))
        return out

    def check(self, phase, speed_allowance=0.0):
        """Raise `_Unstable` on a MuJoCo warning (NaN, inf or huge values in the state) or an explosion."""
        d = self.data
        if self.messages:  # MuJoCo resets a diverged state itself and warns: the warning is the evidence
            raise _Unstable(f"MuJoCo's instability warning during {phase}: {self.messages[0]}")
        speed = float(np.linalg.norm(d.qvel[self.dofs][:3]))
        if speed > self.p.max_speed + speed_allowance:
            raise _Unstable(f"explosion during {phase}: the object reached {speed:.1f} m/s "
                            f"(max_speed {self.p.max_speed:g} m/s beyond the push's own {speed_allowance:.1f} m/s)")

    # ------------------------------------------------------------------ phases

    def run(self, start_angles, squeeze_angles):
        mj, m, d, p = self.mj, self.model, self.data, self.p
        start = np.array([start_angles[j] for j in self.joints])
        target = np.array([squeeze_angles[j] for j in self.joints])
        d.qpos[self.hinges] = start
        d.ctrl[:] = start
        mj.mj_forward(m, d)
        planned = self.pose()
        contacts = self.contacts()
        depth, body = max(((c[4], c[0]) for c in contacts), default=(0.0, ""))
        depth, body = (max(depth, 0.0) * 1e3, body if depth > 0 else "")
        measured = dict(initial_penetration=depth, penetration_body=body, object_mass=self.mass)
        if depth > p.max_penetration:
            return self.unsimulated("penetration", f"initial penetration {depth:.1f} mm by {body} exceeds "
                                    f"max_penetration {p.max_penetration:g} mm (not simulated)", measured)
        self.messages.clear()  # what the compiler said is not a sign of instability
        try:
            settled = self.squeeze_and_settle(start, target)
            reference = planned if p.measure_from == "planned" else self.pose()
            results = [self.push(axis, settled, reference, label) for axis, label in zip(_AXES, DIRECTIONS)]
        except _Unstable as exc:
            return self.unsimulated("unstable", f"unstable simulation: {exc}", measured)
        mj.mj_setState(m, d, settled, mj.mjtState.mjSTATE_INTEGRATION)
        mj.mj_forward(m, d)
        contacts = self.contacts()
        pose = self.pose()
        shift = float(np.linalg.norm(pose[:3] - planned[:3]) * 1e3)
        displacement, rotation = np.array(results).T
        outcome, reason = verdict(self.p, displacement, rotation, contacts, shift)
        return dict(outcome=outcome, reason=reason, displacement=displacement, rotation=rotation,
                   settle_displacement=shift,
                   settle_rotation=_angle(planned[3:], pose[3:]),
                   contact_bodies=[c[0] for c in contacts], contact_pieces=[c[1] for c in contacts],
                   contact_points=np.array([c[2] for c in contacts]).reshape(-1, 3) * 1e3,
                   contact_normals=np.array([c[3] for c in contacts]).reshape(-1, 3),
                   contact_forces=np.array([c[5] for c in contacts]),
                   object_pose=np.r_[pose[:3] * 1e3, pose[3:]],
                   joint_angles=dict(zip(self.joints, d.qpos[self.hinges].tolist())), **measured)

    def squeeze_and_settle(self, start, target):
        """Ramp the servo targets to the squeeze with the object damped, let it settle; the state after."""
        mj, m, d, p = self.mj, self.model, self.data, self.p
        inertia = float(m.body_inertia[self.body].max())
        damping = np.r_[[self.mass / p.settle_damping] * 3, [inertia / p.settle_damping] * 3] if p.settle_damping > 0 else 0.0
        m.dof_damping[self.dofs] = damping
        steps = max(1, round(p.squeeze_time / p.timestep))
        for k in range(steps):
            d.ctrl[:] = start + (target - start) * (k + 1) / steps
            mj.mj_step(m, d)
            self.check("the squeeze")
        for _ in range(round(p.settle_time / p.timestep)):
            mj.mj_step(m, d)
            self.check("settling")
        m.dof_damping[self.dofs] = 0.0
        state = np.empty(mj.mj_stateSize(m, mj.mjtState.mjSTATE_INTEGRATION))
        mj.mj_getState(m, d, state, mj.mjtState.mjSTATE_INTEGRATION)
        return state

    def push(self, axis, settled, reference, label):
        """Push the object along ``axis`` from the settled state; its largest displacement (mm) and rotation (deg)."""
        mj, m, d, p = self.mj, self.model, self.data, self.p
        mj.mj_setState(m, d, settled, mj.mjtState.mjSTATE_INTEGRATION)
        d.xfrc_applied[:] = 0.0
        d.xfrc_applied[self.body, :3] = self.mass * p.acceleration * axis
        chunk = max(1, round(CHECK_INTERVAL / p.timestep))
        steps = round(p.push_time / p.timestep)
        worst_d = worst_r = 0.0
        done = rest = 0
        translation = np.zeros(m.nv, dtype=bool)
        translation[self.dofs.start:self.dofs.start + 3] = True
        try:
            while done < steps:
                n = min(chunk, steps - done)
                mj.mj_step(m, d, n)
                done += n
                self.check(f"the push along {label}", p.acceleration * done * p.timestep)
                pose = self.pose()
                worst_d = max(worst_d, float(np.linalg.norm(pose[:3] - reference[:3])) * 1e3)
                worst_r = max(worst_r, _angle(reference[3:], pose[3:]))
                if worst_d >= LOST * p.max_displacement or worst_r >= LOST * p.max_rotation:
                    break
                still = (np.abs(d.qvel[translation]).max() < REST_SPEED
                         and np.abs(d.qvel[~translation]).max() < REST_SPIN)
                rest = rest + n if still else 0
                if rest * p.timestep >= REST_TIME:
                    break
        finally:
            d.xfrc_applied[:] = 0.0
        return worst_d, worst_r

    # ------------------------------------------------------------------ a reach

    def follow(self, hand, path, squeeze_angles, legs):
        """Move the mocap palm and the servos along the path, each leg in its time steps (``legs``), then squeeze; the
        object's motion (see `simulate_reach`)."""
        mj, m, d, p = self.mj, self.model, self.data, self.p
        mocap = int(m.body(PALM).mocapid[0])
        angles = np.array([[hand.joint_angles(u)[j] for j in self.joints] for u in path])
        target = np.array([squeeze_angles[j] for j in self.joints])
        d.qpos[self.hinges] = d.ctrl[:] = angles[0]
        mj.mj_forward(m, d)
        planned = self.pose()
        moved, turned, first = [0.0], [0.0], (0 if self.contacts() else -1)
        try:
            for i in range(1, len(path)):
                steps = legs[i - 1]
                for k in range(1, steps + 1):
                    t = k / steps
                    u = path[i - 1] + t * (path[i] - path[i - 1])
                    d.mocap_pos[mocap] = u[:3] * MM
                    d.mocap_quat[mocap] = mujoco_quat(rotation_xyz(u[3:6]))
                    d.ctrl[:] = angles[i - 1] + t * (angles[i] - angles[i - 1])
                    mj.mj_step(m, d)
                    self.check("the reach")
                    if first < 0 and d.ncon and self.contacts():
                        first = i
                pose = self.pose()
                moved.append(float(np.linalg.norm(pose[:3] - planned[:3])) * 1e3)
                turned.append(_angle(planned[3:], pose[3:]))
            steps = max(1, round(p.squeeze_time / p.timestep))
            for k in range(steps):
                d.ctrl[:] = angles[-1] + (target - angles[-1]) * (k + 1) / steps
                mj.mj_step(m, d)
                self.check("the squeeze")
            for _ in range(round(p.settle_time / p.timestep)):
                mj.mj_step(m, d)
                self.check("settling")
        except _Unstable as exc:
            nan = np.full(len(path) - len(moved), np.nan)
            return dict(moved=np.r_[moved, nan], turned=np.r_[turned, nan], first_contact=first,
                        moved_after_squeeze=np.nan, turned_after_squeeze=np.nan, contact_bodies=[],
                        duration=float(d.time), outcome="unstable", reason=f"unstable simulation: {exc}")
        pose = self.pose()
        return dict(moved=np.array(moved), turned=np.array(turned), first_contact=first,
                    moved_after_squeeze=float(np.linalg.norm(pose[:3] - planned[:3])) * 1e3,
                    turned_after_squeeze=_angle(planned[3:], pose[3:]),
                    contact_bodies=sorted({c[0] for c in self.contacts()}), duration=float(d.time), outcome="done",
                    reason="simulated the reach and the squeeze")

    def unsimulated(self, outcome, reason, measured):
        nan = np.full(len(DIRECTIONS), np.nan)
        return dict(outcome=outcome, reason=reason, displacement=nan, rotation=nan.copy(), settle_displacement=np.nan,
                   settle_rotation=np.nan, contact_bodies=[], contact_pieces=[], contact_points=np.zeros((0, 3)),
                   contact_normals=np.zeros((0, 3)), contact_forces=np.zeros(0), object_pose=np.full(7, np.nan),
                   joint_angles={}, **measured)
